//! Cancelling a command run in-process by another program (the Python package's
//! `KeyboardInterrupt`): while [`with_cancel`] runs a command, every long step of it reports to
//! and checks the caller's [`Progress`] instead of a fresh one.

use std::cell::RefCell;
use std::sync::Arc;

use udc_core::Progress;

thread_local! {
    static OUTER: RefCell<Option<Arc<Progress>>> = const { RefCell::new(None) };
}

/// Runs `command` on this thread with `progress` as the progress of its long steps: cancelling
/// it stops the command at its next check (with `SimError::Cancelled`).
pub fn with_cancel<T>(progress: Arc<Progress>, command: impl FnOnce() -> T) -> T {
    let previous = OUTER.with(|o| o.replace(Some(progress)));
    let out = command();
    OUTER.with(|o| *o.borrow_mut() = previous);
    out
}

/// The progress a long step of a command reports to: the caller's (see [`with_cancel`]), or a
/// fresh one when the command runs from the command line.
pub fn progress() -> Arc<Progress> {
    OUTER
        .with(|o| o.borrow().clone())
        .unwrap_or_else(|| Arc::new(Progress::new()))
}
