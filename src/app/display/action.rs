//! The display workspace's own actions: every menu entry, shortcut and button of the workspace
//! queues a [`DisplayAction`], and the workspace carries them out once per frame, so every
//! action is reachable from the keyboard and testable. Undo, redo, the theme and quitting are
//! the shell's ([`crate::app::ShellCommand`]).

use egui::{Key, KeyboardShortcut, Modifiers};

pub use crate::app::dialogs::ExportKind;
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

/// One action of the display workspace, queued by its menus, shortcuts and panels and carried
/// out at the end of the frame (after the shell's own commands, [`crate::app::ShellCommand`]).
#[derive(Debug, Clone)]
pub enum DisplayAction {
    /// A committed design change (one undo step).
    Edit(Box<Design>),
    /// Replace the design's optics, keeping the rest (one undo step): the Apply button of a
    /// sampling warning's advice.
    SetOptics(Optics),
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
    SweepParameter(crate::core::sweep::one_axis::SweepParameter),
    /// Open New study… in the Sweep workspace for the current design: with every axis the
    /// dialog starts with, or this one field alone.
    NewStudy(Option<crate::core::sweep::one_axis::SweepParameter>),
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
}

impl DisplayAction {
    /// What the action would leave the unsaved design for, as the unsaved-changes prompt asks
    /// it ("Save before loading the preset?").
    pub(super) fn leaving_for(&self) -> &'static str {
        match self {
            DisplayAction::New => "starting a new design",
            DisplayAction::LoadPreset(_) => "loading the preset",
            _ => "opening another design",
        }
    }
}

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
/// Reads the workspace's keyboard shortcuts into actions. Single-key shortcuts only fire when no
/// text field has focus.
pub fn read_shortcuts(ctx: &egui::Context, out: &mut Vec<DisplayAction>) {
    let typing = ctx.memory(|m| m.focused().is_some());
    ctx.input_mut(|i| {
        // Longest modifier sets first, so Ctrl+Shift+S is not read as Ctrl+S.
        if i.consume_shortcut(&SAVE_AS) {
            out.push(DisplayAction::SaveAs);
        }
        if i.consume_shortcut(&SAVE) {
            out.push(DisplayAction::Save);
        }
        if i.consume_shortcut(&NEW) {
            out.push(DisplayAction::New);
        }
        if i.consume_shortcut(&OPEN) {
            out.push(DisplayAction::Open);
        }
        if i.consume_shortcut(&PIN) {
            out.push(DisplayAction::PinCompare);
        }
        if !typing {
            if i.consume_shortcut(&REROLL) {
                out.push(DisplayAction::Reroll);
            }
            if i.consume_shortcut(&INVERT) {
                out.push(DisplayAction::Invert);
            }
            if i.consume_shortcut(&CLEAR) {
                out.push(DisplayAction::Clear);
            }
            for tool in Tool::ALL {
                if i.consume_shortcut(&KeyboardShortcut::new(Modifiers::NONE, tool.key())) {
                    out.push(DisplayAction::SetTool(tool));
                }
            }
        }
    });
    // The integrations turn Ctrl+C / Ctrl+V into Copy / Paste events rather than key presses.
    if !typing {
        ctx.input(|i| {
            for e in &i.events {
                match e {
                    egui::Event::Copy => out.push(DisplayAction::Copy),
                    egui::Event::Paste(text) => out.push(DisplayAction::Paste(text.clone())),
                    _ => {}
                }
            }
        });
    }
}
