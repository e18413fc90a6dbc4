//! Every action of the studio is a `Command`: menus, shortcuts and buttons push one, and the app
//! applies them once per frame. That keeps every action reachable from the keyboard and testable.

use egui::{Key, KeyboardShortcut, Modifiers};

use crate::core::Design;
use crate::core::design::Optics;

/// Drawing tools of the opening editor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Tool {
    /// Drag to open cells with the brush; right-drag closes them.
    #[default]
    Paint,
    /// Drag to close cells with the brush; right-drag opens them.
    Erase,
    /// Drag a filled rectangle of open cells (right-drag: closed).
    Rect,
    /// Drag a filled ellipse inscribed in the dragged box (right-drag: closed).
    Ellipse,
    /// Drag a straight line as wide as the brush (right-drag: closed).
    Line,
    /// Click to open the connected region of equal cells (right-click: close it).
    Fill,
}

impl Tool {
    /// Every tool, in toolbar order.
    pub const ALL: [Tool; 6] = [
        Tool::Paint,
        Tool::Erase,
        Tool::Rect,
        Tool::Ellipse,
        Tool::Line,
        Tool::Fill,
    ];

    /// Name shown on the toolbar button and in tooltips.
    pub fn label(self) -> &'static str {
        match self {
            Tool::Paint => "Paint",
            Tool::Erase => "Erase",
            Tool::Rect => "Rectangle",
            Tool::Ellipse => "Ellipse",
            Tool::Line => "Line",
            Tool::Fill => "Fill",
        }
    }

    /// Single-key shortcut that selects the tool (no modifier; ignored while typing in a field).
    pub fn key(self) -> Key {
        match self {
            Tool::Paint => Key::B,
            Tool::Erase => Key::E,
            Tool::Rect => Key::R,
            Tool::Ellipse => Key::O,
            Tool::Line => Key::L,
            Tool::Fill => Key::F,
        }
    }
}

/// What the studio can export from the current result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportKind {
    /// The sensor PSF as a float OpenEXR image (RGB for three channels, else the first channel).
    PsfExr,
    /// The sensor PSF as a 16-bit PNG, one file per colour channel.
    PsfPng16,
    /// The log-scaled PSF as an 8-bit PNG, one file per colour channel.
    LogPsfPng,
    /// The MTF table as CSV: horizontal and vertical slices, radial min and mean per channel.
    MtfCsv,
    /// The analysis numbers as JSON, the same object `analyze --json` prints.
    NumbersJson,
}

impl ExportKind {
    /// Every export, in the order of the File > Export menu.
    pub const ALL: [ExportKind; 5] = [
        ExportKind::PsfExr,
        ExportKind::PsfPng16,
        ExportKind::LogPsfPng,
        ExportKind::MtfCsv,
        ExportKind::NumbersJson,
    ];

    /// Menu entry text, ending in an ellipsis because it opens a save dialog.
    pub fn label(self) -> &'static str {
        match self {
            ExportKind::PsfExr => "PSF (float EXR)…",
            ExportKind::PsfPng16 => "PSF (16-bit PNG)…",
            ExportKind::LogPsfPng => "log-PSF (PNG)…",
            ExportKind::MtfCsv => "MTF (CSV)…",
            ExportKind::NumbersJson => "Numbers (JSON)…",
        }
    }

    /// File extension (without the dot) the save dialog suggests.
    pub fn extension(self) -> &'static str {
        match self {
            ExportKind::PsfExr => "exr",
            ExportKind::PsfPng16 | ExportKind::LogPsfPng => "png",
            ExportKind::MtfCsv => "csv",
            ExportKind::NumbersJson => "json",
        }
    }
}

/// One user action, queued by a menu, shortcut or button and applied at the end of the frame.
///
/// The shell handles the theme, overlay and quit commands itself; the rest go to the active
/// workspace.
#[derive(Debug, Clone)]
pub enum Command {
    /// A committed design change (one undo step).
    Edit(Box<Design>),
    /// Replace the design's optics, keeping the rest (one undo step): the Apply button of a
    /// sampling warning's advice.
    SetOptics(Optics),
    /// Step back one design change.
    Undo,
    /// Re-apply the design change last undone.
    Redo,
    /// Start over from the default preset (asks first if there are unsaved changes).
    New,
    /// Ask for a design file to open (asks first if there are unsaved changes).
    Open,
    /// Open this design, built elsewhere (a sweep row's), as a new unsaved document: one undo
    /// step; asks first if there are unsaved changes. `what` names it for the status bar.
    OpenDesign {
        /// The design.
        design: Box<Design>,
        /// Where it came from ("point 3 of sweep `tiny`").
        what: String,
    },
    /// Open the 1-D sweep window for this field of the current design.
    SweepField(crate::core::sweep::field::SweepField),
    /// Open a specific file (recent files, drag and drop, tests).
    OpenPath(std::path::PathBuf),
    /// Save to the current file, or ask for one when the design has never been saved.
    Save,
    /// Ask for a file name and save the design there.
    SaveAs,
    /// Replace the design with the named built-in preset (asks first if there are unsaved changes).
    LoadPreset(String),
    /// Ask for an image or GDSII/DXF mask and import it as the opening.
    ImportPattern,
    /// Import an opening from this file (an image, or the axis pixel of a GDSII/DXF mask).
    ImportOpening(std::path::PathBuf),
    /// Load a spectral response CSV and sample it every given step (nm).
    LoadSpectral(f64),
    /// Ask for a file and write this export of the result on screen.
    Export(ExportKind),
    /// Open the Export-mask dialog.
    ExportMask,
    /// Write the mask with the dialog's options: to this file, or ask for one first.
    WriteMask(Option<std::path::PathBuf>),
    /// Select this drawing tool in the opening editor.
    SetTool(Tool),
    /// Swap open and closed cells of the opening (one undo step).
    Invert,
    /// Close every cell of the opening (one undo step).
    Clear,
    /// Copy the opening to the clipboard as text rows (`#` open, `.` closed).
    Copy,
    /// Paste an opening from text rows.
    Paste(String),
    /// Draw a new random seed for the random tilings (has no visible effect on a periodic tiling).
    Reroll,
    /// Pin the current design and result as "A" for the Compare view; waits for the full-quality
    /// result if it is not ready yet.
    PinCompare,
    /// Forget the pinned design "A".
    ClearCompare,
    /// Switch between the dark and the light theme (saved in the settings).
    ToggleTheme,
    /// Show or hide the teaching overlays and hints (saved in the settings).
    ToggleOverlays,
    /// Show or hide the design-rule rings on the opening editor (saved in the settings).
    ToggleDesignRules,
    /// Close the window, asking first if a workspace has unsaved changes.
    Quit,
}

/// Ctrl+Z (Cmd+Z on macOS): undo.
pub const UNDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
/// Ctrl+Shift+Z (Cmd+Shift+Z on macOS): redo.
pub const REDO: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
/// Ctrl+Y (Cmd+Y on macOS): the alternative redo shortcut.
pub const REDO_Y: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Y);
/// Ctrl+N (Cmd+N on macOS): new design.
pub const NEW: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::N);
/// Ctrl+O (Cmd+O on macOS): open a design file.
pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
/// Ctrl+S (Cmd+S on macOS): save.
pub const SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
/// Ctrl+Shift+S (Cmd+Shift+S on macOS): save as.
pub const SAVE_AS: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::S);
/// I: invert the opening (only when no text field has focus).
pub const INVERT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::I);
/// Delete: clear the opening (only when no text field has focus).
pub const CLEAR: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::Delete);
/// F5: reroll the random tiling's seed (only when no text field has focus).
pub const REROLL: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F5);
/// Ctrl+P (Cmd+P on macOS): pin the current design as A for Compare.
pub const PIN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::P);
/// Ctrl+Q (Cmd+Q on macOS): quit.
pub const QUIT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Q);

/// Reads keyboard shortcuts into commands. Single-key tool shortcuts only fire when no text
/// field has focus.
pub fn shortcuts(ctx: &egui::Context, out: &mut Vec<Command>) {
    let typing = ctx.memory(|m| m.focused().is_some());
    ctx.input_mut(|i| {
        // Longest modifier sets first, so Ctrl+Shift+Z is not read as Ctrl+Z.
        if i.consume_shortcut(&REDO) || i.consume_shortcut(&REDO_Y) {
            out.push(Command::Redo);
        }
        if i.consume_shortcut(&UNDO) {
            out.push(Command::Undo);
        }
        if i.consume_shortcut(&SAVE_AS) {
            out.push(Command::SaveAs);
        }
        if i.consume_shortcut(&SAVE) {
            out.push(Command::Save);
        }
        if i.consume_shortcut(&NEW) {
            out.push(Command::New);
        }
        if i.consume_shortcut(&OPEN) {
            out.push(Command::Open);
        }
        if i.consume_shortcut(&PIN) {
            out.push(Command::PinCompare);
        }
        if i.consume_shortcut(&QUIT) {
            out.push(Command::Quit);
        }
        if !typing {
            if i.consume_shortcut(&REROLL) {
                out.push(Command::Reroll);
            }
            if i.consume_shortcut(&INVERT) {
                out.push(Command::Invert);
            }
            if i.consume_shortcut(&CLEAR) {
                out.push(Command::Clear);
            }
            for tool in Tool::ALL {
                if i.consume_shortcut(&KeyboardShortcut::new(Modifiers::NONE, tool.key())) {
                    out.push(Command::SetTool(tool));
                }
            }
        }
    });
    // The integrations turn Ctrl+C / Ctrl+V into Copy / Paste events rather than key presses.
    if !typing {
        ctx.input(|i| {
            for e in &i.events {
                match e {
                    egui::Event::Copy => out.push(Command::Copy),
                    egui::Event::Paste(text) => out.push(Command::Paste(text.clone())),
                    _ => {}
                }
            }
        });
    }
}
