//! The shell's own commands: what the menu bar and the shell's shortcuts ask for whichever
//! workspace is shown (undo and redo of that workspace, the theme and the other View settings,
//! switching workspaces, Help windows, quitting). A workspace's own actions are its own enum,
//! queued and carried out by the workspace ([`crate::app::DisplayAction`]).

use egui::{Key, KeyboardShortcut, Modifiers};

use super::workspace::WorkspaceId;

/// One command of the shell, queued by the menu bar or a shortcut and applied before the
/// workspace draws, so a switch or an undo shows in the same frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShellCommand {
    /// Step back one change of the shown workspace.
    Undo,
    /// Re-apply the change of the shown workspace last undone.
    Redo,
    /// Switch between the dark and the light theme (saved in the settings).
    ToggleTheme,
    /// Presentation mode on or off (saved in the settings).
    TogglePresentation,
    /// Show or hide the teaching overlays and hints (saved in the settings).
    ToggleOverlays,
    /// Show or hide the design-rule rings on the opening editor (saved in the settings).
    ToggleDesignRules,
    /// View ▸ Compute PSFs on: the CPU or the window's GPU.
    SetBackend(crate::core::psf::route::Backend),
    /// Show this workspace.
    Show(WorkspaceId),
    /// Open Help ▸ Reproduce thesis results.
    OpenReproduce,
    /// Show or hide Help ▸ Lessons.
    ToggleLessons,
    /// File ▸ Open lesson…: a lesson file into Help ▸ Lessons.
    OpenLesson,
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
/// Ctrl+Q (Cmd+Q on macOS): quit.
pub const QUIT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Q);
/// Ctrl+Shift+P (Cmd+Shift+P on macOS): presentation mode on or off (F5, the slide
/// software's key, rerolls the random tiling here).
pub const PRESENTATION: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::P);

/// Reads the shell's keyboard shortcuts into commands (a workspace reads its own,
/// [`crate::app::Workspace::read_shortcuts`]).
pub fn read_shortcuts(ctx: &egui::Context, out: &mut Vec<ShellCommand>) {
    // A pass egui discards (a layout change, such as presentation mode's zoom) is run again
    // with the same input: the shortcut already acted in the first pass.
    if ctx.current_pass_index() > 0 {
        return;
    }
    ctx.input_mut(|i| {
        // Longest modifier sets first, so Ctrl+Shift+Z is not read as Ctrl+Z.
        if i.consume_shortcut(&REDO) || i.consume_shortcut(&REDO_Y) {
            out.push(ShellCommand::Redo);
        }
        if i.consume_shortcut(&UNDO) {
            out.push(ShellCommand::Undo);
        }
        if i.consume_shortcut(&QUIT) {
            out.push(ShellCommand::Quit);
        }
        if i.consume_shortcut(&PRESENTATION) {
            out.push(ShellCommand::TogglePresentation);
        }
    });
}
