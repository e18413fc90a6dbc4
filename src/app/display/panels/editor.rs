//! The opening editor: draw one display pixel's opening on its `N×N` cell grid.
//!
//! A press–drag–release (or a click) is one committed edit: while the pointer is down the panel
//! draws on a private draft of the cells and pushes nothing; on release it pushes a single
//! [`Command::Edit`] through [`PanelCtx::edit`], so a whole stroke is one undo step. The drawing
//! itself is [`crate::core::display::opening_ops`]; this file only maps the pointer to cells.

use egui::{
    Button, Color32, ColorImage, ComboBox, PointerButton, Pos2, Rect, Response, Role, Sense,
    Slider, Stroke as LineStroke, StrokeKind, TextureHandle, TextureOptions, Ui, Vec2, WidgetInfo,
    pos2, vec2,
};

use super::PanelCtx;
use super::editor_rules::{RuleMark, RulesOverlay};
use crate::app::display::action::{self, DisplayAction, Tool};
use crate::core::design::{Design, MAX_CELLS};
use crate::core::display::opening_ops::{self as ops, Symmetry};

/// Space kept around the grid, in points.
const MARGIN_PX: f32 = 4.0;
/// Grid lines are drawn only when a cell is at least this many points wide.
const GRID_LINES_MIN_PX: f32 = 6.0;
/// Largest brush, in cells per side.
pub const MAX_BRUSH_CELLS: usize = 7;

/// The opening editor panel (view state only; the opening itself lives in the document).
pub struct EditorPanel {
    brush_cells: usize,
    symmetry: Symmetry,
    /// The value of the grid-size control, and the design size it was last reset to.
    new_n: usize,
    synced_n: usize,
    /// The stroke in progress while the pointer is down.
    stroke: Option<Stroke>,
    /// Where the grid was drawn last frame, and its cells per side.
    grid_rect: Option<Rect>,
    grid_n: usize,
    view: Option<View>,
    /// The design rules on the canvas (View > Design rules on the editor).
    rules: RulesOverlay,
    /// The R, G, B emitter layer.
    pub emitters: super::editor_emitters::EmitterLayer,
}

impl Default for EditorPanel {
    fn default() -> Self {
        EditorPanel {
            brush_cells: 1,
            symmetry: Symmetry::None,
            new_n: 0,
            synced_n: 0,
            stroke: None,
            grid_rect: None,
            grid_n: 0,
            view: None,
            rules: RulesOverlay::default(),
            emitters: Default::default(),
        }
    }
}

/// One press–drag–release on the grid.
struct Stroke {
    tool: Tool,
    value: f64,
    brush_cells: usize,
    symmetry: Symmetry,
    /// The cells when the pointer went down, and the draft drawn on a copy of them.
    base: Vec<Vec<f64>>,
    draft: Vec<Vec<f64>>,
    start: (usize, usize),
    /// The last cell applied (Paint/Erase: the previous pointer cell; shapes: the current end).
    last: Option<(usize, usize)>,
}

impl Stroke {
    fn begin(
        panel: &EditorPanel,
        tool: Tool,
        secondary: bool,
        cells: &[Vec<f64>],
        start: (usize, usize),
    ) -> Self {
        let mut value = if tool == Tool::Erase { 0.0 } else { 1.0 };
        if secondary {
            value = 1.0 - value;
        }
        let mut stroke = Stroke {
            tool,
            value,
            brush_cells: panel.brush_cells,
            symmetry: panel.symmetry,
            base: cells.to_vec(),
            draft: cells.to_vec(),
            start,
            last: None,
        };
        if tool == Tool::Fill {
            ops::flood_fill(&mut stroke.draft, start.0, start.1, value, stroke.symmetry);
        } else {
            stroke.extend(Some(start), start);
        }
        stroke
    }

    /// Follows the pointer: `inside` is its cell (None off the grid), `clamped` the nearest cell.
    fn extend(&mut self, inside: Option<(usize, usize)>, clamped: (usize, usize)) {
        let (value, brush, sym) = (self.value, self.brush_cells, self.symmetry);
        match self.tool {
            Tool::Paint | Tool::Erase => match inside {
                Some(cell) if self.last != Some(cell) => {
                    let from = self.last.unwrap_or(cell);
                    ops::line(&mut self.draft, from, cell, brush, value, sym);
                    self.last = Some(cell);
                }
                Some(_) => {}
                // Leaving the grid breaks the stroke, so re-entering does not draw across.
                None => self.last = None,
            },
            Tool::Rect | Tool::Ellipse | Tool::Line => {
                if self.last != Some(clamped) {
                    self.draft.clone_from(&self.base);
                    let (a, b) = (self.start, clamped);
                    match self.tool {
                        Tool::Rect => ops::rect(&mut self.draft, a, b, value, sym),
                        Tool::Ellipse => ops::ellipse(&mut self.draft, a, b, value, sym),
                        _ => ops::line(&mut self.draft, a, b, brush, value, sym),
                    }
                    self.last = Some(clamped);
                }
            }
            Tool::Fill => {}
        }
    }
}

/// What is on screen: the cells shown (draft or design), their texture and their readouts,
/// refreshed only when the cells or the theme change.
struct View {
    cells: Vec<Vec<f64>>,
    colors: [Color32; 2],
    texture: TextureHandle,
    open_fraction: f64,
    extent: Option<(usize, usize, usize, usize)>,
}

impl EditorPanel {
    /// The screen rectangle of the cell grid drawn last frame (tests use it to aim the pointer).
    pub fn grid_rect(&self) -> Option<Rect> {
        self.grid_rect
    }

    /// The screen position of the centre of cell `(row, col)` of the grid drawn last frame.
    pub fn cell_center(&self, row: usize, col: usize) -> Option<Pos2> {
        let rect = self.grid_rect?;
        if row >= self.grid_n || col >= self.grid_n {
            return None;
        }
        let cell = rect.width() / self.grid_n as f32;
        Some(rect.min + vec2((col as f32 + 0.5) * cell, (row as f32 + 0.5) * cell))
    }

    /// The cells the grid shows (the stroke's draft while drawing, else the document's).
    pub fn shown_cells(&self) -> Option<&[Vec<f64>]> {
        self.view.as_ref().map(|v| v.cells.as_slice())
    }

    /// The design-rule rings on the canvas (none while the overlay is off or checking).
    pub fn rule_marks(&self) -> &[RuleMark] {
        self.rules.marks()
    }

    /// Whether the canvas's design-rule check is still running.
    pub fn rules_checking(&self) -> bool {
        self.rules.is_checking()
    }

    /// Whether a stroke is in progress (the pointer is down on the grid).
    pub fn is_drawing(&self) -> bool {
        self.stroke.is_some()
    }

    /// Side of the square brush of Paint, Erase and Line, in cells.
    pub fn brush_cells(&self) -> usize {
        self.brush_cells
    }

    /// Sets the brush side in cells, clamped to `1..=MAX_BRUSH_CELLS`.
    pub fn set_brush_cells(&mut self, cells: usize) {
        self.brush_cells = cells.clamp(1, MAX_BRUSH_CELLS);
    }

    /// The mirror symmetry applied to every stroke.
    pub fn symmetry(&self) -> Symmetry {
        self.symmetry
    }

    /// Sets the mirror symmetry applied to every later stroke.
    pub fn set_symmetry(&mut self, symmetry: Symmetry) {
        self.symmetry = symmetry;
    }

    /// Draws the toolbar, brush, symmetry and grid-size controls, the cell grid and the readouts
    /// under it; a finished stroke becomes one edit.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut PanelCtx) {
        let n = ctx.design.opening.n();
        if n != self.synced_n {
            self.synced_n = n;
            self.new_n = n;
        }
        self.rules.update(ui.ctx(), ctx.design, ctx.design_rules);
        tools_ui(ui, ctx);
        self.options_ui(ui, ctx);
        self.emitters.controls_ui(ui, ctx);
        ui.separator();
        let hovered = self.grid_ui(ui, ctx);
        self.readouts_ui(ui, ctx.design, hovered);
        self.rules.summary_ui(ui);
    }

    fn options_ui(&mut self, ui: &mut Ui, ctx: &mut PanelCtx) {
        let cell_um = ctx.design.opening.cell_um();
        ui.horizontal_wrapped(|ui| {
            let brush = Slider::new(&mut self.brush_cells, 1..=MAX_BRUSH_CELLS)
                .text("brush")
                .custom_formatter(|v, _| crate::app::widgets::counted(v, "cell", "cells"));
            ui.add(brush).on_hover_text(format!(
                "Side of the square brush of Paint, Erase and Line, in cells \
                     (1 cell = {} µm)",
                fmt_um(cell_um)
            ));
            ComboBox::from_label("symmetry")
                .selected_text(self.symmetry.label())
                .show_ui(ui, |ui| {
                    for s in Symmetry::ALL {
                        ui.selectable_value(&mut self.symmetry, s, s.label());
                    }
                })
                .response
                .on_hover_text(
                    "Mirror every stroke across the opening's vertical centre line (x), its \
                     horizontal centre line (y) or both",
                );
        });
        ui.horizontal_wrapped(|ui| {
            let n = ctx.design.opening.n();
            let pitch_um = ctx.design.opening.pitch_um;
            let label = ui.label("grid");
            ui.add(
                crate::app::widgets::number(&mut self.new_n)
                    .range(1..=MAX_CELLS)
                    .custom_formatter(|v, _| crate::app::widgets::counted(v, "cell", "cells")),
            )
            .labelled_by(label.id)
            .on_hover_text(format!(
                "Cells per side N (1 to {MAX_CELLS}); the pitch stays {} µm, so a cell \
                     becomes {} µm / N",
                fmt_um(pitch_um),
                fmt_um(pitch_um)
            ));
            let tip = format!(
                "Resample the opening to {0}×{0} cells (nearest neighbour; cell {1} µm). \
                 The shape in µm is kept.",
                self.new_n,
                fmt_um(pitch_um / self.new_n.max(1) as f64)
            );
            let apply = ui
                .add_enabled(self.new_n != n && self.new_n >= 1, Button::new("Apply"))
                .on_hover_text(&tip)
                .on_disabled_hover_text("Change the number of cells per side first");
            if apply.clicked() {
                let mut design = ctx.design.clone();
                let new_n = self.new_n.min(MAX_CELLS);
                design.opening.cells = ops::resample(&design.opening.cells, new_n);
                design.reconcile_subpixels();
                ctx.edit(design);
            }
            let import = ui.button("Import PNG…").on_hover_text(
                "Load the opening from a PNG image: bright pixels open, dark closed; \
                 one image pixel per cell (the pitch in µm is kept)",
            );
            if import.clicked() {
                ctx.actions.push(DisplayAction::ImportPattern);
            }
        });
    }

    /// Draws the grid and handles the pointer; returns the cell under the pointer.
    fn grid_ui(&mut self, ui: &mut Ui, ctx: &mut PanelCtx) -> Option<(usize, usize)> {
        let n = ctx.design.opening.n();
        let line_h = ui.text_style_height(&egui::TextStyle::Body) + ui.spacing().item_spacing.y;
        let avail = ui.available_size();
        // The readouts under the grid, and the design-rule summary when it is shown.
        let lines = if ctx.design_rules { 4.0 } else { 3.0 };
        let side = (avail.x.min(avail.y - lines * line_h) - 2.0 * MARGIN_PX).clamp(16.0, 4096.0);
        let (outer, _) = ui.allocate_exact_size(
            vec2(avail.x.max(side), side + 2.0 * MARGIN_PX),
            Sense::hover(),
        );
        let grid = Rect::from_center_size(outer.center(), Vec2::splat(side));
        let response = ui.interact(
            grid,
            ui.make_persistent_id("opening_editor_grid"),
            Sense::click_and_drag(),
        );
        response.widget_info(|| WidgetInfo::labeled(Role::Canvas, true, "Opening editor"));
        self.grid_rect = Some(grid);
        self.grid_n = n;
        if n == 0 {
            (self.stroke, self.view) = (None, None);
            return None;
        }
        let committed = if self.emitters.active() {
            self.emitters.pointer(&response, ctx, grid, n);
            None
        } else {
            self.pointer(ui, &response, ctx, grid, n)
        };

        // The frame that commits a stroke still draws it: the document takes the edit only
        // after this frame, and drawing its old cells here would blink the stroke away until
        // the next repaint (which may wait for the worker's result).
        let cells = match (&self.stroke, &committed) {
            (Some(s), _) => &s.draft,
            (None, Some(draft)) => draft,
            (None, None) => &ctx.design.opening.cells,
        };
        refresh_view(&mut self.view, ui.ctx(), cells, cell_colors(ui.visuals()));
        let pointer = response
            .hover_pos()
            .or_else(|| self.stroke.as_ref().and(response.interact_pointer_pos()));
        let hovered = pointer.and_then(|p| cell_at(grid, n, p));
        let brush = match ctx.tool {
            Tool::Paint | Tool::Erase | Tool::Line => self.brush_cells,
            _ => 1,
        };
        self.paint_grid(ui, grid, n, hovered.map(|cell| (cell, brush)));
        self.emitters
            .paint(ui, grid, n, ctx.design.subpixels.as_ref());
        // Rings on the border reach past the grid's frame.
        let painter = ui.painter_at(grid.expand(16.0));
        let pitch_um = ctx.design.opening.pitch_um;
        self.rules.paint(&painter, grid, n, pitch_um, &response);
        hovered
    }

    /// Paints the cells, the grid lines and the outline of the brush under the pointer.
    fn paint_grid(&self, ui: &Ui, grid: Rect, n: usize, brush: Option<((usize, usize), usize)>) {
        let Some(view) = &self.view else {
            return;
        };
        let painter = ui.painter_at(grid.expand(2.0));
        let uv = Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0));
        painter.image(view.texture.id(), grid, uv, Color32::WHITE);
        let cell_px = grid.width() / n as f32;
        if cell_px >= GRID_LINES_MIN_PX {
            let [closed, open] = view.colors;
            let stroke = LineStroke::new(
                1.0 / ui.ctx().pixels_per_point(),
                closed.lerp_to_gamma(open, 0.5),
            );
            for i in 1..n {
                let t = i as f32 * cell_px;
                painter.vline(grid.min.x + t, grid.y_range(), stroke);
                painter.hline(grid.x_range(), grid.min.y + t, stroke);
            }
        }
        let frame = ui.visuals().widgets.noninteractive.bg_stroke;
        painter.rect_stroke(grid, 0.0, frame, StrokeKind::Outside);
        if let Some(((r, c), brush)) = brush {
            // The same footprint as `opening_ops::paint`: centred, even brushes reach down-right.
            let brush = brush.max(1);
            let before = (brush - 1) / 2;
            let span = |x: usize| (x.saturating_sub(before), (x + brush - before).min(n));
            let ((r0, r1), (c0, c1)) = (span(r), span(c));
            let corner = |r: usize, c: usize| grid.min + vec2(c as f32, r as f32) * cell_px;
            let footprint = Rect::from_min_max(corner(r0, c0), corner(r1, c1));
            let outline = LineStroke::new(2.0, ui.visuals().selection.bg_fill);
            painter.rect_stroke(footprint, 0.0, outline, StrokeKind::Inside);
        }
    }

    /// Starts, extends and commits the stroke from the pointer state of this frame; returns
    /// the cells of a stroke committed in this frame.
    fn pointer(
        &mut self,
        ui: &Ui,
        response: &Response,
        ctx: &mut PanelCtx,
        grid: Rect,
        n: usize,
    ) -> Option<Vec<Vec<f64>>> {
        let pos = response
            .interact_pointer_pos()
            .or_else(|| ui.input(|i| i.pointer.latest_pos()));
        let down = response.is_pointer_button_down_on();
        // A press and release within one frame is a click: begin here and commit below.
        let quick_click = !down && (response.clicked() || response.secondary_clicked());
        if self.stroke.is_none()
            && (down || quick_click)
            && let Some(p) = pos
        {
            let secondary = if quick_click {
                response.secondary_clicked()
            } else {
                ui.input(|i| i.pointer.button_down(PointerButton::Secondary))
            };
            let cells = &ctx.design.opening.cells;
            // The stroke starts where the button went down: when the press and the first move
            // arrive in one frame, the pointer is already a cell or more further on, and
            // starting there would skip the pressed cell.
            let origin = ui
                .input(|i| i.pointer.press_origin())
                .filter(|o| grid.contains(*o))
                .unwrap_or(p);
            let start = clamped_cell(grid, n, origin);
            self.stroke = Some(Stroke::begin(self, ctx.tool, secondary, cells, start));
        }
        if let (Some(stroke), Some(p)) = (self.stroke.as_mut(), pos) {
            stroke.extend(cell_at(grid, n, p), clamped_cell(grid, n, p));
        }
        if !down && let Some(stroke) = self.stroke.take() {
            // If the design changed under the stroke (e.g. an undo mid-drag), drop the stroke.
            if ctx.design.opening.cells == stroke.base {
                let mut design = ctx.design.clone();
                design.opening.cells = stroke.draft.clone();
                design.reconcile_subpixels();
                ctx.edit(design);
                // Draw the next frame from the document, which then holds the stroke.
                ui.ctx().request_repaint();
                return Some(stroke.draft);
            }
        }
        None
    }

    fn readouts_ui(&self, ui: &mut Ui, design: &Design, hovered: Option<(usize, usize)>) {
        let o = &design.opening;
        let (n, cell_um) = (o.n(), o.cell_um());
        ui.label(format!(
            "pitch {} µm · cell {} µm · {n}×{n} cells",
            fmt_um(o.pitch_um),
            fmt_um(cell_um)
        ))
        .on_hover_text("The display pixel pitch T and the size of one cell, T / N");
        if let Some(view) = &self.view {
            let size = match view.extent {
                Some((r0, c0, r1, c1)) => format!(
                    "opening {} × {} µm (w × h)",
                    fmt_um((c1 - c0 + 1) as f64 * cell_um),
                    fmt_um((r1 - r0 + 1) as f64 * cell_um)
                ),
                None => "no open cells".to_owned(),
            };
            ui.label(format!("open {:.1} % · {size}", 100.0 * view.open_fraction))
                .on_hover_text(
                    "Open fraction: intensity transmittance of the pixel (share of open cells), \
                     and the width × height of the box around the open cells",
                );
        }
        match hovered {
            Some((r, c)) => ui.label(format!(
                "cell ({r}, {c}) · x = {} µm, y = {} µm",
                fmt_um((c as f64 + 0.5) * cell_um),
                fmt_um((r as f64 + 0.5) * cell_um)
            )),
            None => ui.weak("hover the grid for a cell readout (row, col · µm)"),
        }
        .on_hover_text(
            "Cell under the pointer and its centre in the tile frame \
             (origin at the tile's top-left corner, x right, y down, in µm)",
        );
    }
}

/// The tool buttons and the Invert / Clear buttons.
fn tools_ui(ui: &mut Ui, ctx: &mut PanelCtx) {
    ui.horizontal_wrapped(|ui| {
        for tool in Tool::ALL {
            let tip = format!(
                "{} ({}): {}",
                tool.label(),
                tool.key().name(),
                tool_help(tool)
            );
            if ui
                .selectable_label(ctx.tool == tool, tool.label())
                .on_hover_text(tip)
                .clicked()
            {
                ctx.actions.push(DisplayAction::SetTool(tool));
            }
        }
        ui.separator();
        let invert = format!(
            "Invert ({}): swap open and closed cells (transmittance t becomes 1 − t)",
            ui.ctx().format_shortcut(&action::INVERT)
        );
        if ui.button("Invert").on_hover_text(invert).clicked() {
            ctx.actions.push(DisplayAction::Invert);
        }
        let clear = format!(
            "Clear ({}): close every cell",
            ui.ctx().format_shortcut(&action::CLEAR)
        );
        if ui.button("Clear").on_hover_text(clear).clicked() {
            ctx.actions.push(DisplayAction::Clear);
        }
    });
}

fn tool_help(tool: Tool) -> &'static str {
    match tool {
        Tool::Paint => "drag to open cells with the brush; right-drag closes them",
        Tool::Erase => "drag to close cells with the brush; right-drag opens them",
        Tool::Rect => "drag a filled rectangle of open cells (right-drag: closed)",
        Tool::Ellipse => "drag a filled ellipse inscribed in the box (right-drag: closed)",
        Tool::Line => "drag a straight line with the brush (right-drag: closed)",
        Tool::Fill => "click to open the connected region of equal cells (right-click: close it)",
    }
}

/// Open cells light and closed cells dark in both themes: `[closed, open]`.
fn cell_colors(v: &egui::Visuals) -> [Color32; 2] {
    if v.dark_mode {
        [v.extreme_bg_color, v.strong_text_color()]
    } else {
        [v.strong_text_color(), v.extreme_bg_color]
    }
}

/// Re-uploads the texture and the readouts only when the shown cells or the colours changed.
fn refresh_view(
    view: &mut Option<View>,
    ctx: &egui::Context,
    cells: &[Vec<f64>],
    colors: [Color32; 2],
) {
    let stale = view
        .as_ref()
        .is_none_or(|v| v.cells != cells || v.colors != colors);
    if stale {
        let n = cells.len();
        let pixels = cells
            .iter()
            .flat_map(|row| (0..n).map(move |c| row.get(c).copied().unwrap_or(0.0)))
            .map(|t| colors[0].lerp_to_gamma(colors[1], t.clamp(0.0, 1.0) as f32))
            .collect();
        let image = ColorImage::new([n, n], pixels);
        let texture = match view.take() {
            Some(mut old) => {
                old.texture.set(image, TextureOptions::NEAREST);
                old.texture
            }
            None => ctx.load_texture("opening_editor", image, TextureOptions::NEAREST),
        };
        *view = Some(View {
            cells: cells.to_vec(),
            colors,
            texture,
            open_fraction: ops::open_fraction(cells),
            extent: ops::open_extent(cells),
        });
    }
}

/// The cell under `p`, or None off the grid.
fn cell_at(grid: Rect, n: usize, p: Pos2) -> Option<(usize, usize)> {
    if !grid.contains(p) || n == 0 {
        return None;
    }
    Some(clamped_cell(grid, n, p))
}

/// The cell nearest to `p` (clamped onto the grid).
fn clamped_cell(grid: Rect, n: usize, p: Pos2) -> (usize, usize) {
    let cell = grid.width() / n.max(1) as f32;
    let index = |v: f32| ((v / cell).floor().max(0.0) as usize).min(n.saturating_sub(1));
    (index(p.y - grid.min.y), index(p.x - grid.min.x))
}

/// A length in µm with up to two decimals (`168`, `8`, `7.64`).
fn fmt_um(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}
