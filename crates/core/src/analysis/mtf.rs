//! OTF/MTF of a sensor PSF and the numbers derived from it (conventions.md §3).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use udc_fft::complex_plan;

/// Unnormalised 2-D DFT of a real array (DC at `[0, 0]`).
pub fn dft2(a: &Array2<f64>) -> Array2<Complex64> {
    let (h, w) = a.dim();
    // Columns first (contiguous after a transpose), then rows in place.
    let mut t: Vec<Complex64> = vec![Complex64::new(0.0, 0.0); h * w];
    for (y, row) in a.outer_iter().enumerate() {
        for (x, v) in row.iter().enumerate() {
            t[x * h + y] = Complex64::new(*v, 0.0);
        }
    }
    let col_plan = complex_plan(h);
    t.par_chunks_mut(h).for_each(|col| col_plan.process(col));
    let mut data = vec![Complex64::new(0.0, 0.0); h * w];
    for x in 0..w {
        for y in 0..h {
            data[y * w + x] = t[x * h + y];
        }
    }
    let row_plan = complex_plan(w);
    data.par_chunks_mut(w).for_each(|row| row_plan.process(row));
    Array2::from_shape_vec((h, w), data).unwrap_or_else(|_| Array2::zeros((h, w)))
}

/// The MTF of a PSF and its summaries.
#[derive(Debug, Clone)]
pub struct Mtf {
    /// `|OTF|`, DC-centred (`[N/2, N/2]`), `MTF(0) = 1`.
    pub centred: Array2<f64>,
    /// Frequency along x (along a row) through DC, `d = 0 … N/2 − 1`, at `d/N` cycles/pixel.
    pub horizontal: Vec<f64>,
    /// Frequency along y through DC.
    pub vertical: Vec<f64>,
    /// Minimum MTF over every sample of ring `d`, at `d/N` cycles/pixel (conventions.md §3).
    pub radial_min: Vec<f64>,
    /// Mean MTF over every sample of ring `d`.
    pub radial_mean: Vec<f64>,
    /// Trapezoidal area under `radial_min` over `ν = d/N` (cycles/pixel).
    pub auc_radial_min: f64,
    /// Trapezoidal area under `radial_mean` over `ν = d/N` (cycles/pixel).
    pub auc_radial_mean: f64,
    /// `|OTF|²` uncentred, kept for the invertibility score.
    pub power: Array2<f64>,
}

impl Mtf {
    /// Frequencies `d/N` of the slices and rings, in cycles/pixel.
    pub fn freqs_cyc_per_px(&self) -> Vec<f64> {
        let n = self.centred.nrows() as f64;
        (0..self.radial_min.len()).map(|d| d as f64 / n).collect()
    }

    /// AUC normalised by the ideal 0.5 (an MTF of 1 up to Nyquist).
    pub fn auc_normalised(&self) -> f64 {
        self.auc_radial_min / 0.5
    }
}

/// Trapezoidal area under `y` sampled at spacing `dx`.
pub fn trapezoid(y: &[f64], dx: f64) -> f64 {
    y.windows(2).map(|w| 0.5 * (w[0] + w[1]) * dx).sum()
}

/// Ring index `round(hypot(Δrow, Δcol))` of every sample of a DC-centred `n×n` array, cached
/// per `n` (the MTF of every analysis reuses it).
fn ring_table(n: usize) -> Arc<Vec<u32>> {
    static CACHE: OnceLock<Mutex<HashMap<usize, Arc<Vec<u32>>>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    let mut guard = cache.lock().unwrap_or_else(|e| e.into_inner());
    guard
        .entry(n)
        .or_insert_with(|| {
            let c = (n / 2) as f64;
            Arc::new(
                (0..n * n)
                    .map(|i| ((i / n) as f64 - c).hypot((i % n) as f64 - c).round() as u32)
                    .collect(),
            )
        })
        .clone()
}

/// MTF of a square PSF (normalised here, so any positive scale works).
pub fn mtf_of(psf: &Array2<f64>) -> Mtf {
    let n = psf.nrows();
    let sum = psf.sum();
    let scale = if sum > 0.0 { 1.0 / sum } else { 1.0 };
    let otf = dft2(&psf.mapv(|v| v * scale));
    // Divided by |OTF(0)|² (= 1 up to the rounding of the sum) so that MTF(0) = 1 exactly,
    // whichever route summed the PSF.
    let dc = otf.first().map_or(1.0, |c| c.norm_sqr());
    let dc = if dc > 0.0 { dc } else { 1.0 };
    let power = otf.mapv(|c| c.norm_sqr() / dc);
    let c = n / 2;
    // centred index y ↔ DFT index (y + n − c) mod n
    let unshift: Vec<usize> = (0..n).map(|y| (y + n - c) % n).collect();
    let mut centred = Array2::<f64>::zeros((n, n));
    for (y, mut row) in centred.outer_iter_mut().enumerate() {
        let src = power.row(unshift[y]);
        for (x, v) in row.iter_mut().enumerate() {
            *v = src[unshift[x]].sqrt();
        }
    }
    let half = n / 2;
    let horizontal: Vec<f64> = (0..half).map(|d| centred[[half, half + d]]).collect();
    let vertical: Vec<f64> = (0..half).map(|d| centred[[half + d, half]]).collect();
    let mut rmin = vec![f64::INFINITY; half];
    let mut rsum = vec![0.0; half];
    let mut rcount = vec![0usize; half];
    let rings = ring_table(n);
    if let Some(flat) = centred.as_slice() {
        for (v, d) in flat.iter().zip(rings.iter()) {
            let d = *d as usize;
            if d < half {
                rmin[d] = rmin[d].min(*v);
                rsum[d] += v;
                rcount[d] += 1;
            }
        }
    }
    let radial_mean: Vec<f64> = rsum
        .iter()
        .zip(&rcount)
        .map(|(s, c)| s / (*c).max(1) as f64)
        .collect();
    let dnu = 1.0 / n as f64;
    Mtf {
        auc_radial_min: trapezoid(&rmin, dnu),
        auc_radial_mean: trapezoid(&radial_mean, dnu),
        centred,
        horizontal,
        vertical,
        radial_min: rmin,
        radial_mean,
        power,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_psf_has_unit_mtf_and_full_auc() {
        let mut psf = Array2::zeros((16, 16));
        psf[[8, 8]] = 3.0;
        let m = mtf_of(&psf);
        assert!(m.centred.iter().all(|v| (v - 1.0).abs() < 1e-12));
        // ν from 0 to 7/16: area 7/16.
        assert!((m.auc_radial_min - 7.0 / 16.0).abs() < 1e-12);
    }

    #[test]
    fn two_point_psf_has_a_cosine_mtf_along_x_only() {
        // Two deltas one pixel apart along x: MTF(νx) = |cos(π νx)|, flat along y.
        let mut psf = Array2::zeros((32, 32));
        psf[[16, 16]] = 1.0;
        psf[[16, 17]] = 1.0;
        let m = mtf_of(&psf);
        for (d, v) in m.horizontal.iter().enumerate() {
            let want = (std::f64::consts::PI * d as f64 / 32.0).cos().abs();
            assert!((v - want).abs() < 1e-12);
        }
        assert!(m.vertical.iter().all(|v| (v - 1.0).abs() < 1e-12));
        // The radial minimum follows the worst direction (x).
        for (d, v) in m.radial_min.iter().enumerate() {
            assert!(*v <= m.horizontal[d] + 1e-12);
        }
    }

    #[test]
    fn trapezoid_integrates_a_line_exactly() {
        let y: Vec<f64> = (0..11).map(|i| i as f64 * 0.1).collect();
        assert!((trapezoid(&y, 0.1) - 0.5).abs() < 1e-12);
    }
}
