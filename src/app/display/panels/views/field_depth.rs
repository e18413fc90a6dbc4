//! The Field & depth view (thesis §3.7, Figs. 3.29–3.31): PSFs over the field through a
//! display in front of the lens, or of a point at a finite depth, each with its residual after
//! deblurring with the centre (or infinity) PSF; and the saturation study, a capture that clips
//! highlights of the built-in HDR scene against an exposure-bracketed one, both restored. The PSFs are computed on a background job at
//! preview sampling whenever the design or a setting changes; the UI thread only draws.

use std::sync::Arc;

use egui::{ColorImage, TextureHandle, TextureOptions, Ui};
use ndarray::Array2;

use super::images::log_image;
use crate::app::display::panels::Shown;
use crate::app::job::{Job, Keyed};
use crate::app::notice::Notice;
use crate::app::widgets::colormap::Colormap;
use crate::app::widgets::photo::color_image;
use crate::core::Quality;
use crate::core::camera::depth::{DepthResult, DepthSettings, depth_psfs};
use crate::core::camera::depth_capture::{DepthCapture, depth_capture};
use crate::core::camera::field::{FieldResult, FieldSettings, field_psfs};
use crate::core::camera::field_capture::{FieldCapture, field_capture};
use crate::core::camera::saturation::{SaturationResult, SaturationSettings, saturation_study};
use crate::core::design::Design;

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
    /// Clipped against bracketed captures of an HDR scene, restored (Fig. 3.30).
    Saturation,
}

/// The field study's photo is scaled down to this side so a run stays interactive.
const CAPTURE_SIDE_PX: usize = 256;
/// Its capture's signal-to-noise ratio, dB (the CLI's `--snr-db` default).
const CAPTURE_SNR_DB: f64 = 28.0;

/// The built-in photo at [`CAPTURE_SIDE_PX`] and the capture settings of the photo studies.
fn capture_photo()
-> Result<(Vec<Array2<f64>>, crate::core::restore::CaptureSettings), crate::core::SimError> {
    let photo = crate::io::photo::built_in_photo()
        .map_err(|e| crate::core::SimError::Sampling(e.to_string()))?;
    let capture = crate::core::restore::CaptureSettings {
        light: crate::core::restore::Light::SnrDb(CAPTURE_SNR_DB),
        ..crate::core::restore::CaptureSettings::default()
    };
    Ok((
        crate::io::photo::fit_max_side(photo, CAPTURE_SIDE_PX),
        capture,
    ))
}

/// The HDR scene is scaled down to this side so a run stays interactive.
const SCENE_SIDE_PX: usize = 320;

/// The settings a run depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key {
    shown: u64,
    study: Study,
    display_distance_mm: f64,
    max_field_deg: f64,
    object_distance_mm: f64,
    clip_percent: f64,
    brackets: usize,
    capture_photo: bool,
}

enum Outcome {
    /// The field grid, and the photo captured through it when asked for.
    Field(FieldResult, Option<Box<FieldCapture>>),
    /// The depth PSFs, and the photo captured through them when asked for.
    Depth(Box<DepthResult>, Option<Box<DepthCapture>>),
    Saturation(Box<SaturationResult>),
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
    clip_percent: f64,
    brackets: usize,
    /// Also capture the built-in photo through the field's PSFs (patch-wise) and restore it
    /// with the centre PSF, beside the shift-invariant capture.
    capture_photo: bool,
    /// The run, and the line saying where its PSFs were computed.
    job: Keyed<Key, (Outcome, String)>,
    done_key: Option<Key>,
    rows: Vec<Vec<Tile>>,
    summary: String,
    /// Where the PSFs on screen were computed (the route's adapter, or the CPU).
    computed_on: String,
    message: Option<Notice>,
}

impl Default for FieldDepthView {
    fn default() -> Self {
        FieldDepthView {
            study: Study::Field,
            display_distance_mm: 1.0,
            max_field_deg: 30.0,
            object_distance_mm: 100.0,
            clip_percent: 2.0,
            brackets: 3,
            capture_photo: false,
            job: Keyed::idle(),
            done_key: None,
            rows: Vec::new(),
            summary: String::new(),
            computed_on: String::new(),
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

/// A photo (linear planes in `[0, 1]`) as a tile.
fn photo_tile(ctx: &egui::Context, name: &str, caption: String, planes: &[Array2<f64>]) -> Tile {
    let refs: Vec<&Array2<f64>> = planes.iter().collect();
    Tile {
        texture: ctx.load_texture(name, color_image(&refs, 1.0), TextureOptions::LINEAR),
        caption,
    }
}

/// Where a study's PSFs were computed, as the route says after its run.
fn computed_on(route: &udc_gpu::Route) -> String {
    if let Some(note) = route.note() {
        return note;
    }
    match route.adapter() {
        None => "PSFs computed on the CPU (f64)".into(),
        Some(a) => format!("PSFs computed on {a} (f32)"),
    }
}

fn log_picture(planes: &[Array2<f64>]) -> ColorImage {
    let m = mean_plane(planes);
    let peak = m.iter().copied().fold(0.0, f64::max);
    log_image(&m, peak, FLOOR_DECADES, Colormap::default())
}

impl FieldDepthView {
    /// Where the PSFs on screen were computed (empty before the first result).
    pub fn computed_on(&self) -> &str {
        &self.computed_on
    }

    /// Selects the study (tests and menus).
    pub fn set_study(&mut self, study: Study) {
        self.study = study;
    }

    /// Whether a run is in progress.
    pub fn is_running(&self) -> bool {
        self.job.is_running()
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
            clip_percent: self.clip_percent,
            brackets: self.brackets,
            capture_photo: self.capture_photo,
        }
    }

    /// Turns the field study's photo capture on or off (tests and menus).
    pub fn set_capture_photo(&mut self, on: bool) {
        self.capture_photo = on;
    }

    fn start(&mut self, key: Key, shown: &Shown, ctx: &egui::Context) {
        let design: Arc<Design> = shown.design.clone();
        let analysis = shown.analysis.clone();
        // On the route the shown design's PSFs were computed on.
        let route = shown.route.clone();
        let wake = ctx.clone();
        let job = Job::spawn(
            "field and depth job",
            move || wake.request_repaint(),
            move |p| {
                let outcome = match key.study {
                    Study::Field => {
                        let settings = FieldSettings {
                            display_distance_mm: key.display_distance_mm,
                            max_field_deg: key.max_field_deg,
                            quality: Quality::Preview,
                            ..FieldSettings::default()
                        };
                        let r = field_psfs(&design, &settings, route.as_ref(), p)?;
                        let capture = if key.capture_photo {
                            p.check()?;
                            let (photo, capture) = capture_photo()?;
                            Some(Box::new(field_capture(&photo, &r, &capture, settings.nsr)?))
                        } else {
                            None
                        };
                        Ok(Outcome::Field(r, capture))
                    }
                    Study::Depth => {
                        let settings = DepthSettings {
                            object_distance_mm: key.object_distance_mm,
                            quality: Quality::Preview,
                            ..DepthSettings::default()
                        };
                        let r = depth_psfs(&design, &settings, route.as_ref(), p)?;
                        let capture = if key.capture_photo {
                            p.check()?;
                            let (photo, capture) = capture_photo()?;
                            Some(Box::new(depth_capture(&photo, &r, &capture, settings.nsr)?))
                        } else {
                            None
                        };
                        Ok(Outcome::Depth(Box::new(r), capture))
                    }
                    Study::Saturation => {
                        let scene = crate::io::photo::hdr::sample_scene()
                            .map_err(|e| crate::core::SimError::Sampling(e.to_string()))?
                            .downscaled(SCENE_SIDE_PX);
                        let psfs: Vec<&Array2<f64>> =
                            analysis.channels.iter().map(|c| &c.psf).collect();
                        if psfs.len() != scene.planes.len() {
                            return Err(crate::core::SimError::invalid(
                                "channels",
                                "the saturation study needs an R, G, B design",
                            ));
                        }
                        let settings = SaturationSettings {
                            clip_percent: key.clip_percent,
                            brackets: key.brackets,
                            ..SaturationSettings::default()
                        };
                        p.check()?;
                        saturation_study(&scene.planes, &psfs, &settings)
                            .map(|r| Outcome::Saturation(Box::new(r)))
                    }
                }?;
                // Read after the run: a transform the device refused has left its note.
                Ok((outcome, computed_on(&route)))
            },
        );
        self.job.start(key, job);
    }

    /// Takes a finished run.
    pub(super) fn poll(&mut self, ctx: &egui::Context) {
        let Some((key, done)) = self.job.poll() else {
            return;
        };
        self.done_key = Some(key);
        match done {
            Ok((outcome, on)) => {
                self.message = None;
                self.computed_on = on;
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
            Outcome::Field(r, capture) => {
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
                if let Some(c) = capture {
                    let photo = |name: &str, caption: String, planes: &[Array2<f64>]| {
                        photo_tile(ctx, name, caption, planes)
                    };
                    self.rows.push(vec![
                        photo(
                            "field-capture-field",
                            format!(
                                "field-dependent capture, restored: {:.2} dB",
                                c.psnr_db_field
                            ),
                            &c.restored_field,
                        ),
                        photo(
                            "field-capture-invariant",
                            format!(
                                "centre PSF everywhere, restored: {:.2} dB",
                                c.psnr_db_invariant
                            ),
                            &c.restored_invariant,
                        ),
                    ]);
                    self.summary.push_str(&format!(
                        "; photo restored with the centre PSF: field-dependent capture {:.2} dB \
                         (SSIM {:.3}), shift-invariant capture {:.2} dB (SSIM {:.3})",
                        c.psnr_db_field, c.ssim_field, c.psnr_db_invariant, c.ssim_invariant
                    ));
                }
            }
            Outcome::Saturation(r) => {
                let photo = |name: &str, caption: String, planes: &[Array2<f64>]| {
                    photo_tile(ctx, name, caption, planes)
                };
                let scores = |what: &str, run: &crate::core::camera::saturation::SaturationRun| {
                    format!(
                        "{what}: PSNR {:.2} dB, SSIM {:.3}, {:.2} % clipped",
                        run.psnr_db,
                        run.ssim,
                        100.0 * run.clipped_fraction
                    )
                };
                self.rows = vec![
                    vec![
                        photo("sat-truth", "truth (HDR, clipped to show)".into(), &r.truth),
                        photo(
                            "sat-clipped-captured",
                            "one exposure, captured".into(),
                            &r.clipped.captured,
                        ),
                        photo(
                            "sat-clipped-restored",
                            scores("restored", &r.clipped),
                            &r.clipped.restored,
                        ),
                    ],
                    vec![
                        photo(
                            "sat-bracketed-captured",
                            format!("{} exposures merged", r.factors.len()),
                            &r.bracketed.captured,
                        ),
                        photo(
                            "sat-bracketed-restored",
                            scores("restored", &r.bracketed),
                            &r.bracketed.restored,
                        ),
                    ],
                ];
                self.summary = format!(
                    "bracketed HDR gains {:+.2} dB PSNR over one exposure clipping {:.1} % of the pixels",
                    r.bracketed.psnr_db - r.clipped.psnr_db,
                    self.clip_percent
                );
            }
            Outcome::Depth(r, capture) => {
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
                if let Some(c) = capture {
                    let photo = |name: &str, caption: String, planes: &[Array2<f64>]| {
                        photo_tile(ctx, name, caption, planes)
                    };
                    let caption =
                        |what: &str, d: &crate::core::camera::depth_capture::DepthRestored| {
                            format!("{what}: {:.2} dB, SSIM {:.3}", d.psnr_db, d.ssim)
                        };
                    self.rows.push(vec![
                        photo(
                            "depth-photo-inf",
                            caption("object at infinity", &c.infinity),
                            &c.infinity.restored,
                        ),
                        photo(
                            "depth-photo-foc",
                            caption("refocused on it", &c.focused),
                            &c.focused.restored,
                        ),
                        photo(
                            "depth-photo-def",
                            caption("focused at infinity", &c.defocused),
                            &c.defocused.restored,
                        ),
                    ]);
                    self.summary.push_str(&format!(
                        "; photo restored with the infinity PSF: object at infinity {:.2} dB, \
                         refocused on it {:.2} dB, focused at infinity {:.2} dB",
                        c.infinity.psnr_db, c.focused.psnr_db, c.defocused.psnr_db
                    ));
                }
            }
        }
    }

    /// Draws the controls and the pictures; starts a run when the design or a setting changed.
    pub fn ui(&mut self, ui: &mut Ui, shown: &Shown) {
        let egui_ctx = ui.ctx().clone();
        // Keep to the visible part of the panel: a parent that scrolls sideways would otherwise
        // let the thumbnail rows and the controls run past its edge.
        let visible = ui.clip_rect().right() - ui.cursor().left();
        if visible > 0.0 {
            ui.set_max_width(visible);
        }
        ui.horizontal_wrapped(|ui| {
            ui.selectable_value(&mut self.study, Study::Field, "Field (Fig. 3.29)");
            ui.selectable_value(&mut self.study, Study::Depth, "Depth (Fig. 3.31)");
            ui.selectable_value(&mut self.study, Study::Saturation, "Saturation (Fig. 3.30)");
        });
        // The settings on a row of their own, with short sliders: a row wider than the panel
        // does not wrap in egui and would widen the whole view past its edge.
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().slider_width = 90.0;
            match self.study {
                Study::Field => {
                    ui.label("display to lens");
                    ui.add(
                        egui::Slider::new(&mut self.display_distance_mm, 0.0..=5.0).suffix(" mm"),
                    );
                    ui.label("field");
                    ui.add(egui::Slider::new(&mut self.max_field_deg, 1.0..=45.0).suffix("°"));
                    ui.checkbox(&mut self.capture_photo, "capture a photo")
                        .on_hover_text(
                            "Blur the built-in photo patch by patch with the field's PSFs (as a \
                             real camera behind the display would) and restore it with the centre \
                             PSF, beside the same photo blurred by the centre PSF everywhere",
                        );
                }
                Study::Saturation => {
                    ui.label("clipped");
                    ui.add(egui::Slider::new(&mut self.clip_percent, 0.5..=10.0).suffix(" %"));
                    ui.label("exposures, 2 EV apart");
                    ui.add(egui::Slider::new(&mut self.brackets, 2..=7));
                }
                Study::Depth => {
                    ui.label("object distance z1");
                    ui.add(
                        egui::DragValue::new(&mut self.object_distance_mm)
                            .range(20.0..=100_000.0)
                            .speed(5.0)
                            .suffix(" mm"),
                    );
                    ui.checkbox(&mut self.capture_photo, "capture a photo")
                        .on_hover_text(
                            "Blur the built-in photo with each PSF and restore every capture with \
                         the infinity PSF, as the thesis restores every depth (Fig. 3.31)",
                        );
                }
            }
        });
        let key = self.key(shown);
        let running_this = self.job.is_running_for(|k| *k == key);
        if self.done_key != Some(key) && !running_this {
            self.start(key, shown, &egui_ctx);
        }
        if let Some(job) = self.job.job() {
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
        if !self.computed_on.is_empty() {
            ui.weak(&self.computed_on);
        }
        if self.study != Study::Saturation {
            ui.weak(
            "log-PSFs (4 decades, channels averaged) and each PSF deblurred with the reference's \
             Wiener filter; residual = energy of the difference from the reference deblurred by \
             itself, relative to it (0 = identical)",
        );
        }
        let per_row = self.rows.iter().map(Vec::len).max().unwrap_or(1).max(1) as f32;
        let spacing = ui.spacing().item_spacing.x;
        // The row's spacing, the scroll bar and a margin come off before the thumbnails share the
        // rest: a row that is one thumbnail too wide pushes the panel (and its controls) wider.
        let room = ui.available_width() - spacing * per_row - 2.0 * ui.spacing().scroll.bar_width;
        let side = (room / per_row)
            .floor()
            .clamp(*THUMB_PT.start(), *THUMB_PT.end());
        // Vertical only: the thumbnails are sized to the panel's width, never wider.
        egui::ScrollArea::vertical().show(ui, |ui| {
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
