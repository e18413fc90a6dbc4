//! The Export-mask dialog: format, region, tone, layers and grid; a preview of one pixel's
//! drawing and the statistics of the file to be written; then a file dialog and the export on a
//! background task with progress and cancel.

use std::path::PathBuf;
use std::time::Duration;

use egui::{Color32, ColorImage, Stroke, TextureHandle, TextureOptions};

use super::mask_preview::MaskPreview;
use super::rules_check::{RulesCheck, RulesState};
use super::written_check::{WrittenCheck, WrittenState};
use crate::app::display::action::DisplayAction;
use crate::app::job::{Job, JobError};
use crate::core::design::Design;
use crate::core::mask::drc::{DrcReport, ViolationKind};
use crate::core::mask::{BinaryGrid, BorderPolicy, MaskRegion, Tone};
use crate::io::IoError;
use crate::io::mask::{ExportOptions, GdsCells, MaskFormat, PngBits, export_mask, human_bytes};

/// What the region picker shows (the block size is kept while another choice is active).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RegionChoice {
    Pixel,
    Pupil,
    Block,
}

/// The dialog's state, kept while it is closed.
pub struct MaskExportDialog {
    open: bool,
    options: ExportOptions,
    region: RegionChoice,
    block: [u32; 2],
    /// One pixel's drawing and the file's statistics, laid out in the background.
    preview: MaskPreview,
    texture: Option<TextureHandle>,
    /// The export running on its own thread: the report's lines.
    job: Option<Job<Vec<String>>>,
    /// The last export's report (or error), shown in the dialog.
    last: Option<Result<Vec<String>, JobError>>,
    /// The design-rule check at the default rules (`udc-studio drc` checks others), run in
    /// the background while the dialog is open.
    rules: RulesCheck,
    /// The same rules on the geometry the file would hold, in the background.
    written: WrittenCheck,
    /// The window's place and size on the last frame.
    last_rect: Option<egui::Rect>,
}

impl Default for MaskExportDialog {
    fn default() -> Self {
        MaskExportDialog {
            open: false,
            options: ExportOptions::default(),
            region: RegionChoice::Pixel,
            block: [1080, 2400],
            preview: MaskPreview::default(),
            texture: None,
            job: None,
            last: None,
            rules: RulesCheck::default(),
            written: WrittenCheck::default(),
            last_rect: None,
        }
    }
}

impl MaskExportDialog {
    /// Shows the dialog (its options are kept from last time).
    pub fn open(&mut self) {
        self.open = true;
    }

    /// Whether the dialog is on screen.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// The options the next export uses.
    pub fn options(&self) -> &ExportOptions {
        &self.options
    }

    /// Whether the design-rule check of the dialog is still running.
    pub fn rules_checking(&self) -> bool {
        self.rules.is_checking() || self.written.is_checking()
    }

    /// Whether the preview of the current options is still being laid out.
    pub fn previewing(&self) -> bool {
        self.preview.is_computing()
    }

    /// Whether a mask export is being written in the background.
    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// Starts writing `design` to `path` on a background task (one at a time).
    pub fn start(&mut self, design: &Design, path: PathBuf, wake: impl Fn() + Send + 'static) {
        if self.job.is_some() {
            return;
        }
        let (d, o) = (design.clone(), self.options.clone());
        let job = Job::spawn("mask export", wake, move |p| {
            export_mask(&d, &o, &path, p)
                .map(|r| r.lines())
                // File errors already say "cannot <action>" and name the file; only a layout
                // error needs the context, so no message says its what twice.
                .map_err(|e| match e {
                    IoError::MaskLayout(m) => format!("cannot export the mask: {m}"),
                    other => other.to_string(),
                })
        });
        self.last = None;
        self.job = Some(job);
    }

    /// The finished export's report (or error), once.
    pub fn poll(&mut self) -> Option<Result<Vec<String>, JobError>> {
        let result = self.job.as_ref()?.poll()?;
        self.job = None;
        self.last = Some(result.clone());
        Some(result)
    }

    fn region(&self) -> MaskRegion {
        match self.region {
            RegionChoice::Pixel => MaskRegion::PIXEL,
            RegionChoice::Pupil => MaskRegion::Pupil,
            RegionChoice::Block => MaskRegion::Block {
                cols: self.block[0].max(1),
                rows: self.block[1].max(1),
            },
        }
    }

    /// Starts the preview of the current options when they changed, and shows its drawing once
    /// it arrives.
    fn refresh(&mut self, ctx: &egui::Context, design: &Design) {
        self.options.spec.region = self.region();
        let Some(drawn) = self.preview.update(ctx, design, &self.options) else {
            return;
        };

        let image = drawn_image(drawn);
        match &mut self.texture {
            Some(t) => t.set(image, TextureOptions::NEAREST),
            None => {
                self.texture =
                    Some(ctx.load_texture("mask-preview", image, TextureOptions::NEAREST));
            }
        }
    }

    /// Draws the dialog when open; queues [`DisplayAction::WriteMask`] when the user exports.
    pub fn ui(&mut self, ctx: &egui::Context, design: &Design, actions: &mut Vec<DisplayAction>) {
        if !self.open {
            return;
        }
        self.refresh(ctx, design);
        self.rules.update(ctx, design);
        self.written.update(ctx, design, &self.options);
        let mut open = self.open;
        // On a short screen the options and checks scroll; Export and Close stay in view.
        let room = (ctx.content_rect().height() - 170.0).max(160.0);
        let shown = egui::Window::new("Export mask")
            .open(&mut open)
            .collapsible(false)
            .resizable(false)
            .default_width(560.0)
            .show(ctx, |ui| {
                egui::ScrollArea::vertical()
                    .max_height(room)
                    .auto_shrink([true, true])
                    .show(ui, |ui| {
                        ui.horizontal_top(|ui| {
                            ui.vertical(|ui| self.options_ui(ui));
                            // Space, not a separator: a vertical separator grows to the
                            // window's height.
                            ui.add_space(16.0);
                            ui.vertical(|ui| self.preview_ui(ui, design));
                        });
                    });
                ui.separator();
                self.actions_ui(ui, actions);
            });
        // The preview and the checks arrive from their jobs and change the window's height;
        // egui sizes a window from the frame before, so a frame whose size changed is followed
        // by one more (without it the buttons stayed undrawn until the next input).
        let rect = shown.map(|s| s.response.rect);
        if rect != self.last_rect {
            self.last_rect = rect;
            ctx.request_repaint();
        }
        self.open = open;
        if self.job.is_some() {
            // The progress bar moves while the export runs; nothing else needs repainting.
            ctx.request_repaint_after(Duration::from_millis(100));
        }
    }

    fn options_ui(&mut self, ui: &mut egui::Ui) {
        let o = &mut self.options;
        egui::Grid::new("mask-options")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("Format");
                ui.horizontal(|ui| {
                    for f in MaskFormat::ALL {
                        ui.selectable_value(&mut o.format, f, f.label());
                    }
                });
                ui.end_row();
                ui.label("Region");
                ui.vertical(|ui| {
                    ui.radio_value(&mut self.region, RegionChoice::Pixel, "One pixel");
                    ui.radio_value(&mut self.region, RegionChoice::Pupil, "Lens pupil")
                        .on_hover_text("Every pixel over the lens pupil, with the pupil outline");
                    ui.horizontal(|ui| {
                        ui.radio_value(&mut self.region, RegionChoice::Block, "Pixels");
                        ui.add(crate::app::widgets::number(&mut self.block[0]).range(1..=100_000));
                        ui.label("×");
                        ui.add(crate::app::widgets::number(&mut self.block[1]).range(1..=100_000));
                    });
                });
                ui.end_row();
                ui.label("Tone");
                ui.vertical(|ui| {
                    for t in Tone::ALL {
                        ui.radio_value(&mut o.spec.tone, t, t.meaning());
                    }
                });
                ui.end_row();
                ui.label("Border");
                ui.vertical(|ui| {
                    for b in BorderPolicy::ALL {
                        ui.radio_value(&mut o.spec.border, b, border_label(b))
                            .on_hover_text(b.meaning());
                    }
                    if o.spec.border == BorderPolicy::Margin && o.spec.tone == Tone::Chrome {
                        ui.horizontal(|ui| {
                            ui.label("Chrome margin");
                            ui.add(
                                crate::app::widgets::number(&mut o.spec.margin_um)
                                    .range(0.1..=crate::core::mask::border::MAX_MARGIN_UM)
                                    .speed(1.0)
                                    .suffix(" µm"),
                            );
                        });
                    }
                });
                ui.end_row();
                ui.label("Layer / datatype");
                ui.horizontal(|ui| {
                    ui.add(crate::app::widgets::number(&mut o.layer).range(0..=255));
                    ui.label("/");
                    ui.add(crate::app::widgets::number(&mut o.datatype).range(0..=255));
                });
                ui.end_row();
                ui.label("Notes layer");
                ui.add(crate::app::widgets::number(&mut o.note_layer).range(0..=255))
                    .on_hover_text("Pupil outline and the text notes (tone, units, design)");
                ui.end_row();
                ui.label("Grid");
                ui.add(
                    crate::app::widgets::number(&mut o.spec.grid_nm)
                        .range(1..=1000)
                        .suffix(" nm"),
                );
                ui.end_row();
                frame_options_ui(ui, o);
                format_options_ui(ui, o);
            });
    }

    fn preview_ui(&self, ui: &mut egui::Ui, design: &Design) {
        let data = match self.preview.latest() {
            None => {
                ui.weak("Laying out the mask…");
                return;
            }
            Some(Ok(Ok(d))) => d,
            Some(Ok(Err(e))) => {
                ui.colored_label(ui.visuals().error_fg_color, e.to_string());
                return;
            }
            Some(Err(e)) => {
                ui.colored_label(ui.visuals().error_fg_color, e.to_string());
                return;
            }
        };
        let side = 200.0;
        let (rect, _) = ui.allocate_exact_size(egui::vec2(side, side), egui::Sense::hover());
        if let Some(t) = &self.texture {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            ui.painter().image(t.id(), rect, uv, Color32::WHITE);
        }
        let stroke = Stroke::new(1.5, Color32::from_rgb(255, 150, 40));
        for outline in &data.outlines {
            let pts: Vec<egui::Pos2> = outline
                .iter()
                .map(|[x, y]| rect.min + egui::vec2(x * side, y * side))
                .collect();
            ui.painter().add(egui::Shape::closed_line(pts, stroke));
        }
        // Design-rule violations on the pixel, where they are (red rings).
        let red = Stroke::new(1.5, Color32::from_rgb(255, 70, 70));
        let rules = self.rules.state(design);
        let violations = match rules {
            RulesState::Done(r) => r.violations.as_slice(),
            RulesState::Checking | RulesState::Failed(_) => &[],
        };
        for v in violations {
            let [x, y] = v.at_um;
            let scale = side / data.pitch_um.max(f64::MIN_POSITIVE) as f32;
            let centre = rect.min + egui::vec2(x as f32 * scale, y as f32 * scale);
            if rect.expand(4.0).contains(centre) {
                ui.painter().circle_stroke(centre, 4.0, red);
            }
        }
        ui.weak("One pixel: drawn cells, polygon outlines, rule violations (red)");
        if !self.preview.is_current(design, &self.options) {
            ui.weak("Updating for the new options…");
        }
        let s = &data.stats;
        let c = &data.counts;
        egui::Grid::new("mask-stats")
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                let mut row = |k: &str, v: String| {
                    ui.label(k);
                    ui.monospace(v);
                    ui.end_row();
                };
                let n = |v: f64, one: &str, many: &str| crate::app::widgets::counted(v, one, many);
                row(
                    "Pixels",
                    format!(
                        "{} in {}",
                        s.tiles,
                        n(s.orientations as f64, "orientation", "orientations")
                    ),
                );
                row("Polygons", format!("{}", c.polygons));
                row("Vertices", format!("{}", c.vertices));
                row(
                    "References",
                    format!(
                        "{} single, {}",
                        c.references,
                        n(c.arrays as f64, "array", "arrays")
                    ),
                );
                row(
                    "Flattened",
                    n(s.flat_polygons as f64, "polygon", "polygons"),
                );
                row("File size", format!("about {}", human_bytes(c.bytes)));
                row("Open area", format!("{:.4e} µm²", s.open_area_um2));
                row("Open fraction", format!("{:.4}", s.open_fraction()));
            });
        match rules {
            RulesState::Done(r) => {
                drc_ui(ui, r, "Pixel, tiled");
            }
            RulesState::Checking => {
                ui.weak("Design rules: checking…");
            }
            RulesState::Failed(e) => {
                ui.colored_label(ui.visuals().error_fg_color, format!("Design rules: {e}"));
            }
        }
        match self.written.state(design, &self.options) {
            WrittenState::Done(check) => {
                let resp = drc_ui(ui, &check.report, "Written file");
                resp.on_hover_text(check.scope_line());
            }
            WrittenState::Checking(f) => {
                ui.weak(format!("Written file: checking… {:.0} %", 100.0 * f));
            }
            WrittenState::Failed(e) => {
                ui.colored_label(ui.visuals().error_fg_color, format!("Written file: {e}"));
            }
        }
    }

    fn actions_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<DisplayAction>) {
        // The export lays the mask out again on its own task; the button waits only for a
        // layout the options can make.
        let ok = matches!(self.preview.latest(), Some(Ok(Ok(_))));
        ui.horizontal(|ui| {
            if let Some(job) = &self.job {
                ui.add(
                    egui::ProgressBar::new(job.fraction())
                        .desired_width(240.0)
                        .show_percentage()
                        .text("exporting"),
                );
                if ui.button("Cancel").clicked() {
                    job.cancel();
                }
            } else if ui
                .add_enabled(ok, egui::Button::new("Export…"))
                .on_hover_text("Choose a file; the design is saved beside it as .design.json")
                .clicked()
            {
                actions.push(DisplayAction::WriteMask(None));
            }
            if ui.button("Close").clicked() {
                self.open = false;
            }
        });
        match &self.last {
            Some(Ok(lines)) => {
                for l in lines {
                    ui.label(l);
                }
            }
            Some(Err(e)) => {
                ui.colored_label(ui.visuals().error_fg_color, e.to_string());
            }
            None => {}
        }
    }
}

/// The frame, marks and label checkboxes, and their sizes once one is on.
fn frame_options_ui(ui: &mut egui::Ui, o: &mut ExportOptions) {
    let f = &mut o.frame;
    ui.label("Frame and marks");
    ui.horizontal(|ui| {
        ui.checkbox(&mut f.frame, "Die frame")
            .on_hover_text("A ring around the region, on layer frame (10/0 unless a layer map says otherwise; not in PNG)");
        ui.checkbox(&mut f.marks, "Alignment marks")
            .on_hover_text("Four crosses beyond the frame's corners, on layer marks (11/0)");
        ui.checkbox(&mut f.label, "Label")
            .on_hover_text("Design name, date and scale below the region, on layer label (12/0)");
    });
    ui.end_row();
    if !f.any() {
        return;
    }
    let max = crate::core::mask::frame::MAX_FRAME_LENGTH_UM;
    let size = |ui: &mut egui::Ui, name: &str, v: &mut f64, hover: &str| {
        ui.label(name);
        ui.add(
            crate::app::widgets::number(v)
                .range(1.0..=max)
                .speed(1.0)
                .suffix(" µm"),
        )
        .on_hover_text(hover);
        ui.end_row();
    };
    size(
        ui,
        "Margin",
        &mut f.margin_um,
        "Between the region and the frame, the frame and the marks, the marks and the label",
    );
    if f.frame {
        size(
            ui,
            "Frame width",
            &mut f.frame_width_um,
            "Width of the ring",
        );
    }
    if f.marks {
        size(ui, "Mark size", &mut f.mark_size_um, "Side of each cross");
        size(
            ui,
            "Mark arm width",
            &mut f.mark_arm_width_um,
            "Width of a cross's arms",
        );
    }
    if f.label {
        size(
            ui,
            "Label height",
            &mut f.label_height_um,
            "Letter height in DXF and SVG (GDSII texts have none)",
        );
    }
}

/// The rows of the options grid that only one format has.
fn format_options_ui(ui: &mut egui::Ui, o: &mut ExportOptions) {
    match o.format {
        MaskFormat::Gds | MaskFormat::Oas => {
            ui.label("Orientations");
            ui.vertical(|ui| {
                ui.radio_value(&mut o.gds_cells, GdsCells::Strans, "Rotated references")
                    .on_hover_text("One cell; each pixel a reference with reflection and angle");
                ui.radio_value(&mut o.gds_cells, GdsCells::PerOrientation, "One cell each")
                    .on_hover_text("One cell per orientation used; plain references");
            });
            ui.end_row();
        }
        MaskFormat::Png => {
            ui.label("Pixel size");
            ui.add(
                crate::app::widgets::number(&mut o.um_per_px)
                    .range(0.05..=100.0)
                    .speed(0.05)
                    .suffix(" µm"),
            );
            ui.end_row();
            ui.label("Bits");
            ui.horizontal(|ui| {
                ui.radio_value(&mut o.png_bits, PngBits::One, "1-bit");
                ui.radio_value(&mut o.png_bits, PngBits::Eight, "8-bit");
            });
            ui.end_row();
        }
        MaskFormat::Dxf | MaskFormat::Svg => {}
    }
}

/// Drawn cells in blue on a dark background, one texel per cell.
/// The name of a border policy in the dialog.
fn border_label(b: BorderPolicy) -> &'static str {
    match b {
        BorderPolicy::Margin => "Leave cut openings out, frame chrome",
        BorderPolicy::Drop => "Leave cut openings out",
        BorderPolicy::Extend => "Draw cut openings whole",
        BorderPolicy::Cut => "Cut at the edge (a cell to array)",
    }
}

/// The design-rule summary under `title`: the smallest opening and gap, the corner contacts,
/// each in the warning colour when it breaks the default rules. Returns the title's response.
fn drc_ui(ui: &mut egui::Ui, r: &DrcReport, title: &str) -> egui::Response {
    let head = ui
        .strong(format!(
            "{title}: design rules ({} µm features and gaps, no corner contacts)",
            r.rules.min_feature_um
        ))
        .on_hover_text("udc-studio drc checks other rules, from a fab's rules file");
    let line = |ui: &mut egui::Ui, bad: bool, text: String, kind: ViolationKind| {
        let places: Vec<&str> = r
            .violations
            .iter()
            .filter(|v| v.kind == kind)
            .take(5)
            .map(|v| v.place.as_str())
            .collect();
        let color = if bad {
            ui.visuals().warn_fg_color
        } else {
            ui.visuals().text_color()
        };
        let resp = ui.colored_label(color, text);
        if !places.is_empty() {
            resp.on_hover_text(places.join("\n"));
        }
    };
    let um = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.2} µm"));
    let count = |k: ViolationKind| r.counts[k as usize];
    line(
        ui,
        count(ViolationKind::MinFeature) > 0,
        format!("smallest opening {}", um(r.min_feature_um)),
        ViolationKind::MinFeature,
    );
    line(
        ui,
        count(ViolationKind::MinGap) > 0,
        format!("smallest chrome gap {}", um(r.min_gap_um)),
        ViolationKind::MinGap,
    );
    line(
        ui,
        count(ViolationKind::CornerContact) > 0,
        crate::app::widgets::counted(
            r.corner_contacts as f64,
            "corner contact",
            "corner contacts",
        ),
        ViolationKind::CornerContact,
    );
    head
}

fn drawn_image(drawn: &BinaryGrid) -> ColorImage {
    let (w, h) = (drawn.width(), drawn.height());
    let pixels = (0..h)
        .flat_map(|r| (0..w).map(move |c| (c, r)))
        .map(|(c, r)| {
            if drawn.get(c, r) {
                Color32::from_rgb(70, 130, 230)
            } else {
                Color32::from_gray(40)
            }
        })
        .collect();
    ColorImage::new([w, h], pixels)
}
