//! Image quality against the ground truth: PSNR and SSIM (Wang et al. 2004), the two numbers of
//! thesis Fig. 3.8.
//!
//! SSIM follows scikit-image's `structural_similarity(a, b, data_range=1, gaussian_weights=True,
//! sigma=1.5, use_sample_covariance=False)`: local means, variances and covariance under a
//! Gaussian window of σ = 1.5 px truncated at 3.5σ (radius 5, an 11×11 window), constants
//! `C1 = (0.01·1)²` and `C2 = (0.03·1)²`, and the mean of the SSIM map over the pixels whose window
//! lies wholly inside the image (scikit-image crops the 5-pixel border after filtering, so its
//! border mode never shows).

use ndarray::ArrayView2;
use rayon::prelude::*;

use crate::{Sample, SimError};

/// Gaussian σ of the SSIM window, pixels.
pub const SSIM_SIGMA_PX: f64 = 1.5;
/// Radius of the SSIM window: `int(3.5σ + 0.5)` as scipy truncates it.
pub const SSIM_RADIUS_PX: usize = 5;
/// SSIM's `K1` and `K2`.
pub const SSIM_K1: f64 = 0.01;
/// SSIM's `K2` (see `SSIM_K1`).
pub const SSIM_K2: f64 = 0.03;

fn same_size<A: Sample, B: Sample>(
    a: ArrayView2<'_, A>,
    b: ArrayView2<'_, B>,
) -> Result<(), SimError> {
    if a.dim() != b.dim() {
        return Err(SimError::invalid(
            "image",
            format!("the images differ in size ({:?} vs {:?})", a.dim(), b.dim()),
        ));
    }
    if a.is_empty() {
        return Err(SimError::invalid("image", "the images are empty"));
    }
    Ok(())
}

/// `Σ (a − b)²` and the number of pixels.
fn squared_error<A: Sample, B: Sample>(a: ArrayView2<'_, A>, b: ArrayView2<'_, B>) -> (f64, usize) {
    let rows: Vec<f64> = a
        .outer_iter()
        .into_par_iter()
        .zip(b.outer_iter().into_par_iter())
        .map(|(ra, rb)| {
            ra.iter()
                .zip(rb.iter())
                .map(|(x, y)| {
                    let d = (*x).into() - (*y).into();
                    d * d
                })
                .sum()
        })
        .collect();
    (rows.iter().sum(), a.len())
}

/// `10 log10(peak² / MSE)` of a sum of squared errors over `n` pixels; `+∞` when it is 0.
pub(crate) fn psnr_of(sse: f64, n: usize, peak: f64) -> f64 {
    let mse = sse / n as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (peak * peak / mse).log10()
    }
}

/// `10 log10(peak² / MSE)` in dB; `+∞` for identical images.
///
/// # Errors
/// [`SimError::InvalidSetting`] (`image`) for images of different sizes or empty ones.
pub fn psnr_db<A: Sample, B: Sample>(
    a: ArrayView2<'_, A>,
    b: ArrayView2<'_, B>,
    peak: f64,
) -> Result<f64, SimError> {
    same_size(a, b)?;
    let (sse, n) = squared_error(a, b);
    Ok(psnr_of(sse, n, peak))
}

/// PSNR with the MSE pooled over every pixel of every channel (`pairs` = (test, truth)).
///
/// # Errors
/// As [`psnr_db`], and for no pairs at all.
pub fn psnr_db_pooled<A: Sample, B: Sample>(
    pairs: &[(ArrayView2<'_, A>, ArrayView2<'_, B>)],
    peak: f64,
) -> Result<f64, SimError> {
    if pairs.is_empty() {
        return Err(SimError::invalid("image", "no channels"));
    }
    let mut sse = 0.0;
    let mut n = 0;
    for (a, b) in pairs {
        same_size(*a, *b)?;
        let (s, k) = squared_error(*a, *b);
        sse += s;
        n += k;
    }
    Ok(psnr_of(sse, n, peak))
}

/// [`psnr_db_pooled`] of matching planes (`test[c]` against `truth[c]`).
///
/// # Errors
/// As [`psnr_db_pooled`], and for different numbers of planes.
pub fn psnr_db_planes<A: Sample, B: Sample>(
    test: &[ndarray::Array2<A>],
    truth: &[ndarray::Array2<B>],
    peak: f64,
) -> Result<f64, SimError> {
    if test.len() != truth.len() {
        return Err(SimError::invalid(
            "image",
            format!("{} channels against {}", test.len(), truth.len()),
        ));
    }
    let pairs: Vec<_> = test
        .iter()
        .zip(truth)
        .map(|(a, b)| (a.view(), b.view()))
        .collect();
    psnr_db_pooled(&pairs, peak)
}

/// How close a restored image is to its ground truth, plane by plane (channels of a colour
/// image): PSNR pooled over all planes at peak 1 ([`psnr_db_pooled`]) and SSIM averaged over
/// them ([`ssim`]).
///
/// # Errors
/// As [`psnr_db_planes`] and [`ssim`].
pub fn planes_quality<A: Sample, B: Sample>(
    test: &[ndarray::Array2<A>],
    truth: &[ndarray::Array2<B>],
) -> Result<PlanesQuality, SimError> {
    let psnr_db = psnr_db_planes(test, truth, 1.0)?;
    let mut sum = 0.0;
    for (a, b) in test.iter().zip(truth) {
        sum += ssim(a.view(), b.view())?;
    }
    Ok(PlanesQuality {
        psnr_db,
        ssim: sum / test.len().max(1) as f64,
    })
}

/// The scores of [`planes_quality`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanesQuality {
    /// PSNR pooled over the planes, dB.
    pub psnr_db: f64,
    /// SSIM averaged over the planes.
    pub ssim: f64,
}

/// The normalised Gaussian taps `w[t]`, `t = −radius … radius`.
fn gaussian_taps() -> Vec<f64> {
    let r = SSIM_RADIUS_PX as f64;
    let taps: Vec<f64> = (0..=2 * SSIM_RADIUS_PX)
        .map(|t| {
            let d = t as f64 - r;
            (-0.5 * d * d / (SSIM_SIGMA_PX * SSIM_SIGMA_PX)).exp()
        })
        .collect();
    let sum: f64 = taps.iter().sum();
    taps.into_iter().map(|v| v / sum).collect()
}

/// Mean SSIM of `a` against `b` for data in `[0, 1]` (see the module docs).
///
/// # Errors
/// [`SimError::InvalidSetting`] (`image`) for images of different sizes or smaller than the
/// 11×11 window.
pub fn ssim<A: Sample, B: Sample>(
    a: ArrayView2<'_, A>,
    b: ArrayView2<'_, B>,
) -> Result<f64, SimError> {
    same_size(a, b)?;
    let (h, w) = a.dim();
    let win = 2 * SSIM_RADIUS_PX + 1;
    if h < win || w < win {
        return Err(SimError::invalid(
            "image",
            format!("SSIM needs at least {win}×{win} pixels (got {h}×{w})"),
        ));
    }
    let taps = gaussian_taps();
    let (oh, ow) = (h - win + 1, w - win + 1);
    let c1 = (SSIM_K1 * 1.0f64).powi(2);
    let c2 = (SSIM_K2 * 1.0f64).powi(2);
    // Blocks of output rows, each from its own `BLOCK + 10` input rows, so the five moment
    // planes of a block stay in cache. Within a block each tap is an axpy over a whole row,
    // which the compiler vectorises. Block sums are added in order: the same bits whatever the
    // thread count.
    const BLOCK: usize = 48;
    let blocks: Vec<f64> = (0..oh.div_ceil(BLOCK))
        .into_par_iter()
        .map(|blk| {
            let i0 = blk * BLOCK;
            let rows_out = BLOCK.min(oh - i0);
            let rows_in = rows_out + win - 1;
            // Horizontal pass: moments x, y, x², y², xy at the valid columns.
            let mut planes: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; rows_in * ow]);
            let mut src: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; w]);
            for r in 0..rows_in {
                let (ra, rb) = (a.row(i0 + r), b.row(i0 + r));
                for (k, (x, y)) in ra.iter().zip(rb.iter()).enumerate() {
                    let (x, y): (f64, f64) = ((*x).into(), (*y).into());
                    src[0][k] = x;
                    src[1][k] = y;
                    src[2][k] = x * x;
                    src[3][k] = y * y;
                    src[4][k] = x * y;
                }
                for (plane, s) in planes.iter_mut().zip(&src) {
                    let out = &mut plane[r * ow..(r + 1) * ow];
                    let centre = &s[SSIM_RADIUS_PX..SSIM_RADIUS_PX + ow];
                    for (o, v) in out.iter_mut().zip(centre) {
                        *o = taps[SSIM_RADIUS_PX] * v;
                    }
                    // The window is symmetric: one multiply per pair of taps.
                    for (t, g) in taps[..SSIM_RADIUS_PX].iter().enumerate() {
                        let near = &s[t..t + ow];
                        let far = &s[win - 1 - t..win - 1 - t + ow];
                        for ((o, a), b) in out.iter_mut().zip(near).zip(far) {
                            *o += g * (a + b);
                        }
                    }
                }
            }
            // Vertical pass and the SSIM map.
            let mut m: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; ow]);
            let mut sum = 0.0;
            for i in 0..rows_out {
                for (out, plane) in m.iter_mut().zip(&planes) {
                    let row = |t: usize| &plane[(i + t) * ow..(i + t + 1) * ow];
                    for (o, v) in out.iter_mut().zip(row(SSIM_RADIUS_PX)) {
                        *o = taps[SSIM_RADIUS_PX] * v;
                    }
                    for (t, g) in taps[..SSIM_RADIUS_PX].iter().enumerate() {
                        for ((o, a), b) in out.iter_mut().zip(row(t)).zip(row(win - 1 - t)) {
                            *o += g * (a + b);
                        }
                    }
                }
                let [ux, uy, uxx, uyy, uxy] = &m;
                for j in 0..ow {
                    let (ux, uy) = (ux[j], uy[j]);
                    let (vx, vy, vxy) = (uxx[j] - ux * ux, uyy[j] - uy * uy, uxy[j] - ux * uy);
                    sum += ((2.0 * ux * uy + c1) * (2.0 * vxy + c2))
                        / ((ux * ux + uy * uy + c1) * (vx + vy + c2));
                }
            }
            sum
        })
        .collect();
    Ok(blocks.iter().sum::<f64>() / (oh * ow) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;

    #[test]
    fn identical_images_score_one_and_infinity() {
        let a = Array2::from_shape_fn((20, 30), |(y, x)| ((y * 13 + x * 7) % 17) as f64 / 17.0);
        assert_eq!(psnr_db(a.view(), a.view(), 1.0).ok(), Some(f64::INFINITY));
        let s = ssim(a.view(), a.view()).expect("big enough");
        assert!((s - 1.0).abs() < 1e-12, "{s}");
    }

    #[test]
    fn psnr_of_a_constant_offset() {
        let a = Array2::from_elem((8, 8), 0.5);
        let b = Array2::from_elem((8, 8), 0.6);
        // MSE 0.01 → 20 dB.
        let p = psnr_db(a.view(), b.view(), 1.0).expect("same size");
        assert!((p - 20.0).abs() < 1e-9, "{p}");
        let pooled =
            psnr_db_pooled(&[(a.view(), b.view()), (a.view(), a.view())], 1.0).expect("same size");
        assert!((pooled - 10.0 * 200f64.log10()).abs() < 1e-9, "{pooled}");
    }

    #[test]
    fn ssim_of_flat_images_is_the_luminance_term() {
        // No variance anywhere: SSIM = (2ab + C1)/(a² + b² + C1), by hand.
        let a = Array2::from_elem((11, 11), 0.5);
        let b = Array2::from_elem((11, 11), 0.25);
        let want = (2.0 * 0.5 * 0.25 + 1e-4) / (0.25 + 0.0625 + 1e-4);
        let got = ssim(a.view(), b.view()).expect("11×11");
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    }

    #[test]
    fn ssim_rejects_images_smaller_than_the_window() {
        let a = Array2::from_elem((10, 40), 0.5);
        assert!(ssim(a.view(), a.view()).is_err());
    }
}
