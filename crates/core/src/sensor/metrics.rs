//! The display tone curve and the scores of a capture against the ground truth (§5.7): PSNR
//! over the image, SSIM per ROI (worst and mean), both after the tone curve. SSIM and PSNR are
//! [`crate::restore::quality`]'s.

use ndarray::{Array2, Axis, Slice};
use rayon::prelude::*;

use super::roi::RoiGrid;
use crate::restore::quality::{SSIM_RADIUS_PX, psnr_of, ssim};
use crate::{Sample, SimError};

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

    /// The curve applied to each of three planes (`[R, G, B]` electrons).
    pub fn apply_rgb<T: Sample>(&self, rgb_e: &[Array2<T>; 3]) -> [Array2<f64>; 3] {
        rgb_e.each_ref().map(|p| self.apply(p))
    }

    /// The curve applied to every pixel (rows in parallel).
    pub fn apply<T: Sample>(&self, image_e: &Array2<T>) -> Array2<f64> {
        let mut out = Array2::<f64>::zeros(image_e.dim());
        out.axis_iter_mut(Axis(0))
            .into_par_iter()
            .zip(image_e.axis_iter(Axis(0)).into_par_iter())
            .for_each(|(mut o, i)| {
                for (o, i) in o.iter_mut().zip(i.iter()) {
                    *o = self.value((*i).into());
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

/// `tone` over the `rows × cols` crop of `image_e`.
fn toned_crop<T: Sample>(
    image_e: &Array2<T>,
    tone: &ToneCurve,
    rows: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
) -> Array2<f64> {
    image_e
        .slice_axis(Axis(0), Slice::from(rows))
        .slice_axis_move(Axis(1), Slice::from(cols))
        .mapv(|v| tone.value(v.into()))
}

/// Scores a capture against the truth, both in electrons, through the tone curve `tone`,
/// over the ROIs of `grid`. The tone-mapped images are made an ROI at a time, never whole; the
/// SSIMs are those of the whole tone-mapped images bit for bit, the PSNR to rounding (its
/// squared errors are summed ROI by ROI).
///
/// # Errors
/// [`SimError::InvalidSetting`] (`image`) when the sizes differ or are smaller than the SSIM
/// window.
pub fn score<A: Sample, B: Sample>(
    capture_e: &Array2<A>,
    truth_e: &Array2<B>,
    tone: &ToneCurve,
    grid: &RoiGrid,
) -> Result<Scores, SimError> {
    let (h, w) = truth_e.dim();
    if capture_e.dim() != (h, w) {
        return Err(SimError::invalid(
            "image",
            format!(
                "the capture is {:?} pixels, the truth {:?}",
                capture_e.dim(),
                (h, w)
            ),
        ));
    }
    let per_roi: Vec<Result<(f64, f64, f64), SimError>> = (0..grid.rows * grid.cols)
        .into_par_iter()
        .map(|k| {
            let (r, c) = (k / grid.cols, k % grid.cols);
            let (rows, cols) = (grid.row_range(r), grid.col_range(c));
            let area = (rows.len() * cols.len()) as f64;
            let wide_rows = RoiGrid::widened(rows.clone(), SSIM_WINDOW_PX, h);
            let wide_cols = RoiGrid::widened(cols.clone(), SSIM_WINDOW_PX, w);
            let (y0, x0) = (wide_rows.start, wide_cols.start);
            let a = toned_crop(capture_e, tone, wide_rows.clone(), wide_cols.clone());
            let b = toned_crop(truth_e, tone, wide_rows, wide_cols);
            let s = ssim(a.view(), b.view())?;
            // The squared error over the ROI itself (the widened crop may reach into others).
            let mut sse = 0.0;
            for y in rows {
                for x in cols.clone() {
                    let d = a[[y - y0, x - x0]] - b[[y - y0, x - x0]];
                    sse += d * d;
                }
            }
            Ok((s, area, sse))
        })
        .collect();
    let mut roi_ssim = Array2::<f64>::zeros((grid.rows, grid.cols));
    let (mut weighted, mut total, mut sse) = (0.0, 0.0, 0.0);
    for (k, r) in per_roi.into_iter().enumerate() {
        let (s, area, e) = r?;
        roi_ssim[[k / grid.cols, k % grid.cols]] = s;
        weighted += s * area;
        total += area;
        sse += e;
    }
    Ok(Scores {
        worst_roi_ssim: roi_ssim.iter().copied().fold(f64::INFINITY, f64::min),
        mean_ssim: weighted / total.max(1.0),
        roi_ssim,
        psnr_db: psnr_of(sse, h * w, 1.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::restore::quality::psnr_db;

    /// The ROI-at-a-time scores equal those of the whole tone-mapped images: SSIM per ROI bit
    /// for bit, PSNR to rounding.
    #[test]
    fn scores_equal_those_of_the_whole_toned_images() {
        let truth = Array2::from_shape_fn((70, 90), |(y, x)| 50.0 + (x * y % 37) as f64 * 9.0);
        let capture = truth.mapv(|v| v * 1.07 - 3.0 + (v * 13.0).sin() * 8.0);
        let tone = ToneCurve {
            scale: 0.05 / truth.mean().unwrap_or(1.0),
            gamma: 0.3125,
        };
        let grid = RoiGrid::new(truth.dim(), 32);
        let s = score(&capture, &truth, &tone, &grid).expect("same size");
        let (d, t) = (tone.apply(&capture), tone.apply(&truth));
        let whole = psnr_db(d.view(), t.view(), 1.0).expect("same size");
        assert!(
            (s.psnr_db - whole).abs() < 1e-12 * whole,
            "{} vs {whole}",
            s.psnr_db
        );
        for r in 0..grid.rows {
            for c in 0..grid.cols {
                let rows = RoiGrid::widened(grid.row_range(r), SSIM_WINDOW_PX, 70);
                let cols = RoiGrid::widened(grid.col_range(c), SSIM_WINDOW_PX, 90);
                let crop = |a: &Array2<f64>| {
                    a.slice_axis(Axis(0), Slice::from(rows.clone()))
                        .slice_axis_move(Axis(1), Slice::from(cols.clone()))
                        .to_owned()
                };
                let whole = ssim(crop(&d).view(), crop(&t).view()).expect("big enough");
                assert_eq!(s.roi_ssim[[r, c]], whole, "ROI ({r}, {c})");
            }
        }
        assert!(s.worst_roi_ssim < 1.0 && s.worst_roi_ssim > 0.0);
        let bad = Array2::<f64>::zeros((70, 89));
        assert!(score(&bad, &truth, &tone, &grid).is_err());
    }
}
