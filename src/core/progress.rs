//! Progress reporting and cancellation shared between a job and whoever waits for it.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use super::SimError;

/// A progress fraction in `[0, 1]` and a cancel flag. Cheap to poll from any thread.
#[derive(Debug, Default)]
pub struct Progress {
    fraction_bits: AtomicU32,
    cancelled: AtomicBool,
}

impl Progress {
    /// A fresh tracker at 0 % and not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records progress; values are clamped to `[0, 1]`.
    pub fn set(&self, fraction: f32) {
        let f = if fraction.is_finite() {
            fraction.clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.fraction_bits.store(f.to_bits(), Ordering::Relaxed);
    }

    /// The last recorded fraction, in `[0, 1]`.
    pub fn fraction(&self) -> f32 {
        f32::from_bits(self.fraction_bits.load(Ordering::Relaxed))
    }

    /// Asks the job to stop; it returns [`SimError::Cancelled`] at its next [`Progress::check`].
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether [`Progress::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// Returns `Err(Cancelled)` once [`Progress::cancel`] was called; jobs call it between stages.
    ///
    /// # Errors
    /// [`SimError::Cancelled`] when the job was cancelled.
    pub fn check(&self) -> Result<(), SimError> {
        if self.is_cancelled() {
            Err(SimError::Cancelled)
        } else {
            Ok(())
        }
    }
}
