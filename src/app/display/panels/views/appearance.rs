//! The Appearance view (thesis §3.7, Fig. 3.27): a photo shown on the current layout, periodic
//! and random side by side, as the eye sees it at a chosen DPI and viewing distance, with the
//! display-quality numbers beside the camera's AUC; and a scatter of the thesis presets on
//! (camera AUC, display nonuniformity). Everything runs on background jobs.

use std::sync::Arc;

use crate::app::widgets::figure::{PlotFrame, panel_ui_in};
use egui::{TextureHandle, TextureOptions, Ui};
use ndarray::Array2;

use crate::app::display::panels::Shown;
use crate::app::job::{Job, JobError, Keyed};
use crate::app::notice::Notice;
use crate::app::widgets::photo::{built_in, color_image};
use crate::core::Progress;
use crate::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use crate::core::design::Design;
use crate::core::display::appearance::{
    AppearanceSettings, DisplayQuality, appearance, scatter_panel,
};
use crate::io::design::presets;

/// What a run depends on.
#[derive(Debug, Clone, PartialEq)]
struct Key {
    shown: u64,
    dpi: f64,
    viewing_distance_mm: f64,
}

/// One rendered layout: its label, numbers and picture.
struct Row {
    label: String,
    quality: DisplayQuality,
    texture: TextureHandle,
}

pub use crate::core::display::appearance::ScatterPoint;

type Rendered = Vec<(String, DisplayQuality, [Array2<f64>; 3])>;

/// The Appearance view's state.
pub struct AppearanceView {
    dpi: f64,
    viewing_distance_mm: f64,
    job: Keyed<Key, Rendered>,
    done_key: Option<Key>,
    rows: Vec<Row>,
    scatter_job: Option<Job<Vec<ScatterPoint>>>,
    scatter: Vec<ScatterPoint>,
    message: Option<Notice>,
}

impl Default for AppearanceView {
    fn default() -> Self {
        let s = AppearanceSettings::default();
        AppearanceView {
            dpi: s.dpi,
            viewing_distance_mm: s.viewing_distance_mm,
            job: Keyed::idle(),
            done_key: None,
            rows: Vec::new(),
            scatter_job: None,
            scatter: Vec::new(),
            message: None,
        }
    }
}

fn camera_auc(a: &crate::core::Analysis) -> f64 {
    let n = a.channels.len().max(1) as f64;
    a.channels.iter().map(|c| c.mtf.auc_radial_min).sum::<f64>() / n
}

impl AppearanceView {
    /// Display quality of the rendered layouts (periodic first), for tests and the numbers.
    pub fn qualities(&self) -> Vec<(String, DisplayQuality)> {
        self.rows
            .iter()
            .map(|r| (r.label.clone(), r.quality))
            .collect()
    }

    /// Whether a rendering or the scatter is being computed.
    pub fn is_running(&self) -> bool {
        self.job.is_running() || self.scatter_job.is_some()
    }

    /// The scatter's points so far.
    pub fn scatter(&self) -> &[ScatterPoint] {
        &self.scatter
    }

    fn settings(&self) -> AppearanceSettings {
        AppearanceSettings {
            dpi: self.dpi,
            viewing_distance_mm: self.viewing_distance_mm,
            ..AppearanceSettings::default()
        }
    }

    /// Takes a finished run.
    pub(super) fn poll(&mut self, ctx: &egui::Context) {
        if let Some((key, done)) = self.job.poll() {
            match done {
                Ok(rendered) => {
                    self.rows = rendered
                        .into_iter()
                        .enumerate()
                        .map(|(i, (label, quality, planes))| {
                            let p: Vec<&Array2<f64>> = planes.iter().collect();
                            let texture = ctx.load_texture(
                                format!("appearance-{i}"),
                                color_image(&p, 1.0),
                                TextureOptions::LINEAR,
                            );
                            Row {
                                label,
                                quality,
                                texture,
                            }
                        })
                        .collect();
                    self.message = None;
                }
                Err(e) => {
                    self.rows.clear();
                    self.message = Some(Notice::error(e.to_string()));
                }
            }
            self.done_key = Some(key);
        }
        if let Some(done) = self.scatter_job.as_ref().and_then(Job::poll) {
            self.scatter_job = None;
            match done {
                Ok(points) => self.scatter = points,
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
    }

    fn start(&mut self, key: Key, design: Arc<Design>, ctx: &egui::Context) {
        let settings = self.settings();
        let wake = ctx.clone();
        let job = Job::spawn(
            "appearance job",
            move || wake.request_repaint(),
            move |p: &Progress| {
                let photo = built_in()?;
                let mut out = Vec::new();
                for (label, d) in crate::core::display::appearance::periodic_and_random(&design) {
                    let (q, r) = appearance(&d, &photo.planes, &settings, p)?;
                    out.push((label, q, r.planes));
                }
                Ok::<_, JobError>(out)
            },
        );
        self.job.start(key, job);
    }

    /// Starts the scatter of the thesis's presets, their PSFs computed on `route`.
    fn start_scatter(&mut self, route: Arc<udc_gpu::Route>, ctx: &egui::Context) {
        let settings = self.settings();
        let wake = ctx.clone();
        self.scatter_job = Some(Job::spawn(
            "appearance scatter",
            move || wake.request_repaint(),
            move |p: &Progress| {
                let options = AnalyzeOptions {
                    quality: Quality::Preview,
                    expected_psf: false,
                };
                let grey = vec![Array2::from_elem((8, 8), 0.5)];
                let mut out = Vec::new();
                for preset in presets::PRESETS
                    .iter()
                    .filter(|pr| pr.group == presets::PresetGroup::Thesis)
                {
                    let d = presets::load_preset(preset.name)?;
                    // Layouts without room for emitters (the open aperture) have no display.
                    let Ok((q, _)) = appearance(&d, &grey, &settings, p) else {
                        continue;
                    };
                    let a = analyze_with_route(&d, &options, route.as_ref(), p)?;
                    out.push(ScatterPoint {
                        name: preset.name.into(),
                        camera_auc: camera_auc(&a),
                        nonuniformity: q.nonuniformity,
                    });
                }
                Ok::<_, JobError>(out)
            },
        ));
    }

    /// Draws the settings, the two renderings with their numbers and the scatter; starts a run
    /// when the design or a setting changed.
    pub fn ui(&mut self, ui: &mut Ui, shown: &Shown) {
        let egui_ctx = ui.ctx().clone();
        ui.horizontal_wrapped(|ui| {
            ui.label("Display:");
            ui.add(
                egui::DragValue::new(&mut self.dpi)
                    .range(50.0..=1200.0)
                    .speed(5.0)
                    .suffix(" DPI"),
            );
            ui.label("viewing distance:");
            ui.add(
                egui::DragValue::new(&mut self.viewing_distance_mm)
                    .range(50.0..=2000.0)
                    .speed(5.0)
                    .suffix(" mm"),
            );
            let eye = self.settings().eye_fwhm_um();
            ui.weak(format!("eye blur FWHM {eye:.0} um (1 arcmin)"));
            if ui
                .add_enabled(
                    self.scatter_job.is_none(),
                    egui::Button::new("Scatter presets"),
                )
                .on_hover_text("Camera AUC against display nonuniformity for every thesis preset")
                .clicked()
            {
                // On the route the design on screen was computed on.
                self.start_scatter(shown.route.clone(), &egui_ctx);
            }
            if self.is_running() {
                ui.spinner();
            }
        });
        let key = Key {
            shown: shown.generation,
            dpi: self.dpi,
            viewing_distance_mm: self.viewing_distance_mm,
        };
        let stale = self.done_key.as_ref() != Some(&key);
        let running_this = self.job.is_running_for(|k| *k == key);
        if stale && !running_this {
            self.start(key, shown.design.clone(), &egui_ctx);
        }
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        ui.label(format!(
            "camera AUC (radial min, mean of channels, this design): {:.4}",
            camera_auc(&shown.analysis)
        ));
        egui::ScrollArea::vertical().show(ui, |ui| {
            // One side for both renderings, from the width they share, so periodic and random
            // are compared at the same scale.
            let n = self.rows.len().max(1) as f32;
            let side = ((ui.available_width() - ui.spacing().item_spacing.x * n) / n)
                .floor()
                .clamp(120.0, 420.0);
            ui.horizontal_top(|ui| {
                for row in &self.rows {
                    ui.vertical(|ui| {
                        ui.strong(&row.label);
                        ui.image((row.texture.id(), egui::vec2(side, side)));
                        ui.label(format!(
                            "nonuniformity {:.4}   aliasing {:.4}",
                            row.quality.nonuniformity, row.quality.aliasing
                        ));
                        ui.weak(format!(
                            "image error {:.4}, pixel-harmonic energy {:.3}",
                            row.quality.image_error, row.quality.harmonic_fraction
                        ));
                    });
                }
            });
            if !self.scatter.is_empty() {
                let panel = scatter_panel(&self.scatter);
                ui.strong(&panel.title);
                let frame = PlotFrame {
                    legend_above: true,
                    ..PlotFrame::tall(260.0)
                };
                panel_ui_in(ui, "appearance-scatter", &panel, frame);
            }
        });
    }
}
