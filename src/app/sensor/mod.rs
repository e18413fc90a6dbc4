//! The sensor previewer workspace (thesis chapter 5): load an HDR scene, pick a sensor and the
//! exposure, and compare the four strategies of Table 5.4 — gain maps, bin maps, saturation
//! maps, captures and per-ROI SSIM. Every parameter is live: a change runs a preview on a
//! downscaled scene at once, then the full scene, on a background thread (a newer change
//! cancels the running job). The UI thread only draws.

mod action;
mod colour;
mod gain_panel;
mod numbers;
mod panels;
pub mod study_view;
mod workspace;

use crate::app::notice::Notice;
pub use crate::core::Quality;
use std::path::PathBuf;
use std::sync::Arc;

use crate::app::dialogs::{PendingDialog, Purpose};
use crate::app::history::{History, Snapshot};
use crate::app::job::{Job, JobError, Keyed};
use crate::core::sensor::{Scene, SensorRun, SensorSettings, run};

use crate::io::photo::hdr;

pub use action::SensorAction;
pub use gain_panel::FlatPatchCheck;

/// The preview runs on the scene scaled to at most this side (the core's preview size, benched).
pub const PREVIEW_SIDE_PX: usize = crate::core::sensor::PREVIEW_MAX_SIDE_PX;

/// A scene and its preview-sized copy.
pub struct LoadedScene {
    /// The file name it was read from (or the name it was given).
    pub name: String,
    /// The scene at full size, for the full-quality run.
    pub scene: Scene,
    /// The scene downscaled to at most `PREVIEW_SIDE_PX` per side, for the quick preview run.
    pub preview: Scene,
}

/// A finished run on screen.
pub struct ShownRun {
    /// Generation of the settings it was computed for (older than the newest: stale).
    pub generation: u64,
    /// Preview (downscaled scene) or full scene.
    pub quality: Quality,
    /// Every strategy's capture, maps and scores, with the ground truth.
    pub run: Arc<SensorRun>,
}

/// What a sensor run was started for: the generation of the scene and settings, and the quality.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RunKey {
    generation: u64,
    quality: Quality,
}

/// Which picture the centre shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorView {
    /// The ground truth beside one strategy's capture, gain map, bin map and saturated pixels.
    Maps,
    /// Two strategies' captures, side by side or split, with their worst-ROI SSIM and PSNR.
    Compare,
    /// Contrast and noise against pixel pitch, to find the optimal pitch (Fig. 5.3).
    Curves,
    /// One region at every bin size across light levels, and the binning modes (Fig. 5.4).
    Study,
}

/// How the Compare view shows its two captures A and B.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompareMode {
    /// A and B as two pictures next to each other.
    SideBySide,
    /// One picture, A left and B right of a movable split line.
    Split,
}

/// How the exposure is chosen in the controls (each keeps its own number).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExposureKind {
    /// The scene's mean fills a fraction of the full well (Table 5.4: 5 %).
    Mean,
    /// A percentile of the scene's luminance fills a fraction of the full well.
    Percentile,
    /// A fixed number of electrons per µm² at radiance 1.
    Absolute,
}

impl Snapshot for SensorSettings {
    /// Equal settings, NaN included (a NaN field must not look like a change every frame).
    fn same(&self, other: &Self) -> bool {
        self == other || format!("{self:?}") == format!("{other:?}")
    }
}

/// The workspace's state.
pub struct SensorWorkspace {
    scene: Option<Arc<LoadedScene>>,
    load: Option<Job<LoadedScene>>,
    /// The built-in sample scene was asked for (once, when no scene is open).
    sample_requested: bool,
    dialog: Option<PendingDialog>,
    /// The sensor, exposure, ROI size, strategies and seed of the next run, with their undo
    /// history; the panels change them only through [`SensorAction`]s.
    history: History<SensorSettings>,
    /// What the panels queued this frame, carried out after the UI ([`SensorWorkspace::act`]).
    actions: Vec<SensorAction>,
    /// The settings and scene of the newest generation.
    submitted: Option<(SensorSettings, usize)>,
    generation: u64,
    job: Keyed<RunKey, SensorRun>,
    shown: Option<ShownRun>,
    message: Option<Notice>,
    /// The bin-size study (Fig. 5.4): its own job, started from its view.
    pub study: study_view::StudyView,
    flat: FlatPatchCheck,
    panels: panels::Panels,
}

/// What a panel may look at, and where it sends what it wants done.
pub struct SensorCtx<'a> {
    /// The settings of the next run (read-only; change them with [`SensorAction::Live`]).
    pub settings: &'a SensorSettings,
    /// The open scene, if any.
    pub scene: Option<&'a Arc<LoadedScene>>,
    /// A scene is being read.
    pub loading: bool,
    /// A file dialog is open.
    pub asking: bool,
    /// The run on screen, if any.
    pub shown: Option<&'a ShownRun>,
    /// The run in progress: its quality and the share done.
    pub running: Option<(Quality, f32)>,
    /// The message line.
    pub message: Option<&'a Notice>,
    /// The flat-patch check, a panel with its own job.
    pub flat: &'a mut FlatPatchCheck,
    /// The bin-size study, a view with its own job.
    pub study: &'a mut study_view::StudyView,
    /// Where the panel queues what it wants done; carried out after the frame's UI.
    pub actions: &'a mut Vec<SensorAction>,
}

type TextureKey = (u64, Quality, usize, usize, u32);

impl Default for SensorWorkspace {
    fn default() -> Self {
        SensorWorkspace {
            scene: None,
            load: None,
            sample_requested: false,
            dialog: None,
            history: History::new(SensorSettings::default()),
            actions: Vec::new(),
            submitted: None,
            generation: 0,
            job: Keyed::idle(),
            shown: None,
            message: None,
            study: study_view::StudyView::default(),
            flat: FlatPatchCheck::default(),
            panels: panels::Panels::default(),
        }
    }
}

impl SensorWorkspace {
    /// The open scene, if any.
    pub fn scene(&self) -> Option<&Arc<LoadedScene>> {
        self.scene.as_ref()
    }

    /// The run on screen, if any.
    pub fn shown(&self) -> Option<&ShownRun> {
        self.shown.as_ref()
    }

    /// True once the full-scene result of the newest settings is on screen, and the flat-patch
    /// check of its current inputs.
    pub fn is_up_to_date(&self) -> bool {
        self.load.is_none()
            && self
                .shown
                .as_ref()
                .is_some_and(|s| s.generation == self.generation && s.quality == Quality::Full)
            && self.flat.is_up_to_date(self.history.current())
    }

    /// Chooses the two captures of the Compare view and how they are shown.
    pub fn set_compare(&mut self, a: usize, b: usize, mode: CompareMode, split: f32) {
        self.act(SensorAction::Compare { a, b, mode, split });
    }

    /// The picture the centre shows.
    pub fn view(&self) -> SensorView {
        self.panels.views.view
    }

    /// Shows `view` in the centre ([`SensorAction::Show`]).
    pub fn show(&mut self, view: SensorView) {
        self.act(SensorAction::Show(view));
    }

    /// Pictures of runs built so far (each a figure built once, then drawn from the cache).
    pub fn figure_builds(&self) -> u64 {
        self.panels.views.figure_builds()
    }

    /// The panels and what they may look at, borrowed apart so that a panel draws from the
    /// context while it holds its own state.
    fn split(&mut self) -> (&mut panels::Panels, SensorCtx<'_>) {
        let ctx = SensorCtx {
            settings: self.history.current(),
            scene: self.scene.as_ref(),
            loading: self.load.is_some(),
            asking: self.dialog.is_some(),
            shown: self.shown.as_ref(),
            running: self.job.current().map(|(k, j)| (k.quality, j.fraction())),
            message: self.message.as_ref(),
            flat: &mut self.flat,
            study: &mut self.study,
            actions: &mut self.actions,
        };
        (&mut self.panels, ctx)
    }

    /// The left panel.
    pub fn controls_ui(&mut self, ui: &mut egui::Ui) {
        let (panels, mut ctx) = self.split();
        panels.controls.ui(ui, &mut ctx);
    }

    /// The right panel.
    pub fn numbers_ui(&mut self, ui: &mut egui::Ui) {
        let (panels, mut ctx) = self.split();
        panels.numbers.ui(ui, &mut ctx);
    }

    /// The centre.
    pub fn views_ui(&mut self, ui: &mut egui::Ui) {
        let (panels, mut ctx) = self.split();
        panels.views.ui(ui, &mut ctx);
    }

    /// The flat-patch check of the gain controls.
    pub fn flat_patch_check(&mut self) -> &mut FlatPatchCheck {
        &mut self.flat
    }

    /// The flat-patch check, read-only (for `step_until` conditions).
    pub fn flat_patch_check_ref(&self) -> &FlatPatchCheck {
        &self.flat
    }

    /// The loaded scene's name.
    pub fn scene_name(&self) -> Option<&str> {
        self.scene.as_ref().map(|s| s.name.as_str())
    }

    /// The latest message and whether it is an error.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Reads an HDR file on a background thread; the current scene stays until it succeeds.
    pub fn load_scene(&mut self, path: PathBuf, ctx: &egui::Context) {
        let wake = ctx.clone();
        self.load = Some(Job::spawn(
            "HDR reader",
            move || wake.request_repaint(),
            move |_| {
                let scene = hdr::load_hdr(&path)?;
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                let preview = scene.downscaled(PREVIEW_SIDE_PX);
                Ok::<_, JobError>(LoadedScene {
                    name,
                    scene,
                    preview,
                })
            },
        ));
    }

    /// Uses an in-memory scene (tests, and scenes made by other panels).
    pub fn set_scene(&mut self, name: &str, scene: Scene) {
        // A scene still being read (the sample) must not replace this one when it arrives.
        self.load = None;
        self.sample_requested = true;
        let preview = scene.downscaled(PREVIEW_SIDE_PX);
        self.scene = Some(Arc::new(LoadedScene {
            name: name.into(),
            scene,
            preview,
        }));
        self.submitted = None;
    }

    /// The settings of the next run (including a live edit not yet committed).
    pub fn settings(&self) -> &SensorSettings {
        self.history.current()
    }

    /// Edits the settings as a queued live edit does (for tests); one undo step once committed.
    pub fn settings_mut(&mut self) -> &mut SensorSettings {
        self.history.current_mut()
    }

    /// Carries out one action now, as the queue does after the frame's UI.
    pub fn act(&mut self, action: SensorAction) {
        match action {
            SensorAction::Live(settings) => *self.history.current_mut() = *settings,
            SensorAction::Undo => {
                self.history.undo();
                let e = self.history.current().exposure;
                self.panels.controls.show_exposure(e);
            }
            SensorAction::Redo => {
                self.history.redo();
                let e = self.history.current().exposure;
                self.panels.controls.show_exposure(e);
            }
            SensorAction::AskHdr => {
                self.dialog = Some(PendingDialog::spawn(Purpose::Hdr, None, None));
            }
            SensorAction::Show(view) => self.panels.views.view = view,
            SensorAction::Compare { a, b, mode, split } => {
                let v = &mut self.panels.views;
                v.compare = [a, b];
                v.compare_mode = mode;
                v.split = split.clamp(0.0, 1.0);
            }
        }
    }

    /// Carries out what the panels queued this frame.
    pub fn apply_queued(&mut self) {
        for action in std::mem::take(&mut self.actions) {
            self.act(action);
        }
    }

    /// Whether there is a settings change to undo, including one not yet committed.
    pub fn can_undo(&self) -> bool {
        self.history.can_undo()
    }

    /// Whether there is an undone change to redo.
    pub fn can_redo(&self) -> bool {
        self.history.can_redo()
    }

    /// Takes finished loads, dialogs and runs; starts the runs the settings call for.
    pub fn poll(&mut self, ctx: &egui::Context) {
        self.study.poll(ctx);
        if self.scene.is_none() && self.load.is_none() && !self.sample_requested {
            // Something to look at before the user finds an HDR file.
            self.sample_requested = true;
            let wake = ctx.clone();
            self.load = Some(Job::spawn(
                "sample scene reader",
                move || wake.request_repaint(),
                |_| {
                    let scene = hdr::sample_scene()?;
                    let preview = scene.downscaled(PREVIEW_SIDE_PX);
                    Ok::<_, JobError>(LoadedScene {
                        name: hdr::SAMPLE_SCENE_NAME.into(),
                        scene,
                        preview,
                    })
                },
            ));
        }
        if let Some(answer) = self.dialog.as_ref().and_then(PendingDialog::poll) {
            self.dialog = None;
            match answer {
                Ok(Some(path)) => self.load_scene(path, ctx),
                Ok(None) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(done) = self.load.as_ref().and_then(Job::poll) {
            self.load = None;
            match done {
                Ok(s) => {
                    self.message = Some(Notice::info(format!("loaded {}", s.name)));
                    self.scene = Some(Arc::new(s));
                    self.submitted = None;
                }
                Err(e) => {
                    self.message = Some(Notice::error(format!("cannot open the HDR scene: {e}")))
                }
            }
        }
        if let Some((job, done)) = self.job.poll() {
            match done {
                Ok(run) if job.generation == self.generation => {
                    self.shown = Some(ShownRun {
                        generation: job.generation,
                        quality: job.quality,
                        run: Arc::new(run),
                    });
                    self.panels.views.forget_figures();
                    if self.message.as_ref().is_some_and(Notice::is_error) {
                        self.message = None;
                    }
                    if job.quality == Quality::Preview {
                        self.start(Quality::Full, ctx);
                    }
                }
                Ok(_) | Err(JobError::Cancelled) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        let idle = !ctx.input(|i| i.pointer.any_down()) && !ctx.egui_wants_keyboard_input();
        if idle {
            self.history.commit();
        }
        // A change of scene or settings: a new generation, preview first.
        self.flat.poll(self.history.current(), ctx);
        let Some(scene) = &self.scene else {
            return;
        };
        let scene_id = Arc::as_ptr(scene) as usize;
        // Compared in place: cloning the settings every frame would be work the UI does not need.
        let unchanged = self
            .submitted
            .as_ref()
            .is_some_and(|(s, id)| s == self.history.current() && *id == scene_id);
        if !unchanged {
            self.submitted = Some((self.history.current().clone(), scene_id));
            if let Err(e) = self.history.current().validate() {
                self.message = Some(Notice::error(e.to_string()));
                return;
            }
            self.generation += 1;
            self.start(Quality::Preview, ctx);
        }
    }

    fn start(&mut self, quality: Quality, ctx: &egui::Context) {
        let Some(scene) = self.scene.clone() else {
            return;
        };
        // Dropping the running job cancels it.
        self.job.stop();
        let settings = match quality {
            Quality::Preview => self
                .settings()
                .for_preview(scene.scene.dim(), scene.preview.dim()),
            Quality::Full => self.history.current().clone(),
        };
        let wake = ctx.clone();
        let job = Job::spawn(
            "sensor job",
            move || wake.request_repaint(),
            move |p| {
                let s = match quality {
                    Quality::Preview => &scene.preview,
                    Quality::Full => &scene.scene,
                };
                run(s, &settings, p)
            },
        );
        self.job.start(
            RunKey {
                generation: self.generation,
                quality,
            },
            job,
        );
    }
}
