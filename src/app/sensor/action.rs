//! What the sensor workspace's panels ask for: every change of the settings goes through this
//! queue and is carried out after the frame's UI ([`super::SensorWorkspace::act`]), through the
//! undo history.

use super::{CompareMode, SensorView};
use crate::core::sensor::SensorSettings;

/// A change the panels queue.
#[derive(Debug, Clone)]
pub enum SensorAction {
    /// A live edit from a control (a drag, a typed number, a pick): the settings as edited. The
    /// history makes it one undo step once the pointer is up and no text field has focus.
    Live(Box<SensorSettings>),
    /// Steps back one settings change.
    Undo,
    /// Re-applies the change last undone.
    Redo,
    /// Ask for an HDR scene (a file dialog).
    AskHdr,
    /// Show this picture in the centre.
    Show(SensorView),
    /// The Compare view's captures A and B (strategy indices), how they are shown, and where
    /// the split line is (0 … 1 of the width).
    Compare {
        /// Capture A.
        a: usize,
        /// Capture B.
        b: usize,
        /// Side by side or split.
        mode: CompareMode,
        /// The split line, a share of the width.
        split: f32,
    },
}
