//! The studio (egui/eframe). The only module that touches egui.
//!
//! `StudioApp` is the shell: it owns the list of [`Workspace`]s (display layouts, phase masks,
//! sensor previewer, sweep results), the menu bar, the status bar, the unsaved-changes prompt and
//! the settings. Every frame it reads its own shortcuts and lets the active workspace read its
//! own, draws the menus, applies its own [`ShellCommand`]s (undo, theme, switch, quit…), draws
//! the active workspace (which takes its finished jobs and draws its panels), then has the
//! workspace carry out the actions it queued ([`Workspace::apply`]) and hands on the requests one
//! workspace sent another ([`Shell::send`]).

pub mod autosave;
pub mod commands;
pub mod compute;
pub mod dialogs;
pub mod display;
pub mod error;
pub mod history;
pub mod icon;
pub mod job;
pub mod lessons;
mod menu;
pub mod notice;
pub mod phase;
pub mod presentation;
pub mod reproduce;
pub mod save_figure;
pub mod sensor;
pub mod settings;
pub mod study_start;
pub mod sweep;
pub mod widgets;
pub mod workspace;

use crate::app::notice::Notice;
use std::path::PathBuf;
use std::time::Duration;

use anyhow::Result;

pub use commands::ShellCommand;
pub use display::panels;
pub use display::{
    DisplayAction, DisplayWorkspace, Document, ExportKind, JobResult, LeftTab, Payload, Tool,
    Worker,
};
pub use settings::{AppDirs, Settings};
use workspace::Pending;
pub use workspace::{DroppedKind, Request, Shell, Workspace, WorkspaceId};

/// How often the design is autosaved while it changes.
pub const AUTOSAVE_EVERY: Duration = Duration::from_secs(3);

/// How the studio starts.
pub struct StudioOptions {
    /// Where settings and autosaves live.
    pub dirs: AppDirs,
    /// Open this file instead of restoring the autosave.
    pub design_path: Option<PathBuf>,
    /// Native file dialogs (off in tests, where nothing may block).
    pub native_dialogs: bool,
    /// How often the design is autosaved while it changes.
    pub autosave_every: Duration,
    /// The window's GPU (eframe's wgpu device), for View ▸ Compute PSFs on; `None` where the
    /// window does not draw with wgpu, and in tests that do not hand one in.
    pub gpu: Option<std::sync::Arc<udc_gpu::Gpu>>,
}

/// Opens the studio window with `design_path` (or the last session's design, or the default).
///
/// # Errors
/// When no window can be created (no display).
pub fn run_studio(design_path: Option<PathBuf>) -> Result<()> {
    let mut viewport = egui::ViewportBuilder::default()
        .with_title("UDC Studio")
        .with_inner_size([1440.0, 900.0])
        .with_min_inner_size([900.0, 600.0]);
    if let Some(icon) = icon::window_icon() {
        viewport = viewport.with_icon(icon);
    }
    let mut options = eframe::NativeOptions {
        viewport,
        ..Default::default()
    };
    // The kernels' device lives on the window's instance: give it the driver's memory budget
    // (Vulkan's VK_EXT_memory_budget, D3D12), as the headless device has.
    if let eframe::egui_wgpu::WgpuSetup::CreateNew(setup) = &mut options.wgpu_options.wgpu_setup {
        setup.instance_descriptor.memory_budget_thresholds = udc_gpu::device::WINDOW_MEMORY_BUDGET;
    }
    let mut studio = StudioOptions {
        dirs: AppDirs::platform(),
        design_path,
        native_dialogs: true,
        autosave_every: AUTOSAVE_EVERY,
        gpu: None,
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
            studio.gpu = window_gpu(cc);
            Ok(Box::new(StudioApp::new(&cc.egui_ctx, studio)))
        }),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the studio window: {e}"))
}

/// The compute kernels on the GPU the window draws with, or `None` where eframe does not
/// render with wgpu (or the adapter refuses a second device). A device of its own on the
/// window's adapter, not the window's device: a resize reconfigures the window's surface, which
/// waits for that device's queue to go idle, and a transform of seconds there (a 600-DPI design
/// on a slow GPU; any design on a software driver) made the reconfiguration fail and eframe
/// abort. It is also the process's shared device, which the jobs a study or a quick
/// reproduction runs resolve their `backend` parameter on.
pub fn window_gpu(cc: &eframe::CreationContext<'_>) -> Option<std::sync::Arc<udc_gpu::Gpu>> {
    let rs = cc.wgpu_render_state.as_ref()?;
    let gpu = std::sync::Arc::new(udc_gpu::Gpu::on_adapter(&rs.adapter).ok()?);
    udc_gpu::Gpu::share(&gpu);
    Some(gpu)
}

/// Set by the Ctrl-C / SIGTERM handler; the next frame closes the window.
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// The studio: the workspaces and what they share.
pub struct StudioApp {
    workspaces: Vec<Box<dyn Workspace>>,
    active: WorkspaceId,
    shell: Shell,
    title: String,
    reproduce: reproduce::ReproduceWindow,
    save_figure: save_figure::SaveFigureWindow,
    lessons: lessons::LessonsPanel,
}

impl StudioApp {
    /// Starts the studio: opens `design_path`, or restores the autosave, or the default preset.
    pub fn new(ctx: &egui::Context, options: StudioOptions) -> Self {
        let mut shell = Shell::new(
            ctx.clone(),
            options.dirs,
            options.native_dialogs,
            options.autosave_every,
            options.gpu,
        );
        presentation::apply(ctx, &shell.settings);
        ctx.set_fonts(fonts_with_symbols());
        // The switch shows them in this order.
        let workspaces: Vec<Box<dyn Workspace>> = vec![
            Box::new(DisplayWorkspace::new(&mut shell, options.design_path)),
            Box::new(
                phase::PhaseWorkspace::new(&shell.dirs, shell.native_dialogs, shell.autosave_every)
                    .with_route(shell.compute.shared()),
            ),
            Box::new(sensor::SensorWorkspace::default()),
            Box::new(sweep::SweepWorkspace::default()),
        ];
        let reproduce =
            reproduce::ReproduceWindow::new(shell.dirs.data_dir.as_deref(), shell.native_dialogs);
        let lessons = lessons::LessonsPanel::default().with_route(shell.compute.shared());
        StudioApp {
            workspaces,
            active: WorkspaceId::Display,
            shell,
            title: String::new(),
            reproduce,
            save_figure: save_figure::SaveFigureWindow::default(),
            lessons,
        }
    }

    /// Help ▸ Reproduce thesis results.
    pub fn reproduce(&self) -> &reproduce::ReproduceWindow {
        &self.reproduce
    }

    /// Help ▸ Lessons.
    pub fn lessons(&self) -> &lessons::LessonsPanel {
        &self.lessons
    }

    /// Help ▸ Lessons, to drive.
    pub fn lessons_mut(&mut self) -> &mut lessons::LessonsPanel {
        &mut self.lessons
    }

    /// Checks a prediction in the open lesson against the display workspace's result.
    pub fn check_lesson(
        &mut self,
        guess: crate::core::lesson::measure::Guess,
    ) -> Option<lessons::Verdict> {
        let on = self.on_screen();
        self.lessons.check(&on, guess)
    }

    /// Reveals the open lesson's answer on the display workspace's result.
    pub fn reveal_lesson(&mut self) {
        let on = self.on_screen();
        self.lessons.reveal(&on);
    }

    /// What a lesson measures: the Display workspace's result when it is its design's at full
    /// quality, and the Phase workspace's PSFs when they are its design's.
    fn on_screen(&mut self) -> lessons::OnScreen {
        let display = self
            .display_workspace()
            .filter(|d| d.is_up_to_date())
            .and_then(|d| d.shown().cloned());
        let p = self.ws::<phase::PhaseWorkspace>();
        let phase = p
            .shown()
            .filter(|_| p.is_up_to_date())
            .map(|s| lessons::PhaseShown {
                design: s.design.clone(),
                psfs: s.psfs.clone(),
            });
        lessons::OnScreen { display, phase }
    }

    fn display_workspace(&mut self) -> Option<&mut DisplayWorkspace> {
        self.workspaces
            .iter_mut()
            .find(|w| w.id() == WorkspaceId::Display)
            .and_then(|w| w.as_any_mut().downcast_mut::<DisplayWorkspace>())
    }

    /// Carries out a lesson step's setup: the Display workspace shown, the preset loaded
    /// (asking first if there are unsaved changes), the view selected; or the Phase workspace
    /// shown with its design changed (one undo step).
    fn lesson_setup(&mut self, setup: lessons::Setup) {
        use crate::core::views::saved::DisplayView;
        use display::panels::views::ViewTab;
        if let Some(change) = setup.phase {
            self.active = WorkspaceId::Phase;
            let p = self.ws_mut::<phase::PhaseWorkspace>();
            let changed = change.apply(p.design());
            p.set_design(changed);
            p.show(phase::PhaseView::Psf);
            return;
        }
        if setup.preset.is_none() && setup.change.is_none() && setup.view.is_none() {
            // A step that only says what to look at keeps the workspace on screen.
            return;
        }
        self.active = WorkspaceId::Display;
        let shell = &mut self.shell;
        let Some(d) = self
            .workspaces
            .iter_mut()
            .find(|w| w.id() == WorkspaceId::Display)
            .and_then(|w| w.as_any_mut().downcast_mut::<DisplayWorkspace>())
        else {
            return;
        };
        if let Some(p) = setup.preset {
            d.act(DisplayAction::LoadPreset(p), shell);
        }
        if let Some(c) = setup.change {
            let changed = c.apply(d.design());
            d.act(DisplayAction::Edit(Box::new(changed)), shell);
        }
        if let Some(v) = setup.view {
            d.views().set_tab(match v {
                DisplayView::Psf => ViewTab::Psf,
                DisplayView::LogPsf => ViewTab::LogPsf,
                DisplayView::Rgb => ViewTab::Rgb,
                DisplayView::Mtf2d => ViewTab::Mtf2d,
                DisplayView::Mtf => ViewTab::MtfPlots,
                DisplayView::Theory => ViewTab::Theory,
            });
        }
    }

    /// The Save figure window.
    pub fn save_figure(&self) -> &save_figure::SaveFigureWindow {
        &self.save_figure
    }

    /// The Save figure window, to drive.
    pub fn save_figure_mut(&mut self) -> &mut save_figure::SaveFigureWindow {
        &mut self.save_figure
    }

    /// Help ▸ Reproduce thesis results, to drive.
    pub fn reproduce_mut(&mut self) -> &mut reproduce::ReproduceWindow {
        &mut self.reproduce
    }

    /// The workspace of type `T`: the one way from the shell to a workspace's state (tests
    /// reach each workspace through it; nothing workspace-specific lives in the shell).
    pub fn ws<T: Workspace>(&self) -> &T {
        self.workspaces
            .iter()
            .find_map(|w| w.as_any().downcast_ref::<T>())
            .expect("every workspace type is in the list from the start")
    }

    /// The workspace of type `T`, mutable.
    pub fn ws_mut<T: Workspace>(&mut self) -> &mut T {
        self.workspaces
            .iter_mut()
            .find_map(|w| w.as_any_mut().downcast_mut::<T>())
            .expect("every workspace type is in the list from the start")
    }

    /// Runs `f` on the workspace of type `T` with the shell it edits through (its history's
    /// status line, dialogs, settings): how an action is carried out as its menu item would.
    pub fn ws_with_shell<T: Workspace, R>(&mut self, f: impl FnOnce(&mut T, &mut Shell) -> R) -> R {
        let shell = &mut self.shell;
        let ws = self
            .workspaces
            .iter_mut()
            .find_map(|w| w.as_any_mut().downcast_mut::<T>())
            .expect("every workspace type is in the list from the start");
        f(ws, shell)
    }

    fn workspace_mut(&mut self, id: WorkspaceId) -> &mut dyn Workspace {
        let i = self
            .workspaces
            .iter()
            .position(|w| w.id() == id)
            .unwrap_or(0);
        self.workspaces[i].as_mut()
    }

    /// The status-bar message.
    pub fn status(&self) -> Option<&Notice> {
        self.shell.status()
    }

    /// Runs a shell command as if its menu item or shortcut had been used.
    pub fn command(&mut self, command: ShellCommand) {
        self.apply(command);
    }

    /// The workspace on screen.
    pub fn workspace(&self) -> WorkspaceId {
        self.active
    }

    /// Switches between the workspaces.
    pub fn set_workspace(&mut self, workspace: WorkspaceId) {
        self.active = workspace;
    }

    /// Carries out one of the shell's own commands.
    fn apply(&mut self, command: ShellCommand) {
        match command {
            ShellCommand::Undo => self.workspace_mut(self.active).undo(),
            ShellCommand::Redo => self.workspace_mut(self.active).redo(),
            ShellCommand::ToggleTheme => {
                self.shell.settings.dark = !self.shell.settings.dark;
                presentation::apply(&self.shell.ctx, &self.shell.settings);
                self.shell.save_settings();
            }
            ShellCommand::ToggleLessons => self.lessons.toggle(),
            ShellCommand::OpenLesson => {
                let (ctx, native) = (self.shell.ctx.clone(), self.shell.native_dialogs);
                self.lessons.ask_file(&ctx, native);
            }
            ShellCommand::TogglePresentation => {
                self.shell.settings.presentation = !self.shell.settings.presentation;
                presentation::apply(&self.shell.ctx, &self.shell.settings);
                self.shell.save_settings();
            }
            ShellCommand::ToggleOverlays => {
                self.shell.settings.overlays = !self.shell.settings.overlays;
                self.shell.save_settings();
            }
            ShellCommand::SetBackend(backend) => {
                self.shell.settings.backend = backend;
                self.shell.compute.set(backend);
                self.shell.save_settings();
                self.shell.send(WorkspaceId::Display, Request::Recompute);
            }
            ShellCommand::ToggleDesignRules => {
                self.shell.settings.design_rules = !self.shell.settings.design_rules;
                self.shell.save_settings();
            }
            ShellCommand::Show(id) => self.active = id,
            ShellCommand::OpenReproduce => {
                self.reproduce.open = true;
                self.reproduce.select(self.reproduce.selected());
            }
            ShellCommand::Quit => self.quit(false),
        }
    }

    /// Closes the window, first asking when a workspace has unsaved changes.
    fn quit(&mut self, confirmed: bool) {
        if !confirmed && let Some(ws) = self.workspaces.iter().find(|w| w.is_dirty()) {
            self.shell.confirm = Some((ws.id(), Pending::Quit));
            return;
        }
        self.shell.quit_confirmed = true;
        self.shell
            .ctx
            .send_viewport_cmd(egui::ViewportCommand::Close);
    }

    fn status_ui(&mut self, ui: &mut egui::Ui) {
        let hint = self.workspace_mut(self.active).hint();
        ui.horizontal(|ui| {
            if let Some(n) = self.shell.status() {
                let color = if n.is_error() {
                    ui.visuals().error_fg_color
                } else {
                    ui.visuals().text_color()
                };
                let text = n.text.clone();
                // The button first: a long message is cut to the window (hover shows it whole)
                // and never pushes Dismiss out of reach.
                if ui
                    .small_button("Dismiss")
                    .on_hover_text("Dismiss")
                    .clicked()
                {
                    self.shell.clear_status();
                } else {
                    ui.add(egui::Label::new(egui::RichText::new(&text).color(color)).truncate())
                        .on_hover_text(&text);
                }
            } else {
                ui.weak(hint);
            }
        });
    }

    /// Files dropped on the window go to the active workspace, else to the first that takes
    /// them, which is then shown (an HDR scene dropped on the display opens the sensor).
    fn dropped_files(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        for p in dropped {
            let kind = DroppedKind::of(&p);
            if kind == DroppedKind::Lesson {
                self.lessons.open_file(&p, ctx);
                continue;
            }
            let active = self.active;
            let shell = &mut self.shell;
            let mut order: Vec<&mut Box<dyn Workspace>> = self.workspaces.iter_mut().collect();
            order.sort_by_key(|w| w.id() != active);
            let taker = order
                .into_iter()
                .find_map(|w| w.open_dropped(&p, kind, shell).then(|| w.id()));
            match taker {
                Some(id) => self.active = id,
                None => self
                    .shell
                    .set_status(Notice::error(format!("no workspace opens {}", p.display()))),
            }
        }
    }

    /// The window's close button asks first when there are unsaved changes.
    fn close_request(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested())
            && !self.shell.quit_confirmed
            && self.workspaces.iter().any(|w| w.is_dirty())
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.quit(false);
        }
    }

    /// The unsaved-changes prompt.
    fn confirm_ui(&mut self, ctx: &egui::Context) {
        let Some((id, pending)) = self.shell.confirm else {
            return;
        };
        let what = match pending {
            Pending::Quit => "quitting",
            Pending::Action(leaving_for) => leaving_for,
        };
        let name = self.workspace_mut(id).document_name();
        let can_save = self.workspace_mut(id).can_save_in_place();
        let mut choice = None;
        egui::Modal::new(egui::Id::unique("unsaved-changes")).show(ctx, |ui| {
            ui.heading("Unsaved changes");
            let kept = if pending == Pending::Quit {
                "The autosave brings them back at the next start, but they are in no file of \
                 yours."
            } else {
                "Undo brings them back, but they are in no file of yours."
            };
            ui.label(format!(
                "\"{name}\" has changes that are not saved. {kept} Save before {what}?"
            ));
            ui.horizontal(|ui| {
                if can_save && ui.button("Save").clicked() {
                    choice = Some(UnsavedChoice::Save);
                }
                if !can_save
                    && ui
                        .button("Save as…")
                        .on_hover_text("Choose a file; then do it again")
                        .clicked()
                {
                    choice = Some(UnsavedChoice::SaveAs);
                }
                if ui.button("Don't save").clicked() {
                    choice = Some(UnsavedChoice::Discard);
                }
                if ui.button("Cancel").clicked() || ui.input(|i| i.key_pressed(egui::Key::Escape)) {
                    choice = Some(UnsavedChoice::Cancel);
                }
            });
        });
        let Some(choice) = choice else {
            return;
        };
        self.shell.confirm = None;
        if choice == UnsavedChoice::Cancel {
            return;
        }
        if choice == UnsavedChoice::SaveAs {
            // The dialog answers later: the user repeats what they asked once the file exists.
            self.with_workspace(id, |ws, shell| ws.save_as(shell));
            return;
        }
        if choice == UnsavedChoice::Save {
            self.with_workspace(id, |ws, shell| ws.save(shell));
            if self.workspace_mut(id).is_dirty() {
                // Not saved (cancelled Save-as, or an error in the status bar): stay.
                return;
            }
        }
        match pending {
            Pending::Quit => self.quit(true),
            Pending::Action(_) => self.with_workspace(id, |ws, shell| ws.resume(shell)),
        }
    }

    /// Runs `f` on workspace `id` with the shell lent to it.
    fn with_workspace(&mut self, id: WorkspaceId, f: impl FnOnce(&mut dyn Workspace, &mut Shell)) {
        let shell = &mut self.shell;
        if let Some(ws) = self.workspaces.iter_mut().find(|w| w.id() == id) {
            f(ws.as_mut(), shell);
        }
    }

    /// Draws one frame (shared by the native window and the test harness).
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        if INTERRUPTED.swap(false, std::sync::atomic::Ordering::Relaxed) {
            self.shell.quit_confirmed = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        let mut cmds = Vec::new();
        commands::read_shortcuts(&ctx, &mut cmds);
        self.workspace_mut(self.active).read_shortcuts(&ctx);
        egui::Panel::top("menu").show(ui, |ui| self.menu_ui(ui, &mut cmds));
        for c in cmds {
            self.apply(c);
        }
        egui::Panel::bottom("status").show(ui, |ui| self.status_ui(ui));
        let on = if self.lessons.is_open() {
            self.on_screen()
        } else {
            lessons::OnScreen::default()
        };
        self.lessons.ui(ui, &on, self.shell.native_dialogs);
        if let Some(setup) = self.lessons.take_setup() {
            self.lesson_setup(setup);
        }
        let active = self.active;
        self.with_workspace(active, |ws, shell| ws.ui(ui, shell));
        if let Some(why) = crate::app::widgets::take_refused() {
            self.shell.set_status(Notice::error(why));
        }
        self.dropped_files(&ctx);
        self.close_request(&ctx);
        self.confirm_ui(&ctx);
        self.reproduce.ui(&ctx, self.shell.compute.effective());
        if let Some(request) = crate::app::widgets::figure::take_save_request(&ctx) {
            let caption = self.workspace_mut(self.active).figure_caption();
            self.save_figure.open(request.0, caption);
        }
        if let Some(n) = self.save_figure.ui(&ctx, self.shell.native_dialogs) {
            self.shell.set_status(n);
        }
        // Each workspace carries out what it queued, even if a switch or a drop has just shown
        // another.
        for ws in &mut self.workspaces {
            ws.apply(&mut self.shell);
        }
        for (id, request) in std::mem::take(&mut self.shell.sent) {
            self.with_workspace(id, |ws, shell| ws.request(request, shell));
        }
        if std::mem::take(&mut self.shell.reproduce_asked) {
            self.apply(ShellCommand::OpenReproduce);
        }
        if let Some(id) = self.shell.switch_to.take() {
            self.active = id;
        }
        let title = self.workspace_mut(self.active).title();
        if self.title != title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
    }
}

impl eframe::App for StudioApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame_ui(ui);
    }

    fn on_exit(&mut self) {
        for ws in &mut self.workspaces {
            ws.save_now_blocking();
        }
        let _ = self.shell.settings.save(&self.shell.dirs);
    }
}

/// egui's fonts, with the monospace font behind the proportional one: Ubuntu Light has no
/// superscript minus (e⁻², the reports' electron units) and other symbols Hack draws.
fn fonts_with_symbols() -> egui::FontDefinitions {
    let mut fonts = egui::FontDefinitions::default();
    let mono = fonts
        .families
        .get(&egui::FontFamily::Monospace)
        .and_then(|f| f.first())
        .cloned();
    if let Some(mono) = mono {
        let proportional = fonts
            .families
            .entry(egui::FontFamily::Proportional)
            .or_default();
        if !proportional.contains(&mono) {
            proportional.push(mono);
        }
    }
    fonts
}

/// The answers of the unsaved-changes prompt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum UnsavedChoice {
    /// Save to the document's file, then go on.
    Save,
    /// Ask for a file (the document has none yet); the user repeats the command after.
    SaveAs,
    /// Go on without saving.
    Discard,
    /// Do nothing.
    Cancel,
}
