//! The residual blur of a PSF deblurred with another (thesis Figs. 3.29 and 3.31, insets): how
//! far a PSF measured at one field point or depth is from the kernel the restoration assumes.
//!
//! Definition (conventions.md "Field, depth and saturation"): with the restore Wiener filter `W`
//! built from the reference PSF `k_ref` at noise-to-signal ratio `nsr`,
//! `r_point = W(k_point)` and `r_ref = W(k_ref)`. Deblurring a PSF with itself does not give a
//! unit impulse (the filter's own bias, `|K|²/(|K|² + nsr)`), so the residual is measured
//! against that: `residual_rel = Σ (r_point − r_ref)² / Σ r_ref²`, exactly 0 for identical PSFs.

use crate::Setting;
use ndarray::Array2;

use crate::SimError;
use crate::restore::spectrum::{PadGrid, Padding, Spectrum};
use crate::restore::wiener::wiener;

/// A Wiener filter built once from a reference PSF, to deblur other PSFs with it.
#[derive(Debug, Clone)]
pub struct Deblur {
    grid: PadGrid,
    kernel: Spectrum,
    nsr: f64,
    reference: Array2<f64>,
    reference_energy: f64,
}

impl Deblur {
    /// The filter of `reference` (a PSF with its axis at `[H/2, W/2]`) at `nsr`.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] (`nsr`) for a negative or non-finite `nsr`, or a reference PSF
    /// that deblurs to nothing.
    pub fn new(reference: &Array2<f64>, nsr: f64) -> Result<Self, SimError> {
        if !(nsr.is_finite() && nsr >= 0.0) {
            return Err(SimError::invalid(
                Setting::Nsr,
                format!("must be a finite number ≥ 0 (got {nsr:?})"),
            ));
        }
        let grid = PadGrid::new(reference.dim(), reference.dim(), Padding::Linear);
        let kernel = grid.forward_kernel(reference);
        let r = wiener(&grid, reference.view(), &kernel, nsr)?;
        let energy = r.iter().map(|v| v * v).sum::<f64>();
        if !(energy > 0.0) {
            return Err(SimError::invalid(
                "psf",
                "the reference PSF deblurs to nothing",
            ));
        }
        Ok(Deblur {
            grid,
            kernel,
            nsr,
            reference: r,
            reference_energy: energy,
        })
    }

    /// The reference PSF deblurred by its own filter (≈ a unit impulse at the centre).
    pub fn reference(&self) -> &Array2<f64> {
        &self.reference
    }

    /// `psf` deblurred with the reference's filter, and its `residual_rel` (module docs).
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] (`psf`) when `psf` is not the reference's size.
    pub fn residual(&self, psf: &Array2<f64>) -> Result<(f64, Array2<f64>), SimError> {
        if psf.dim() != self.reference.dim() {
            return Err(SimError::invalid(
                "psf",
                format!(
                    "is {:?}, the reference PSF {:?}",
                    psf.dim(),
                    self.reference.dim()
                ),
            ));
        }
        let r = wiener(&self.grid, psf.view(), &self.kernel, self.nsr)?;
        let diff: f64 = r
            .iter()
            .zip(self.reference.iter())
            .map(|(a, b)| (a - b) * (a - b))
            .sum();
        Ok((diff / self.reference_energy, r))
    }
}

/// Mean `residual_rel` over channels of `points` against `references`, with the deblurred PSFs.
///
/// # Errors
/// As [`Deblur::residual`].
pub fn channel_residuals(
    filters: &[Deblur],
    points: &[Array2<f64>],
) -> Result<(Vec<f64>, Vec<Array2<f64>>), SimError> {
    let mut values = Vec::with_capacity(points.len());
    let mut deblurred = Vec::with_capacity(points.len());
    for (f, p) in filters.iter().zip(points) {
        let (v, r) = f.residual(p)?;
        values.push(v);
        deblurred.push(r);
    }
    Ok((values, deblurred))
}

/// The mean of `values` (0 for none).
pub fn mean(values: &[f64]) -> f64 {
    if values.is_empty() {
        0.0
    } else {
        values.iter().sum::<f64>() / values.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blob(w: usize, cx: f64, sigma: f64) -> Array2<f64> {
        let c = (w / 2) as f64;
        let mut a = Array2::from_shape_fn((w, w), |(y, x)| {
            let (dy, dx) = (y as f64 - c, x as f64 - cx);
            (-(dx * dx + dy * dy) / (2.0 * sigma * sigma)).exp()
        });
        let s = a.sum();
        a /= s;
        a
    }

    #[test]
    fn identical_psfs_have_zero_residual_and_different_ones_do_not() {
        let k = blob(32, 16.0, 1.5);
        let d = Deblur::new(&k, 0.00371).expect("valid");
        let (same, _) = d.residual(&k).expect("same size");
        assert_eq!(same, 0.0);
        let (wider, _) = d.residual(&blob(32, 16.0, 2.5)).expect("same size");
        let (shifted, _) = d.residual(&blob(32, 17.0, 1.5)).expect("same size");
        assert!(wider > 0.01 && shifted > 0.01, "{wider} {shifted}");
        assert!(Deblur::new(&k, f64::NAN).is_err());
        assert!(d.residual(&blob(30, 15.0, 1.5)).is_err());
    }
}
