//! The bin-size study view (Fig. 5.4): a region of the scene captured at bins 1, 2, 4 and 8
//! across light levels, the bin the theory predicts framed black and the best framed blue, and
//! the binning modes at a small and a large gain; exported as CSV. It runs as its own
//! background job, started by the user, because it is 64 captures.

use std::path::PathBuf;
use std::sync::Arc;

use egui::{Color32, Stroke, TextureHandle, Ui, vec2};
use ndarray::Array2;

use super::LoadedScene;
use crate::app::dialogs::{FileSpec, ask};
use crate::app::job::{Job, JobError, Writes};
use crate::app::notice::Notice;
use crate::app::widgets::figure::image_texture;
use crate::core::figure::{ColorScale, Colormap, Image};
use crate::core::sensor::study::{BinStudy, StudyCapture, StudySpec, bin_study};
use crate::core::sensor::{BIN_SIZES, BinMode, SensorSettings};

/// Frame of the bin the optimal-pitch theory predicts (the thesis's black box; white here, on
/// the dark theme).
const PREDICTED: Color32 = Color32::from_rgb(235, 235, 235);
/// Frame of the bin with the best SSIM (the thesis's blue box).
const BEST: Color32 = Color32::from_rgb(60, 140, 255);
/// Sides of the studied region the user can pick, pixels.
const SIDES_PX: [usize; 3] = [64, 128, 256];

/// A finished study on screen.
struct Shown {
    study: Arc<BinStudy>,
    sweep: Vec<TextureHandle>,
    modes: Vec<TextureHandle>,
    /// Where it was taken: scene name, centre and side.
    origin: String,
}

/// The study's settings, job and result (view state: never undone).
pub struct StudyView {
    /// Centre of the region, scene pixels `[x, y]`; `None` = the scene's centre.
    centre_px: Option<[usize; 2]>,
    side_px: usize,
    spec: StudySpec,
    job: Option<(Job<BinStudy>, String)>,
    shown: Option<Shown>,
    dialog: Option<Job<Option<PathBuf>>>,
    writes: Writes,
    message: Option<Notice>,
}

impl Default for StudyView {
    fn default() -> Self {
        StudyView {
            centre_px: None,
            side_px: 128,
            spec: StudySpec::default(),
            job: None,
            shown: None,
            dialog: None,
            writes: Writes::default(),
            message: None,
        }
    }
}

/// The `side × side` crop of `lum` around `centre` (clamped into the image).
fn crop(lum: &Array2<f64>, centre: [usize; 2], side: usize) -> Array2<f64> {
    let (h, w) = lum.dim();
    let side = side.min(h).min(w);
    let x0 = centre[0].saturating_sub(side / 2).min(w - side);
    let y0 = centre[1].saturating_sub(side / 2).min(h - side);
    Array2::from_shape_fn((side, side), |(y, x)| lum[[y0 + y, x0 + x]])
}

impl StudyView {
    /// The study on screen, if any.
    pub fn study(&self) -> Option<&BinStudy> {
        self.shown.as_ref().map(|s| s.study.as_ref())
    }

    /// The latest message (progress of a CSV write, an error).
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Takes the finished study, dialog answers and CSV writes (called every frame from the
    /// workspace, whichever view is on screen).
    pub fn poll(&mut self, ctx: &egui::Context) {
        if let Some(result) = self.job.as_ref().and_then(|(j, _)| j.poll()) {
            let origin = self.job.take().map(|(_, o)| o).unwrap_or_default();
            match result {
                Ok(study) => {
                    // The tone-mapped capture, black at 0 and white at 1.
                    let upload = |c: &StudyCapture, i: usize, part: &str| {
                        let img = Image::pixels(
                            "capture",
                            Arc::new(c.display.clone()),
                            ColorScale::Linear { max: 1.0 },
                            Colormap::Gray,
                        );
                        image_texture(ctx, format!("study-{part}-{i}"), &img)
                    };
                    let sweep = study
                        .sweep
                        .iter()
                        .enumerate()
                        .map(|(i, c)| upload(c, i, "sweep"))
                        .collect();
                    let modes = study
                        .modes
                        .iter()
                        .enumerate()
                        .map(|(i, c)| upload(c, i, "modes"))
                        .collect();
                    self.message = None;
                    self.shown = Some(Shown {
                        study: Arc::new(study),
                        sweep,
                        modes,
                        origin,
                    });
                }
                Err(JobError::Cancelled) => {
                    self.message = Some(Notice::info("bin-size study cancelled"));
                }
                Err(e) => self.message = Some(Notice::error(format!("bin-size study: {e}"))),
            }
        }
        if let Some(answer) = self.dialog.as_ref().and_then(Job::poll) {
            self.dialog = None;
            match answer {
                Ok(Some(path)) => self.write_csv(path, ctx),
                Ok(None) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(n) = self.writes.poll() {
            self.message = Some(n);
        }
    }

    /// Writes the shown study to `path` as CSV on a helper thread (no dialog).
    pub fn write_csv(&mut self, path: PathBuf, ctx: &egui::Context) {
        let Some(s) = &self.shown else {
            self.message = Some(Notice::error("no bin-size study to export yet"));
            return;
        };
        let text = crate::io::sensor::bin_study_csv::bin_study_csv(&s.study);
        let wake = ctx.clone();
        self.message = Some(Notice::info(format!("writing {}…", path.display())));
        self.writes.spawn(
            move || wake.request_repaint(),
            move || {
                crate::io::safe_file::write_atomic(&path, text.as_bytes())
                    .map(|()| format!("wrote {}", path.display()))
                    .map_err(|e| e.to_string())
            },
        );
    }

    /// Starts the study on the region of `scene` (the full-size scene) with `settings`'
    /// sensor, seed and tone curve.
    pub fn start(&mut self, scene: &LoadedScene, settings: &SensorSettings, ctx: &egui::Context) {
        let lum = scene.scene.luminance();
        let (h, w) = lum.dim();
        let centre = self.centre_px.unwrap_or([w / 2, h / 2]);
        let region = crop(&lum, centre, self.side_px);
        let origin = format!(
            "{}, {} px square around ({}, {}) px",
            scene.name,
            region.nrows(),
            centre[0],
            centre[1]
        );
        let (settings, spec) = (settings.clone(), self.spec.clone());
        let wake = ctx.clone();
        let job = Job::spawn(
            "bin-size study",
            move || wake.request_repaint(),
            move |p| bin_study(&region, &settings, &spec, p),
        );
        self.job = Some((job, origin));
    }

    /// Draws the controls and the two grids.
    pub fn ui(&mut self, ui: &mut Ui, scene: Option<&LoadedScene>, settings: &SensorSettings) {
        ui.label(
            "Fig. 5.4: one region captured at every bin size as the light grows. A white \
             frame marks the bin the optimal-pitch theory predicts, a blue frame the best SSIM \
             (both frames when they agree).",
        );
        let Some(scene) = scene else {
            ui.label("Open a scene first.");
            return;
        };
        let (h, w) = scene.scene.dim();
        let centre = self.centre_px.get_or_insert([w / 2, h / 2]);
        ui.horizontal_wrapped(|ui| {
            ui.label("Region centre x");
            ui.add(crate::app::widgets::number(&mut centre[0]).range(0..=w.saturating_sub(1)))
                .on_hover_text("Scene pixels from the left");
            ui.label("y");
            ui.add(crate::app::widgets::number(&mut centre[1]).range(0..=h.saturating_sub(1)))
                .on_hover_text("Scene pixels from the top");
            ui.label("side");
            egui::ComboBox::from_id_salt("study_side")
                .selected_text(format!("{} px", self.side_px))
                .show_ui(ui, |ui| {
                    for s in SIDES_PX {
                        ui.selectable_value(&mut self.side_px, s, format!("{s} px"));
                    }
                });
            ui.separator();
            let lo = self.spec.modes_gains[0];
            ui.label("modes at");
            ui.add(
                crate::app::widgets::number(&mut self.spec.modes_light_e_per_um2)
                    .range(0.1..=1e4)
                    .suffix(" e-/µm²"),
            );
            ui.label(format!("gains {lo} and"));
            ui.add(
                crate::app::widgets::number(&mut self.spec.modes_gains[1])
                    .range(1.0..=settings.sensor.max_gain)
                    .suffix("×"),
            );
        });
        ui.horizontal(|ui| {
            match &self.job {
                Some((job, _)) => {
                    ui.add(egui::ProgressBar::new(job.fraction()).show_percentage());
                    if ui.button("Cancel").clicked() {
                        job.cancel();
                    }
                }
                None => {
                    if ui.button("Run the study").clicked() {
                        self.start(scene, settings, ui.ctx());
                    }
                }
            }
            let can_export = self.shown.is_some() && self.dialog.is_none();
            if ui
                .add_enabled(can_export, egui::Button::new("Export CSV…"))
                .clicked()
            {
                let wake = ui.ctx().clone();
                let spec = FileSpec::save(
                    "Save the bin-size study",
                    ("Bin-size study (CSV)", &["csv"]),
                    "bin-size-study.csv",
                );
                self.dialog = Some(ask(spec, move || wake.request_repaint()));
            }
        });
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        let Some(shown) = &self.shown else {
            return;
        };
        ui.weak(format!(
            "{} · sweep: {} binning at gain {}",
            shown.origin,
            self.spec.sweep_mode.label(),
            self.spec.sweep_gain
        ));
        egui::ScrollArea::both().show(ui, |ui| {
            let side = ((ui.available_width() - 140.0) / BIN_SIZES.len() as f32).clamp(48.0, 128.0);
            let study = &shown.study;
            egui::Grid::new("study_sweep")
                .spacing(vec2(6.0, 6.0))
                .show(ui, |ui| {
                    ui.label("");
                    for n in BIN_SIZES {
                        ui.strong(format!("bin {n}×{n}"));
                    }
                    ui.end_row();
                    for (row, choice) in study.choices.iter().enumerate() {
                        ui.label(format!("{} e-/µm²", choice.light_e_per_um2));
                        for (k, n) in BIN_SIZES.iter().enumerate() {
                            let i = row * BIN_SIZES.len() + k;
                            let (Some(c), Some(t)) = (study.sweep.get(i), shown.sweep.get(i))
                            else {
                                continue;
                            };
                            let frame = if *n == choice.best_bin {
                                Some(BEST)
                            } else if *n == choice.predicted_bin {
                                Some(PREDICTED)
                            } else {
                                None
                            };
                            let both = *n == choice.best_bin && *n == choice.predicted_bin;
                            thumb_ui(ui, t, c, side, frame, both);
                        }
                        ui.end_row();
                    }
                });
            ui.separator();
            ui.strong(format!(
                "Fig. 5.4b: the binning modes at {} e-/µm²",
                self.spec.modes_light_e_per_um2
            ));
            egui::Grid::new("study_modes")
                .spacing(vec2(6.0, 6.0))
                .show(ui, |ui| {
                    let per_row = BIN_SIZES.len();
                    for (r, chunk) in study.modes.chunks(per_row).enumerate() {
                        if let Some(first) = chunk.first() {
                            let mode = match first.mode {
                                BinMode::AnalogAdditive => {
                                    format!("additive ({})", first.additive_gain.label())
                                }
                                m => m.label().to_string(),
                            };
                            ui.label(format!("{mode}, gain {}", first.gain))
                                .on_hover_text(
                                    "additive (scaled): read at g/N, no extra saturation; additive \
                                 (same): read at g, the least read noise, saturates N times \
                                 sooner",
                                );
                        }
                        for (k, c) in chunk.iter().enumerate() {
                            if let Some(t) = shown.modes.get(r * per_row + k) {
                                thumb_ui(ui, t, c, side, None, false);
                            }
                        }
                        ui.end_row();
                    }
                });
        });
    }
}

/// One capture: its picture (framed in `frame`'s colour) and its SSIM under it.
fn thumb_ui(
    ui: &mut Ui,
    t: &TextureHandle,
    c: &StudyCapture,
    side: f32,
    frame: Option<Color32>,
    both: bool,
) {
    ui.vertical(|ui| {
        let r = ui.add(egui::Image::new(t).fit_to_exact_size(vec2(side, side)));
        if let Some(color) = frame {
            ui.painter().rect_stroke(
                r.rect.expand(2.0),
                0.0,
                Stroke::new(3.0, color),
                egui::StrokeKind::Outside,
            );
        }
        if both {
            ui.painter().rect_stroke(
                r.rect.expand(6.0),
                0.0,
                Stroke::new(2.0, PREDICTED),
                egui::StrokeKind::Outside,
            );
            ui.add_space(6.0);
        }
        let sat = if c.saturated_fraction > 0.0 {
            format!(", {:.1} % sat.", 100.0 * c.saturated_fraction)
        } else {
            String::new()
        };
        ui.label(format!("SSIM {:.3}{sat}", c.ssim));
    });
}
