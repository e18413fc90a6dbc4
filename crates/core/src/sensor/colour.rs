//! The colour sensor of [`super::run`] with [`Cfa::Rggb`]: the RGB scene on a Bayer mosaic,
//! each strategy's readout demosaiced, and its scores in luminance and per channel.
//!
//! **Channel response.** The filters are taken to pass exactly the scene's linear R, G and B:
//! a red site collects `k · R`, a green site `k · G`, a blue site `k · B` expected electrons,
//! where `k` is the exposure's electrons per unit radiance, set on the **luminance** as for
//! the monochrome sensor (Table 5.4: the luminance mean at 5 % of the full well). The
//! luminance weights sum to 1, so a grey scene exposes every site exactly as the monochrome
//! sensor exposes its pixel: the two sensors are compared at the same light, and only the
//! scene's colour, the mosaic, same-colour binning and the demosaic set them apart. A scene
//! of one plane (luminance), or of any count but three, is taken as grey, `R = G = B = Y`. Real filters overlap and
//! pass less light; leaving that out keeps the comparison about the readout.
//!
//! **Scores.** The truth is the noise-free RGB electrons. A readout (a mosaic) is demosaiced
//! ([`super::demosaic`]); its luminance (`0.2126 R + 0.7152 G + 0.0722 B`) becomes the
//! strategy's `capture` and is scored against the scene's luminance exactly as the monochrome
//! capture is, so Table 5.4's ordering can be compared between the two. The tone curve keeps
//! the **luminance** normalisation (`display_mean / mean(truth luminance)`) and is applied to
//! each channel, so a grey pixel displays as in monochrome; each channel is also scored
//! against the same channel of the truth ([`ChannelScores`]).
//!
//! **Precision.** The exposure is drawn from the mosaic's expected electrons in `f64`, exactly
//! as the monochrome sensor's; the colour planes kept (the truth's RGB, each capture's
//! demosaiced RGB) are `f32`, about 7 significant digits, far below the ADC's step and the shot
//! noise, and half the memory (the Limits chapter has the peaks). A mosaic is never kept beside
//! its RGB: the demosaic keeps each site's own sample, so the mosaic is the RGB read at each
//! site's colour ([`ColourTruth::mosaic_e`], [`ColourCapture::mosaic_e`]).

use ndarray::{Array2, Axis};
use rayon::prelude::*;

use super::binning::Readout;
use super::cfa::{self, Cfa};
use super::demosaic::demosaic_rggb_to;
use super::metrics::{self, ToneCurve};
use super::roi::RoiGrid;
use super::scene::{LUMINANCE_WEIGHTS, Scene};
use crate::{Sample, SimError};

/// Channel names in plane order.
pub const CHANNEL_NAMES: [&str; 3] = ["R", "G", "B"];

/// Working bytes per scene pixel that a colour run adds to a monochrome one: the truth's RGB
/// electrons (3 planes of 4 bytes); [`KEPT_BYTES_PER_PIXEL`] per strategy kept.
pub const EXTRA_BYTES_PER_PIXEL: u64 = 3 * 4;

/// What a kept strategy's colour capture adds per scene pixel: its demosaiced RGB (3 planes of
/// 4 bytes).
pub const KEPT_BYTES_PER_PIXEL: u64 = 3 * 4;

/// One channel's scores, as [`super::StrategyResult`]'s for luminance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelScores {
    /// Lowest ROI SSIM of the channel.
    pub worst_roi_ssim: f64,
    /// Area-weighted mean ROI SSIM of the channel.
    pub mean_ssim: f64,
    /// PSNR of the channel, peak 1.
    pub psnr_db: f64,
}

/// The colour ground truth of a run.
#[derive(Debug, Clone)]
pub struct ColourTruth {
    /// Expected electrons per site under each filter, `[R, G, B]` (noise-free, not clipped).
    pub rgb_e: [Array2<f32>; 3],
}

impl ColourTruth {
    /// The expected electrons of the RGGB mosaic, what the sensor is exposed to (to `f32`).
    pub fn mosaic_e(&self) -> Array2<f32> {
        cfa::mosaic_of(self.rgb_e.each_ref())
    }

    /// `rgb_e` through the tone curve, `[0, 1]`.
    pub fn display_rgb(&self, tone: &ToneCurve) -> [Array2<f64>; 3] {
        tone.apply_rgb(&self.rgb_e)
    }
}

/// One strategy's colour capture.
#[derive(Debug, Clone)]
pub struct ColourCapture {
    /// The demosaiced capture, `[R, G, B]`, electrons.
    pub rgb_e: [Array2<f32>; 3],
    /// Scores of each channel against the truth's, `[R, G, B]`.
    pub channels: [ChannelScores; 3],
}

impl ColourCapture {
    /// The readout as the sensor gives it: the estimate per site of the RGGB mosaic, electrons
    /// (the demosaic keeps each site's own sample).
    pub fn mosaic_e(&self) -> Array2<f32> {
        cfa::mosaic_of(self.rgb_e.each_ref())
    }

    /// `rgb_e` through the tone curve, `[0, 1]`.
    pub fn display_rgb(&self, tone: &ToneCurve) -> [Array2<f64>; 3] {
        tone.apply_rgb(&self.rgb_e)
    }
}

/// The expected electrons of the RGGB mosaic a colour run is exposed to, `f64`: each site's
/// plane of `scene` times `electrons_per_radiance`; `electrons` (the scene's luminance times
/// the same, which the run has made already) for a grey scene (see the module docs).
pub(super) fn expose_mosaic(
    scene: &Scene,
    electrons: &Array2<f64>,
    electrons_per_radiance: f64,
) -> Array2<f64> {
    match scene.planes.as_slice() {
        [r, g, b] => cfa::mosaic_scaled([r, g, b], electrons_per_radiance),
        _ => electrons.clone(),
    }
}

/// The colour truth of a run, `f32`: `[R, G, B]` of `planes` (the scene's, let go one by one
/// as they are converted) times `electrons_per_radiance`, or the grey `mosaic_e` three times.
pub(super) fn truth(
    planes: Vec<std::borrow::Cow<'_, Array2<f64>>>,
    mosaic_e: &Array2<f64>,
    electrons_per_radiance: f64,
) -> ColourTruth {
    #[allow(clippy::cast_possible_truncation)]
    let narrow = |p: &Array2<f64>, k: f64| p.mapv(|v| (v * k) as f32);
    let rgb_e = match <[_; 3]>::try_from(planes) {
        Ok(rgb) => rgb.map(|p| narrow(&p, electrons_per_radiance)),
        Err(_) => {
            let grey = narrow(mosaic_e, 1.0);
            [grey.clone(), grey.clone(), grey]
        }
    };
    ColourTruth { rgb_e }
}

/// The luminance of three planes, `f64`.
pub fn luminance<T: Sample>(rgb: &[Array2<T>; 3]) -> Array2<f64> {
    let mut out = Array2::<f64>::zeros(rgb[0].dim());
    luminance_into(rgb, &mut out);
    out
}

/// [`luminance`] written over `out`, a plane of the planes' size.
fn luminance_into<T: Sample>(rgb: &[Array2<T>; 3], out: &mut Array2<f64>) {
    let [wr, wg, wb] = LUMINANCE_WEIGHTS;
    out.axis_iter_mut(Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(y, mut row)| {
            for (x, o) in row.iter_mut().enumerate() {
                let (r, g, b): (f64, f64, f64) = (
                    rgb[0][[y, x]].into(),
                    rgb[1][[y, x]].into(),
                    rgb[2][[y, x]].into(),
                );
                *o = wr * r + wg * g + wb * b;
            }
        });
}

/// Develops a readout: without a colour truth (a monochrome run) it is returned as it is;
/// with one, its mosaic is demosaiced, the readout's estimate becomes the luminance of the
/// result, and the colour capture with its per-channel scores comes along.
///
/// # Errors
/// As [`metrics::score`].
pub(super) fn develop(
    mut readout: Readout,
    truth: Option<&ColourTruth>,
    tone: &ToneCurve,
    grid: &RoiGrid,
) -> Result<(Readout, Option<ColourCapture>), SimError> {
    let Some(truth) = truth else {
        return Ok((readout, None));
    };
    // Demosaiced straight from the f64 estimate into f32 planes, which hold the mosaic's every
    // sample; the luminance then replaces the estimate in its own buffer. No plane is allocated
    // but the RGB: a 16-megapixel run would otherwise free and allocate 200 MB per strategy.
    let rgb_e: [Array2<f32>; 3] = demosaic_rggb_to(&readout.estimate_e);
    let mut channels = [ChannelScores {
        worst_roi_ssim: 0.0,
        mean_ssim: 0.0,
        psnr_db: 0.0,
    }; 3];
    for (c, out) in channels.iter_mut().enumerate() {
        let s = metrics::score(&rgb_e[c], &truth.rgb_e[c], tone, grid)?;
        *out = ChannelScores {
            worst_roi_ssim: s.worst_roi_ssim,
            mean_ssim: s.mean_ssim,
            psnr_db: s.psnr_db,
        };
    }
    luminance_into(&rgb_e, &mut readout.estimate_e);
    Ok((readout, Some(ColourCapture { rgb_e, channels })))
}

/// Whether `cfa` needs the colour path.
pub(super) fn is_colour(cfa: Cfa) -> bool {
    cfa != Cfa::None
}
