//! The editor's Emitters layer (thesis §3.7, Fig. 3.26): R, G and B subpixels painted on the
//! opaque cells of the opening, drawn as coloured overlays. Every change is one
//! [`PanelCtx::edit`], so it is undone like any other edit; painting an emitter on an open cell
//! is refused with a status message (emitters are opaque).

use egui::{Color32, Rect, Response, Ui, vec2};

use super::PanelCtx;
use crate::core::design::{Subpixel, SubpixelChecks, Subpixels};
use crate::core::display::emitters::{auto_place, closed_cells};

/// What the emitter brush paints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmitterBrush {
    /// Paint one colour's emitter.
    Paint(Subpixel),
    /// Remove emitters.
    Erase,
}

/// The layer's view state: shown or not, the brush, the last refusal.
#[derive(Debug, Default)]
pub struct EmitterLayer {
    /// Whether the layer is drawn and the brush active.
    pub shown: bool,
    /// The brush in use while the layer is shown (`None`: the opening tools draw).
    pub brush: Option<EmitterBrush>,
    /// Why the last paint was refused, or what the last action did.
    pub status: Option<String>,
    /// The cell painted last during this press: the document takes an edit only after the
    /// frame, so painting it again next frame would push a duplicate.
    last: Option<(usize, usize)>,
}

/// Overlay colour of a subpixel.
fn colour(s: Subpixel) -> Color32 {
    match s {
        Subpixel::Red => Color32::from_rgba_unmultiplied(230, 40, 40, 170),
        Subpixel::Green => Color32::from_rgba_unmultiplied(40, 200, 60, 170),
        Subpixel::Blue => Color32::from_rgba_unmultiplied(50, 90, 240, 170),
    }
}

impl EmitterLayer {
    /// Whether the pointer on the grid paints emitters instead of the opening.
    pub fn active(&self) -> bool {
        self.shown && self.brush.is_some()
    }

    /// The layer's row: toggle, brushes, auto-placement and the per-colour checks.
    pub fn controls_ui(&mut self, ui: &mut Ui, ctx: &mut PanelCtx) {
        ui.horizontal_wrapped(|ui| {
            ui.checkbox(&mut self.shown, "Emitters").on_hover_text(
                "Show and paint the R, G, B subpixels (they must sit on closed cells)",
            );
            if !self.shown {
                return;
            }
            for (label, b) in [
                ("R", EmitterBrush::Paint(Subpixel::Red)),
                ("G", EmitterBrush::Paint(Subpixel::Green)),
                ("B", EmitterBrush::Paint(Subpixel::Blue)),
                ("erase", EmitterBrush::Erase),
            ] {
                if ui.selectable_label(self.brush == Some(b), label).clicked() {
                    self.brush = if self.brush == Some(b) { None } else { Some(b) };
                }
            }
            if ui
                .button("Auto-place")
                .on_hover_text("Three equal-area rectangles, as large as the closed cells allow")
                .clicked()
            {
                match auto_place(&ctx.design.opening, 0.0) {
                    Some(sp) => {
                        let mut d = ctx.design.clone();
                        d.subpixels = Some(sp);
                        ctx.edit(d);
                        self.status = None;
                    }
                    None => {
                        self.status =
                            Some("no room for three equal emitters in the closed area".into());
                    }
                }
            }
        });
        if self.shown {
            match &ctx.design.subpixels {
                Some(sp) => {
                    let c = SubpixelChecks::of(sp, ctx.design.opening.cell_um());
                    ui.label(format!(
                        "emitter area R {:.0}, G {:.0}, B {:.0} µm²; equal-area deviation {:.1} %",
                        c.area_um2[0], c.area_um2[1], c.area_um2[2], c.equal_area_deviation_pct
                    ));
                }
                None => {
                    ui.weak("no emitter layer yet (views use an automatic placement)");
                }
            }
            if let Some(s) = &self.status {
                ui.colored_label(ui.visuals().warn_fg_color, s);
            }
        }
    }

    /// Paints the emitter under the pointer while the button is down; one edit per change.
    pub fn pointer(&mut self, response: &Response, ctx: &mut PanelCtx, grid: Rect, n: usize) {
        let Some(brush) = self.brush else { return };
        if !(response.is_pointer_button_down_on() || response.clicked()) {
            self.last = None;
            return;
        }
        let Some(p) = response.interact_pointer_pos() else {
            return;
        };
        if !grid.contains(p) || n == 0 {
            return;
        }
        let cell = grid.width() / n as f32;
        let r = (((p.y - grid.min.y) / cell) as usize).min(n - 1);
        let c = (((p.x - grid.min.x) / cell) as usize).min(n - 1);
        if self.last == Some((r, c)) {
            return;
        }
        self.last = Some((r, c));
        let value = match brush {
            EmitterBrush::Paint(s) => {
                let closed = closed_cells(&ctx.design.opening);
                if !closed
                    .get(r)
                    .and_then(|row| row.get(c))
                    .copied()
                    .unwrap_or(false)
                {
                    self.status = Some(format!(
                        "cell (row {r}, column {c}) is open: emitters go on closed cells"
                    ));
                    return;
                }
                Some(s)
            }
            EmitterBrush::Erase => None,
        };
        let mut d = ctx.design.clone();
        let sp = d.subpixels.get_or_insert_with(|| Subpixels::empty(n));
        if sp.cells.len() != n {
            *sp = Subpixels::empty(n);
        }
        if sp.cells[r][c] == value {
            return;
        }
        sp.cells[r][c] = value;
        self.status = None;
        ctx.edit(d);
    }

    /// Draws the emitters over the grid when the layer is shown.
    pub fn paint(&self, ui: &Ui, grid: Rect, n: usize, subpixels: Option<&Subpixels>) {
        let (true, Some(sp)) = (self.shown, subpixels) else {
            return;
        };
        if n == 0 || sp.cells.len() != n {
            return;
        }
        let painter = ui.painter_at(grid);
        let cell = grid.width() / n as f32;
        for (r, row) in sp.cells.iter().enumerate() {
            for (c, s) in row.iter().enumerate() {
                if let Some(s) = s {
                    let min = grid.min + vec2(c as f32, r as f32) * cell;
                    painter.rect_filled(
                        Rect::from_min_size(min, vec2(cell, cell)),
                        0.0,
                        colour(*s),
                    );
                }
            }
        }
    }
}
