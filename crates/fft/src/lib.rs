//! The FFT plans every transform in UDC Studio runs on: rustfft's complex plans in double and
//! single precision and realfft's real-input plans, each made once per length and direction and
//! kept for the process (planning measures nothing, but costs far more than one small transform).
//!
//! A crate of its own because rustfft's planners are generic: the crate that calls
//! `FftPlanner::<f64>::plan_fft_forward` compiles every algorithm the planner can choose (the
//! scalar, SSE and AVX butterflies of every size, for each precision). Made here, they compile
//! once; the core calls the plans through `dyn Fft`, as it did before, and compiles none of
//! them (docs/src/budgets.md has the build times).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

use realfft::RealFftPlanner;
pub use realfft::{ComplexToReal, RealToComplex};
use rustfft::FftPlanner;
pub use rustfft::{Fft, FftDirection};

/// The planners and the plans they made, by length (and direction).
struct Plans {
    real: RealFftPlanner<f64>,
    complex: FftPlanner<f64>,
    single: FftPlanner<f32>,
    real_forward: HashMap<usize, Arc<dyn RealToComplex<f64>>>,
    real_inverse: HashMap<usize, Arc<dyn ComplexToReal<f64>>>,
    /// Keyed by length and whether inverse.
    complex_plans: HashMap<(usize, bool), Arc<dyn Fft<f64>>>,
    single_plans: HashMap<(usize, bool), Arc<dyn Fft<f32>>>,
}

fn plans() -> MutexGuard<'static, Plans> {
    static PLANS: OnceLock<Mutex<Plans>> = OnceLock::new();
    // A panic while planning leaves the maps consistent (a plan is inserted whole or not at all).
    PLANS
        .get_or_init(|| {
            Mutex::new(Plans {
                real: RealFftPlanner::new(),
                complex: FftPlanner::new(),
                single: FftPlanner::new(),
                real_forward: HashMap::new(),
                real_inverse: HashMap::new(),
                complex_plans: HashMap::new(),
                single_plans: HashMap::new(),
            })
        })
        .lock()
        .unwrap_or_else(|e| e.into_inner())
}

/// The real-to-complex (forward) plan of length `n`.
pub fn real_plan(n: usize) -> Arc<dyn RealToComplex<f64>> {
    let Plans {
        real, real_forward, ..
    } = &mut *plans();
    real_forward
        .entry(n)
        .or_insert_with(|| real.plan_fft_forward(n))
        .clone()
}

/// The complex-to-real (inverse, unnormalised) plan of length `n`.
pub fn real_inverse_plan(n: usize) -> Arc<dyn ComplexToReal<f64>> {
    let Plans {
        real, real_inverse, ..
    } = &mut *plans();
    real_inverse
        .entry(n)
        .or_insert_with(|| real.plan_fft_inverse(n))
        .clone()
}

/// The forward complex plan of length `n`.
pub fn complex_plan(n: usize) -> Arc<dyn Fft<f64>> {
    complex_plan_f64(n, FftDirection::Forward)
}

/// The inverse complex plan of length `n` (unnormalised, as rustfft's).
pub fn complex_inverse_plan(n: usize) -> Arc<dyn Fft<f64>> {
    complex_plan_f64(n, FftDirection::Inverse)
}

fn complex_plan_f64(n: usize, direction: FftDirection) -> Arc<dyn Fft<f64>> {
    let Plans {
        complex,
        complex_plans,
        ..
    } = &mut *plans();
    complex_plans
        .entry((n, direction == FftDirection::Inverse))
        .or_insert_with(|| complex.plan_fft(n, direction))
        .clone()
}

/// The single-precision complex plan of length `n`, forward or inverse (unnormalised). The
/// phase-mask relay runs its Fresnel steps in f32: twice the throughput, and its fields need
/// ~1e-6 relative accuracy, not 1e-15.
pub fn complex_plan_f32(n: usize, inverse: bool) -> Arc<dyn Fft<f32>> {
    let direction = if inverse {
        FftDirection::Inverse
    } else {
        FftDirection::Forward
    };
    let Plans {
        single,
        single_plans,
        ..
    } = &mut *plans();
    single_plans
        .entry((n, inverse))
        .or_insert_with(|| single.plan_fft(n, direction))
        .clone()
}
