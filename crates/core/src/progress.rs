//! Progress reporting and cancellation shared between a job and whoever waits for it.

use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

use crate::SimError;

/// A progress fraction in `[0, 1]` and a cancel flag. Cheap to poll from any thread.
#[derive(Debug, Default)]
pub struct Progress {
    fraction_bits: AtomicU32,
    cancelled: AtomicBool,
    /// The share of the bar that [`Progress::set`] fills: `start` in the high 32 bits, `1 − end`
    /// in the low ones, so the all-zero default is the whole bar.
    span_bits: AtomicU64,
}

/// Returned by [`Progress::span`]: puts the previous span back when dropped.
#[must_use = "the span ends when the guard is dropped"]
#[derive(Debug)]
pub struct SpanGuard<'a> {
    progress: &'a Progress,
    previous: u64,
}

impl Drop for SpanGuard<'_> {
    fn drop(&mut self) {
        self.progress
            .span_bits
            .store(self.previous, Ordering::Relaxed);
    }
}

impl Progress {
    /// A fresh tracker at 0 % and not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records progress; values are clamped to `[0, 1]` and mapped onto the current
    /// [`Progress::span`] (the whole bar unless a span is open).
    pub fn set(&self, fraction: f32) {
        let f = if fraction.is_finite() {
            fraction.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (start, end) = self.span_range();
        let f = start + f * (end - start);
        self.fraction_bits.store(f.to_bits(), Ordering::Relaxed);
    }

    fn span_range(&self) -> (f32, f32) {
        let bits = self.span_bits.load(Ordering::Relaxed);
        let start = f32::from_bits((bits >> 32) as u32);
        let end = 1.0 - f32::from_bits(bits as u32);
        (start, end)
    }

    /// Until the guard is dropped, [`Progress::set`]'s `0 … 1` fills only `[start, end]` of
    /// the current span: a step that reports its own progress from 0 to 1 (the denoiser inside
    /// a restoration) then moves the bar by its share of the job only. Spans nest.
    pub fn span(&self, start: f32, end: f32) -> SpanGuard<'_> {
        let clamp = |v: f32| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        let (lo, hi) = self.span_range();
        let (a, b) = (clamp(start), clamp(end).max(clamp(start)));
        let (new_lo, new_hi) = (lo + a * (hi - lo), lo + b * (hi - lo));
        let bits = (u64::from(new_lo.to_bits()) << 32) | u64::from((1.0 - new_hi).to_bits());
        let previous = self.span_bits.swap(bits, Ordering::Relaxed);
        SpanGuard {
            progress: self,
            previous,
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_map_and_nest_and_end_with_their_guard() {
        let p = Progress::new();
        p.set(0.5);
        assert_eq!(p.fraction(), 0.5);
        {
            let _outer = p.span(0.2, 0.6);
            p.set(0.5);
            assert!((p.fraction() - 0.4).abs() < 1e-6);
            {
                let _inner = p.span(0.5, 1.0);
                p.set(0.0);
                assert!((p.fraction() - 0.4).abs() < 1e-6);
                p.set(1.0);
                assert!((p.fraction() - 0.6).abs() < 1e-6);
            }
            p.set(1.0);
            assert!((p.fraction() - 0.6).abs() < 1e-6);
        }
        p.set(1.0);
        assert_eq!(p.fraction(), 1.0);
    }
}
