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

use ndarray::{Array2, Axis};
use rayon::prelude::*;

use super::binning::Readout;
use super::cfa::{self, Cfa};
use super::demosaic::demosaic_rggb;
use super::metrics::{self, ToneCurve};
use super::roi::RoiGrid;
use super::scene::{LUMINANCE_WEIGHTS, Scene};
use crate::SimError;

/// Channel names in plane order.
pub const CHANNEL_NAMES: [&str; 3] = ["R", "G", "B"];

/// Working bytes per scene pixel that a colour run adds to a monochrome one: the truth's RGB
/// electrons and mosaic (4 planes of 8 bytes); [`KEPT_BYTES_PER_PIXEL`] per strategy kept.
pub const EXTRA_BYTES_PER_PIXEL: u64 = 4 * 8;

/// What a kept strategy's colour capture adds per scene pixel: its mosaic and demosaiced RGB
/// (4 planes of 8 bytes).
pub const KEPT_BYTES_PER_PIXEL: u64 = 4 * 8;

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
    pub rgb_e: [Array2<f64>; 3],
    /// The expected electrons of the RGGB mosaic: what the sensor is exposed to.
    pub mosaic_e: Array2<f64>,
}

impl ColourTruth {
    /// `rgb_e` through the tone curve, `[0, 1]`.
    pub fn display_rgb(&self, tone: &ToneCurve) -> [Array2<f64>; 3] {
        tone.apply_rgb(&self.rgb_e)
    }
}

/// One strategy's colour capture.
#[derive(Debug, Clone)]
pub struct ColourCapture {
    /// The readout as the sensor gives it: the estimate per site of the RGGB mosaic, electrons.
    pub mosaic_e: Array2<f64>,
    /// The demosaiced capture, `[R, G, B]`, electrons.
    pub rgb_e: [Array2<f64>; 3],
    /// Scores of each channel against the truth's, `[R, G, B]`.
    pub channels: [ChannelScores; 3],
}

impl ColourCapture {
    /// `rgb_e` through the tone curve, `[0, 1]`.
    pub fn display_rgb(&self, tone: &ToneCurve) -> [Array2<f64>; 3] {
        tone.apply_rgb(&self.rgb_e)
    }
}

/// The expected electrons of a colour run: `[R, G, B]` planes of `scene` times
/// `electrons_per_radiance` (see the module docs; one plane is grey) and their mosaic.
pub(super) fn expose(
    scene: &Scene,
    electrons_per_radiance: f64,
) -> ([Array2<f64>; 3], Array2<f64>) {
    let rgb: [Array2<f64>; 3] = match scene.planes.as_slice() {
        [r, g, b] => [r, g, b].map(|p| p.mapv(|v| v * electrons_per_radiance)),
        _ => {
            let y = scene.luminance().mapv(|v| v * electrons_per_radiance);
            [y.clone(), y.clone(), y]
        }
    };
    let mosaic = cfa::mosaic([&rgb[0], &rgb[1], &rgb[2]]);
    (rgb, mosaic)
}

/// The luminance of three planes.
pub fn luminance(rgb: &[Array2<f64>; 3]) -> Array2<f64> {
    let mut out = Array2::<f64>::zeros(rgb[0].dim());
    let [wr, wg, wb] = LUMINANCE_WEIGHTS;
    out.axis_iter_mut(Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(y, mut row)| {
            for (x, o) in row.iter_mut().enumerate() {
                *o = wr * rgb[0][[y, x]] + wg * rgb[1][[y, x]] + wb * rgb[2][[y, x]];
            }
        });
    out
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
    let rgb_e = demosaic_rggb(&readout.estimate_e);
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
    let mosaic_e = std::mem::replace(&mut readout.estimate_e, luminance(&rgb_e));
    Ok((
        readout,
        Some(ColourCapture {
            mosaic_e,
            rgb_e,
            channels,
        }),
    ))
}

/// Whether `cfa` needs the colour path.
pub(super) fn is_colour(cfa: Cfa) -> bool {
    cfa != Cfa::None
}
