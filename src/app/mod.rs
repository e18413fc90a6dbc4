//! The studio (egui/eframe). The only module that touches egui.
//!
//! `StudioApp` owns the document (undoable), the simulation worker, the shown results, the
//! panels and the session (files, dialogs, autosave). Every frame it (1) takes finished results,
//! (2) draws the panels, which push [`Command`]s, and (3) applies those commands once.

mod actions;
pub mod commands;
pub mod dialogs;
pub mod document;
pub mod job;
mod menu;
pub mod notice;
pub mod panels;
pub mod phase;
pub mod sensor;
pub mod settings;
pub mod widgets;
mod worker;

use crate::app::notice::Notice;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;

pub use commands::{Command, ExportKind, Tool};
pub use document::Document;
pub use settings::{AppDirs, Settings};
pub use worker::{JobResult, Payload, Worker};

use crate::core::Design;
use crate::core::analyze::Quality;
use crate::io::{design_file, presets};
use panels::{DisplayPreview, PanelCtx, Pinned, Shown};

/// How often the design is autosaved while it changes.
pub const AUTOSAVE_EVERY: Duration = Duration::from_secs(3);

/// How the studio starts.
pub struct StudioOptions {
    pub dirs: AppDirs,
    /// Open this file instead of restoring the autosave.
    pub design_path: Option<PathBuf>,
    /// Native file dialogs (off in tests, where nothing may block).
    pub native_dialogs: bool,
    /// How often the design is autosaved while it changes.
    pub autosave_every: Duration,
}

/// Opens the studio window with `design_path` (or the last session's design, or the default).
///
/// # Errors
/// When no window can be created (no display).
pub fn run_studio(design_path: Option<PathBuf>) -> Result<()> {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("UDC Studio")
            .with_inner_size([1440.0, 900.0])
            .with_min_inner_size([900.0, 600.0]),
        ..Default::default()
    };
    let studio = StudioOptions {
        dirs: AppDirs::platform(),
        design_path,
        native_dialogs: true,
        autosave_every: AUTOSAVE_EVERY,
    };
    eframe::run_native(
        "UDC Studio",
        options,
        Box::new(move |cc| {
            // Ctrl-C or SIGTERM in the terminal closes the window the normal way (no prompt:
            // the design is autosaved on exit), instead of killing it between autosaves.
            let ctx = cc.egui_ctx.clone();
            let _ = ctrlc::set_handler(move || {
                INTERRUPTED.store(true, std::sync::atomic::Ordering::Relaxed);
                ctx.request_repaint();
            });
            Ok(Box::new(StudioApp::new(&cc.egui_ctx, studio)))
        }),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the studio window: {e}"))
}

/// Set by the Ctrl-C / SIGTERM handler; the next frame closes the window.
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Results on screen (the last good ones stay when a newer job fails).
#[derive(Default)]
pub struct Results {
    pub shown: Option<Shown>,
    pub display: Option<DisplayPreview>,
    pub pinned: Option<Pinned>,
    /// Pin the next full-quality result of the current generation.
    pin_requested: bool,
}

/// View state: persisted, never undone.
pub struct View {
    pub workspace: Workspace,
    pub tool: Tool,
    pub settings: Settings,
    pub left_tab: LeftTab,
}

/// The studio's workspaces: display layouts (chapter 3), phase masks (chapter 4) and the sensor
/// previewer (chapter 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Workspace {
    Display,
    Phase,
    Sensor,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeftTab {
    Opening,
    Tiling,
    Optics,
    Optimize,
}

/// A design being read from disk: the design and the path it came from, or a message.
type LoadTask = job::Job<(Design, Option<PathBuf>)>;

/// Files, dialogs, autosave and messages.
pub struct Session {
    dirs: AppDirs,
    native_dialogs: bool,
    dialog: Option<dialogs::PendingDialog>,
    load: Option<LoadTask>,
    writes: job::Writes,
    confirm: Option<Command>,
    last_autosave: Instant,
    autosaved: Option<Design>,
    spectral_step_nm: f64,
    quit_confirmed: bool,
    autosave_every: Duration,
    /// The latest message for the status bar, and whether it is an error.
    pub status: Option<Notice>,
    /// The status is the simulation's error, which its next good result clears.
    pub status_is_simulation_error: bool,
}

struct Panels {
    editor: panels::editor::EditorPanel,
    tiling: panels::tiling::TilingPanel,
    optics: panels::optics::OpticsPanel,
    optimize: panels::optimize::OptimizePanel,
    numbers: panels::numbers::NumbersPanel,
    views: panels::views::ViewsPanel,
    mask_export: panels::mask_export::MaskExportDialog,
}

/// The studio.
pub struct StudioApp {
    doc: Document,
    sensor: sensor::SensorWorkspace,
    phase: phase::PhaseWorkspace,
    worker: Worker,
    results: Results,
    view: View,
    session: Session,
    panels: Panels,
    title: String,
    egui_ctx: egui::Context,
}

impl StudioApp {
    /// Starts the studio: opens `design_path`, or restores the autosave, or the default preset.
    pub fn new(ctx: &egui::Context, options: StudioOptions) -> Self {
        let settings = Settings::load(&options.dirs);
        ctx.set_visuals(if settings.dark {
            egui::Visuals::dark()
        } else {
            egui::Visuals::light()
        });
        let mut status = None;
        let (design, path) = match options.design_path.as_deref().map(design_file::load_design) {
            Some(Ok(d)) => (d, options.design_path.clone()),
            Some(Err(e)) => {
                status = Some(Notice::error(e.to_string()));
                (restore_or_default(&options.dirs, &mut status), None)
            }
            None => (restore_or_default(&options.dirs, &mut status), None),
        };
        let wake_ctx = ctx.clone();
        let worker = Worker::spawn(move || wake_ctx.request_repaint());
        let phase = phase::PhaseWorkspace::new(
            &options.dirs,
            options.native_dialogs,
            options.autosave_every,
        );
        let mut app = StudioApp {
            doc: Document::new(design.clone(), path),
            sensor: sensor::SensorWorkspace::default(),
            phase,
            worker,
            results: Results::default(),
            view: View {
                workspace: Workspace::Display,
                tool: Tool::Paint,
                settings,
                left_tab: LeftTab::Opening,
            },
            session: Session {
                dirs: options.dirs,
                native_dialogs: options.native_dialogs,
                dialog: None,
                load: None,
                writes: job::Writes::default(),
                confirm: None,
                last_autosave: Instant::now(),
                autosaved: Some(design),
                spectral_step_nm: 30.0,
                quit_confirmed: false,
                autosave_every: options.autosave_every,
                status,
                status_is_simulation_error: false,
            },
            panels: Panels {
                editor: Default::default(),
                tiling: Default::default(),
                optics: Default::default(),
                optimize: Default::default(),
                numbers: Default::default(),
                views: Default::default(),
                mask_export: Default::default(),
            },
            title: String::new(),
            egui_ctx: ctx.clone(),
        };
        app.submit();
        app
    }

    /// The design being edited.
    pub fn design(&self) -> &Design {
        self.doc.design()
    }

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
            && self.session.load.is_none()
    }

    /// The status-bar message and whether it is an error.
    pub fn status(&self) -> Option<&Notice> {
        self.session.status.as_ref()
    }

    /// The editor panel (tests use its grid rectangle to draw with the pointer).
    pub fn editor(&self) -> &panels::editor::EditorPanel {
        &self.panels.editor
    }

    /// Queues a command as if a menu item or shortcut had been used.
    pub fn command(&mut self, command: Command) {
        self.apply(vec![command]);
    }

    /// The optimize panel (tests read its runs).
    pub fn optimizer(&self) -> &panels::optimize::OptimizePanel {
        &self.panels.optimize
    }

    /// The optimize panel's settings (tests set up runs through it).
    pub fn optimizer_settings(&mut self) -> &mut crate::core::optimize::OptimizeSettings {
        &mut self.panels.optimize.settings
    }

    /// The sensor previewer workspace.
    pub fn sensor(&mut self) -> &mut sensor::SensorWorkspace {
        &mut self.sensor
    }

    /// The sensor previewer, read-only (for `step_until` conditions).
    pub fn sensor_ref(&self) -> &sensor::SensorWorkspace {
        &self.sensor
    }

    /// The phase-mask workspace.
    pub fn phase(&mut self) -> &mut phase::PhaseWorkspace {
        &mut self.phase
    }

    /// The phase-mask workspace, read-only (for `step_until` conditions).
    pub fn phase_ref(&self) -> &phase::PhaseWorkspace {
        &self.phase
    }

    /// The workspace on screen.
    pub fn workspace(&self) -> Workspace {
        self.view.workspace
    }

    /// Switches between the display-layout, phase-mask and sensor workspaces.
    pub fn set_workspace(&mut self, workspace: Workspace) {
        self.view.workspace = workspace;
    }

    /// The result views (tests pick tabs and read the Restore view).
    pub fn views(&mut self) -> &mut panels::views::ViewsPanel {
        &mut self.panels.views
    }

    /// The Restore view's results.
    pub fn restore_view(&self) -> &panels::views::restore::RestoreView {
        &self.panels.views.restore
    }

    /// Shows a tab of the left panel.
    pub fn show_left_tab(&mut self, tab: LeftTab) {
        self.view.left_tab = tab;
    }

    pub fn tool(&self) -> Tool {
        self.view.tool
    }

    fn submit(&mut self) {
        self.worker.submit(self.doc.design().clone());
    }

    /// Takes finished results; keeps the last good result when a job fails.
    fn take_results(&mut self) {
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
                Payload::Analysis { quality, result } => match result {
                    Ok(a) => {
                        let shown = Shown {
                            generation: r.generation,
                            quality,
                            analysis: Arc::new(a),
                            design: Arc::new(self.doc.design().clone()),
                        };
                        if quality == Quality::Full && self.results.pin_requested {
                            self.results.pin_requested = false;
                            self.results.pinned = Some(Pinned {
                                design: shown.design.clone(),
                                analysis: shown.analysis.clone(),
                            });
                        }
                        self.results.shown = Some(shown);
                        // A good result answers the simulation's own error, not the others
                        // (a file kept aside, a failed save) the user has not read yet.
                        if self.session.status_is_simulation_error {
                            self.session.status = None;
                            self.session.status_is_simulation_error = false;
                        }
                    }
                    Err(e) => {
                        self.session.status =
                            Some(Notice::error(format!("cannot simulate this design: {e}")));
                        self.session.status_is_simulation_error = true;
                    }
                },
            }
        }
    }

    fn left_ui(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        ui.horizontal(|ui| {
            for (tab, label) in [
                (LeftTab::Opening, "Opening"),
                (LeftTab::Tiling, "Tiling"),
                (LeftTab::Optics, "Optics"),
                (LeftTab::Optimize, "Optimize"),
            ] {
                if ui
                    .selectable_label(self.view.left_tab == tab, label)
                    .clicked()
                {
                    self.view.left_tab = tab;
                }
            }
        });
        ui.separator();
        let mut pctx = panel_ctx(&self.doc, &self.results, &self.view, cmds);
        egui::ScrollArea::vertical().show(ui, |ui| match self.view.left_tab {
            LeftTab::Opening => self.panels.editor.ui(ui, &mut pctx),
            LeftTab::Tiling => self.panels.tiling.ui(ui, &mut pctx),
            LeftTab::Optics => self.panels.optics.ui(ui, &mut pctx),
            LeftTab::Optimize => self.panels.optimize.ui(ui, &mut pctx),
        });
    }

    fn status_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            if let Some(n) = &self.session.status {
                let color = if n.is_error() { ui.visuals().error_fg_color } else { ui.visuals().text_color() };
                // The button first: a long message is cut to the window (hover shows it whole)
                // and never pushes Dismiss out of reach.
                if ui.small_button("Dismiss").on_hover_text("Dismiss").clicked() {
                    self.session.status = None;
                } else {
                    ui.add(egui::Label::new(egui::RichText::new(&n.text).color(color)).truncate())
                        .on_hover_text(&n.text);
                }
            } else {
                ui.weak("Ready. Draw on the opening (B paint, E erase, R rectangle, O ellipse, L line, F fill).");
            }
        });
    }

    /// Draws one frame (shared by the native window and the test harness).
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        if INTERRUPTED.swap(false, std::sync::atomic::Ordering::Relaxed) {
            self.session.quit_confirmed = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        self.take_results();
        let mut cmds = Vec::new();
        commands::shortcuts(&ctx, &mut cmds);
        egui::Panel::top("menu").show(ui, |ui| self.menu_ui(ui, &mut cmds));
        egui::Panel::bottom("status").show(ui, |ui| self.status_ui(ui));
        if self.view.workspace == Workspace::Phase {
            // Undo and redo act on the phase parameters here; the opening edits do not apply.
            cmds.retain(|c| match c {
                Command::Undo => {
                    self.phase.undo();
                    false
                }
                Command::Redo => {
                    self.phase.redo();
                    false
                }
                Command::Invert
                | Command::Clear
                | Command::Reroll
                | Command::Copy
                | Command::Paste(_) => false,
                _ => true,
            });
            egui::Panel::left("phase_controls")
                .resizable(true)
                .default_size(380.0)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| self.phase.controls_ui(ui));
                });
            egui::Panel::right("phase_numbers")
                .resizable(true)
                .default_size(400.0)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| self.phase.numbers_ui(ui));
                });
            egui::CentralPanel::default().show(ui, |ui| self.phase.views_ui(ui));
            self.dropped_files(&ctx, &mut cmds);
            self.close_request(&ctx, &mut cmds);
            self.confirm_ui(&ctx, &mut cmds);
            self.apply(cmds);
            self.poll_session();
            return;
        }
        if self.view.workspace == Workspace::Sensor {
            egui::Panel::left("sensor_controls")
                .resizable(true)
                .default_size(360.0)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| self.sensor.controls_ui(ui));
                });
            egui::Panel::right("sensor_numbers")
                .resizable(true)
                .default_size(420.0)
                .show(ui, |ui| self.sensor.numbers_ui(ui));
            egui::CentralPanel::default().show(ui, |ui| self.sensor.views_ui(ui));
            self.dropped_files(&ctx, &mut cmds);
            self.close_request(&ctx, &mut cmds);
            self.confirm_ui(&ctx, &mut cmds);
            self.apply(cmds);
            self.poll_session();
            return;
        }
        egui::Panel::left("design")
            .resizable(true)
            .default_size(420.0)
            .show(ui, |ui| self.left_ui(ui, &mut cmds));
        let progress = self.worker.progress();
        egui::Panel::right("numbers")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                let mut pctx = panel_ctx(&self.doc, &self.results, &self.view, &mut cmds);
                ui.heading("Numbers");
                self.panels.numbers.ui(ui, &mut pctx, progress);
            });
        egui::CentralPanel::default().show(ui, |ui| {
            let mut pctx = panel_ctx(&self.doc, &self.results, &self.view, &mut cmds);
            self.panels.views.ui(ui, &mut pctx);
        });
        self.dropped_files(&ctx, &mut cmds);
        self.close_request(&ctx, &mut cmds);
        self.confirm_ui(&ctx, &mut cmds);
        self.panels
            .mask_export
            .ui(&ctx, self.doc.design(), &mut cmds);
        self.apply(cmds);
        self.poll_session();
        if self.title != self.doc.title() {
            self.title = self.doc.title();
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(self.title.clone()));
        }
    }
}

/// What the panels see this frame (disjoint borrows of the app's fields).
fn panel_ctx<'a>(
    doc: &'a Document,
    results: &'a Results,
    view: &'a View,
    commands: &'a mut Vec<Command>,
) -> PanelCtx<'a> {
    PanelCtx {
        design: doc.design(),
        shown: results.shown.as_ref(),
        display: results.display.as_ref(),
        pinned: results.pinned.as_ref(),
        overlays: view.settings.overlays,
        tool: view.tool,
        commands,
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

impl eframe::App for StudioApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame_ui(ui);
    }

    fn on_exit(&mut self) {
        self.autosave_now_blocking();
        self.phase.save_now_blocking();
        let _ = self.view.settings.save(&self.session.dirs);
    }
}
