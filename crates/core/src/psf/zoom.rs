//! Partial DFTs ("zooms"): `n_out` consecutive outputs `k = k0 … k0 + n_out − 1` of the
//! length-`m` DFT `A(k) = Σ_n x(n) exp(−2πi n k / m)` of `n_in` consecutive inputs
//! `n = n0 … n0 + n_in − 1` (all other inputs zero). The PSF only needs the sensor window of a
//! grid whose size `M` is fixed by the physics (conventions.md §2) and is often a poor FFT size
//! (1524 = 4·3·127, 6100 = 4·25·61: rustfft runs them 3–6× slower per point than a 2·3·5-smooth
//! size), so three exact ways to get those outputs compete on an operation count:
//!
//! - **slice**: the full `M`-point FFT, then read the outputs: `fft(M) + M + n_out`;
//! - **chirp-z** (Bluestein with a free, fast convolution length `L ≥ n_in + n_out − 1`,
//!   2·3·5-smooth): `2·fft(L) + L + n_in + n_out`;
//! - **matrix DFT**: `n_in · n_out` complex multiply-adds (wins for tiny inputs or outputs).
//!
//! `fft(n) = n·log2 n` for a 7-smooth `n`, and `NON_SMOOTH_FACTOR` times that otherwise
//! (rustfft falls back to Rader/Bluestein; measured 3.3–5.6× on this project's sizes). Every
//! phase is reduced exactly in integers before the one `sin`/`cos`, so all three agree with the
//! full FFT to rounding (~1e-15 of the largest output).

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::{Arc, Mutex, OnceLock};

use rustfft::Fft;
use rustfft::num_complex::Complex64;

use crate::psf::chirp_z::{ChirpWork, ChirpZ, convolution_len};
use udc_fft::complex_plan;

/// How much slower rustfft runs a size with a prime factor above 7, per `n·log2 n`.
pub const NON_SMOOTH_FACTOR: f64 = 4.0;

/// Which exact algorithm a [`Zoom`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ZoomKind {
    /// Full `M`-point FFT, outputs read from it.
    Slice,
    /// Chirp-z (Bluestein) with a fast convolution length.
    Chirp,
    /// Direct matrix-vector product.
    Matrix,
}

/// Modelled cost of a complex FFT of length `n`, in complex multiply-adds.
pub fn fft_ops(n: usize) -> f64 {
    let nf = n.max(2) as f64;
    let base = nf * nf.log2();
    if is_7_smooth(n) {
        base
    } else {
        NON_SMOOTH_FACTOR * base
    }
}

fn is_7_smooth(mut n: usize) -> bool {
    if n == 0 {
        return false;
    }
    for p in [2, 3, 5, 7] {
        while n.is_multiple_of(p) {
            n /= p;
        }
    }
    n == 1
}

/// `exp(−2πi num/den)`, the numerator reduced exactly first.
fn unit(num: i128, den: i128) -> Complex64 {
    let r = num.rem_euclid(den);
    Complex64::from_polar(1.0, -2.0 * PI * r as f64 / den as f64)
}

enum Imp {
    Slice(Arc<dyn Fft<f64>>),
    Chirp {
        chirp: ChirpZ<f64>,
        post: Vec<Complex64>,
    },
    Matrix(Vec<Complex64>),
}

/// A planned partial DFT (see the module docs). Build once, run on many inputs.
pub struct Zoom {
    m: usize,
    n0: i64,
    n_in: usize,
    k0: i64,
    n_out: usize,
    imp: Imp,
}

/// Per-thread buffers of a [`Zoom`].
pub struct ZoomScratch {
    buf: Vec<Complex64>,
    fft: Vec<Complex64>,
    chirp: ChirpWork<f64>,
}

/// Modelled cost of each kind, in complex multiply-adds.
pub fn zoom_ops(kind: ZoomKind, m: usize, n_in: usize, n_out: usize) -> f64 {
    match kind {
        ZoomKind::Slice => fft_ops(m) + (m + n_out) as f64,
        ZoomKind::Chirp => {
            let l = convolution_len(n_in, n_out);
            2.0 * fft_ops(l) + (l + n_in + n_out) as f64
        }
        ZoomKind::Matrix => (n_in * n_out) as f64,
    }
}

/// The cheapest kind by [`zoom_ops`].
pub fn cheapest(m: usize, n_in: usize, n_out: usize) -> ZoomKind {
    [ZoomKind::Matrix, ZoomKind::Chirp, ZoomKind::Slice]
        .into_iter()
        .min_by(|a, b| zoom_ops(*a, m, n_in, n_out).total_cmp(&zoom_ops(*b, m, n_in, n_out)))
        .unwrap_or(ZoomKind::Slice)
}

/// Modelled cost of the cheapest kind.
pub fn best_ops(m: usize, n_in: usize, n_out: usize) -> f64 {
    zoom_ops(cheapest(m, n_in, n_out), m, n_in, n_out)
}

/// Zooms kept for reuse: a sweep analyses many designs with one pupil and one window, so every
/// call after the first finds its chirps and kernel spectra here (~0.2 ms each to build).
const CACHED_ZOOMS: usize = 64;

type ZoomKey = (usize, i64, usize, i64, usize);

/// The cheapest exact zoom for these ranges, shared process-wide.
pub fn cached(m: usize, n0: i64, n_in: usize, k0: i64, n_out: usize) -> Arc<Zoom> {
    static CACHE: OnceLock<Mutex<HashMap<ZoomKey, Arc<Zoom>>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    let key = (m, n0, n_in, k0, n_out);
    if let Some(z) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return z.clone();
    }
    // Built outside the lock: two threads may both build it, and either copy is right.
    let z = Arc::new(Zoom::new(m, n0, n_in, k0, n_out));
    let mut guard = cache.lock().unwrap_or_else(|e| e.into_inner());
    if guard.len() >= CACHED_ZOOMS {
        guard.clear();
    }
    guard.insert(key, z.clone());
    z
}

impl Zoom {
    /// The cheapest exact zoom for these ranges.
    pub fn new(m: usize, n0: i64, n_in: usize, k0: i64, n_out: usize) -> Zoom {
        Zoom::with_kind(cheapest(m, n_in, n_out), m, n0, n_in, k0, n_out)
    }

    /// A zoom of the given kind (tests compare the kinds).
    pub fn with_kind(
        kind: ZoomKind,
        m: usize,
        n0: i64,
        n_in: usize,
        k0: i64,
        n_out: usize,
    ) -> Zoom {
        let (mi, n0i, k0i) = (m as i128, i128::from(n0), i128::from(k0));
        let imp = match kind {
            ZoomKind::Slice => Imp::Slice(complex_plan(m)),
            ZoomKind::Matrix => Imp::Matrix(
                (0..n_out as i128)
                    .flat_map(|j| (0..n_in as i128).map(move |i| unit((n0i + i) * (k0i + j), mi)))
                    .collect(),
            ),
            ZoomKind::Chirp => {
                // n·k = n0 k0 + n0 j + i k0 + (i² + j² − (j − i)²)/2 with n = n0 + i, k = k0 + j:
                // a convolution in i ↔ j between two chirps (the half-integer phases as
                // exp(−πi q²/m) = unit(q², 2m)).
                let pre = (0..n_in as i128)
                    .map(|i| unit(i * k0i, mi) * unit(i * i, 2 * mi))
                    .collect();
                let post = (0..n_out as i128)
                    .map(|j| unit(n0i * (k0i + j), mi) * unit(j * j, 2 * mi))
                    .collect();
                let chirp = ChirpZ::new(pre, n_out, |d| {
                    let d = i128::from(d);
                    unit(d * d, 2 * mi).conj()
                });
                Imp::Chirp { chirp, post }
            }
        };
        Zoom {
            m,
            n0,
            n_in,
            k0,
            n_out,
            imp,
        }
    }

    /// Which algorithm this zoom runs.
    pub fn kind(&self) -> ZoomKind {
        match self.imp {
            Imp::Slice(_) => ZoomKind::Slice,
            Imp::Chirp { .. } => ZoomKind::Chirp,
            Imp::Matrix(_) => ZoomKind::Matrix,
        }
    }

    /// Modelled cost of one [`Zoom::process`].
    pub fn ops(&self) -> f64 {
        zoom_ops(self.kind(), self.m, self.n_in, self.n_out)
    }

    /// Buffers for [`Zoom::process`] (one set per thread).
    pub fn scratch(&self) -> ZoomScratch {
        let (buf, fft) = match &self.imp {
            Imp::Slice(p) => (self.m, p.get_inplace_scratch_len()),
            Imp::Chirp { .. } | Imp::Matrix(_) => (0, 0),
        };
        ZoomScratch {
            buf: vec![Complex64::new(0.0, 0.0); buf],
            fft: vec![Complex64::new(0.0, 0.0); fft],
            chirp: ChirpWork::new(),
        }
    }

    /// `out[j] = A(k0 + j)` for `input[i] = x(n0 + i)`. Slices shorter than the plan's ranges
    /// are read as zeros / filled partly.
    pub fn process(&self, input: &[Complex64], out: &mut [Complex64], s: &mut ZoomScratch) {
        let zero = Complex64::new(0.0, 0.0);
        let input = &input[..input.len().min(self.n_in)];
        let n_out = out.len().min(self.n_out);
        match &self.imp {
            Imp::Slice(plan) => {
                let m = self.m as i64;
                s.buf.iter_mut().for_each(|v| *v = zero);
                for (i, x) in input.iter().enumerate() {
                    s.buf[(self.n0 + i as i64).rem_euclid(m) as usize] = *x;
                }
                plan.process_with_scratch(&mut s.buf, &mut s.fft);
                for (j, o) in out[..n_out].iter_mut().enumerate() {
                    *o = s.buf[(self.k0 + j as i64).rem_euclid(m) as usize];
                }
            }
            Imp::Chirp { chirp, post } => {
                let y = chirp.convolve(input.len(), |i| input[i], &mut s.chirp);
                for ((o, b), p) in out[..n_out].iter_mut().zip(y).zip(post) {
                    *o = b * p;
                }
            }
            Imp::Matrix(mat) => {
                for (o, row) in out[..n_out].iter_mut().zip(mat.chunks(self.n_in.max(1))) {
                    *o = row.iter().zip(input).map(|(a, x)| a * x).sum();
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_matches_the_direct_sum() {
        // An awkward size, an input off the origin and an output range that wraps past m/2.
        let (m, n0, n_in, k0, n_out) = (30usize, -7i64, 11usize, 9i64, 14usize);
        let x: Vec<Complex64> = (0..n_in)
            .map(|i| Complex64::new((i as f64 * 0.7).sin(), 0.3 * i as f64 - 1.0))
            .collect();
        let want: Vec<Complex64> = (0..n_out as i64)
            .map(|j| {
                x.iter()
                    .enumerate()
                    .map(|(i, v)| v * unit(i128::from((n0 + i as i64) * (k0 + j)), m as i128))
                    .sum()
            })
            .collect();
        for kind in [ZoomKind::Slice, ZoomKind::Chirp, ZoomKind::Matrix] {
            let z = Zoom::with_kind(kind, m, n0, n_in, k0, n_out);
            let mut out = vec![Complex64::new(0.0, 0.0); n_out];
            z.process(&x, &mut out, &mut z.scratch());
            for (a, b) in out.iter().zip(&want) {
                assert!((a - b).norm() < 1e-12, "{kind:?}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn the_cost_model_prefers_chirp_for_awkward_sizes_and_matrix_for_tiny_ones() {
        assert_eq!(cheapest(6100, 2000, 1177), ZoomKind::Chirp);
        assert_eq!(cheapest(1536, 500, 1536), ZoomKind::Slice);
        assert_eq!(cheapest(1524, 21, 8), ZoomKind::Matrix);
    }
}
