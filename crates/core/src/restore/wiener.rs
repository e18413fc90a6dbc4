//! Wiener deconvolution (conventions.md §5): `X = Y·K* / (|K|² + nsr)` on the zero-padded grid,
//! cropped back and clipped at 0.

use crate::Setting;
use ndarray::{Array2, ArrayView2};

use rustfft::num_complex::Complex64;

use super::spectrum::{KernelRows, PadGrid, Spectrum};
use crate::{Sample, SimError};

/// The noise-to-signal ratio of the thesis's Wiener filter.
pub const THESIS_NSR: f64 = 0.00371;

/// Restores one channel. `kernel` is the spectrum of the channel's PSF (normalised to sum 1, so
/// `K(0) = 1` and `nsr` is relative to the DC gain) on `grid`, the same one the blur used.
/// Negative values, which no intensity can take, are clipped to 0; values above 1 are kept.
///
/// # Errors
/// [`SimError::InvalidSetting`] (`method.nsr`) unless `nsr` is finite and ≥ 0.
pub fn wiener(
    grid: &PadGrid,
    captured: ArrayView2<'_, f64>,
    kernel: &Spectrum,
    nsr: f64,
) -> Result<Array2<f64>, SimError> {
    check_nsr(nsr)?;
    let mut x = grid.filter(captured, |i, y| filtered(y, kernel.data[i], nsr));
    x.mapv_inplace(|v| v.max(0.0));
    Ok(x)
}

/// [`wiener`] by [`PadGrid::convolve`]: the same restoration of a plane held in `f32` or
/// `f64`, without the whole padded spectra (what `restore::simulate` uses, so that a
/// camera-size photo fits in memory).
///
/// # Errors
/// As [`wiener`].
pub fn wiener_streamed<T: Sample>(
    grid: &PadGrid,
    captured: ArrayView2<'_, T>,
    kernel: &KernelRows,
    nsr: f64,
) -> Result<Array2<T>, SimError> {
    check_nsr(nsr)?;
    let mut x = grid.convolve(captured, kernel, |y, k| filtered(y, k, nsr));
    x.mapv_inplace(|v| if v > T::default() { v } else { T::default() });
    Ok(x)
}

/// Refuses a noise-to-signal ratio that is not a finite number ≥ 0.
pub(crate) fn check_nsr(nsr: f64) -> Result<(), SimError> {
    if nsr.is_finite() && nsr >= 0.0 {
        Ok(())
    } else {
        Err(SimError::invalid(
            Setting::MethodNsr,
            format!("must be a finite number ≥ 0 (got {nsr:?})"),
        ))
    }
}

/// One frequency of the Wiener filter: `Y·K* / (|K|² + nsr)`.
fn filtered(y: Complex64, k: Complex64, nsr: f64) -> Complex64 {
    let denom = k.norm_sqr() + nsr;
    // nsr = 0 with a zero of K: that frequency is lost, leave it at 0 rather than divide.
    if denom > 0.0 {
        y * k.conj() / denom
    } else {
        y * 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::spectrum::Padding;
    use super::*;

    #[test]
    fn a_delta_psf_returns_the_input() {
        let image = Array2::from_shape_fn((17, 23), |(y, x)| ((y * 31 + x * 7) % 13) as f64 / 13.0);
        let mut delta = Array2::<f64>::zeros((8, 8));
        delta[[4, 4]] = 1.0;
        let grid = PadGrid::new(image.dim(), delta.dim(), Padding::Linear);
        let k = grid.forward_kernel(&delta);
        let x = wiener(&grid, image.view(), &k, 0.0).expect("valid nsr");
        for (a, b) in x.iter().zip(image.iter()) {
            assert!((a - b).abs() < 1e-12);
        }
        // With an nsr the delta's gain becomes 1/(1 + nsr).
        let x = wiener(&grid, image.view(), &k, 0.25).expect("valid nsr");
        for (a, b) in x.iter().zip(image.iter()) {
            assert!((a - b / 1.25).abs() < 1e-12);
        }
    }

    #[test]
    fn the_streamed_filter_equals_the_whole_grid_route() {
        let image = Array2::from_shape_fn((37, 53), |(y, x)| ((y * 31 + x * 7) % 13) as f64 / 13.0);
        let psf = Array2::from_shape_fn((9, 7), |(y, x)| 1.0 / (1.0 + (y * 7 + x) as f64));
        for padding in [Padding::Linear, Padding::Double] {
            let grid = PadGrid::new(image.dim(), psf.dim(), padding);
            let whole = wiener(&grid, image.view(), &grid.forward_kernel(&psf), 0.01).unwrap();
            let rows = grid.kernel_rows(&psf);
            let f64_plane = wiener_streamed(&grid, image.view(), &rows, 0.01).unwrap();
            let f32_plane =
                wiener_streamed(&grid, image.mapv(|v| v as f32).view(), &rows, 0.01).unwrap();
            for ((a, b), c) in whole.iter().zip(&f64_plane).zip(&f32_plane) {
                assert!((a - b).abs() < 1e-5, "{padding:?}: {a} vs {b}");
                assert!((a - f64::from(*c)).abs() < 1e-5, "{padding:?}: {a} vs {c}");
            }
        }
    }

    #[test]
    fn a_bad_nsr_is_an_error() {
        let grid = PadGrid::new((4, 4), (3, 3), Padding::Linear);
        let k = grid.forward_kernel(&Array2::from_elem((3, 3), 1.0 / 9.0));
        let err = wiener(&grid, Array2::zeros((4, 4)).view(), &k, f64::NAN);
        assert!(
            err.err()
                .map(|e| e.to_string())
                .unwrap_or_default()
                .contains("method.nsr")
        );
    }
}
