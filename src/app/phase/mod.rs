//! The phase-mask workspace (thesis chapter 4): two microlens arrays around a T-OLED, folded into
//! thin plates with a folding wavelength λ0 per lenslet. Every parameter is live: a change runs
//! the channel PSFs at preview sampling at once, then at the thesis sampling, on a background
//! thread (a newer change cancels the running job and stale results are dropped). The V matrix
//! and the λ0 optimizer run on request, with progress and Cancel. The UI thread only draws.
//!
//! The parameters have their own undo history (Ctrl+Z / Ctrl+Shift+Z while the workspace is
//! shown) and are kept between runs in `phase-design.json` beside the studio's autosave.

mod capture;
mod capture_view;
mod compare;
mod export;
mod kernels;
mod optimizer;
mod optimizer_view;
mod panels;
mod persist;
mod plate_rules;
mod response;
mod views;
mod workspace;

use crate::app::notice::Notice;
pub use crate::core::Quality;
use std::sync::Arc;
use std::time::{Duration, Instant};

use egui::Color32;

pub use capture::CaptureRow;
pub use compare::CompareRun;
pub use export::HeightFormat;
pub use kernels::ShownKernels;
pub use optimizer::{OptimizerResult, ShownV};
pub use response::CustomResponse;

use crate::app::autosave::Autosave;
use crate::app::history::{History, Snapshot};
use crate::app::job::{Job, JobError, Keyed};
use crate::app::settings::AppDirs;
use crate::core::SimError;
use crate::core::design::Channel;
use crate::core::phase::geometry::lenslet_count;
use crate::core::phase::{
    Allocation, Incidence, PhaseDesign, PhaseOptics, PhasePsfs, PhaseSampling, VMatrix, phase_psfs,
    wavelength_grid_nm,
};
use crate::io::spectral;
use optimizer::LongJob;

/// Where the workspace keeps its design, inside the studio's data directory.
pub const DESIGN_FILE: &str = "phase-design.json";

/// The colour channels the PSFs and the optimizer use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChannelSet {
    /// R 610, G 530, B 470 nm.
    Peaks,
    /// The thesis's sensor response sampled on the 401:10:691 nm grid.
    Spectral,
    /// A response CSV the user opened (the number tells one load from the next), on the grid.
    Custom(u32),
}

impl ChannelSet {
    /// Name shown in the channel picker.
    pub fn label(self) -> &'static str {
        match self {
            ChannelSet::Peaks => "peaks (R 610, G 530, B 470 nm)",
            ChannelSet::Spectral => "spectral (thesis response, 401-691 nm)",
            ChannelSet::Custom(_) => "custom response",
        }
    }
}

/// Which picture the centre shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseView {
    /// The channel PSFs at the chosen incidence angle beside the bare T-OLED's, with their MTFs
    /// and the blur matrix of all directions.
    Psf,
    /// The folded plate's height profile around a chosen lenslet, and every lenslet's λ0.
    Geometry,
    /// The V matrix and the λ0 optimizer's allocation.
    Optimizer,
    /// Photos captured through the design and restored (§4.5), and the setup comparison.
    Capture,
}

/// PSFs on screen, with what they were computed for.
pub struct ShownPsfs {
    /// Generation of the parameters they were computed for (older than the newest: stale).
    pub generation: u64,
    /// Preview or thesis sampling.
    pub quality: Quality,
    /// The design they were computed for.
    pub design: PhaseDesign,
    /// The optical chain: double MLA, or the single mask of Lemma 1.
    pub optics: PhaseOptics,
    /// The colour channels they were computed for.
    pub channels: ChannelSet,
    /// The channel PSFs through the design and through the bare T-OLED, with their MTFs.
    pub psfs: Arc<PhasePsfs>,
    /// How long the computation took, in milliseconds.
    pub elapsed_ms: f64,
}

/// What a PSF run was started for.
struct PsfKey {
    generation: u64,
    quality: Quality,
    design: PhaseDesign,
    optics: PhaseOptics,
    channels: ChannelSet,
}

/// What the newest generation was started for (compared in place with the controls each frame).
struct Submitted {
    design: PhaseDesign,
    channels: ChannelSet,
    single_mask: bool,
    angle_deg: f64,
    target: Quality,
}

/// The workspace's state.
pub struct PhaseWorkspace {
    history: History<PhaseDesign>,
    /// Preview only, or preview then the thesis sampling (also the V matrix's and optimizer's).
    pub quality: Quality,
    /// The colour channels the PSFs and the optimizer use.
    pub channels: ChannelSet,
    /// Lemma 1's comparison: one plate at the display, no second MLA.
    pub single_mask: bool,
    /// Incidence angle of the PSFs, in degrees.
    pub angle_deg: f64,
    /// Plot the PSFs on a log10 scale instead of a linear one.
    pub log_psf: bool,
    /// Half width of the PSF plots, in sensor pixels either side of the image point.
    pub psf_half_width_px: usize,
    /// The picture the centre shows.
    pub view: PhaseView,
    /// Keep f_MLA equal to the pitch when the pitch is edited (the thesis's choice).
    pub link_focal: bool,
    selected_lenslet: usize,
    spectral: Option<Result<Vec<Channel>, String>>,
    submitted: Option<Submitted>,
    generation: u64,
    /// The PSFs of the newest parameters and the milliseconds they took.
    job: Keyed<PsfKey, (PhasePsfs, f64)>,
    shown: Option<ShownPsfs>,
    message: Option<Notice>,
    v_job: Option<LongJob<VMatrix>>,
    v: Option<ShownV>,
    opt_job: Option<LongJob<(VMatrix, Allocation)>>,
    optimized: Option<OptimizerResult>,
    opt_message: Option<Notice>,
    /// `phase-design.json`, written a few seconds after a change.
    autosave: Autosave<PhaseDesign>,
    autosave_every: Duration,
    export: export::ExportState,
    response: response::ResponseState,
    kernels: kernels::KernelState,
    capture: capture::CaptureState,
    compare: compare::CompareState,
}

impl Snapshot for PhaseDesign {
    /// Equal designs, NaN included (a NaN field must not look like a change every frame).
    fn same(&self, other: &Self) -> bool {
        self == other || format!("{self:?}") == format!("{other:?}")
    }
}

/// Colour of a wavelength, blue at 400 nm through green to red at 700 nm (thesis Fig. 4.4).
pub fn wavelength_color(nm: f64) -> Color32 {
    let t = ((nm - 400.0) / 300.0).clamp(0.0, 1.0) as f32;
    egui::ecolor::Hsva::new(2.0 / 3.0 * (1.0 - t), 0.9, 1.0, 1.0).into()
}

impl PhaseWorkspace {
    /// The workspace with the design kept in `dirs` (or the thesis's 600-DPI design).
    pub fn new(dirs: &AppDirs, native_dialogs: bool, autosave_every: Duration) -> Self {
        let design_path = dirs.data_dir.as_ref().map(|d| d.join(DESIGN_FILE));
        let (design, message) = persist::load_design(design_path.as_deref());
        PhaseWorkspace {
            // The profile starts at the lenslet beside the axis.
            selected_lenslet: lenslet_count(&design) / 2,
            autosave: Autosave::new(design_path, Some(design.clone()), persist::write_design),
            history: History::new(design),
            quality: Quality::Full,
            channels: ChannelSet::Peaks,
            single_mask: false,
            angle_deg: 0.0,
            log_psf: false,
            psf_half_width_px: 24,
            view: PhaseView::Psf,
            link_focal: true,
            spectral: None,
            submitted: None,
            generation: 0,
            job: Keyed::idle(),
            shown: None,
            message,
            v_job: None,
            v: None,
            opt_job: None,
            optimized: None,
            opt_message: None,
            autosave_every,
            export: export::ExportState::new(native_dialogs),
            response: response::ResponseState::new(native_dialogs),
            kernels: kernels::KernelState::new(native_dialogs),
            capture: capture::CaptureState::new(native_dialogs),
            compare: compare::CompareState::new(native_dialogs),
        }
    }

    /// The design being edited.
    pub fn design(&self) -> &PhaseDesign {
        self.history.current()
    }

    /// Edits the design as the controls do: the change runs at once and becomes one undo step
    /// when no pointer button is held and no text field has focus.
    pub fn design_mut(&mut self) -> &mut PhaseDesign {
        self.history.current_mut()
    }

    /// Replaces the design as one undo step.
    pub fn set_design(&mut self, design: PhaseDesign) {
        self.history.edit(design);
    }

    /// The PSFs on screen, if any.
    pub fn shown(&self) -> Option<&ShownPsfs> {
        self.shown.as_ref()
    }

    /// True once the PSFs of the newest parameters are on screen at the chosen quality.
    pub fn is_up_to_date(&self) -> bool {
        !self.job.is_running()
            && self
                .shown
                .as_ref()
                .is_some_and(|s| s.generation == self.generation && s.quality == self.quality)
    }

    /// The latest message about the design or its PSFs, and whether it is an error.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// The latest message of the V matrix or the optimizer.
    pub fn optimizer_message(&self) -> Option<&Notice> {
        self.opt_message.as_ref()
    }

    /// The latest message of an export.
    pub fn export_message(&self) -> Option<&Notice> {
        self.export.message()
    }

    /// The computed V matrix on screen, if any.
    pub fn v(&self) -> Option<&ShownV> {
        self.v.as_ref()
    }

    /// The optimizer's last result, if any.
    pub fn optimized(&self) -> Option<&OptimizerResult> {
        self.optimized.as_ref()
    }

    /// Whether the λ0 optimizer is running.
    pub fn is_optimizing(&self) -> bool {
        self.opt_job.is_some()
    }

    /// Whether the V matrix is being computed.
    pub fn is_computing_v(&self) -> bool {
        self.v_job.is_some()
    }

    /// Whether a height-profile export is being written.
    pub fn is_exporting(&self) -> bool {
        self.export.is_running()
    }

    /// Whether there is a change to undo, including an edit not yet committed.
    pub fn can_undo(&self) -> bool {
        self.history.can_undo()
    }

    /// Whether there is an undone change to redo.
    pub fn can_redo(&self) -> bool {
        self.history.can_redo()
    }

    /// Steps back one parameter change.
    pub fn undo(&mut self) -> bool {
        self.history.undo()
    }

    /// Redoes one undone change.
    pub fn redo(&mut self) -> bool {
        self.history.redo()
    }

    /// The channels of the chosen set (the spectral ones are made once).
    fn channel_list(&mut self, set: ChannelSet) -> Result<Vec<Channel>, String> {
        match set {
            ChannelSet::Peaks => Ok(Channel::rgb_peaks()),
            ChannelSet::Spectral => self
                .spectral
                .get_or_insert_with(|| {
                    spectral::channels_from_response(
                        &spectral::thesis_response(),
                        &wavelength_grid_nm(),
                    )
                })
                .clone(),
            ChannelSet::Custom(serial) => self.response.channels(serial),
        }
    }

    fn optics(&self) -> PhaseOptics {
        if self.single_mask {
            PhaseOptics::SingleMask
        } else {
            PhaseOptics::DoubleMla
        }
    }

    /// Takes finished jobs, commits idle edits, saves, and starts the runs the controls call for.
    pub fn poll(&mut self, ctx: &egui::Context) {
        self.export.poll(ctx);
        self.take_psfs(ctx);
        self.take_long_jobs(ctx);
        self.poll_response(ctx);
        self.poll_kernels(ctx);
        self.poll_capture(ctx);
        self.poll_compare(ctx);
        let idle = !ctx.input(|i| i.pointer.any_down()) && !ctx.egui_wants_keyboard_input();
        if idle {
            self.history.commit();
        }
        self.autosave_tick(ctx);
        if self.job.is_running()
            || self.v_job.is_some()
            || self.opt_job.is_some()
            || self.is_computing_kernels()
        {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        let unchanged = self.submitted.as_ref().is_some_and(|s| {
            s.design.same(self.history.current())
                && s.channels == self.channels
                && s.single_mask == self.single_mask
                && s.angle_deg.to_bits() == self.angle_deg.to_bits()
                && s.target == self.quality
        });
        if unchanged {
            return;
        }
        self.submitted = Some(Submitted {
            design: self.history.current().clone(),
            channels: self.channels,
            single_mask: self.single_mask,
            angle_deg: self.angle_deg,
            target: self.quality,
        });
        // Whatever happens next, results of older parameters are stale.
        self.generation += 1;
        // Dropping the running job cancels it.
        self.job.stop();
        if let Err(e) = self.history.current().validate() {
            self.message = Some(Notice::error(e.to_string()));
            return;
        }
        if !(self.angle_deg.is_finite() && self.angle_deg.abs() <= 80.0) {
            self.message = Some(Notice::error(format!(
                "the angle {} ° is outside -80 to 80 °",
                self.angle_deg
            )));
            return;
        }
        if self.message.as_ref().is_some_and(Notice::is_error) {
            self.message = None;
        }
        self.start(Quality::Preview, ctx);
    }

    fn start(&mut self, quality: Quality, ctx: &egui::Context) {
        let Some(sub) = &self.submitted else {
            return;
        };
        let design = sub.design.clone();
        let set = sub.channels;
        let angle = sub.angle_deg;
        let channels = match self.channel_list(set) {
            Ok(c) => c,
            Err(e) => {
                self.message = Some(Notice::error(format!("cannot make the channels: {e}")));
                return;
            }
        };
        self.job.stop();
        let optics = self.optics();
        let wake = ctx.clone();
        let d = design.clone();
        let job = Job::spawn(
            "PSF job",
            move || wake.request_repaint(),
            move |p| {
                let t0 = Instant::now();
                let sampling = PhaseSampling::for_quality(quality);
                let r = phase_psfs(
                    &d,
                    &sampling,
                    &channels,
                    optics,
                    Incidence::AngleDeg(angle),
                    p,
                )?;
                Ok::<_, SimError>((r, t0.elapsed().as_secs_f64() * 1e3))
            },
        );
        self.job.start(
            PsfKey {
                generation: self.generation,
                quality,
                design,
                optics,
                channels: set,
            },
            job,
        );
    }

    /// Cancels the running PSF job; the last result stays.
    pub fn cancel_psfs(&mut self) {
        if self.job.is_running() {
            self.job.stop();
            self.message = Some(Notice::info("PSF run cancelled; the last result stays"));
        }
    }

    fn take_psfs(&mut self, ctx: &egui::Context) {
        let Some((job, done)) = self.job.poll() else {
            return;
        };
        match done {
            Ok((psfs, ms)) if job.generation == self.generation => {
                self.shown = Some(ShownPsfs {
                    generation: job.generation,
                    quality: job.quality,
                    design: job.design,
                    optics: job.optics,
                    channels: job.channels,
                    psfs: Arc::new(psfs),
                    elapsed_ms: ms,
                });
                if self.message.as_ref().is_some_and(Notice::is_error) {
                    self.message = None;
                }
                if job.quality == Quality::Preview && self.quality == Quality::Full {
                    self.start(Quality::Full, ctx);
                }
            }
            Ok(_) | Err(JobError::Cancelled) => {}
            Err(e) => self.message = Some(Notice::error(e.to_string())),
        }
    }
}
