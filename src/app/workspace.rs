//! The shape every workspace has, and what the shell lends it each frame.
//!
//! A workspace (display layouts, phase masks, sensor previewer, sweep results) owns its
//! document, panels, background jobs, undo history and autosave file. The shell
//! ([`super::StudioApp`]) owns only the list of workspaces, the menu bar, the status bar, the
//! unsaved-changes prompt and the settings; it applies its own commands (undo, theme, switch,
//! quit), draws the active workspace, and has each workspace carry out the actions its own
//! menus, shortcuts and panels queued.
//! Adding a workspace is one folder under `app/`, one [`WorkspaceId`] and one line in
//! [`super::StudioApp::new`].

use std::any::Any;
use std::path::Path;
use std::time::Duration;

use super::notice::Notice;
use super::settings::{AppDirs, Settings};
use crate::core::Design;

/// The studio's workspaces: display layouts (chapter 3), phase masks (chapter 4), the sensor
/// previewer (chapter 5) and a sweep's results (issue 19).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorkspaceId {
    /// Draw, tile, analyse, restore and optimize a display pixel's opening.
    Display,
    /// Folded double microlens arrays around a T-OLED.
    Phase,
    /// Spatially-varying gain and binning on HDR scenes.
    Sensor,
    /// The table and plots of a sweep's results folder (issue 19).
    Sweep,
}

/// A workspace of the studio.
pub trait Workspace: Any {
    /// Which one it is.
    fn id(&self) -> WorkspaceId;
    /// Its name in the workspace switch.
    fn label(&self) -> &'static str;
    /// The switch's tooltip: what it is for.
    fn about(&self) -> &'static str;
    /// The status bar's line when there is no message: how to start.
    fn hint(&self) -> &'static str;
    /// A short tour for the Help menu: what to do first and where the results are.
    fn tour(&self) -> &'static [&'static str];
    /// Its keyboard shortcuts (keys, action), for the Help menu.
    fn shortcuts(&self) -> &'static [(&'static str, &'static str)];
    /// Reads its own keyboard shortcuts into its queue while it is shown; called before
    /// anything is drawn, right after the shell has read its own.
    fn read_shortcuts(&mut self, _ctx: &egui::Context) {}
    /// Takes finished background work and draws its panels (side panels, then the centre) into
    /// `ui`; panels queue what they want done in the workspace.
    fn ui(&mut self, ui: &mut egui::Ui, shell: &mut Shell);
    /// Carries out what its panels, menus and shortcuts queued this frame (the shell calls it
    /// once per frame, after drawing).
    fn apply(&mut self, _shell: &mut Shell) {}
    /// Steps back one change (Edit ▸ Undo, Ctrl+Z).
    fn undo(&mut self) {}
    /// Re-applies the change last undone (Edit ▸ Redo, Ctrl+Shift+Z).
    fn redo(&mut self) {}
    /// Whether Undo / Redo would change something.
    fn can_undo(&self) -> bool;
    /// See [`Workspace::can_undo`].
    fn can_redo(&self) -> bool;
    /// Its entries at the top of the File menu (the shell adds Quit).
    fn file_menu_ui(&mut self, _ui: &mut egui::Ui, _shell: &Shell) {}
    /// Its entries in the Edit menu, below Undo and Redo.
    fn edit_menu_ui(&mut self, _ui: &mut egui::Ui) {}
    /// Menus of its own, after Edit.
    fn menus_ui(&mut self, _ui: &mut egui::Ui) {}
    /// Takes a file dropped on the window if it opens files of that kind (the shell decides the
    /// kind once, [`DroppedKind::of`]); returns whether it did.
    fn open_dropped(&mut self, _path: &Path, _kind: DroppedKind, _shell: &mut Shell) -> bool {
        false
    }
    /// Carries out what another workspace asked of it ([`Shell::send`]); a request it has no
    /// use for is ignored.
    fn request(&mut self, _request: Request, _shell: &mut Shell) {}
    /// Changes that are in no file yet (the unsaved-changes prompt asks before losing them).
    fn is_dirty(&self) -> bool {
        false
    }
    /// Whether Save writes to a known file without asking (the prompt then offers Save).
    fn can_save_in_place(&self) -> bool {
        false
    }
    /// Saves to its file (the unsaved-changes prompt's Save).
    fn save(&mut self, _shell: &mut Shell) {}
    /// Asks for a file to save to (the prompt's Save as…, when there is no file yet).
    fn save_as(&mut self, _shell: &mut Shell) {}
    /// Carries out the action it held for the unsaved-changes prompt ([`Shell::confirm`]), now
    /// that the user chose to go on.
    fn resume(&mut self, _shell: &mut Shell) {}
    /// The document's name for the prompt and the window title.
    fn document_name(&self) -> String {
        self.label().to_string()
    }
    /// The caption a figure saved from it carries: what is shown, with its parameters.
    fn figure_caption(&self) -> String {
        self.document_name()
    }
    /// The window title while it is shown.
    fn title(&self) -> String {
        format!("{} — UDC Studio", self.label())
    }
    /// Writes its autosave now (on exit).
    fn save_now_blocking(&mut self) {}
    /// For the shell's typed accessors.
    fn as_any(&self) -> &dyn Any;
    /// For the shell's typed accessors.
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// What one workspace asks of another through the shell ([`Shell::send`]).
#[derive(Debug, Clone)]
pub enum Request {
    /// Compute the current design again (the PSFs' backend changed).
    Recompute,
    /// Open this design, built elsewhere (a sweep row's), as a new unsaved document of the
    /// display workspace: one undo step there; it asks first if there are unsaved changes.
    OpenDesign {
        /// The design.
        design: Box<Design>,
        /// Where it came from ("point 3 of sweep `tiny`"), for the status bar.
        what: String,
    },
    /// Open New study… for this design (the Sweep workspace), with its times on screen and
    /// the Restore view's settings.
    NewStudy {
        /// The design and what the study takes from its workspace.
        start: Box<crate::app::study_start::StudyStart>,
        /// One field to vary alone ("Study this parameter…"); `None`: the dialog's start.
        field: Option<crate::core::sweep::one_axis::SweepParameter>,
    },
    /// Open this phase-mask design (a study point's) in the Phase workspace, as one undo step
    /// there.
    OpenPhaseDesign {
        /// The design.
        design: Box<crate::core::phase::PhaseDesign>,
        /// Where it came from, for the status bar.
        what: String,
    },
    /// Pin this display design (a study point's) as A for Compare: the Display workspace
    /// analyses it at full quality and pins it, the current design untouched.
    PinDesign {
        /// The design.
        design: Box<Design>,
        /// Where it came from, for the status bar.
        what: String,
    },
    /// Send the current design to the Sweep workspace's New study… (the Display workspace).
    StudyCurrentDesign,
}

/// What waits for the answer of the unsaved-changes prompt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Pending {
    /// Closing the window.
    Quit,
    /// An action the workspace holds until the answer ([`Workspace::resume`]); what it leaves
    /// the changes for, as the prompt asks it ("loading the preset").
    Action(&'static str),
}

/// What the shell lends a workspace: where files live, the settings, and the status bar.
pub struct Shell {
    /// The egui context, to wake the UI from jobs and copy to the clipboard.
    pub ctx: egui::Context,
    /// Where settings and autosaves live.
    pub dirs: AppDirs,
    /// Native file dialogs (off in tests, where nothing may block).
    pub native_dialogs: bool,
    /// How often documents are autosaved while they change.
    pub autosave_every: Duration,
    /// Persisted view settings (theme, overlays, recent files).
    pub settings: Settings,
    status: Option<Notice>,
    /// The status is a simulation's error, which its next good result clears.
    status_is_simulation_error: bool,
    /// A workspace asks to be shown (a dropped HDR file goes to the sensor previewer).
    pub(super) switch_to: Option<WorkspaceId>,
    /// What waits for the unsaved-changes answer, and whose changes the prompt is about.
    pub(super) confirm: Option<(WorkspaceId, Pending)>,
    /// Where the display's PSFs are computed (View ▸ Compute PSFs on).
    pub compute: crate::app::compute::Compute,
    /// The user chose to quit: the window closes without asking again.
    pub(super) quit_confirmed: bool,
    /// Requests a workspace sends to another (a sweep row's design to the display).
    pub(super) sent: Vec<(WorkspaceId, Request)>,
    /// A workspace asked for Help ▸ Reproduce thesis results (the Sweep workspace's empty
    /// state).
    pub(super) reproduce_asked: bool,
}

impl Shell {
    pub(super) fn new(
        ctx: egui::Context,
        dirs: AppDirs,
        native_dialogs: bool,
        autosave_every: Duration,
        gpu: Option<std::sync::Arc<udc_gpu::Gpu>>,
    ) -> Self {
        let settings = Settings::load(&dirs);
        Shell {
            ctx,
            dirs,
            native_dialogs,
            autosave_every,
            compute: crate::app::compute::Compute::new(gpu, settings.backend),
            settings,
            status: None,
            status_is_simulation_error: false,
            switch_to: None,
            confirm: None,
            quit_confirmed: false,
            sent: Vec::new(),
            reproduce_asked: false,
        }
    }

    /// The status bar's message.
    pub fn status(&self) -> Option<&Notice> {
        self.status.as_ref()
    }

    /// Shows a message in the status bar.
    pub fn set_status(&mut self, notice: Notice) {
        self.status = Some(notice);
        self.status_is_simulation_error = false;
    }

    /// Removes the status bar's message.
    pub fn clear_status(&mut self) {
        self.status = None;
        self.status_is_simulation_error = false;
    }

    /// Shows a simulation's error; [`Shell::simulation_ok`] clears it.
    pub fn set_simulation_error(&mut self, notice: Notice) {
        self.status = Some(notice);
        self.status_is_simulation_error = true;
    }

    /// A good result answers the simulation's own error, not the other messages (a file kept
    /// aside, a failed save) the user has not read yet.
    pub fn simulation_ok(&mut self) {
        if self.status_is_simulation_error {
            self.clear_status();
        }
    }

    /// Asks the unsaved-changes question of workspace `id` before an action it holds, which
    /// would leave the changes for `leaving_for` ("loading the preset"); if the user goes on,
    /// the shell calls its [`Workspace::resume`].
    pub fn confirm(&mut self, id: WorkspaceId, leaving_for: &'static str) {
        self.confirm = Some((id, Pending::Action(leaving_for)));
    }

    /// Shows workspace `id` at the end of the frame.
    pub fn show(&mut self, id: WorkspaceId) {
        self.switch_to = Some(id);
    }

    /// Hands `request` to workspace `id` at the end of the frame and shows that workspace
    /// (the Sweep workspace opens a row's design in the display's document, undoable there).
    /// Opens Help ▸ Reproduce thesis results after this frame's workspaces.
    pub fn open_reproduce(&mut self) {
        self.reproduce_asked = true;
    }

    /// Sends `request` to workspace `id` and shows it.
    pub fn send(&mut self, id: WorkspaceId, request: Request) {
        self.sent.push((id, request));
        self.switch_to = Some(id);
    }

    /// Writes the settings; a failure is reported in the status bar.
    pub fn save_settings(&mut self) {
        if let Err(e) = self.settings.save(&self.dirs) {
            self.set_status(Notice::error(format!("cannot save settings: {e}")));
        }
    }

    /// A callback that wakes the UI (for jobs).
    pub fn waker(&self) -> impl Fn() + Send + 'static {
        let ctx = self.ctx.clone();
        move || ctx.request_repaint()
    }
}

/// A side panel's width: `share` of the window's `total` width, within `min..=max` px, so
/// that at 1024 px the centre keeps about half the window and at 4K the panels stop growing.
/// Wide content scrolls or wraps inside it instead of pushing the panel over the centre; the
/// user may drag it narrower.
pub fn side_panel(panel: egui::Panel, total: f32, share: f32, min: f32, max: f32) -> egui::Panel {
    let width = (total * share).clamp(min, max);
    panel
        .resizable(true)
        .default_size(width)
        .size_range(min.min(width)..=width)
}

/// Below this window width the controls and the numbers share one side panel, as two tabs,
/// so the views in the centre keep more than half the window.
pub const NARROW_PX: f32 = 1280.0;

/// The layout the workspaces share: controls on the left and numbers on the right, both
/// scrolling and sized to the window (see [`side_panel`]), the views in the centre; in a window
/// narrower than [`NARROW_PX`] the controls and the numbers are two tabs of the left panel.
/// Each part is a method of the workspace; none of them may be what polls its jobs, since a
/// tab that is not shown is not drawn.
pub fn three_panels<W>(
    ws: &mut W,
    ui: &mut egui::Ui,
    left: (&'static str, fn(&mut W, &mut egui::Ui)),
    right: (&'static str, fn(&mut W, &mut egui::Ui)),
    centre: fn(&mut W, &mut egui::Ui),
) {
    let total = ui.available_width();
    let (left_id, draw_left) = left;
    let (right_id, draw_right) = right;
    if total < NARROW_PX {
        let tab_id = egui::Id::unique((left_id, "numbers tab"));
        let mut numbers: bool = ui.data(|d| d.get_temp(tab_id)).unwrap_or(false);
        side_panel(egui::Panel::left(left_id), total, 0.36, 280.0, 460.0).show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.selectable_value(&mut numbers, false, "Controls");
                ui.selectable_value(&mut numbers, true, "Numbers");
            });
            ui.separator();
            egui::ScrollArea::both().show(ui, |ui| {
                if numbers {
                    draw_right(ws, ui);
                } else {
                    draw_left(ws, ui);
                }
            });
        });
        ui.data_mut(|d| d.insert_temp(tab_id, numbers));
    } else {
        side_panel(egui::Panel::left(left_id), total, 0.3, 300.0, 420.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| draw_left(ws, ui))
        });
        // Wide tables scroll sideways inside the panel instead of spilling out of it.
        side_panel(egui::Panel::right(right_id), total, 0.26, 300.0, 440.0).show(ui, |ui| {
            egui::ScrollArea::both().show(ui, |ui| draw_right(ws, ui))
        });
    }
    egui::CentralPanel::default().show(ui, |ui| centre(ws, ui));
}

/// What a file dropped on the window is. The shell decides it once and offers the file to the
/// workspaces (the active one first); each workspace names only the kinds it opens.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DroppedKind {
    /// A sweep's results folder, or its `sweep.json` or `results.csv`.
    SweepResults,
    /// An HDR scene: Radiance `.hdr` or OpenEXR `.exr`.
    HdrScene,
    /// A design file (`.json`).
    Design,
    /// A photograph or a pattern: PNG, JPEG or TIFF.
    Image,
    /// A CSV table (a spectral response).
    Table,
    /// A photolithography mask: GDSII, OASIS or DXF.
    Mask,
    /// A measured PSF set (`.npy`, as `psf import` writes it).
    PsfSet,
    /// A lesson (`.toml` saying `format = "udc-studio-lesson"`): the shell opens it.
    Lesson,
    /// Anything else.
    Unknown,
}

/// Whether the TOML file at `path` says it is a lesson (in its first kilobyte).
fn is_lesson(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 1024];
    let n = std::fs::File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .unwrap_or(0);
    String::from_utf8_lossy(&head[..n]).contains("udc-studio-lesson")
}

impl DroppedKind {
    /// The kind of `path`, from its extension (a sweep's results by the `sweep.json` beside it).
    pub fn of(path: &Path) -> DroppedKind {
        use crate::io::sweep::manifest::{MANIFEST_FILE, results_dir};
        if results_dir(path).is_some_and(|d| d.join(MANIFEST_FILE).exists()) {
            return DroppedKind::SweepResults;
        }
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "hdr" | "exr" => DroppedKind::HdrScene,
            "json" => DroppedKind::Design,
            "png" | "jpg" | "jpeg" | "tif" | "tiff" => DroppedKind::Image,
            "csv" => DroppedKind::Table,
            "gds" | "gds2" | "gdsii" | "oas" | "oasis" | "dxf" => DroppedKind::Mask,
            "npy" => DroppedKind::PsfSet,
            "toml" if is_lesson(path) => DroppedKind::Lesson,
            _ => DroppedKind::Unknown,
        }
    }
}
