//! Small background tasks (file reads and writes) so the UI thread only draws. Each task runs on
//! its own thread, wakes the UI when done, and is polled once per frame.

use std::sync::mpsc::{Receiver, TryRecvError, channel};

/// A value being produced on another thread.
pub struct Task<T> {
    rx: Receiver<T>,
}

impl<T: Send + 'static> Task<T> {
    /// Runs `job` on a new thread; `wake` is called when it is done.
    pub fn spawn(
        name: &str,
        wake: impl Fn() + Send + 'static,
        job: impl FnOnce() -> T + Send + 'static,
    ) -> Self {
        let (tx, rx) = channel();
        let spawned = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                let _ = tx.send(job());
                wake();
            });
        if spawned.is_err() {
            // Could not start a thread: the task never completes and `poll` reports it gone.
            let (_, rx) = channel();
            return Task { rx };
        }
        Task { rx }
    }

    /// `Some(value)` once done; `None` while running.
    pub fn poll(&self) -> Option<Result<T, ()>> {
        match self.rx.try_recv() {
            Ok(v) => Some(Ok(v)),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(())),
        }
    }
}
