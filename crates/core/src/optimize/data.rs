//! The data-driven loss of §3.4.2: photos blurred by each channel's PSF and restored with a
//! Wiener filter (noise-free, circular on a patch), scored by the mean squared residual over the
//! worst 10 % of pixels (hard-sample mining), with its gradient with respect to the PSFs.
//!
//! The thesis writes the loss as a sum over the top 10 %; we take the mean so that its weight
//! (conventions.md §6: 10) balances the area and invertibility terms whatever the patch count.

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::SimError;
use crate::psf::spectra::dft2_complex;

/// Noise-to-signal ratio of the Wiener filter (conventions.md §5).
pub const DATA_NSR: f64 = 0.00371;
/// Fraction of the largest residuals kept.
pub const TOP_FRACTION: f64 = 0.1;

/// Square training patches, one plane per channel, and their spectra.
#[derive(Debug, Clone)]
pub struct DataSet {
    /// Side of the square patches, px.
    pub side_px: usize,
    /// `spectra[photo][channel]`.
    spectra: Vec<Vec<Array2<Complex64>>>,
}

/// Index of PSF pixel `y` (axis at `c`) on a circular grid of `s` with the axis at 0.
fn wrap(y: usize, c: usize, s: usize) -> usize {
    (y as i64 - c as i64).rem_euclid(s as i64) as usize
}

/// Box-downscales `plane` by an integer factor so its short side is at least `side`, then crops
/// the centre `side × side`. `None` when the plane is smaller than `side`.
fn patch(plane: &Array2<f64>, side: usize) -> Option<Array2<f64>> {
    let (h, w) = plane.dim();
    let short = h.min(w);
    if short < side || side == 0 {
        return None;
    }
    let f = (short / side).max(1);
    let (h2, w2) = (h / f, w / f);
    let (y0, x0) = ((h2 - side) / 2, (w2 - side) / 2);
    let area = (f * f) as f64;
    // (`s!` slicing is off limits: the macro expands to an `allow(unsafe_code)` we forbid.)
    Some(Array2::from_shape_fn((side, side), |(y, x)| {
        let (sy, sx) = ((y0 + y) * f, (x0 + x) * f);
        let mut acc = 0.0;
        for yy in sy..sy + f {
            for xx in sx..sx + f {
                acc += plane[[yy, xx]];
            }
        }
        acc / area
    }))
}

impl DataSet {
    /// Patches of `side_px` from photos (`photos[i][channel]`, values in `[0, 1]`); photos too
    /// small for a patch are skipped.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] when no photo gives a patch or channel counts differ from
    /// `channels`.
    pub fn new(
        photos: &[Vec<Array2<f64>>],
        channels: usize,
        side_px: usize,
    ) -> Result<Self, SimError> {
        let mut spectra = Vec::new();
        for (i, photo) in photos.iter().enumerate() {
            if photo.len() != channels {
                return Err(SimError::invalid(
                    "data",
                    format!(
                        "photo {i} has {} channels, the design {channels}",
                        photo.len()
                    ),
                ));
            }
            let planes: Option<Vec<_>> = photo.iter().map(|p| patch(p, side_px)).collect();
            if let Some(planes) = planes {
                spectra.push(
                    planes
                        .iter()
                        .map(|p| dft2_complex(&p.mapv(|v| Complex64::new(v, 0.0)), false))
                        .collect(),
                );
            }
        }
        if spectra.is_empty() {
            return Err(SimError::invalid(
                "data",
                format!("no photo is at least {side_px}×{side_px} pixels"),
            ));
        }
        Ok(DataSet { side_px, spectra })
    }

    /// Number of photos that gave a patch.
    pub fn len(&self) -> usize {
        self.spectra.len()
    }

    /// Whether no photo gave a patch (never true once built).
    pub fn is_empty(&self) -> bool {
        self.spectra.is_empty()
    }

    /// The loss for the channel PSFs (each `W×W`, axis at `W/2`, `W ≤ side`) and, with `grad`,
    /// `∂L/∂psf` per channel.
    pub fn loss(&self, psfs: &[Array2<f64>], grad: bool) -> (f64, Option<Vec<Array2<f64>>>) {
        let s = self.side_px;
        let norm = (s * s) as f64;
        // OTF of each PSF embedded circularly with its axis at [0, 0].
        let otfs: Vec<Array2<Complex64>> = psfs
            .par_iter()
            .map(|psf| {
                let c = psf.nrows() / 2;
                let mut e = Array2::<Complex64>::zeros((s, s));
                for ((y, x), v) in psf.indexed_iter() {
                    let (ey, ex) = (wrap(y, c, s), wrap(x, c, s));
                    e[[ey, ex]] += Complex64::new(*v, 0.0);
                }
                dft2_complex(&e, false)
            })
            .collect();
        let responses: Vec<Array2<f64>> = otfs
            .iter()
            .map(|k| k.mapv(|z| z.norm_sqr() / (z.norm_sqr() + DATA_NSR)))
            .collect();
        // Residuals r = x̂ − x = IDFT(X (H − 1)) / S², per photo and channel.
        let residuals: Vec<Vec<Array2<f64>>> = self
            .spectra
            .par_iter()
            .map(|photo| {
                photo
                    .iter()
                    .zip(&responses)
                    .map(|(x, h)| {
                        let y = ndarray::Zip::from(x)
                            .and(h)
                            .map_collect(|x, h| x * (h - 1.0));
                        dft2_complex(&y, true).mapv(|z| z.re / norm)
                    })
                    .collect()
            })
            .collect();
        let mut all: Vec<f64> = residuals
            .iter()
            .flatten()
            .flat_map(|r| r.iter().map(|v| v * v))
            .collect();
        let count = ((TOP_FRACTION * all.len() as f64).ceil() as usize).clamp(1, all.len().max(1));
        let total = all.len();
        if total == 0 {
            return (0.0, None);
        }
        let pivot = total - count;
        all.select_nth_unstable_by(pivot, f64::total_cmp);
        let threshold = all[pivot];
        let loss = all[pivot..].iter().sum::<f64>() / count as f64;
        if !grad {
            return (loss, None);
        }
        // ∂L/∂H per channel, summed over photos: Re(X · conj(DFT(∂L/∂r))) / S².
        let channels = psfs.len();
        let g_h: Vec<Array2<f64>> = (0..channels)
            .into_par_iter()
            .map(|c| {
                let mut acc = Array2::<f64>::zeros((s, s));
                for (photo, res) in self.spectra.iter().zip(&residuals) {
                    let g_r = res[c].mapv(|v| {
                        if v * v >= threshold {
                            Complex64::new(2.0 * v / count as f64, 0.0)
                        } else {
                            Complex64::new(0.0, 0.0)
                        }
                    });
                    let g = dft2_complex(&g_r, false);
                    ndarray::Zip::from(&mut acc)
                        .and(&photo[c])
                        .and(&g)
                        .for_each(|a, x, g| *a += (x * g.conj()).re / norm);
                }
                acc
            })
            .collect();
        let grads = otfs
            .par_iter()
            .zip(g_h.par_iter())
            .zip(psfs.par_iter())
            .map(|((k, gh), psf)| {
                // H = P/(P + nsr), P = |K|²; ∂L/∂K = 2 ∂L/∂P K; ∂L/∂psf = Re(DFTᴴ ∂L/∂K).
                let g_k = ndarray::Zip::from(k).and(gh).map_collect(|k, gh| {
                    let d = k.norm_sqr() + DATA_NSR;
                    2.0 * gh * DATA_NSR / (d * d) * k
                });
                let g_e = dft2_complex(&g_k, true);
                let (w, c) = (psf.nrows(), psf.nrows() / 2);
                Array2::from_shape_fn((w, w), |(y, x)| g_e[[wrap(y, c, s), wrap(x, c, s)]].re)
            })
            .collect();
        (loss, Some(grads))
    }
}
