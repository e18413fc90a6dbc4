//! What the phase workspace's panels ask for: every change of the design goes through this
//! queue and is carried out after the frame's UI ([`super::PhaseWorkspace::act`]), through the
//! undo history.

use crate::core::phase::PhaseDesign;

/// A change the panels queue.
#[derive(Debug, Clone)]
pub enum PhaseAction {
    /// A live edit from a control (a drag, a typed number): the design as edited. The history
    /// makes it one undo step once the pointer is up and no text field has focus.
    Live(Box<PhaseDesign>),
    /// A new design as one undo step (the thesis design).
    Set(Box<PhaseDesign>),
    /// The optimizer's allocation as the λ0 plan (one undo step), if it still fits.
    ApplyOptimized,
    /// Steps back one parameter change.
    Undo,
    /// Re-applies the change last undone.
    Redo,
}
