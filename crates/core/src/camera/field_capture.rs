//! A capture through field-dependent PSFs (thesis §3.7, Fig. 3.29): the photo spans the field
//! grid of [`crate::camera::field::field_psfs`] (its corner pixels at the corner field angles; row index
//! along `θy`, column along `θx`, as PSF arrays are `[row, col]` = `[y, x]`), and every pixel is
//! blurred by the bilinear blend of the PSFs of the four grid points around it:
//! `i_blur = Σ_k w_k(x, y) · (i_sharp ∗ k_k)`, the usual interpolated-PSF model of a slowly
//! varying blur. The capture is exposed with §5's noise and restored with the centre PSF's Wiener
//! filter, beside the same photo captured through the centre PSF everywhere.

use crate::Setting;
use ndarray::{Array2, Zip};

use crate::SimError;
use crate::camera::field::FieldResult;
use crate::restore::capture::{CaptureSettings, blur, expose};
use crate::restore::quality::planes_quality;
use crate::restore::spectrum::{PadGrid, Padding};
use crate::restore::wiener::wiener;

/// The two captures and their restorations' scores.
#[derive(Debug, Clone)]
pub struct FieldCapture {
    /// Restored from the field-dependent capture, one plane per channel.
    pub restored_field: Vec<Array2<f64>>,
    /// Restored from the capture through the centre PSF everywhere.
    pub restored_invariant: Vec<Array2<f64>>,
    /// PSNR of `restored_field` against the photo, dB.
    pub psnr_db_field: f64,
    /// PSNR of `restored_invariant` against the photo, dB.
    pub psnr_db_invariant: f64,
    /// Mean SSIM over channels of `restored_field`.
    pub ssim_field: f64,
    /// Mean SSIM over channels of `restored_invariant`.
    pub ssim_invariant: f64,
}

/// Bilinear weight of grid node `k` (of `n` per side) at position `t ∈ [0, 1]`.
fn hat(t: f64, k: usize, n: usize) -> f64 {
    let u = t * (n - 1) as f64;
    (1.0 - (u - k as f64).abs()).max(0.0)
}

/// Captures `photo` (linear, `[0, 1]`, one plane per channel) through the field's PSFs and
/// through its centre PSF, and restores both with the centre PSF at `nsr`.
///
/// # Errors
/// [`SimError::InvalidSetting`] for a photo that does not match the field's channels, bad capture
/// settings or `nsr`.
pub fn field_capture(
    photo: &[Array2<f64>],
    field: &FieldResult,
    capture: &CaptureSettings,
    nsr: f64,
) -> Result<FieldCapture, SimError> {
    let Some(first) = photo.first() else {
        return Err(SimError::invalid(Setting::Photo, "has no planes"));
    };
    let dim = first.dim();
    if photo.len() != field.centre.len() || photo.iter().any(|p| p.dim() != dim) {
        return Err(SimError::invalid(
            Setting::Photo,
            format!(
                "needs {} planes of one size (got {})",
                field.centre.len(),
                photo.len()
            ),
        ));
    }
    let n = (field.points.len() as f64).sqrt().round() as usize;
    if n < 2 || n * n != field.points.len() {
        return Err(SimError::invalid(
            Setting::Grid,
            "the field grid is not square",
        ));
    }
    let kdim = field.centre[0].dim();
    let grid = PadGrid::new(dim, kdim, Padding::Double);
    let (h, w) = dim;
    let ty = |r: usize| r as f64 / (h.max(2) - 1) as f64;
    let tx = |c: usize| c as f64 / (w.max(2) - 1) as f64;
    let mut captured_field = Vec::with_capacity(photo.len());
    let mut captured_invariant = Vec::with_capacity(photo.len());
    let mut kernels = Vec::with_capacity(photo.len());
    for (c, plane) in photo.iter().enumerate() {
        let centre = grid.forward_kernel(&field.centre[c]);
        let mut acc = Array2::<f64>::zeros(dim);
        for (k, p) in field.points.iter().enumerate() {
            let (gy, gx) = (k / n, k % n);
            let blurred = blur(&grid, plane.view(), &grid.forward_kernel(&p.psfs[c]));
            Zip::indexed(&mut acc)
                .and(&blurred)
                .for_each(|(r, col), a, b| *a += hat(ty(r), gy, n) * hat(tx(col), gx, n) * b);
        }
        captured_field.push(expose(acc.view(), capture, c)?.image);
        let uniform = blur(&grid, plane.view(), &centre);
        captured_invariant.push(expose(uniform.view(), capture, c)?.image);
        kernels.push(centre);
    }
    let restore = |captured: &[Array2<f64>]| -> Result<Vec<Array2<f64>>, SimError> {
        captured
            .iter()
            .zip(&kernels)
            .map(|(y, k)| wiener(&grid, y.view(), k, nsr))
            .collect()
    };
    let restored_field = restore(&captured_field)?;
    let restored_invariant = restore(&captured_invariant)?;
    let field = planes_quality(&restored_field, photo)?;
    let invariant = planes_quality(&restored_invariant, photo)?;
    let (psnr_db_field, ssim_field) = (field.psnr_db, field.ssim);
    let (psnr_db_invariant, ssim_invariant) = (invariant.psnr_db, invariant.ssim);
    Ok(FieldCapture {
        restored_field,
        restored_invariant,
        psnr_db_field,
        psnr_db_invariant,
        ssim_field,
        ssim_invariant,
    })
}

#[cfg(test)]
mod tests {
    use super::hat;

    #[test]
    fn bilinear_weights_sum_to_one() {
        for t in [0.0, 0.1, 0.5, 0.77, 1.0] {
            let s: f64 = (0..3).map(|k| hat(t, k, 3)).sum();
            assert!((s - 1.0).abs() < 1e-12, "{t}: {s}");
        }
        assert_eq!(hat(0.0, 0, 3), 1.0);
        assert_eq!(hat(1.0, 2, 3), 1.0);
    }
}
