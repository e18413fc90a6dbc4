//! Running a core job from Python: the GIL released, Ctrl-C honoured, panics contained.
//!
//! The job runs on a scoped worker thread. The calling thread gives up the GIL (so other
//! Python threads run, and several `analyze` calls proceed in parallel) and waits for the
//! job's result, waking every [`POLL`] to take the GIL back just long enough to ask Python
//! whether a signal arrived. A `KeyboardInterrupt` cancels the job's [`Progress`], waits for
//! the job to stop at its next check, and is raised in the caller. A panic in the job becomes a
//! `RuntimeError`, never an abort of the interpreter.

use std::sync::mpsc::RecvTimeoutError;
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use udc_core::Progress;

/// How often a waiting call checks for Ctrl-C.
const POLL: Duration = Duration::from_millis(50);

/// Runs `job` off the GIL and returns its value, or the Python error it or a signal produced.
///
/// # Errors
/// The job's own error (already a Python exception), `KeyboardInterrupt` on Ctrl-C, or
/// `RuntimeError` if the job panicked.
pub fn run<T, F>(py: Python<'_>, job: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce(&Progress) -> PyResult<T> + Send,
{
    let progress = Progress::new();
    let progress = &progress;
    wait(py, move || job(progress), || progress.cancel())
}

/// Runs `job` off the GIL on a worker thread; on Ctrl-C calls `stop` (which asks the job to
/// end early), waits for the job, and raises the `KeyboardInterrupt`.
///
/// # Errors
/// As [`run`].
pub fn wait<T, F, S>(py: Python<'_>, job: F, stop: S) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> PyResult<T> + Send,
    S: Fn() + Send,
{
    py.detach(move || {
        std::thread::scope(|scope| {
            // The result comes back through a channel, so the caller wakes the moment the job
            // ends (not at its next poll); a panicking job drops the sender instead.
            let (done, result) = std::sync::mpsc::sync_channel(1);
            let worker = scope.spawn(move || {
                let _ = done.send(job());
            });
            let mut interrupt = None;
            let outcome = loop {
                match result.recv_timeout(POLL) {
                    Ok(value) => break Some(value),
                    Err(RecvTimeoutError::Disconnected) => break None,
                    Err(RecvTimeoutError::Timeout) => {}
                }
                if interrupt.is_none()
                    && let Err(e) = Python::attach(|py| py.check_signals())
                {
                    stop();
                    interrupt = Some(e);
                }
            };
            let joined = worker.join();
            match (interrupt, outcome, joined) {
                (Some(signal), _, _) => Err(signal),
                (None, Some(value), _) => value,
                (None, None, Err(panic)) => Err(PyRuntimeError::new_err(format!(
                    "internal error in udc_studio: {}",
                    panic_text(&panic)
                ))),
                (None, None, Ok(())) => Err(PyRuntimeError::new_err(
                    "internal error in udc_studio: the job ended without a result",
                )),
            }
        })
    })
}

fn panic_text(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".to_string())
}
