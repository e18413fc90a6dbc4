//! Binning (§5.5.2, Table 5.1) and the ROI readout that applies a gain map and a bin map.
//!
//! Bins are `n×n` squares aligned to their ROI's top-left corner and cut at the ROI's (and the
//! image's) edge, so an ROI of a side that is not a multiple of `n` ends in narrower bins. Every
//! pixel of a bin carries the bin's estimate.

use ndarray::{Array2, ArrayViewMut2, Axis};
use rayon::prelude::*;

use super::noise::{Adc, BinRead, Frame, read_analog, read_pixel};
use super::roi::RoiGrid;
use super::{AdditiveGain, BinMode, SensorSpec};

/// Table 5.1: the variance of the per-pixel estimate `l̂` of a bin of `pixels` pixels at light
/// `light_e` (electrons per pixel), read at amplifier gain `amp_gain` (`ĝ` for additive
/// binning, `g/N` or `g` by [`AdditiveGain`]; `g` otherwise):
///
/// | mode | variance |
/// |---|---|
/// | no binning (`pixels` = 1) | `l* + σ_pre² + σ_post²/g²` |
/// | additive | `l*/N + σ_pre²/N + σ_post²/(N² ĝ²)` |
/// | average | `l*/N + σ_pre²/N + σ_post²/g²` |
/// | digital | `l*/N + σ_pre²/N + σ_post²/(N g²)` |
///
/// ADC quantisation is left out, as in the thesis.
pub fn variance(
    mode: BinMode,
    light_e: f64,
    sensor: &SensorSpec,
    amp_gain: f64,
    pixels: usize,
) -> f64 {
    let n = pixels.max(1) as f64;
    let (pre2, post2) = (
        sensor.sigma_pre_e * sensor.sigma_pre_e,
        sensor.sigma_post_e * sensor.sigma_post_e,
    );
    let g2 = amp_gain * amp_gain;
    let shared = (light_e + pre2) / n;
    shared
        + match mode {
            _ if pixels <= 1 => post2 / g2,
            BinMode::AnalogAdditive => post2 / (n * n * g2),
            BinMode::AnalogAverage => post2 / g2,
            BinMode::Digital => post2 / (n * g2),
        }
}

/// Read-noise RMS of the per-pixel estimate of a bin of `pixels` pixels whose pixel gain is
/// `gain` (additive bins read at the `ĝ` of `additive`): Table 5.1 at `l* = 0`.
pub fn read_sigma_e(
    mode: BinMode,
    additive: AdditiveGain,
    sensor: &SensorSpec,
    gain: f64,
    pixels: usize,
) -> f64 {
    let amp = mode.amplifier_gain(gain, pixels, additive);
    variance(mode, 0.0, sensor, amp, pixels).sqrt()
}

/// A readout of the whole image: the estimate, the saturation map and the maps of what was done.
#[derive(Debug, Clone)]
pub struct Readout {
    /// `l̂` per unit pixel, electrons.
    pub estimate_e: Array2<f64>,
    /// Whether the pixel's (or its bin's) code hit the top.
    pub saturated: Array2<bool>,
    /// The pixel gain `g` (additive bins are read at the `ĝ` of their [`AdditiveGain`]).
    pub gain: Array2<f32>,
    /// Side of the bin that holds the pixel, unit pixels (one of [`super::BIN_SIZES`]).
    pub bin: Array2<u8>,
}

impl Readout {
    /// The fraction of pixels that saturated.
    pub fn saturated_fraction(&self) -> f64 {
        fraction_true(&self.saturated)
    }
}

/// The fraction of `true` in `map` (0 for an empty one).
pub fn fraction_true(map: &Array2<bool>) -> f64 {
    let count: usize = map
        .axis_iter(Axis(0))
        .into_par_iter()
        .map(|row| row.iter().filter(|s| **s).count())
        .sum();
    count as f64 / map.len().max(1) as f64
}

/// A bin side as the bin map stores it (sides are at most 8; validated with the settings).
pub(crate) fn bin_side(n: usize) -> u8 {
    u8::try_from(n).unwrap_or(u8::MAX)
}

/// Reads `frame` ROI by ROI: ROI `(r, c)` at pixel gain `roi_gain[[r, c]]` in bins of
/// `roi_bin[[r, c]]` (see the module docs), combined in `mode` (additive bins amplified as
/// `additive` says).
///
/// # Panics
/// If `roi_gain` or `roi_bin` are not `grid.rows × grid.cols`, or the frame is not
/// `grid.dim`.
pub fn read_regions(
    frame: &Frame,
    grid: &RoiGrid,
    roi_gain: &Array2<f64>,
    roi_bin: &Array2<usize>,
    mode: BinMode,
    additive: AdditiveGain,
    adc: &Adc,
) -> Readout {
    let charge = frame.charge_e.as_standard_layout();
    let post = frame.post_noise_e.as_standard_layout();
    let (charge, post) = (
        charge.as_slice().unwrap_or_default(),
        post.as_slice().unwrap_or_default(),
    );
    read_by_bands(frame, grid, roi_gain, roi_bin, |r, maps| {
        let BandMaps {
            mut est,
            mut sat,
            mut gain,
            mut bin,
        } = maps;
        let band = Band {
            est: est.as_slice_mut().unwrap_or_default(),
            sat: sat.as_slice_mut().unwrap_or_default(),
            gain: gain.as_slice_mut().unwrap_or_default(),
            bin: bin.as_slice_mut().unwrap_or_default(),
        };
        let how = (mode, additive);
        read_band(r, grid, (charge, post), roi_gain, roi_bin, how, adc, band);
    })
}

/// One band of ROI rows of the four output maps, as 2-D views (`grid.roi_px` rows, or fewer at
/// the bottom, by `grid.dim.1`), in the order of [`Readout`]'s fields.
pub(crate) struct BandMaps<'a> {
    pub est: ArrayViewMut2<'a, f64>,
    pub sat: ArrayViewMut2<'a, bool>,
    pub gain: ArrayViewMut2<'a, f32>,
    pub bin: ArrayViewMut2<'a, u8>,
}

/// The frame of every region readout (monochrome here, Bayer in `cfa`): checks the maps'
/// sizes, then fills the readout's four maps one band of ROI rows at a time in parallel,
/// `read(r, maps)` writing ROI row `r`.
///
/// # Panics
/// If `roi_gain` or `roi_bin` are not `grid.rows × grid.cols`, or the frame is not
/// `grid.dim`.
pub(crate) fn read_by_bands(
    frame: &Frame,
    grid: &RoiGrid,
    roi_gain: &Array2<f64>,
    roi_bin: &Array2<usize>,
    read: impl Fn(usize, BandMaps<'_>) + Sync,
) -> Readout {
    assert_eq!(roi_gain.dim(), (grid.rows, grid.cols), "one gain per ROI");
    assert_eq!(roi_bin.dim(), (grid.rows, grid.cols), "one bin per ROI");
    assert_eq!(frame.charge_e.dim(), grid.dim, "a frame of the grid's size");
    let mut est = Array2::<f64>::zeros(grid.dim);
    let mut sat = Array2::from_elem(grid.dim, false);
    let mut gain = Array2::<f32>::zeros(grid.dim);
    let mut bin = Array2::<u8>::zeros(grid.dim);
    let band = grid.roi_px;
    est.axis_chunks_iter_mut(Axis(0), band)
        .into_par_iter()
        .zip(sat.axis_chunks_iter_mut(Axis(0), band).into_par_iter())
        .zip(gain.axis_chunks_iter_mut(Axis(0), band).into_par_iter())
        .zip(bin.axis_chunks_iter_mut(Axis(0), band).into_par_iter())
        .enumerate()
        .for_each(|(r, (((est, sat), gain), bin))| {
            read(
                r,
                BandMaps {
                    est,
                    sat,
                    gain,
                    bin,
                },
            );
        });
    Readout {
        estimate_e: est,
        saturated: sat,
        gain,
        bin,
    }
}

/// One band of ROI rows of the four output maps, row-major, `grid.dim.1` wide.
struct Band<'a> {
    est: &'a mut [f64],
    sat: &'a mut [bool],
    gain: &'a mut [f32],
    bin: &'a mut [u8],
}

/// Reads ROI row `r` into `out` (see [`read_regions`]).
#[allow(clippy::too_many_arguments)]
fn read_band(
    r: usize,
    grid: &RoiGrid,
    (charge, post): (&[f32], &[f32]),
    roi_gain: &Array2<f64>,
    roi_bin: &Array2<usize>,
    (mode, additive): (BinMode, AdditiveGain),
    adc: &Adc,
    out: Band<'_>,
) {
    let w = grid.dim.1;
    let rows = grid.row_range(r);
    let y0 = rows.start;
    for c in 0..grid.cols {
        let cols = grid.col_range(c);
        let g = roi_gain[[r, c]];
        let n = roi_bin[[r, c]].max(1);
        for y in rows.clone() {
            let o = (y - y0) * w;
            out.gain[o + cols.start..o + cols.end].fill(g as f32);
            out.bin[o + cols.start..o + cols.end].fill(bin_side(n));
        }
        if n == 1 {
            for y in rows.clone() {
                let (i, o) = (y * w, (y - y0) * w);
                for x in cols.clone() {
                    let read = read_pixel(charge[i + x].into(), post[i + x].into(), g, adc);
                    out.est[o + x] = read.estimate_e;
                    out.sat[o + x] = read.saturated;
                }
            }
            continue;
        }
        for by in rows.clone().step_by(n) {
            let ys = by..(by + n).min(rows.end);
            for bx in cols.clone().step_by(n) {
                let xs = bx..(bx + n).min(cols.end);
                let pixels = ys.len() * xs.len();
                let amp = mode.amplifier_gain(g, pixels, additive);
                let read = if mode == BinMode::Digital {
                    let (mut sum, mut saturated) = (0.0, false);
                    for y in ys.clone() {
                        for x in xs.clone() {
                            let (c, p) = (charge[y * w + x].into(), post[y * w + x].into());
                            let rd = read_pixel(c, p, amp, adc);
                            sum += rd.estimate_e;
                            saturated |= rd.saturated;
                        }
                    }
                    BinRead {
                        estimate_e: sum / pixels as f64,
                        saturated,
                    }
                } else {
                    let sum: f64 = ys
                        .clone()
                        .flat_map(|y| &charge[y * w + xs.start..y * w + xs.end])
                        .map(|&c| f64::from(c))
                        .sum();
                    read_analog(mode, amp, sum, pixels, post[by * w + bx].into(), adc)
                };
                for y in ys.clone() {
                    let o = (y - y0) * w;
                    out.est[o + xs.start..o + xs.end].fill(read.estimate_e);
                    out.sat[o + xs.start..o + xs.end].fill(read.saturated);
                }
            }
        }
    }
}
