//! The phase-mask workspace (thesis chapter 4): two microlens arrays around a T-OLED, folded into
//! thin plates with a folding wavelength λ0 per lenslet. Every parameter is live: a change runs
//! the channel PSFs at preview sampling at once, then at the thesis sampling, on a background
//! thread (a newer change cancels the running job and stale results are dropped). The V matrix
//! and the λ0 optimizer run on request, with progress and Cancel. The UI thread only draws.
//!
//! The parameters have their own undo history (Ctrl+Z / Ctrl+Shift+Z while the workspace is
//! shown) and are kept between runs in `phase-design.json` beside the studio's autosave.

mod action;
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
mod psf;
mod response;
mod swatches;
mod views;
mod workspace;

use crate::app::notice::Notice;
pub use crate::core::Quality;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use egui::Color32;

pub use action::{CaptureChoices, PhaseAction, PhaseChoices};
pub use capture::CaptureRow;
pub use compare::{CompareRun, CompareState};
pub use export::HeightFormat;
pub use kernels::ShownKernels;
pub use optimizer::{OptimizerResult, ShownV};
pub use psf::ShownPsfs;
pub use response::CustomResponse;

use crate::app::autosave::Autosave;
use crate::app::error::StudioError;
use crate::app::history::{History, Snapshot};
use crate::app::settings::AppDirs;
use crate::core::design::Channel;
use crate::core::phase::geometry::lenslet_count;
use crate::core::phase::{PhaseDesign, PhaseOptics, wavelength_grid_nm};
use crate::io::design::spectral;
use crate::io::error::SpectralError;

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

/// The workspace's state.
pub struct PhaseWorkspace {
    history: History<PhaseDesign>,
    /// Where the operators' Bloch relays run (View ▸ Compute PSFs on), read at each job.
    route: Arc<Mutex<Arc<udc_gpu::Route>>>,
    /// Preview only, or preview then the thesis sampling (also the V matrix's and optimizer's).
    pub quality: Quality,
    /// The colour channels the PSFs and the optimizer use.
    pub channels: ChannelSet,
    /// Lemma 1's comparison: one plate at the display, no second MLA.
    pub single_mask: bool,
    /// Incidence angle of the PSFs, in degrees.
    pub angle_deg: f64,
    /// The lenslet the plate profile and the per-lenslet editor show.
    selected_lenslet: usize,
    /// The thesis response's channels on the grid, made the first time they are asked for.
    spectral: Option<Result<Vec<Channel>, SpectralError>>,
    /// The message line of the design and its PSFs (a refused value, a failed run or
    /// autosave).
    message: Option<Notice>,
    psf: psf::PsfState,
    optimizer: optimizer::OptimizerState,
    /// `phase-design.json`, written a few seconds after a change.
    autosave: Autosave<PhaseDesign>,
    autosave_every: Duration,
    export: export::ExportState,
    response: response::ResponseState,
    kernels: kernels::KernelState,
    capture: capture::CaptureState,
    compare: compare::CompareState,
    /// What the panels queued this frame, carried out after the UI ([`PhaseWorkspace::act`]).
    actions: Vec<PhaseAction>,
    panels: panels::Panels,
    /// The UI's context, kept from the last frame: the jobs an action starts wake it.
    egui_ctx: egui::Context,
    /// What the panels read about the jobs' results, worked out once a frame in `poll`
    /// (three panels draw from it; the capture's key resolves a setup).
    facts: Facts,
    /// Study > New study… was chosen: sent to the Sweep workspace in `apply`.
    study_asked: bool,
}

/// Derived flags the panels read, worked out once a frame.
#[derive(Default, Clone, Copy)]
struct Facts {
    can_apply: bool,
    kernels_stale: bool,
    capture_current: bool,
}

/// What a panel may look at, and where it sends what it wants done. The design and the run
/// choices are read-only: a panel edits a copy and queues it ([`PhaseAction::Live`],
/// [`PhaseAction::Choose`]). The comparison's and the export's selections (which setups,
/// which light levels, the export's sampling) are lent: they say what a job will run, are not
/// part of the design and have no undo.
pub struct PhaseCtx<'a> {
    /// The design being edited.
    pub design: &'a PhaseDesign,
    /// How the PSFs and the long jobs run.
    pub choices: PhaseChoices,
    /// There is a change to undo / to redo.
    pub can_undo: bool,
    /// There is an undone change to redo.
    pub can_redo: bool,
    /// The optimizer's allocation still fits the design.
    pub can_apply: bool,
    /// The lenslet the profile and the per-lenslet editor show.
    pub selected_lenslet: usize,
    /// The message line of the design and its PSFs.
    pub message: Option<&'a Notice>,
    psf: &'a psf::PsfState,
    optimizer: &'a optimizer::OptimizerState,
    response: &'a response::ResponseState,
    kernels: &'a kernels::KernelState,
    kernels_stale: bool,
    capture: &'a capture::CaptureState,
    capture_current: bool,
    export: &'a mut export::ExportState,
    compare: &'a mut compare::CompareState,
    /// Where the panel queues what it wants done; carried out after the frame's UI.
    pub actions: &'a mut Vec<PhaseAction>,
}

impl PhaseCtx<'_> {
    /// Queues `action`.
    pub fn queue(&mut self, action: PhaseAction) {
        self.actions.push(action);
    }

    /// The design to draw geometry from: the current one if valid, else the shown PSFs'.
    pub(super) fn drawable(&self) -> Option<PhaseDesign> {
        if self.design.validate().is_ok() {
            Some(self.design.clone())
        } else {
            self.psf.shown.as_ref().map(|s| s.design.clone())
        }
    }
}

impl Snapshot for PhaseDesign {
    /// Equal designs, NaN included (a NaN field must not look like a change every frame).
    fn same(&self, other: &Self) -> bool {
        self == other || format!("{self:?}") == format!("{other:?}")
    }
}

/// Colour of a wavelength, blue at 400 nm through green to red at 700 nm (thesis Fig. 4.4;
/// the figure palette's).
pub fn wavelength_color(nm: f64) -> Color32 {
    crate::app::widgets::figure::color32(crate::core::figure::palette::wavelength(nm))
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
            spectral: None,
            message,
            psf: psf::PsfState::default(),
            optimizer: optimizer::OptimizerState::default(),
            autosave_every,
            export: export::ExportState::new(native_dialogs),
            response: response::ResponseState::new(native_dialogs),
            kernels: kernels::KernelState::new(native_dialogs),
            capture: capture::CaptureState::new(native_dialogs),
            compare: compare::CompareState::new(native_dialogs),
            actions: Vec::new(),
            panels: panels::Panels::default(),
            egui_ctx: egui::Context::default(),
            facts: Facts::default(),
            study_asked: false,
            route: Arc::new(Mutex::new(Arc::new(udc_gpu::Route::cpu()))),
        }
    }

    /// The workspace with its operators' propagations on `route` (the studio's View ▸ Compute
    /// PSFs on), read at the start of each capture or comparison.
    #[must_use]
    pub fn with_route(self, route: Arc<Mutex<Arc<udc_gpu::Route>>>) -> Self {
        PhaseWorkspace { route, ..self }
    }

    /// The GPU the operators' propagations run on now (View ▸ Compute PSFs on), or `None` on
    /// the CPU.
    pub fn operators_on(&self) -> Option<String> {
        self.route.lock().ok()?.adapter()
    }

    /// The Bloch relay a job hands its operators to: the route when it runs on a device, else
    /// `None` (the chain's own CPU relay).
    fn relay(&self) -> Option<Arc<dyn crate::core::phase::chain::BlochRelay>> {
        let route = self.route.lock().ok()?.clone();
        route.adapter()?;
        Some(route)
    }

    /// The run choices (quality, channels, optics, angle).
    pub fn choices(&self) -> PhaseChoices {
        PhaseChoices {
            quality: self.quality,
            channels: self.channels,
            single_mask: self.single_mask,
            angle_deg: self.angle_deg,
        }
    }

    /// The picture the centre shows.
    pub fn view(&self) -> PhaseView {
        self.panels.views.view
    }

    /// Shows `view` in the centre ([`PhaseAction::Show`]).
    pub fn show(&mut self, view: PhaseView) {
        self.act(PhaseAction::Show(view));
    }

    /// The panels and what they may look at, borrowed apart so that a panel draws from the
    /// context while it holds its own state.
    fn split(&mut self) -> (&mut panels::Panels, PhaseCtx<'_>) {
        let choices = self.choices();
        let ctx = PhaseCtx {
            design: self.history.current(),
            choices,
            can_undo: self.history.can_undo(),
            can_redo: self.history.can_redo(),
            can_apply: self.facts.can_apply,
            selected_lenslet: self.selected_lenslet,
            message: self.message.as_ref(),
            psf: &self.psf,
            optimizer: &self.optimizer,
            response: &self.response,
            kernels: &self.kernels,
            kernels_stale: self.facts.kernels_stale,
            capture: &self.capture,
            capture_current: self.facts.capture_current,
            export: &mut self.export,
            compare: &mut self.compare,
            actions: &mut self.actions,
        };
        (&mut self.panels, ctx)
    }

    /// The left panel: the design's parameters, the simulation choices and the exports.
    pub fn controls_ui(&mut self, ui: &mut egui::Ui) {
        let (panels, mut ctx) = self.split();
        panels.controls.ui(ui, &mut ctx);
    }

    /// The right panel: geometry, light and sharpness numbers.
    pub fn numbers_ui(&mut self, ui: &mut egui::Ui) {
        let (panels, mut ctx) = self.split();
        panels.numbers.ui(ui, &mut ctx);
    }

    /// The centre: PSFs, geometry, the optimizer or the captures.
    pub fn views_ui(&mut self, ui: &mut egui::Ui) {
        let (panels, mut ctx) = self.split();
        panels.views.ui(ui, &mut ctx);
    }

    /// The design being edited.
    pub fn design(&self) -> &PhaseDesign {
        self.history.current()
    }

    /// What New study… starts from: the design and, when its PSFs on screen are its own, how
    /// long they took.
    pub fn study_start(&self) -> crate::app::study_start::StudyStart {
        let mut start = crate::app::study_start::StudyStart::phase(self.design().clone());
        start.times.on_screen = self
            .shown()
            .filter(|s| s.design == *self.design())
            .map(|s| (s.elapsed_ms, s.quality));
        start
    }

    /// Opens New study… for the design (sent in the next `apply`), as the Study menu does.
    pub fn ask_study(&mut self) {
        self.study_asked = true;
    }

    /// Sends New study… to the Sweep workspace when it was asked for.
    pub(super) fn send_study(&mut self, shell: &mut crate::app::Shell) {
        if std::mem::take(&mut self.study_asked) {
            shell.send(
                crate::app::WorkspaceId::Sweep,
                crate::app::workspace::Request::NewStudy {
                    start: Box::new(self.study_start()),
                    field: None,
                },
            );
        }
    }

    /// Edits the design as a queued live edit does (for tests): the change runs at once and
    /// becomes one undo step when no pointer button is held and no text field has focus.
    pub fn design_mut(&mut self) -> &mut PhaseDesign {
        self.history.current_mut()
    }

    /// Replaces the design as one undo step ([`PhaseAction::Set`]).
    pub fn set_design(&mut self, design: PhaseDesign) {
        self.act(PhaseAction::Set(Box::new(design)));
    }

    /// Carries out one action now, as the queue does after the frame's UI.
    pub fn act(&mut self, action: PhaseAction) {
        let ctx = self.egui_ctx.clone();
        match action {
            PhaseAction::Live(design) => *self.history.current_mut() = *design,
            PhaseAction::Set(design) => {
                self.history.edit(*design);
            }
            PhaseAction::ApplyOptimized => {
                self.apply_optimized();
            }
            PhaseAction::Undo => {
                self.history.undo();
            }
            PhaseAction::Redo => {
                self.history.redo();
            }
            PhaseAction::Choose(c) => {
                self.quality = c.quality;
                self.channels = c.channels;
                self.single_mask = c.single_mask;
                self.angle_deg = c.angle_deg;
            }
            PhaseAction::SelectLenslet(i) => self.selected_lenslet = i,
            PhaseAction::Show(view) => self.panels.views.view = view,
            PhaseAction::CancelPsfs => self.cancel_psfs(),
            PhaseAction::ComputeV => self.compute_v(&ctx),
            PhaseAction::Optimize => self.run_optimizer(&ctx),
            PhaseAction::CancelOptimizer => self.cancel_long_jobs(),
            PhaseAction::KernelChannel(c) => self.set_kernel_channel(c),
            PhaseAction::ComputeKernels => self.compute_kernels(&ctx),
            PhaseAction::AskKernelFile => self.ask_kernel_file(&ctx),
            PhaseAction::CancelKernels => self.cancel_kernels(),
            PhaseAction::AskResponse => self.ask_response(&ctx),
            PhaseAction::Export(format) => self.ask_export(format, &ctx),
            PhaseAction::AskCapturePhoto => self.ask_capture_photo(),
            PhaseAction::BuiltInCapturePhoto => self.use_built_in_capture_photo(),
            PhaseAction::Capture(c) => self.set_capture_choices(c),
            PhaseAction::CancelCapture => self.cancel_capture(),
            PhaseAction::RunCompare => self.run_compare(&ctx),
            PhaseAction::AskCompareFile => self.ask_compare_file(&ctx),
            PhaseAction::CancelCompare => self.cancel_compare(),
        }
    }

    /// Carries out what the panels queued this frame.
    pub fn apply_queued(&mut self) {
        for action in std::mem::take(&mut self.actions) {
            self.act(action);
        }
    }

    /// The PSFs on screen, if any.
    pub fn shown(&self) -> Option<&ShownPsfs> {
        self.psf.shown.as_ref()
    }

    /// True once the PSFs of the newest parameters are on screen at the chosen quality.
    pub fn is_up_to_date(&self) -> bool {
        !self.psf.job.is_running()
            && self
                .psf
                .shown
                .as_ref()
                .is_some_and(|s| s.generation == self.psf.generation && s.quality == self.quality)
    }

    /// The latest message about the design or its PSFs, and whether it is an error.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// The latest message of the V matrix or the optimizer.
    pub fn optimizer_message(&self) -> Option<&Notice> {
        self.optimizer.message.as_ref()
    }

    /// The latest message of an export.
    pub fn export_message(&self) -> Option<&Notice> {
        self.export.message()
    }

    /// The computed V matrix on screen, if any.
    pub fn v(&self) -> Option<&ShownV> {
        self.optimizer.v.as_ref()
    }

    /// The optimizer's last result, if any.
    pub fn optimized(&self) -> Option<&OptimizerResult> {
        self.optimizer.optimized.as_ref()
    }

    /// Whether the λ0 optimizer is running.
    pub fn is_optimizing(&self) -> bool {
        self.optimizer.opt_job.is_running()
    }

    /// Whether the V matrix is being computed.
    pub fn is_computing_v(&self) -> bool {
        self.optimizer.v_job.is_running()
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
    fn channel_list(&mut self, set: ChannelSet) -> Result<Vec<Channel>, StudioError> {
        match set {
            ChannelSet::Peaks => Ok(Channel::rgb_peaks()),
            ChannelSet::Spectral => Ok(self
                .spectral
                .get_or_insert_with(|| {
                    spectral::channels_from_response(
                        &spectral::thesis_response(),
                        &wavelength_grid_nm(),
                    )
                })
                .clone()?),
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
        self.egui_ctx = ctx.clone();
        self.export.poll(ctx);
        self.poll_psfs(ctx);
        self.poll_optimizer(ctx);
        self.poll_response(ctx);
        self.poll_kernels(ctx);
        self.poll_capture(ctx);
        self.poll_compare(ctx);
        let capturing = self.view() == PhaseView::Capture;
        if capturing {
            // Captures run while their view is shown, for its current inputs.
            self.capture_tick(ctx);
        }
        self.facts = Facts {
            can_apply: self.can_apply(),
            kernels_stale: self.kernels_are_stale(),
            // Only the capture view reads it; its key resolves the bare T-OLED's setup.
            capture_current: capturing && self.capture_is_current(),
        };
        let idle = !ctx.input(|i| i.pointer.any_down()) && !ctx.egui_wants_keyboard_input();
        if idle {
            self.history.commit();
        }
        self.autosave_tick(ctx);
        if self.psf.job.is_running()
            || self.optimizer.v_job.is_running()
            || self.optimizer.opt_job.is_running()
            || self.is_computing_kernels()
        {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        self.resubmit_psfs(ctx);
    }
}
