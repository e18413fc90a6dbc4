//! Every action of the studio is a `Command`: menus, shortcuts and buttons push one, and the app
//! applies them once per frame. That keeps every action reachable from the keyboard and testable.

use egui::{Key, KeyboardShortcut, Modifiers};

use crate::core::Design;

/// Drawing tools of the opening editor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Tool {
    #[default]
    Paint,
    Erase,
    Rect,
    Ellipse,
    Line,
    Fill,
}

impl Tool {
    pub const ALL: [Tool; 6] = [
        Tool::Paint,
        Tool::Erase,
        Tool::Rect,
        Tool::Ellipse,
        Tool::Line,
        Tool::Fill,
    ];

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
    PsfExr,
    PsfPng16,
    LogPsfPng,
    MtfCsv,
    NumbersJson,
}

impl ExportKind {
    pub const ALL: [ExportKind; 5] = [
        ExportKind::PsfExr,
        ExportKind::PsfPng16,
        ExportKind::LogPsfPng,
        ExportKind::MtfCsv,
        ExportKind::NumbersJson,
    ];

    pub fn label(self) -> &'static str {
        match self {
            ExportKind::PsfExr => "PSF (float EXR)…",
            ExportKind::PsfPng16 => "PSF (16-bit PNG)…",
            ExportKind::LogPsfPng => "log-PSF (PNG)…",
            ExportKind::MtfCsv => "MTF (CSV)…",
            ExportKind::NumbersJson => "Numbers (JSON)…",
        }
    }

    pub fn extension(self) -> &'static str {
        match self {
            ExportKind::PsfExr => "exr",
            ExportKind::PsfPng16 | ExportKind::LogPsfPng => "png",
            ExportKind::MtfCsv => "csv",
            ExportKind::NumbersJson => "json",
        }
    }
}

#[derive(Debug, Clone)]
pub enum Command {
    /// A committed design change (one undo step).
    Edit(Box<Design>),
    Undo,
    Redo,
    New,
    Open,
    /// Open a specific file (recent files, drag and drop, tests).
    OpenPath(std::path::PathBuf),
    Save,
    SaveAs,
    LoadPreset(String),
    ImportPattern,
    /// Import an opening from this file (an image, or the axis pixel of a GDSII/DXF mask).
    ImportOpening(std::path::PathBuf),
    /// Load a spectral response CSV and sample it every given step (nm).
    LoadSpectral(f64),
    Export(ExportKind),
    /// Open the Export-mask dialog.
    ExportMask,
    /// Write the mask with the dialog's options: to this file, or ask for one first.
    WriteMask(Option<std::path::PathBuf>),
    SetTool(Tool),
    Invert,
    Clear,
    /// Copy the opening to the clipboard as text rows (`#` open, `.` closed).
    Copy,
    /// Paste an opening from text rows.
    Paste(String),
    Reroll,
    PinCompare,
    ClearCompare,
    ToggleTheme,
    ToggleOverlays,
    Quit,
}

pub const UNDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
pub const REDO: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
pub const REDO_Y: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Y);
pub const NEW: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::N);
pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
pub const SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
pub const SAVE_AS: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::S);
pub const INVERT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::I);
pub const CLEAR: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::Delete);
pub const REROLL: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F5);
pub const PIN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::P);
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
