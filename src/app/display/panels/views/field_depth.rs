//! The Field & depth view (thesis §3.7, Figs. 3.29 and 3.31): PSFs over the field through a
//! display in front of the lens, or of a point at a finite depth, each with its residual after
//! deblurring with the centre (or infinity) PSF. The PSFs are computed on a background job at
//! preview sampling whenever the design or a setting changes; the UI thread only draws.

use std::sync::Arc;

use egui::{ColorImage, TextureHandle, TextureOptions, Ui};
use ndarray::Array2;

use super::images::log_image;
use crate::app::display::panels::Shown;
use crate::app::job::Job;
use crate::app::notice::Notice;
use crate::app::widgets::colormap::Colormap;
use crate::core::Quality;
use crate::core::depth::{DepthResult, DepthSettings, depth_psfs};
use crate::core::design::Design;
use crate::core::field::{FieldResult, FieldSettings, field_psfs};

/// Decades below the peak shown by the thumbnails.
const FLOOR_DECADES: f64 = 4.0;
/// Largest and smallest side of a thumbnail, points (they shrink to fit a row in the panel).
const THUMB_PT: std::ops::RangeInclusive<f32> = 48.0..=160.0;

/// Which study the view shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Study {
    /// PSFs on a field grid (Fig. 3.29).
    #[default]
    Field,
    /// PSFs of a point at a finite depth (Fig. 3.31).
    Depth,
}

/// The settings a run depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key {
    shown: u64,
    study: Study,
    display_distance_mm: f64,
    max_field_deg: f64,
    object_distance_mm: f64,
}

enum Outcome {
    Field(FieldResult),
    Depth(Box<DepthResult>),
}

/// A picture with its caption.
struct Tile {
    caption: String,
    texture: TextureHandle,
}

/// The view's state: settings, the running job and the last pictures and numbers.
pub struct FieldDepthView {
    study: Study,
    display_distance_mm: f64,
    max_field_deg: f64,
    object_distance_mm: f64,
    job: Option<(Key, Job<Outcome>)>,
    done_key: Option<Key>,
    rows: Vec<Vec<Tile>>,
    summary: String,
    message: Option<Notice>,
}

impl Default for FieldDepthView {
    fn default() -> Self {
        FieldDepthView {
            study: Study::Field,
            display_distance_mm: 1.0,
            max_field_deg: 30.0,
            object_distance_mm: 100.0,
            job: None,
            done_key: None,
            rows: Vec::new(),
            summary: String::new(),
            message: None,
        }
    }
}

/// The channel mean of per-channel planes.
fn mean_plane(planes: &[Array2<f64>]) -> Array2<f64> {
    let mut acc = planes
        .first()
        .map_or_else(|| Array2::zeros((1, 1)), |p| Array2::zeros(p.dim()));
    for p in planes {
        acc += p;
    }
    acc / planes.len().max(1) as f64
}

fn log_picture(planes: &[Array2<f64>]) -> ColorImage {
    let m = mean_plane(planes);
    let peak = m.iter().copied().fold(0.0, f64::max);
    log_image(&m, peak, FLOOR_DECADES, Colormap::default())
}

impl FieldDepthView {
    /// Selects the study (tests and menus).
    pub fn set_study(&mut self, study: Study) {
        self.study = study;
    }

    /// Whether a run is in progress.
    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// The one-line summary of the last result (tests read it).
    pub fn summary(&self) -> &str {
        &self.summary
    }

    fn key(&self, shown: &Shown) -> Key {
        Key {
            shown: shown.generation,
            study: self.study,
            display_distance_mm: self.display_distance_mm,
            max_field_deg: self.max_field_deg,
            object_distance_mm: self.object_distance_mm,
        }
    }

    fn start(&mut self, key: Key, design: Arc<Design>, ctx: &egui::Context) {
        let wake = ctx.clone();
        let job = Job::spawn(
            "field and depth job",
            move || wake.request_repaint(),
            move |p| match key.study {
                Study::Field => field_psfs(
                    &design,
                    &FieldSettings {
                        display_distance_mm: key.display_distance_mm,
                        max_field_deg: key.max_field_deg,
                        quality: Quality::Preview,
                        ..FieldSettings::default()
                    },
                    p,
                )
                .map(Outcome::Field),
                Study::Depth => depth_psfs(
                    &design,
                    &DepthSettings {
                        object_distance_mm: key.object_distance_mm,
                        quality: Quality::Preview,
                        ..DepthSettings::default()
                    },
                    p,
                )
                .map(|r| Outcome::Depth(Box::new(r))),
            },
        );
        self.job = Some((key, job));
    }

    fn poll(&mut self, ctx: &egui::Context) {
        let Some(done) = self.job.as_ref().and_then(|(_, j)| j.poll()) else {
            return;
        };
        let key = self.job.take().map(|(k, _)| k);
        self.done_key = key;
        match done {
            Ok(outcome) => {
                self.message = None;
                self.show(outcome, ctx);
            }
            Err(e) => self.message = Some(Notice::error(e.to_string())),
        }
    }

    fn show(&mut self, outcome: Outcome, ctx: &egui::Context) {
        let tile = |name: String, caption: String, planes: &[Array2<f64>]| Tile {
            texture: ctx.load_texture(name, log_picture(planes), TextureOptions::NEAREST),
            caption,
        };
        match outcome {
            Outcome::Field(r) => {
                let n = (r.points.len() as f64).sqrt().round() as usize;
                self.rows = r
                    .points
                    .chunks(n.max(1))
                    .rev()
                    .enumerate()
                    .map(|(i, row)| {
                        row.iter()
                            .enumerate()
                            .flat_map(|(j, p)| {
                                let at = format!("{:.0}°, {:.0}°", p.field_deg[0], p.field_deg[1]);
                                [
                                    tile(
                                        format!("field-psf-{i}-{j}"),
                                        format!("PSF at {at}"),
                                        &p.psfs,
                                    ),
                                    tile(
                                        format!("field-res-{i}-{j}"),
                                        format!("residual {:.2e}", p.residual_rel),
                                        &p.deblurred,
                                    ),
                                ]
                            })
                            .collect()
                    })
                    .collect();
                self.summary = format!(
                    "max residual_rel {:.2e} over ±{:.0}° at {:.2} mm",
                    r.max_residual_rel, self.max_field_deg, self.display_distance_mm
                );
            }
            Outcome::Depth(r) => {
                self.rows = vec![
                    vec![
                        tile(
                            "depth-inf".into(),
                            "infinity PSF (kernel)".into(),
                            &r.infinity,
                        ),
                        tile(
                            "depth-foc".into(),
                            "focused at the object".into(),
                            &r.focused,
                        ),
                        tile(
                            "depth-foc-res".into(),
                            format!("residual {:.2e}", r.residual_rel_focused),
                            &r.deblurred_focused,
                        ),
                    ],
                    vec![
                        tile(
                            "depth-def".into(),
                            "focused at infinity".into(),
                            &r.defocused,
                        ),
                        tile(
                            "depth-def-res".into(),
                            format!("residual {:.2e}", r.residual_rel_defocused),
                            &r.deblurred_defocused,
                        ),
                    ],
                ];
                let waves = r
                    .defocus_waves
                    .get(r.defocus_waves.len() / 2)
                    .copied()
                    .unwrap_or(0.0);
                self.summary = format!(
                    "z2 = {:.3} mm, PSF scale z2/f = {:.4} ({:+.2} %), defocus {:.1} waves at the \
                     pupil rim, blur {:.0} µm",
                    r.image_distance_mm,
                    r.psf_scale,
                    100.0 * (r.psf_scale - 1.0),
                    waves,
                    r.defocus_blur_um
                );
            }
        }
    }

    /// Draws the controls and the pictures; starts a run when the design or a setting changed.
    pub fn ui(&mut self, ui: &mut Ui, shown: &Shown) {
        let egui_ctx = ui.ctx().clone();
        self.poll(&egui_ctx);
        ui.horizontal_wrapped(|ui| {
            ui.selectable_value(&mut self.study, Study::Field, "Field (Fig. 3.29)");
            ui.selectable_value(&mut self.study, Study::Depth, "Depth (Fig. 3.31)");
            ui.separator();
            match self.study {
                Study::Field => {
                    ui.label("display to lens");
                    ui.add(
                        egui::Slider::new(&mut self.display_distance_mm, 0.0..=5.0).suffix(" mm"),
                    );
                    ui.label("field");
                    ui.add(egui::Slider::new(&mut self.max_field_deg, 1.0..=45.0).suffix("°"));
                }
                Study::Depth => {
                    ui.label("object distance z1");
                    ui.add(
                        egui::DragValue::new(&mut self.object_distance_mm)
                            .range(20.0..=100_000.0)
                            .speed(5.0)
                            .suffix(" mm"),
                    );
                }
            }
        });
        let key = self.key(shown);
        let running_this = self.job.as_ref().is_some_and(|(k, _)| *k == key);
        if self.done_key != Some(key) && !running_this {
            self.start(key, shown.design.clone(), &egui_ctx);
        }
        if let Some((_, job)) = &self.job {
            let mut cancel = false;
            ui.horizontal(|ui| {
                ui.add(
                    egui::ProgressBar::new(job.fraction())
                        .desired_width(200.0)
                        .show_percentage(),
                );
                cancel = ui.button("Cancel").clicked();
            });
            if cancel {
                job.cancel();
            }
        }
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        ui.label(&self.summary);
        ui.weak(
            "log-PSFs (4 decades, channels averaged) and each PSF deblurred with the reference's \
             Wiener filter; residual = energy of the difference from the reference deblurred by \
             itself, relative to it (0 = identical)",
        );
        let per_row = self.rows.iter().map(Vec::len).max().unwrap_or(1).max(1) as f32;
        let spacing = ui.spacing().item_spacing.x;
        let side =
            (ui.available_width() / per_row - spacing).clamp(*THUMB_PT.start(), *THUMB_PT.end());
        egui::ScrollArea::both().show(ui, |ui| {
            for row in &self.rows {
                ui.horizontal(|ui| {
                    for t in row {
                        ui.vertical(|ui| {
                            ui.add(
                                egui::Image::new(&t.texture)
                                    .fit_to_exact_size(egui::vec2(side, side)),
                            );
                            ui.small(&t.caption);
                        });
                    }
                });
            }
        });
    }
}
