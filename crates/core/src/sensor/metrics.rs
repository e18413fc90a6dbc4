//! The display tone curve and the scores of a capture against the ground truth (§5.7): PSNR
//! over the image, SSIM per ROI (worst and mean), both after the tone curve. SSIM and PSNR are
//! [`crate::restore::quality`]'s.

use ndarray::{Array2, ArrayView2, Axis, Slice};
use rayon::prelude::*;

use super::roi::RoiGrid;
use crate::SimError;
use crate::restore::quality::{SSIM_RADIUS_PX, psnr_db, ssim};

/// The SSIM window's side: the smallest image (and ROI) that can be scored.
pub const SSIM_WINDOW_PX: usize = 2 * SSIM_RADIUS_PX + 1;

/// Display and metric tone curve: `clamp(x · scale, 0, 1)^gamma`, with `scale` set so the
/// ground truth's mean maps to `display_mean` (Table 5.4: mean 0.05, γ = 1/3.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToneCurve {
    /// Display units per electron.
    pub scale: f64,
    /// Exponent applied after scaling and clamping (Table 5.4: 1/3.2).
    pub gamma: f64,
}

impl ToneCurve {
    /// The tone-mapped display value of `x_e` electrons, in `[0, 1]`.
    pub fn value(&self, x_e: f64) -> f64 {
        let v = (x_e * self.scale).clamp(0.0, 1.0);
        if (self.gamma - 0.3125).abs() < 1e-15 {
            // x^(5/16) as four square roots of x⁵: the same number (to an ulp or two) for a
            // fraction of the cost of powf, on the default curve.
            let x2 = v * v;
            (x2 * x2 * v).sqrt().sqrt().sqrt().sqrt()
        } else {
            v.powf(self.gamma)
        }
    }

    /// The curve applied to every pixel (rows in parallel).
    pub fn apply(&self, image_e: &Array2<f64>) -> Array2<f64> {
        let mut out = Array2::<f64>::zeros(image_e.dim());
        out.axis_iter_mut(Axis(0))
            .into_par_iter()
            .zip(image_e.axis_iter(Axis(0)).into_par_iter())
            .for_each(|(mut o, i)| {
                for (o, i) in o.iter_mut().zip(i.iter()) {
                    *o = self.value(*i);
                }
            });
        out
    }
}

/// Scores of one capture.
#[derive(Debug, Clone)]
pub struct Scores {
    /// SSIM of each ROI (an edge ROI thinner than the SSIM window is scored over the
    /// window-wide strip at the image edge).
    pub roi_ssim: Array2<f64>,
    /// Lowest ROI SSIM, the metric of Table 5.4.
    pub worst_roi_ssim: f64,
    /// Mean of the ROI SSIMs weighted by their areas.
    pub mean_ssim: f64,
    /// PSNR over the whole image, peak 1.
    pub psnr_db: f64,
}

fn crop<'a>(
    a: &'a Array2<f64>,
    rows: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
) -> ArrayView2<'a, f64> {
    a.slice_axis(Axis(0), Slice::from(rows))
        .slice_axis_move(Axis(1), Slice::from(cols))
}

/// Scores a tone-mapped capture against the tone-mapped truth over the ROIs of `grid`.
///
/// # Errors
/// [`SimError::InvalidField`] (`image`) when the sizes differ or are smaller than the SSIM
/// window.
pub fn score(
    display: &Array2<f64>,
    truth: &Array2<f64>,
    grid: &RoiGrid,
) -> Result<Scores, SimError> {
    let (h, w) = truth.dim();
    let per_roi: Vec<Result<(f64, f64), SimError>> = (0..grid.rows * grid.cols)
        .into_par_iter()
        .map(|k| {
            let (r, c) = (k / grid.cols, k % grid.cols);
            let (rows, cols) = (grid.row_range(r), grid.col_range(c));
            let area = (rows.len() * cols.len()) as f64;
            let rows = RoiGrid::widened(rows, SSIM_WINDOW_PX, h);
            let cols = RoiGrid::widened(cols, SSIM_WINDOW_PX, w);
            let s = ssim(
                crop(display, rows.clone(), cols.clone()),
                crop(truth, rows, cols),
            )?;
            Ok((s, area))
        })
        .collect();
    let mut roi_ssim = Array2::<f64>::zeros((grid.rows, grid.cols));
    let (mut weighted, mut total) = (0.0, 0.0);
    for (k, r) in per_roi.into_iter().enumerate() {
        let (s, area) = r?;
        roi_ssim[[k / grid.cols, k % grid.cols]] = s;
        weighted += s * area;
        total += area;
    }
    Ok(Scores {
        worst_roi_ssim: roi_ssim.iter().copied().fold(f64::INFINITY, f64::min),
        mean_ssim: weighted / total.max(1.0),
        roi_ssim,
        psnr_db: psnr_db(display.view(), truth.view(), 1.0)?,
    })
}
