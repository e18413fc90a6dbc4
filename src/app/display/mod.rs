//! The display-layout workspace (thesis chapter 3): draw one pixel's opening, tile it, and see
//! the PSF, MTF, numbers, a capture and its restoration live; optimize the opening.
//!
//! It owns the design document (undoable), the simulation [`Worker`], the results on screen,
//! its panels and its files (open, save, import, export, autosave). Each frame it (1) takes
//! finished results, (2) draws the panels, which queue [`DisplayAction`]s (as do its menus and
//! shortcuts), and (3) carries those actions out when the shell calls [`Workspace::apply`].

pub mod action;
mod apply;
pub mod document;
pub mod labels;
mod menu;
pub mod panels;
mod worker;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::autosave::Autosave;
use super::dialogs::PendingDialog;
use super::job::{Job, Writes};
use super::notice::Notice;
use super::settings::AppDirs;
use super::workspace::{DroppedKind, Request, Shell, Workspace, WorkspaceId, side_panel};
use crate::core::Design;
use crate::core::analysis::analyze::Quality;
use crate::io::design::{file as design_file, presets};
pub use action::{DisplayAction, ExportKind, Tool};
pub use document::Document;
use panels::{DisplayPreview, PanelCtx, Pinned, Shown};
pub use worker::{JobResult, Payload, Worker};

/// Results on screen (the last good ones stay when a newer job fails).
#[derive(Default)]
pub struct Results {
    /// The newest analysis of the current design (preview, then full quality).
    pub shown: Option<Shown>,
    /// The rasterised display over the pupil.
    pub display: Option<DisplayPreview>,
    /// The design pinned as A for Compare.
    pub pinned: Option<Pinned>,
    /// Pin the next full-quality result of the current generation.
    pin_requested: bool,
    /// A design sent to be pinned (a study point's), analysed at full quality, and where it
    /// came from.
    pin_job: Option<(String, Job<Pinned>)>,
    /// Whether the shown result's warnings carry their advice (the full-quality result comes
    /// first without it).
    advised: bool,
}

/// The tabs of the left panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeftTab {
    /// The pixel editor.
    Opening,
    /// Pitch, tiling mode and seed.
    Tiling,
    /// Wavelengths, lens and sensor.
    Optics,
    /// The opening optimizer.
    Optimize,
    /// A prototype's measured PSF: compare, fit.
    Measured,
}

/// A design being read from disk: the design and the path it came from (`None`: an imported
/// opening, an edit of the current design).
type LoadJob = Job<(Design, Option<PathBuf>)>;

/// The document's files: dialogs, reads, writes and autosave.
struct Files {
    dialog: Option<PendingDialog>,
    load: Option<LoadJob>,
    writes: Writes,
    /// The design kept beside the user's files (none in tests without a data directory).
    autosave: Autosave<Design>,
    /// The wavelength step of a spectral response being loaded, in nm.
    spectral_step_nm: f64,
}

struct Panels {
    editor: panels::editor::EditorPanel,
    tiling: panels::tiling::TilingPanel,
    optics: panels::optics::OpticsPanel,
    optimize: panels::optimize::OptimizePanel,
    measured: panels::measured::MeasuredPanel,
    numbers: panels::numbers::NumbersPanel,
    views: panels::views::ViewsPanel,
    mask_export: panels::mask_export::MaskExportDialog,
    one_axis_sweep: panels::one_axis_sweep::OneAxisSweepWindow,
}

/// The display-layout workspace.
pub struct DisplayWorkspace {
    doc: Document,
    worker: Worker,
    results: Results,
    panels: Panels,
    tool: Tool,
    left_tab: LeftTab,
    files: Files,
    egui_ctx: egui::Context,
    /// What its panels, menus and shortcuts asked for this frame, carried out in
    /// [`Workspace::apply`].
    queued: Vec<DisplayAction>,
    /// The action that waits for the unsaved-changes answer ([`Workspace::resume`]).
    awaiting: Option<DisplayAction>,
}

impl DisplayWorkspace {
    /// Opens New study… in the Sweep workspace for the design on screen (`field` alone as
    /// its axis, if given), with its analysis time to scale the estimate when its result is
    /// the design's, and the Restore view's settings and photo.
    pub fn new_study(
        &mut self,
        field: Option<crate::core::sweep::one_axis::SweepParameter>,
        shell: &mut Shell,
    ) {
        let on_screen = self
            .shown()
            .filter(|_| self.is_up_to_date())
            .map(|s| (s.analysis.elapsed_ms, s.quality));
        let (restore, photo, restore_ms) = self.panels.views.restore.study_setup();
        let start = crate::app::study_start::StudyStart {
            subject: crate::core::sweep::study::StudySubject::Display(Box::new(
                self.design().clone(),
            )),
            times: crate::core::sweep::study::StudyTimes {
                on_screen,
                restore_ms,
            },
            restore,
            photo,
        };
        shell.send(
            WorkspaceId::Sweep,
            Request::NewStudy {
                start: Box::new(start),
                field,
            },
        );
    }

    /// Opens `design_path`, or restores the autosave, or the default preset; a problem is
    /// reported in the shell's status bar.
    pub fn new(shell: &mut Shell, design_path: Option<PathBuf>) -> Self {
        let mut status = None;
        let (design, path) = match design_path.as_deref().map(design_file::load_design) {
            Some(Ok(d)) => (d, design_path.clone()),
            Some(Err(e)) => {
                status = Some(Notice::error(e.to_string()));
                (restore_or_default(&shell.dirs, &mut status), None)
            }
            None => (restore_or_default(&shell.dirs, &mut status), None),
        };
        if let Some(n) = status {
            shell.set_status(n);
        }
        let wake_ctx = shell.ctx.clone();
        let worker = Worker::spawn(move || wake_ctx.request_repaint(), shell.compute.shared());
        let mut ws = DisplayWorkspace {
            doc: Document::new(design.clone(), path),
            worker,
            results: Results::default(),
            panels: Panels {
                editor: Default::default(),
                tiling: Default::default(),
                optics: Default::default(),
                optimize: Default::default(),
                measured: Default::default(),
                numbers: Default::default(),
                views: Default::default(),
                mask_export: Default::default(),
                one_axis_sweep: Default::default(),
            },
            tool: Tool::Paint,
            left_tab: LeftTab::Opening,
            files: Files {
                dialog: None,
                load: None,
                writes: Writes::default(),
                autosave: Autosave::new(
                    shell.dirs.autosave_path(),
                    Some(design),
                    apply::write_autosave,
                ),
                spectral_step_nm: 30.0,
            },
            egui_ctx: shell.ctx.clone(),
            queued: Vec::new(),
            awaiting: None,
        };
        ws.submit();
        ws
    }

    /// The design being edited.
    pub fn design(&self) -> &Design {
        self.doc.design()
    }

    /// The document: the design, its file and its undo history.
    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// The result on screen, if any.
    pub fn shown(&self) -> Option<&Shown> {
        self.results.shown.as_ref()
    }

    /// The pinned comparison design, if any.
    pub fn pinned(&self) -> Option<&Pinned> {
        self.results.pinned.as_ref()
    }

    /// Whether the shown result is the full-quality result of the current design.
    pub fn is_up_to_date(&self) -> bool {
        self.results
            .shown
            .as_ref()
            .is_some_and(|s| s.generation == self.worker.generation() && s.quality == Quality::Full)
            && self.results.advised
            && self.files.load.is_none()
    }

    /// The editor panel (tests use its grid rectangle to draw with the pointer).
    pub fn editor(&self) -> &panels::editor::EditorPanel {
        &self.panels.editor
    }

    /// The optimize panel (tests read its runs).
    pub fn optimizer(&self) -> &panels::optimize::OptimizePanel {
        &self.panels.optimize
    }

    /// The optimize panel's settings (tests set up runs through it).
    pub fn optimizer_settings(&mut self) -> &mut crate::core::optimize::OptimizeSettings {
        &mut self.panels.optimize.settings
    }

    /// The result views (tests pick tabs and read the Restore view).
    pub fn views(&mut self) -> &mut panels::views::ViewsPanel {
        &mut self.panels.views
    }

    /// The Appearance view's renderings and scatter.
    pub fn appearance_view(&self) -> &panels::views::appearance::AppearanceView {
        &self.panels.views.appearance
    }

    /// The Restore view's results.
    pub fn restore_view(&self) -> &panels::views::restore::RestoreView {
        &self.panels.views.restore
    }

    /// The Export-mask dialog (its options and whether an export runs).
    pub fn mask_export(&self) -> &panels::mask_export::MaskExportDialog {
        &self.panels.mask_export
    }

    /// The Measured PSF panel.
    pub fn measured(&self) -> &panels::measured::MeasuredPanel {
        &self.panels.measured
    }

    /// The Measured PSF panel, to drive it (tests).
    pub fn measured_mut(&mut self) -> &mut panels::measured::MeasuredPanel {
        &mut self.panels.measured
    }

    /// The "sweep this parameter" window.
    pub fn one_axis_sweep(&self) -> &panels::one_axis_sweep::OneAxisSweepWindow {
        &self.panels.one_axis_sweep
    }

    /// The "sweep this parameter" window, to set it up (tests).
    pub fn field_sweep_mut(&mut self) -> &mut panels::one_axis_sweep::OneAxisSweepWindow {
        &mut self.panels.one_axis_sweep
    }

    /// Shows a tab of the left panel.
    pub fn show_left_tab(&mut self, tab: LeftTab) {
        self.left_tab = tab;
    }

    /// The editor's current tool.
    pub fn tool(&self) -> Tool {
        self.tool
    }

    fn submit(&mut self) {
        self.worker.submit(self.doc.design().clone());
    }

    /// Takes every finished job of the workspace, its panels' included; the panels only start
    /// them (and draw their progress).
    fn poll(&mut self, shell: &mut Shell) {
        self.take_results(shell);
        self.poll_pin(shell);
        self.poll_files(shell);
        self.panels.optimize.poll();
        self.panels.measured.poll(&self.egui_ctx);
        self.panels.one_axis_sweep.poll();
        self.panels.views.poll(&self.egui_ctx);
    }

    /// Takes finished results; keeps the last good result when a job fails.
    fn take_results(&mut self, shell: &mut Shell) {
        for r in self.worker.poll() {
            if r.generation != self.worker.generation() {
                continue;
            }
            match r.payload {
                Payload::Display {
                    side,
                    values,
                    sample_um,
                    pupil_diameter_um,
                } => {
                    self.results.display = Some(DisplayPreview {
                        generation: r.generation,
                        side,
                        values: Arc::new(values),
                        sample_um,
                        pupil_diameter_um,
                    });
                }
                Payload::Analysis {
                    quality,
                    advised,
                    result,
                    route,
                } => match result {
                    Ok(a) => {
                        self.results.advised = advised;
                        let shown = Shown {
                            generation: r.generation,
                            quality,
                            analysis: Arc::new(a),
                            design: Arc::new(self.doc.design().clone()),
                            route,
                        };
                        if quality == Quality::Full && self.results.pin_requested {
                            self.results.pin_requested = false;
                            self.results.pinned =
                                Some(Pinned::now(shown.design.clone(), shown.analysis.clone()));
                        }
                        self.results.shown = Some(shown);
                        shell.simulation_ok();
                    }
                    Err(e) => shell.set_simulation_error(Notice::error(format!(
                        "cannot simulate this design: {}",
                        labels::in_ui_words(&e.to_string())
                    ))),
                },
            }
        }
    }

    fn left_ui(&mut self, ui: &mut egui::Ui, shell: &Shell) {
        // Five tabs overflow the narrowest panel (a 1024-px window): they wrap. Presentation
        // mode folds the advanced workflows away (unless one is open).
        let presenting = crate::app::presentation::is_on(ui.ctx());
        ui.horizontal_wrapped(|ui| {
            for (tab, label) in [
                (LeftTab::Opening, "Opening"),
                (LeftTab::Tiling, "Tiling"),
                (LeftTab::Optics, "Optics"),
                (LeftTab::Optimize, "Optimize"),
                (LeftTab::Measured, "Measured"),
            ] {
                let advanced = matches!(tab, LeftTab::Optimize | LeftTab::Measured);
                if presenting && advanced && self.left_tab != tab {
                    continue;
                }
                if ui.selectable_label(self.left_tab == tab, label).clicked() {
                    self.left_tab = tab;
                }
            }
        });
        ui.separator();
        let mut pctx = panel_ctx(&self.doc, &self.results, shell, self.tool, &mut self.queued);
        egui::ScrollArea::vertical().show(ui, |ui| match self.left_tab {
            LeftTab::Opening => self.panels.editor.ui(ui, &mut pctx),
            LeftTab::Tiling => self.panels.tiling.ui(ui, &mut pctx),
            LeftTab::Optics => self.panels.optics.ui(ui, &mut pctx),
            LeftTab::Optimize => self.panels.optimize.ui(ui, &mut pctx),
            LeftTab::Measured => self.panels.measured.ui(ui, &mut pctx),
        });
    }
}

impl Workspace for DisplayWorkspace {
    fn id(&self) -> WorkspaceId {
        WorkspaceId::Display
    }

    fn label(&self) -> &'static str {
        "Display layouts"
    }

    fn about(&self) -> &'static str {
        "Chapter 3: draw, tile, analyse, restore, optimize"
    }

    fn hint(&self) -> &'static str {
        "Ready. Draw on the opening (B paint, E erase, R rectangle, O ellipse, L line, F fill)."
    }

    fn tour(&self) -> &'static [&'static str] {
        &[
            "Draw one display pixel's opening on the left (Opening tab): white cells let light \
             through.",
            "The log-PSF in the centre and the Numbers on the right follow every stroke; AUC is \
             the area under the radially-minimum MTF: higher is sharper.",
            "Tiling repeats the pixel or rotates and flips it at random, which spreads the \
             diffraction orders into a softer halo.",
            "Optimize searches for an opening whose blur is easy to invert; Restore shows a \
             photo captured through the display and restored.",
            "File > Export mask writes GDSII, OASIS, DXF, SVG or PNG for photolithography.",
            "Teaching? Presets > Fourier optics: slits, a circle, gratings; the Theory view lays \
             the textbook formula over the simulation.",
        ]
    }

    fn shortcuts(&self) -> &'static [(&'static str, &'static str)] {
        &[
            (
                "B E R O L F",
                "paint, erase, rectangle, ellipse, line, fill",
            ),
            ("I", "invert the opening"),
            ("Del", "clear the opening"),
            ("Ctrl+C / Ctrl+V", "copy / paste the opening as text"),
            ("F5", "a new seed for the random tiling"),
            ("Ctrl+P", "pin the design as A for Compare"),
            ("Ctrl+Shift+P", "presentation mode (for a projector)"),
            (
                "Ctrl+N / Ctrl+O / Ctrl+S / Ctrl+Shift+S",
                "new, open, save, save as",
            ),
        ]
    }

    fn read_shortcuts(&mut self, ctx: &egui::Context) {
        action::read_shortcuts(ctx, &mut self.queued);
    }

    fn ui(&mut self, ui: &mut egui::Ui, shell: &mut Shell) {
        // Jobs are taken here, not in the panels: a tab that is not shown is not drawn.
        self.poll(shell);
        let total = ui.available_width();
        // The pixel editor wants room; the numbers table fits in 240 px.
        side_panel(egui::Panel::left("design"), total, 0.3, 290.0, 440.0)
            .show(ui, |ui| self.left_ui(ui, shell));
        let progress = self.worker.progress();
        // The AUC is what a designer watches while drawing: the numbers stay beside the views
        // at every width (the table is four columns so that it fits the narrowest panel).
        side_panel(egui::Panel::right("numbers"), total, 0.27, 270.0, 400.0).show(ui, |ui| {
            let mut pctx = panel_ctx(&self.doc, &self.results, shell, self.tool, &mut self.queued);
            ui.heading("Numbers");
            // Vertical only: warnings wrap at the panel's width, and the table fits it.
            egui::ScrollArea::vertical().show(ui, |ui| {
                self.panels.numbers.ui(ui, &mut pctx, progress);
            });
        });
        egui::CentralPanel::default().show(ui, |ui| {
            let mut pctx = panel_ctx(&self.doc, &self.results, shell, self.tool, &mut self.queued);
            self.panels.views.ui(ui, &mut pctx);
        });
        let ctx = ui.ctx().clone();
        self.panels
            .mask_export
            .ui(&ctx, self.doc.design(), &mut self.queued);
        self.panels.one_axis_sweep.ui(&ctx);
    }

    fn apply(&mut self, shell: &mut Shell) {
        for action in std::mem::take(&mut self.queued) {
            self.act(action, shell);
        }
    }

    fn undo(&mut self) {
        if self.doc.undo() {
            self.submit();
        }
    }

    fn redo(&mut self) {
        if self.doc.redo() {
            self.submit();
        }
    }

    fn can_undo(&self) -> bool {
        self.doc.can_undo()
    }

    fn can_redo(&self) -> bool {
        self.doc.can_redo()
    }

    fn file_menu_ui(&mut self, ui: &mut egui::Ui, shell: &Shell) {
        self.file_menu(ui, shell);
    }

    fn edit_menu_ui(&mut self, ui: &mut egui::Ui) {
        self.edit_menu(ui);
    }

    fn menus_ui(&mut self, ui: &mut egui::Ui) {
        self.extra_menus(ui);
    }

    fn open_dropped(&mut self, path: &Path, kind: DroppedKind, shell: &mut Shell) -> bool {
        self.dropped_file(path, kind, shell)
    }

    fn request(&mut self, request: Request, shell: &mut Shell) {
        match request {
            Request::OpenDesign { design, what } => {
                self.act(DisplayAction::OpenDesign { design, what }, shell);
            }
            Request::StudyCurrentDesign => self.new_study(None, shell),
            Request::Recompute => self.submit(),
            Request::PinDesign { design, what } => self.pin_design(*design, what, shell),
            Request::NewStudy { .. } | Request::OpenPhaseDesign { .. } => {}
        }
    }

    fn is_dirty(&self) -> bool {
        self.doc.is_dirty()
    }

    fn can_save_in_place(&self) -> bool {
        self.doc.path.is_some()
    }

    fn save(&mut self, shell: &mut Shell) {
        self.apply_one(DisplayAction::Save, true, shell);
    }

    fn save_as(&mut self, shell: &mut Shell) {
        self.apply_one(DisplayAction::SaveAs, true, shell);
    }

    fn resume(&mut self, shell: &mut Shell) {
        if let Some(action) = self.awaiting.take() {
            self.apply_one(action, true, shell);
        }
    }

    fn document_name(&self) -> String {
        self.doc.design().name.clone()
    }

    fn figure_caption(&self) -> String {
        match self.shown() {
            Some(s) => crate::core::views::saved::caption(&s.design, &s.analysis),
            None => self.document_name(),
        }
    }

    fn title(&self) -> String {
        self.doc.title()
    }

    fn save_now_blocking(&mut self) {
        self.autosave_now_blocking();
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

/// What the panels see this frame (disjoint borrows of the workspace's fields).
fn panel_ctx<'a>(
    doc: &'a Document,
    results: &'a Results,
    shell: &Shell,
    tool: Tool,
    actions: &'a mut Vec<DisplayAction>,
) -> PanelCtx<'a> {
    PanelCtx {
        design: doc.design(),
        shown: results.shown.as_ref(),
        display: results.display.as_ref(),
        pinned: results.pinned.as_ref(),
        overlays: shell.settings.overlays,
        design_rules: shell.settings.design_rules,
        native_dialogs: shell.native_dialogs,
        tool,
        actions,
    }
}

/// The autosaved design of the last session, or the default preset.
fn restore_or_default(dirs: &AppDirs, status: &mut Option<Notice>) -> Design {
    if let Some(path) = dirs.autosave_path().filter(|p| p.exists()) {
        match design_file::load_design(&path) {
            Ok(d) => return d,
            Err(e) => {
                // Keep the unreadable autosave aside instead of overwriting it.
                let kept = match crate::io::safe_file::keep_aside(&path) {
                    Ok(aside) => format!(
                        "kept it as {} beside it",
                        aside.file_name().unwrap_or_default().to_string_lossy()
                    ),
                    Err(e) => format!("it stays where it was ({e})"),
                };
                *status = Some(Notice::error(format!(
                    "could not restore the last design ({e}); {kept}; opened the default \
                         design"
                )));
            }
        }
    }
    presets::load_preset(presets::DEFAULT_PRESET).unwrap_or_default()
}
