//! What the sensor workspace's panels ask for: every change of the settings goes through this
//! queue and is carried out after the frame's UI ([`super::SensorWorkspace::act`]), through the
//! undo history.

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
}
