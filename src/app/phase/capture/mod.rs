//! The phase workspace's Capture & restore view (thesis §4.5): a photo captured through the
//! current design and through the bare T-OLED of the same pitch, restored and scored (PSNR and
//! SSIM on the eq. 4.13 field of view), at a light level chosen on a log slider.
//!
//! Everything runs in `core::phase::imaging` on a background thread with progress and Cancel;
//! the worker also makes the pictures, so the UI thread only uploads and draws them. An
//! operator (the blur matrix of every direction, eq. 4.12) costs seconds, a capture and
//! restoration a fraction of one: operators are kept per design, optics, sampling, channels and
//! photo width, so moving the light slider or the noise seed only captures and restores again.

use crate::app::notice::Notice;
use std::ops::Range;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use egui::{ColorImage, TextureHandle, TextureOptions};
use ndarray::Array2;

use super::{CaptureChoices, ChannelSet, PhaseWorkspace, Quality};
use crate::app::dialogs::{PendingDialog, Purpose};
use crate::app::job::{Job, JobError, Streaming};
use crate::app::widgets::photo::{Photo, built_in, color_image};
use crate::core::design::Channel;
use crate::core::phase::imaging::{
    PhaseBlur, RestoreRun, Setup, capture_and_restore, thesis_denoise,
};
use crate::core::phase::{PhaseDesign, PhaseOptics, PhaseSampling, Relay};
use crate::core::restore::Denoise;
use crate::core::{Progress, SimError};
use crate::io::photo;

mod worker;
use worker::{Light, SetupJob, run_setups};

/// The widest photo whose spectral operator, through the lenslet period, needs no quick look
/// through the peak wavelengths first (256 columns: about 1 s on 2 cores, docs/src/benchmarks.md).
const SPECTRAL_WITHOUT_QUICK_LOOK: usize = 256;

/// Operators kept (each is `width² × channels` numbers: 1.5 MB for a 256 px photo).
const KEPT_OPERATORS: usize = 6;

/// What an operator depends on.
#[derive(Debug, Clone, PartialEq)]
struct OperatorKey {
    design: PhaseDesign,
    optics: PhaseOptics,
    quality: Quality,
    channels: ChannelSet,
    width: usize,
}

/// What a run depends on: the operators' keys and the capture's settings.
#[derive(Debug, Clone, PartialEq)]
struct RunKey {
    operators: Vec<OperatorKey>,
    photo: u64,
    photons_bits: u64,
    seed: u64,
    denoise: Denoise,
}

/// One setup's result, with its pictures uploaded.
pub struct CaptureRow {
    /// Name of the setup shown with its pictures ("this design: …" or "bare T-OLED, …").
    pub label: String,
    /// The optical chain the photo went through.
    pub optics: PhaseOptics,
    /// Light transmittance ratio of the setup (the polariser's ½ included for the double MLA).
    pub ltr: f64,
    /// Full field of view of the setup (eq. 4.13), in degrees.
    pub fov_deg: f64,
    /// Columns the scores are taken on (the field of view).
    pub valid: Range<usize>,
    /// The mean square of the photo's content at the horizontal frequencies the setup passes
    /// < 1 % of ([`unpassed_mse`](crate::core::phase::imaging::unpassed_mse)); 0 when it passes
    /// them all.
    pub unpassed_mse: f64,
    /// The capture, the denoised capture, the restoration and their PSNR and SSIM.
    pub run: RestoreRun,
    textures: RowTextures,
}

/// The pictures of one setup's row, uploaded.
pub(super) struct RowTextures {
    pub(super) captured: TextureHandle,
    /// `None` when no denoiser ran.
    pub(super) denoised: Option<TextureHandle>,
    pub(super) restored: TextureHandle,
    pub(super) difference: TextureHandle,
}

/// The pictures of one setup's row, made on the worker thread.
struct RowImages {
    captured: ColorImage,
    denoised: Option<ColorImage>,
    restored: ColorImage,
    difference: ColorImage,
}

/// One setup's result as the worker returns it, pictures not yet uploaded.
struct Finished {
    label: String,
    key: OperatorKey,
    blur: Arc<PhaseBlur>,
    built: bool,
    fov_deg: f64,
    unpassed_mse: f64,
    run: RestoreRun,
    images: RowImages,
}

/// The step under way: what it is and when it started (for the time left).
type Step = Arc<Mutex<(String, Instant)>>;

/// A capture in flight for its settings: each setup's result arrives as soon as it is ready (its
/// index among the rows, the result).
type CaptureJob = Streaming<RunKey, (usize, Finished)>;

pub(super) struct CaptureState {
    native_dialogs: bool,
    photo: Option<Arc<Photo>>,
    photo_id: u64,
    photo_texture: Option<TextureHandle>,
    photo_load: Option<Job<Photo>>,
    dialog: Option<PendingDialog>,
    /// Photons on an open display aperture per pixel of value 1.
    pub(super) photons: f64,
    /// The channels of the capture: the thesis's spectral response by default, as the CLI.
    pub(super) channels: ChannelSet,
    pub(super) seed: u64,
    /// The denoiser before the solver: the thesis's chapter 4 by default.
    pub(super) denoise: Denoise,
    operators: Vec<(OperatorKey, Arc<PhaseBlur>)>,
    operators_built: usize,
    job: Option<CaptureJob>,
    /// The running capture's step.
    step: Step,
    done_key: Option<RunKey>,
    rows: Vec<CaptureRow>,
    message: Option<Notice>,
}

impl CaptureState {
    pub fn new(native_dialogs: bool) -> Self {
        CaptureState {
            native_dialogs,
            photo: None,
            photo_id: 0,
            photo_texture: None,
            photo_load: None,
            dialog: None,
            photons: 1600.0,
            channels: ChannelSet::Spectral,
            seed: 0,
            denoise: thesis_denoise(),
            operators: Vec::new(),
            operators_built: 0,
            job: None,
            step: Arc::new(Mutex::new((String::new(), Instant::now()))),
            done_key: None,
            rows: Vec::new(),
            message: None,
        }
    }
}

impl CaptureState {
    pub(super) fn photo_arc(&self) -> Option<Arc<Photo>> {
        self.photo.clone()
    }

    /// The results on screen: this design first, then the bare T-OLED.
    pub fn rows(&self) -> &[CaptureRow] {
        &self.rows
    }

    /// The latest message of the view, and whether it is an error.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Name of the photo the view captures, once one is loaded.
    pub fn photo_name(&self) -> Option<&str> {
        self.photo.as_ref().map(|p| p.name.as_str())
    }

    /// The light, channels, seed and denoiser of the next run.
    pub fn choices(&self) -> CaptureChoices {
        CaptureChoices {
            photons: self.photons,
            channels: self.channels,
            seed: self.seed,
            denoise: self.denoise,
        }
    }

    /// The step under way, its fraction and the seconds it has run, while a capture runs.
    pub(in crate::app::phase) fn progress(&self) -> Option<(String, f32, f64)> {
        self.job.as_ref().map(|j| {
            let (step, since) = self
                .step
                .lock()
                .map(|s| (s.0.clone(), s.1.elapsed().as_secs_f64()))
                .unwrap_or_default();
            (step, j.job().fraction(), since)
        })
    }

    pub(in crate::app::phase) fn photo_texture(&self) -> Option<&TextureHandle> {
        self.photo_texture.as_ref()
    }
}

/// The captured, denoised, restored and |restored − truth| pictures of a run.
fn run_images(run: &RestoreRun, truth: &[Array2<f64>]) -> RowImages {
    fn refs(v: &[Array2<f64>]) -> Vec<&Array2<f64>> {
        v.iter().collect()
    }
    let diff: Vec<Array2<f64>> = run
        .restored
        .iter()
        .zip(truth)
        .map(|(r, t)| (r - t).mapv(f64::abs))
        .collect();
    RowImages {
        captured: color_image(&refs(&run.captured), 1.0),
        denoised: (!run.denoised.is_empty()).then(|| color_image(&refs(&run.denoised), 1.0)),
        restored: color_image(&refs(&run.restored), 1.0),
        difference: color_image(&refs(&diff), photo::DIFFERENCE_GAIN),
    }
}

/// The name of a setup in the view.
fn setup_label(optics: PhaseOptics, design: &PhaseDesign) -> String {
    match optics {
        PhaseOptics::DoubleMla => format!("this design: double MLA, T = {}", design.fold),
        PhaseOptics::SingleMask => format!("this design: single mask, T = {}", design.fold),
        PhaseOptics::Toled => format!("bare T-OLED, pitch {} µm", design.pitch_um),
    }
}

impl PhaseWorkspace {
    /// The results on screen: this design first, then the bare T-OLED.
    pub fn capture_rows(&self) -> &[CaptureRow] {
        self.capture.rows()
    }

    /// True while a photo loads or a capture runs.
    pub fn is_capturing(&self) -> bool {
        self.capture.job.is_some() || self.capture.photo_load.is_some()
    }

    /// Whether the rows on screen are of the current design, photo and settings.
    pub fn capture_is_current(&self) -> bool {
        self.capture.job.is_none()
            && self.capture.done_key.is_some()
            && self.capture.done_key == self.capture_key()
    }

    /// The latest message of the view, and whether it is an error.
    pub fn capture_message(&self) -> Option<&Notice> {
        self.capture.message()
    }

    /// Name of the photo the view captures, once one is loaded.
    pub fn capture_photo_name(&self) -> Option<&str> {
        self.capture.photo_name()
    }

    /// How many operators were built since the workspace opened (a cached one is not counted).
    pub fn capture_operators_built(&self) -> usize {
        self.capture.operators_built
    }

    /// Light level: photons an open display aperture would pass to a white pixel.
    pub fn capture_photons(&self) -> f64 {
        self.capture.photons
    }

    /// The denoiser before the solver.
    pub fn capture_denoise(&self) -> Denoise {
        self.capture.denoise
    }

    /// The light, channels, seed and denoiser of the captures and the comparison.
    pub fn capture_choices(&self) -> CaptureChoices {
        self.capture.choices()
    }

    /// Sets the light, channels, seed and denoiser ([`super::PhaseAction::Capture`]).
    pub(in crate::app::phase) fn set_capture_choices(&mut self, c: CaptureChoices) {
        self.capture.photons = c.photons;
        self.capture.channels = c.channels;
        self.capture.seed = c.seed;
        self.capture.denoise = c.denoise;
    }

    /// Loads a photo on a background thread, scaled to the sensor's width at most; a photo
    /// that cannot be read leaves the current one in place.
    pub fn load_capture_photo(&mut self, path: PathBuf, ctx: &egui::Context) {
        let wake = ctx.clone();
        let max_side = u32::try_from(self.history.current().camera.pixels).unwrap_or(u32::MAX);
        self.capture.photo_load = Some(Job::spawn(
            "photo reader",
            move || wake.request_repaint(),
            move |_| {
                let planes = photo::load_photo(&path, Some(max_side))?;
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                Ok::<_, crate::io::IoError>(Photo { name, planes })
            },
        ));
    }

    /// Goes back to the built-in photo.
    pub fn use_built_in_capture_photo(&mut self) {
        self.capture.photo = None;
        self.capture.photo_load = None;
    }

    /// Stops the running capture; the last pictures stay.
    pub fn cancel_capture(&mut self) {
        if let Some(j) = self.capture.job.take() {
            self.capture.message = Some(Notice::info("capture cancelled; the last result stays"));
            // The same settings would start it again at once: wait for a change.
            self.capture.done_key = Some(j.stop().0);
        }
    }

    pub(super) fn ask_capture_photo(&mut self) {
        if !self.capture.native_dialogs {
            self.capture.message = Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        if self.capture.dialog.is_none() {
            self.capture.dialog = Some(PendingDialog::spawn(Purpose::Photo, None, None));
        }
    }

    fn set_capture_photo(&mut self, p: Photo, ctx: &egui::Context) {
        let planes: Vec<&Array2<f64>> = p.planes.iter().collect();
        self.capture.photo_texture = Some(ctx.load_texture(
            "phase-capture-truth",
            color_image(&planes, 1.0),
            TextureOptions::LINEAR,
        ));
        self.capture.photo = Some(Arc::new(p));
        self.capture.photo_id += 1;
    }

    /// The two setups of a run: this design through its optics, the bare T-OLED of its pitch.
    fn capture_setups(&self) -> Result<Vec<(PhaseDesign, PhaseOptics)>, SimError> {
        self.history.current().validate()?;
        let bare = Setup::Bare {
            pitch_um: self.history.current().pitch_um,
        }
        .resolve(
            self.history.current(),
            &crate::core::phase::PhaseSampling::for_quality(self.quality),
            &[],
            // The bare T-OLED has no plan to optimize: nothing to relay.
            None,
            &Progress::new(),
        )?;
        Ok(vec![(self.history.current().clone(), self.optics()), bare])
    }

    fn capture_key(&self) -> Option<RunKey> {
        let photo = self.capture.photo.as_ref()?;
        let width = photo.planes.first().map_or(0, Array2::ncols);
        let setups = self.capture_setups().ok()?;
        Some(RunKey {
            operators: setups
                .into_iter()
                .map(|(design, optics)| OperatorKey {
                    design,
                    optics,
                    quality: self.quality,
                    channels: self.capture.channels,
                    width,
                })
                .collect(),
            photo: self.capture.photo_id,
            photons_bits: self.capture.photons.to_bits(),
            seed: self.capture.seed,
            denoise: self.capture.denoise,
        })
    }

    /// Takes a loaded photo, an answered dialog and a finished run (every frame).
    pub(super) fn poll_capture(&mut self, ctx: &egui::Context) {
        if let Some(answer) = self.capture.dialog.as_ref().and_then(PendingDialog::poll) {
            self.capture.dialog = None;
            match answer {
                Ok(Some(path)) => self.load_capture_photo(path, ctx),
                Ok(None) => {}
                Err(e) => self.capture.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(done) = self.capture.photo_load.as_ref().and_then(Job::poll) {
            self.capture.photo_load = None;
            match done {
                Ok(p) => {
                    self.capture.message = None;
                    self.set_capture_photo(p, ctx);
                }
                // The previous photo stays.
                Err(e) => {
                    self.capture.message =
                        Some(Notice::error(format!("cannot open the photo: {e}")));
                }
            }
        }
        let Some(job) = &self.capture.job else {
            return;
        };
        // Twice a second is enough for a progress bar and leaves the cores to the job.
        ctx.request_repaint_after(std::time::Duration::from_millis(500));
        let arrived = job.arrived();
        for (i, f) in arrived {
            self.show_finished(i, f, ctx);
        }
        let Some(done) = self.capture.job.as_ref().and_then(Streaming::ended) else {
            return;
        };
        let Some(job) = self.capture.job.take() else {
            return;
        };
        let late = job.arrived();
        for (i, f) in late {
            self.show_finished(i, f, ctx);
        }
        match done {
            Ok(()) => {
                let seconds = job.job().elapsed().as_secs_f64();
                self.capture.message = Some(Notice::info(format!(
                    "captured and restored in {seconds:.1} s"
                )));
                self.capture.done_key = Some(job.key().clone());
            }
            Err(JobError::Cancelled) => {}
            // Not retried until a setting changes.
            Err(e) => {
                self.capture.message = Some(Notice::error(e.to_string()));
                self.capture.done_key = Some(job.key().clone());
            }
        }
    }

    /// Uploads one setup's pictures and puts its row in place `i`; keeps a new operator.
    fn show_finished(&mut self, i: usize, f: Finished, ctx: &egui::Context) {
        if f.built {
            self.capture.operators_built += 1;
            self.capture.operators.retain(|(k, _)| *k != f.key);
            self.capture.operators.push((f.key.clone(), f.blur.clone()));
            let excess = self.capture.operators.len().saturating_sub(KEPT_OPERATORS);
            self.capture.operators.drain(..excess);
        }
        let RowImages {
            captured,
            denoised,
            restored,
            difference,
        } = f.images;
        let tex = |name: &str, img: ColorImage| {
            ctx.load_texture(
                format!("phase-capture-{i}-{name}"),
                img,
                TextureOptions::LINEAR,
            )
        };
        let row = CaptureRow {
            label: f.label,
            optics: f.key.optics,
            ltr: f.blur.ltr,
            fov_deg: f.fov_deg,
            valid: f.blur.valid.clone(),
            unpassed_mse: f.unpassed_mse,
            run: f.run,
            textures: RowTextures {
                captured: tex("captured", captured),
                denoised: denoised.map(|d| tex("denoised", d)),
                restored: tex("restored", restored),
                difference: tex("difference", difference),
            },
        };
        let rows = &mut self.capture.rows;
        if i < rows.len() {
            rows[i] = row;
        } else {
            rows.push(row);
        }
    }

    /// Starts a run when the view is shown and its inputs changed (not while a slider is held).
    pub(super) fn capture_tick(&mut self, ctx: &egui::Context) {
        if self.capture.photo.is_none() && self.capture.photo_load.is_none() {
            match built_in() {
                Ok(mut p) => {
                    p.planes = photo::fit_max_side(p.planes, self.history.current().camera.pixels);
                    self.set_capture_photo(p, ctx);
                }
                Err(e) => {
                    self.capture.message = Some(Notice::error(format!("the built-in photo: {e}")));
                    return;
                }
            }
        }
        if ctx.input(|i| i.pointer.any_down()) {
            return;
        }
        let key = match self.capture_setups() {
            Ok(_) => self.capture_key(),
            Err(e) => {
                if self.capture.job.is_none()
                    && !self.capture.message.as_ref().is_some_and(Notice::is_error)
                {
                    self.capture.message = Some(Notice::error(format!("cannot capture: {e}")));
                }
                return;
            }
        };
        let Some(key) = key else {
            return;
        };
        let running = self.capture.job.as_ref().map(Streaming::key);
        if self.capture.done_key.as_ref() == Some(&key) || running == Some(&key) {
            return;
        }
        self.start_capture(key, ctx);
    }

    fn start_capture(&mut self, key: RunKey, ctx: &egui::Context) {
        let Some(photo) = self.capture.photo.clone() else {
            return;
        };
        let cached = |this: &Self, k: &OperatorKey| {
            this.capture
                .operators
                .iter()
                .find(|(c, _)| c == k)
                .map(|(_, b)| b.clone())
        };
        // A spectral operator through the whole display (a λ0 plan) takes ~10× the peaks' time:
        // when one must be built, a quick look through the peak wavelengths comes first (as the
        // PSFs' preview, then full). Through the lenslet period a photo up to
        // SPECTRAL_WITHOUT_QUICK_LOOK columns wide is itself quick.
        let mut passes = vec![self.capture.channels];
        let quick = |k: &OperatorKey| {
            let sampling = PhaseSampling::for_quality(k.quality);
            k.width <= SPECTRAL_WITHOUT_QUICK_LOOK
                && sampling.relay_for(&k.design, k.optics) == Relay::LensletPeriod
        };
        let building = key
            .operators
            .iter()
            .any(|k| cached(self, k).is_none() && !quick(k));
        if building && self.capture.channels != ChannelSet::Peaks {
            passes.insert(0, ChannelSet::Peaks);
        }
        let mut jobs = Vec::new();
        for set in passes {
            let channels = match self.channel_list(set) {
                Ok(c) => Arc::new(c),
                Err(e) => {
                    self.capture.message =
                        Some(Notice::error(format!("cannot make the channels: {e}")));
                    self.capture.done_key = Some(key);
                    return;
                }
            };
            for (row, k) in key.operators.iter().enumerate() {
                let mut k = k.clone();
                k.channels = set;
                let blur = cached(self, &k);
                jobs.push(SetupJob {
                    row,
                    key: k,
                    blur,
                    channels: channels.clone(),
                });
            }
        }
        // Dropping the running job cancels it.
        self.capture.job = None;
        let (photons, seed, denoise) = (
            self.capture.photons,
            self.capture.seed,
            self.capture.denoise,
        );
        let relay = self.relay();
        let step: Step = Arc::new(Mutex::new((String::new(), Instant::now())));
        let (s, wake) = (step.clone(), ctx.clone());
        let job = Streaming::spawn(
            "capture job",
            key,
            move || wake.request_repaint(),
            move |p, tx| {
                let light = Light {
                    photons,
                    seed,
                    denoise,
                    relay,
                };
                run_setups(&jobs, &photo.planes, &light, p, &s, tx)
            },
        );
        self.capture.job = Some(job);
        self.capture.step = step;
    }
}

impl CaptureRow {
    pub(super) fn textures(&self) -> &RowTextures {
        &self.textures
    }
}
