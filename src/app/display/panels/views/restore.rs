//! The Restore view (thesis §3.5): a photo captured through the current design (and the pinned
//! design A, on the same photo and light), denoised (BM3D by default, as the thesis) and restored,
//! with PSNR and SSIM. The simulation runs on a background thread whenever the design, the photo
//! or a setting changes; the previous pictures stay until the new ones arrive.

use crate::app::notice::Notice;
use std::path::PathBuf;
use std::sync::Arc;

use egui::{TextureHandle, TextureOptions, Ui};
use ndarray::Array2;

use crate::app::dialogs::{PendingDialog, Purpose};
use crate::app::display::panels::{PanelCtx, Pinned, Shown};
use crate::app::job::{Job, Keyed};
use crate::app::widgets::photo::{Photo, built_in, color_image};
use crate::core::Analysis;
use crate::core::figure::Panel;
use crate::core::restore::capture::REFERENCE_LTR;
use crate::core::restore::figures::{difference_planes, photo_panel};
use crate::core::restore::{
    CaptureSettings, CgSettings, Denoise, Light, Method, Recipe, RestoreMethod, RestoreResult,
    RestoreSettings, Sigma2, THESIS_NSR, simulate,
};
use crate::core::sweep::study::RestoreSetup;
use crate::io::photo;

/// Photos are scaled down to this side so a run stays interactive.
const MAX_SIDE_PX: u32 = 1024;
/// Gain of the difference image (as the CLI's).
const DIFFERENCE_GAIN: f64 = photo::DIFFERENCE_GAIN;

/// The settings a run depends on, compared to decide when to rerun.
#[derive(Debug, Clone, PartialEq)]
struct Key {
    photo: u64,
    shown: u64,
    pinned: Option<usize>,
    snr_db: f64,
    method: RestoreMethod,
    nsr: f64,
    lambda: f64,
    seed: u64,
    denoise: Denoise,
}

/// Captured, denoised (when a denoiser ran), restored and difference images of one design,
/// uploaded.
struct Row {
    label: String,
    result: RestoreResult,
    textures: Vec<Picture>,
}

/// One of a row's pictures: its texture and the stage it shows.
struct Picture {
    texture: TextureHandle,
    stage: Stage,
}

/// The stages a row shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    Captured,
    Denoised,
    Restored,
    Difference,
}

fn stage_name(stage: Stage) -> &'static str {
    match stage {
        Stage::Captured => "captured",
        Stage::Denoised => "denoised",
        Stage::Restored => "restored",
        Stage::Difference => "difference",
    }
}

/// The gain a stage is shown with: the difference is brightened to be seen.
fn gain(stage: Stage) -> f64 {
    if stage == Stage::Difference {
        DIFFERENCE_GAIN
    } else {
        1.0
    }
}

fn caption(stage: Stage) -> String {
    match stage {
        Stage::Denoised => "denoised (BM3D)".into(),
        Stage::Difference => format!("|restored - truth| x {DIFFERENCE_GAIN:.0}"),
        Stage::Captured | Stage::Restored => stage_name(stage).into(),
    }
}

/// The Restore view's state: the photo, the light level and restoration method, the background
/// run and its results for the current and the pinned design.
pub struct RestoreView {
    photo: Option<Arc<Photo>>,
    photo_id: u64,
    photo_texture: Option<TextureHandle>,
    photo_load: Option<Job<Photo>>,
    dialog: Option<PendingDialog>,
    snr_db: f64,
    method: RestoreMethod,
    nsr: f64,
    lambda: f64,
    seed: u64,
    denoise: Denoise,
    /// The run for the newest settings (their key).
    job: Keyed<Key, Vec<(String, RestoreResult)>>,
    done_key: Option<Key>,
    rows: Vec<Row>,
    message: Option<Notice>,
    /// How long the last finished run took, ms (a study's estimate adds it per point).
    last_run_ms: Option<f64>,
}

impl Default for RestoreView {
    fn default() -> Self {
        RestoreView {
            photo: None,
            photo_id: 0,
            photo_texture: None,
            photo_load: None,
            dialog: None,
            snr_db: 28.0,
            method: RestoreMethod::Wiener,
            nsr: THESIS_NSR,
            lambda: CgSettings::default().lambda,
            seed: 0,
            denoise: Denoise::default(),
            job: Keyed::idle(),
            done_key: None,
            rows: Vec::new(),
            message: None,
            last_run_ms: None,
        }
    }
}

impl RestoreView {
    /// The numbers of the current design's run (tests read them).
    pub fn current(&self) -> Option<&RestoreResult> {
        self.rows.first().map(|r| &r.result)
    }

    /// The numbers of the pinned design's run, when a design is pinned.
    pub fn pinned(&self) -> Option<&RestoreResult> {
        self.rows.get(1).map(|r| &r.result)
    }

    /// Whether a photo is loading or a capture-and-restore run is in progress.
    pub fn is_running(&self) -> bool {
        self.job.is_running() || self.photo_load.is_some()
    }

    /// The denoiser before the deblurring.
    pub fn denoise(&self) -> Denoise {
        self.denoise
    }

    /// Sets the denoiser before the deblurring (the Denoise control does this).
    pub fn set_denoise(&mut self, denoise: Denoise) {
        self.denoise = denoise;
    }

    /// Sets the light level, as the SNR of a white pixel behind the reference display, in dB
    /// (the slider spans 16 to 48 dB).
    pub fn set_snr_db(&mut self, snr_db: f64) {
        self.snr_db = snr_db;
    }

    /// Loads a photo file on a background thread (the open dialog and dropped files call this).
    pub fn load_photo(&mut self, path: PathBuf, ctx: &egui::Context) {
        let wake = ctx.clone();
        self.photo_load = Some(Job::spawn(
            "photo reader",
            move || wake.request_repaint(),
            move |_| {
                let planes = photo::load_photo(&path, Some(MAX_SIDE_PX))?;
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                Ok::<_, crate::io::IoError>(Photo { name, planes })
            },
        ));
    }

    fn set_photo(&mut self, p: Photo, ctx: &egui::Context) {
        let planes: Vec<&Array2<f64>> = p.planes.iter().collect();
        self.photo_texture = Some(ctx.load_texture(
            "restore-truth",
            color_image(&planes, 1.0),
            TextureOptions::LINEAR,
        ));
        self.photo = Some(Arc::new(p));
        self.photo_id += 1;
    }

    /// What a study that restores takes from the view: its settings, its photo and how long
    /// its last run took (ms).
    pub fn study_setup(&self) -> (RestoreSetup, Option<Arc<Photo>>, Option<f64>) {
        let setup = RestoreSetup {
            snr_db: self.snr_db,
            method: self.method,
            nsr: self.nsr,
            lambda: self.lambda,
            noise_seed: self.seed,
            denoise: self.denoise,
        };
        (setup, self.photo.clone(), self.last_run_ms)
    }

    /// Takes an answered dialog, a read photo and a finished run.
    pub(super) fn poll(&mut self, ctx: &egui::Context) {
        if let Some(answer) = self.dialog.as_ref().and_then(PendingDialog::poll) {
            self.dialog = None;
            match answer {
                Ok(Some(path)) => self.load_photo(path, ctx),
                Ok(None) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(done) = self.photo_load.as_ref().and_then(Job::poll) {
            self.photo_load = None;
            match done {
                Ok(p) => {
                    self.message = None;
                    self.set_photo(p, ctx);
                }
                // The previous photo stays.
                Err(e) => self.message = Some(Notice::error(format!("cannot open the photo: {e}"))),
            }
        }
        if let Some(f) = self.job.finished() {
            let (key, done) = (Some(f.key), f.result);
            if done.is_ok() {
                self.last_run_ms = Some(f.elapsed.as_secs_f64() * 1e3);
            }
            match done {
                Ok(runs) => {
                    self.rows = runs
                        .into_iter()
                        .enumerate()
                        .map(|(i, (label, result))| {
                            let c: Vec<&Array2<f64>> = result.captured.iter().collect();
                            let n: Vec<&Array2<f64>> = result.denoised.iter().collect();
                            let r: Vec<&Array2<f64>> = result.restored.iter().collect();
                            let diff: Vec<Array2<f64>> = match &self.photo {
                                Some(p) => difference_planes(&result.restored, &p.planes),
                                None => Vec::new(),
                            };
                            let d: Vec<&Array2<f64>> = diff.iter().collect();
                            let tex = |name: &str, img| {
                                ctx.load_texture(
                                    format!("restore-{i}-{name}"),
                                    img,
                                    TextureOptions::LINEAR,
                                )
                            };
                            let picture = |stage, planes: &[&Array2<f64>]| Picture {
                                texture: tex(stage_name(stage), color_image(planes, gain(stage))),
                                stage,
                            };
                            let mut textures = vec![picture(Stage::Captured, &c)];
                            if !n.is_empty() {
                                textures.push(picture(Stage::Denoised, &n));
                            }
                            textures.push(picture(Stage::Restored, &r));
                            textures.push(picture(Stage::Difference, &d));
                            Row {
                                label,
                                result,
                                textures,
                            }
                        })
                        .collect();
                    self.message = None;
                    self.done_key = key;
                }
                // Not retried until a setting changes.
                Err(e) => {
                    self.message = Some(Notice::error(e.to_string()));
                    self.done_key = key;
                }
            }
        }
    }

    fn key(&self, shown: &Shown, pinned: Option<&Pinned>) -> Key {
        Key {
            photo: self.photo_id,
            shown: shown.generation * 2 + u64::from(shown.quality == crate::core::Quality::Full),
            pinned: pinned.map(|p| Arc::as_ptr(&p.analysis) as usize),
            snr_db: self.snr_db,
            method: self.method,
            nsr: self.nsr,
            lambda: self.lambda,
            seed: self.seed,
            denoise: self.denoise,
        }
    }

    fn start(&mut self, key: Key, shown: &Shown, pinned: Option<&Pinned>, ctx: &egui::Context) {
        let Some(photo) = self.photo.clone() else {
            return;
        };
        // Dropping the running job cancels it.
        self.job.stop();
        let method = match self.method {
            RestoreMethod::Wiener => Method::Wiener { nsr: self.nsr },
            RestoreMethod::Cg => Method::Cg(CgSettings {
                lambda: self.lambda,
                ..CgSettings::default()
            }),
        };
        let settings = RestoreSettings {
            capture: CaptureSettings {
                light: Light::SnrDb(self.snr_db),
                seed: self.seed,
                ..CaptureSettings::default()
            },
            method,
            denoise: self.denoise,
            ..RestoreSettings::default()
        };
        // The names the Compare tab uses, so A and B read apart here too.
        let (a, b) = match pinned {
            Some(p) => {
                let (a, b) = super::compare::captions(p, &shown.design);
                (Some(a), b)
            }
            None => (None, format!("current: {}", shown.design.name)),
        };
        let b = match shown.quality {
            crate::core::Quality::Preview => format!("{b}, preview estimate"),
            crate::core::Quality::Full => b,
        };
        let mut designs: Vec<(String, Arc<Analysis>)> = vec![(b, shown.analysis.clone())];
        if let (Some(a), Some(p)) = (a, pinned) {
            designs.push((a, p.analysis.clone()));
        }
        let wake = ctx.clone();
        let job = Job::spawn(
            "restore job",
            move || wake.request_repaint(),
            move |p| {
                let mut out = Vec::new();
                for (label, analysis) in designs {
                    let psfs: Vec<&Array2<f64>> =
                        analysis.channels.iter().map(|c| &c.psf).collect();
                    if psfs.len() != photo.planes.len() {
                        return Err(format!(
                            "{label} has {} colour channels; the photo has {}",
                            psfs.len(),
                            photo.planes.len()
                        ));
                    }
                    let mut s = settings.clone();
                    s.capture.ltr_relative = analysis.ltr / REFERENCE_LTR;
                    let r = simulate(&photo.planes, &psfs, &s, p)
                        .map_err(|e| format!("{label}: {e}"))?;
                    out.push((label, r));
                }
                Ok::<_, String>(out)
            },
        );
        self.job.start(key, job);
    }

    /// Draws the controls, the pictures and the numbers; starts a new run when the design, the
    /// pinned design, the photo or a setting changed.
    pub fn ui(&mut self, ui: &mut Ui, shown: &Shown, ctx: &mut PanelCtx) {
        let egui_ctx = ui.ctx().clone();
        // The built-in photo is decoded the first time the view is shown, not at start-up.
        if self.photo.is_none() && self.photo_load.is_none() {
            match built_in() {
                Ok(p) => self.set_photo(p, &egui_ctx),
                Err(e) => self.message = Some(Notice::error(format!("the built-in photo: {e}"))),
            }
        }
        self.controls_ui(ui);
        let key = self.key(shown, ctx.pinned);
        let stale = self.done_key.as_ref() != Some(&key);
        let running_this = self.job.is_running_for(|k| *k == key);
        if stale && !running_this && self.photo.is_some() {
            self.start(key, shown, ctx.pinned, &egui_ctx);
        }
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        // A window that drops light makes a capture too clean (conventions §5): say so here,
        // where the capture is shown, with the fix.
        if let Some(w) = crate::core::analysis::light::capture_light_warning(&shown.analysis) {
            ui.colored_label(ui.visuals().warn_fg_color, w);
        }
        if ctx.pinned.is_none() {
            ui.weak("Pin a design as A (Compare menu) to see both on the same photo and light.");
        }
        egui::ScrollArea::both().show(ui, |ui| self.images_ui(ui));
    }

    fn controls_ui(&mut self, ui: &mut Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Photo:");
            ui.strong(self.photo.as_ref().map_or("(loading)", |p| p.name.as_str()));
            if ui
                .add_enabled(self.dialog.is_none(), egui::Button::new("Open photo…"))
                .on_hover_text(
                    "A PNG or JPEG (scaled to at most 1024 px); or drop one on the window",
                )
                .clicked()
            {
                self.dialog = Some(PendingDialog::spawn(Purpose::Photo, None, None));
            }
            if ui.button("Built-in photo").clicked() {
                self.photo = None;
                self.photo_load = None;
            }
            if self.is_running() {
                ui.spinner();
                if let Some(j) = self.job.job() {
                    ui.weak(format!("{:.0} %", 100.0 * j.fraction()));
                }
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.add(
                egui::Slider::new(&mut self.snr_db, 16.0..=48.0)
                    .step_by(1.0)
                    .suffix(" dB")
                    .text("SNR"),
            )
            .on_hover_text(format!(
                "Light level as the SNR of a white pixel behind the reference T-OLED display \
                 (24/28/32/36/40 dB = 273/654/1608/4005/10024 e-); now {:.0} e-",
                Light::SnrDb(self.snr_db).electrons(crate::core::restore::capture::READ_NOISE_E)
            ));
            ui.separator();
            for m in RestoreMethod::ALL {
                ui.selectable_value(&mut self.method, m, m.label());
            }
            match self.method {
                RestoreMethod::Wiener => {
                    ui.add(
                        crate::app::widgets::number(&mut self.nsr)
                            .range(0.0..=1.0)
                            .speed(0.0001)
                            .prefix("nsr ")
                            .max_decimals(5),
                    )
                    .on_hover_text(
                        "Noise-to-signal ratio of the Wiener filter (the thesis: 0.00371)",
                    );
                }
                RestoreMethod::Cg => {
                    ui.add(
                        crate::app::widgets::number(&mut self.lambda)
                            .range(0.0..=1.0)
                            .speed(0.0001)
                            .prefix("λ ")
                            .max_decimals(5),
                    )
                    .on_hover_text("Weight of the gradient penalty");
                }
            }
            ui.separator();
            ui.add(crate::app::widgets::number(&mut self.seed).prefix("noise seed "));
        });
        ui.horizontal_wrapped(|ui| {
            // The current design's σ² (the pinned one's may differ by its LTR): chapter 3's table
            // is on the reference display's scale, divided by ltr_relative² for ours.
            let ltr_relative = self.current().map_or(1.0, |r| {
                r.electrons_per_unit / r.light_e.max(f64::MIN_POSITIVE)
            });
            // The capture the view runs (`start`): its light, this display's LTR, no ADC.
            let noise = crate::core::restore::CaptureNoise::of(&CaptureSettings {
                light: Light::SnrDb(self.snr_db),
                ltr_relative,
                ..CaptureSettings::default()
            });
            let thesis = Sigma2::Thesis(Recipe::Iccp21).resolve(&noise);
            let matched = self.current().map(|_| noise.white_variance());
            crate::app::widgets::denoise::denoise_ui(
                ui,
                &mut self.denoise,
                Recipe::Iccp21,
                thesis,
                matched,
            );
        });
    }

    /// A row's stage as a figure panel, titled with the row and the caption.
    fn stage_panel(&self, row: &Row, stage: Stage, caption: &str) -> Panel {
        let r = &row.result;
        let title = format!("{}: {caption}", row.label);
        let refs = |v: &[Array2<f64>]| -> Vec<Array2<f64>> { v.to_vec() };
        let planes = match stage {
            Stage::Captured => refs(&r.captured),
            Stage::Denoised => refs(&r.denoised),
            Stage::Restored => refs(&r.restored),
            Stage::Difference => match &self.photo {
                Some(p) => difference_planes(&r.restored, &p.planes),
                None => Vec::new(),
            },
        };
        let planes: Vec<&Array2<f64>> = planes.iter().collect();
        photo_panel(&title, &planes, gain(stage))
    }

    fn images_ui(&self, ui: &mut Ui) {
        // Up to four pictures in a row fit the view's width (a 1024-point window included).
        let gap = ui.spacing().item_spacing.x;
        let side = ((ui.available_width() - 3.0 * gap - 8.0) / 4.0).clamp(96.0, 240.0);
        let size_of = |t: &TextureHandle| {
            let [w, h] = t.size();
            let s = side / w.max(h).max(1) as f32;
            egui::vec2(w as f32 * s, h as f32 * s)
        };
        if let Some(t) = &self.photo_texture {
            ui.label("Ground truth");
            ui.image((t.id(), size_of(t)));
        }
        for row in &self.rows {
            ui.separator();
            let r = &row.result;
            ui.horizontal_wrapped(|ui| {
                ui.strong(&row.label);
                let denoised = match (r.denoised_psnr_db, r.denoise.sigma2) {
                    (Some(p), Some(s)) => format!(", denoised {p:.2} dB with σ² {s:.2e}"),
                    _ => ", no denoiser".to_string(),
                };
                ui.label(format!(
                    "restored PSNR {:.2} dB, SSIM {:.3}  (captured {:.2} dB{denoised});  {:.0} e- at white, {:.0} ms",
                    r.psnr_db, r.ssim, r.captured_psnr_db, r.electrons_per_unit, r.elapsed_ms
                ));
            });
            let sat: f64 = r
                .channels
                .iter()
                .map(|c| c.saturated_fraction)
                .fold(0.0, f64::max);
            if sat > 0.0 {
                ui.colored_label(
                    ui.visuals().warn_fg_color,
                    format!("{:.2} % of pixels reached the full well", 100.0 * sat),
                );
            }
            ui.horizontal(|ui| {
                for p in &row.textures {
                    ui.vertical(|ui| {
                        let caption = caption(p.stage);
                        ui.label(&caption);
                        let response = ui.add(
                            egui::Image::new((p.texture.id(), size_of(&p.texture)))
                                .alt_text(format!("{} {caption}", row.label))
                                .sense(egui::Sense::click()),
                        );
                        // The figure is drawn from the planes only when asked for: a photo's
                        // planes are too large to copy into a panel per picture and frame.
                        response.context_menu(|ui| {
                            if ui.button("Save figure…").clicked() {
                                let panel = self.stage_panel(row, p.stage, &caption);
                                crate::app::widgets::figure::request_save(ui.ctx(), &panel);
                                ui.close();
                            }
                        });
                    });
                }
            });
        }
    }
}
