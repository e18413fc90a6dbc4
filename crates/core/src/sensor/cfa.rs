//! Colour filter arrays: the RGGB Bayer mosaic, and the readouts of chapter 5 on a Bayer sensor,
//! where binning combines sites of the **same colour** (thesis §5.6: the BFS-U3-200S6C is a
//! Bayer colour camera; Jin and Hirakawa 2012 analyse binning on such sensors).
//!
//! **Mosaic.** Site `(y, x)` of an RGGB sensor sits under the filter [`rggb_channel`]: red at
//! even row and even column, blue at odd row and odd column, green elsewhere (`Gr` on the red
//! rows, `Gb` on the blue rows). Its expected electrons are the scene's linear channel of that
//! colour times the exposure's electrons per radiance ([`mosaic`]); the `colour` module states
//! the response assumption.
//!
//! **Same-colour binning.** The sites of one colour *phase* (R, Gr, Gb or B: one of the four
//! `(y mod 2, x mod 2)`) form a grid of pitch 2. A bin of side `n` combines `n×n` sites of one
//! phase: every other row and column of a `2n×2n` super-block. For `n = 2` this is quad-Bayer
//! binning: a 4×4 super-block holds a 2×2 bin of each of R, Gr, Gb and B. Gr and Gb are binned
//! apart, so every bin holds `n²` sites, Table 5.1's `N`, whatever its colour. As in the
//! monochrome readout, bins start at the ROI's first site of each phase and are cut at the
//! ROI's (and the image's) edge; every site of a bin carries the bin's estimate, so the readout
//! is still a full-resolution RGGB mosaic, ready for the `demosaic` module. Gain and bin size stay
//! one per ROI.
//!
//! **Snapshot.** The two-shot strategies' snapshot bins 2×2 same-colour sites (a 4×4
//! super-block per block), and an ROI's peak is its brightest block of **any** colour, so
//! eq. 5.3's gain keeps the brightest channel from clipping.
//!
//! **Row-wise gains.** Alternating rows alternate in *pairs* of rows (one R/G and one G/B row
//! at each gain, as dual-ISO Bayer sensors do) and substitute from the same-colour rows two
//! above and below; the single-shot per-pixel gain of a site comes from the readout of the
//! previous site of the same colour (two to the left).

use std::ops::Range;

use ndarray::{Array2, ArrayView2, Axis};
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;

use super::binning::{BandMaps, Readout, bin_side, read_by_bands};
use super::gain::{SNAPSHOT_BLOCK_PX, Snapshot};
use super::noise::{Adc, Frame, photons, read_analog, read_bin, read_pixel, row_rng, stream};
use super::roi::RoiGrid;
use super::{AdditiveGain, BinMode, SensorSpec};

/// The sensor's colour filter array.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Cfa {
    /// No filters: a monochrome sensor that sees the scene's luminance (`none`).
    #[default]
    #[strum(serialize = "none")]
    None,
    /// An RGGB Bayer mosaic with same-colour binning and a demosaic (`rggb`).
    #[strum(serialize = "rggb")]
    Rggb,
}

impl Cfa {
    /// Every colour filter array, in menu order.
    pub const ALL: [Cfa; 2] = [Cfa::None, Cfa::Rggb];

    /// The name the CLI takes and reports print.
    pub fn label(self) -> &'static str {
        self.into()
    }
}

/// The colour under RGGB site `(y, x)`: 0 = red, 1 = green, 2 = blue.
pub fn rggb_channel(y: usize, x: usize) -> usize {
    match (y % 2, x % 2) {
        (0, 0) => 0,
        (1, 1) => 2,
        _ => 1,
    }
}

/// The RGGB mosaic of three equal-sized planes: each site takes the plane of its colour.
///
/// # Panics
/// If the planes differ in size.
pub fn mosaic(rgb: [&Array2<f64>; 3]) -> Array2<f64> {
    mosaic_scaled(rgb, 1.0)
}

/// [`mosaic`] of the three planes times `scale` (each site's sample is multiplied once, so the
/// sites read exactly as the scaled planes would).
///
/// # Panics
/// If the planes differ in size.
pub fn mosaic_scaled(rgb: [&Array2<f64>; 3], scale: f64) -> Array2<f64> {
    mosaic_with(rgb, |v| v * scale)
}

/// The RGGB mosaic of three equal-sized planes of any sample type, each site's sample as it is.
///
/// # Panics
/// If the planes differ in size.
pub fn mosaic_of<T: Copy + Send + Sync + Default>(rgb: [&Array2<T>; 3]) -> Array2<T> {
    mosaic_with(rgb, |v| v)
}

/// The RGGB mosaic of three equal-sized planes, each site's sample through `f`.
fn mosaic_with<T: Copy + Sync, U: Default + Send + Sync>(
    rgb: [&Array2<T>; 3],
    f: impl Fn(T) -> U + Sync,
) -> Array2<U> {
    let dim = rgb[0].dim();
    assert!(
        rgb.iter().all(|p| p.dim() == dim),
        "three planes of one size"
    );
    let mut out = Array2::<U>::default(dim);
    out.axis_iter_mut(Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(y, mut row)| {
            for (x, o) in row.iter_mut().enumerate() {
                *o = f(rgb[rggb_channel(y, x)][[y, x]]);
            }
        });
    out
}

/// The first index of `range` with `index mod 2 == phase`, if any.
fn first_of_phase(range: &Range<usize>, phase: usize) -> Option<usize> {
    let first = range.start + (range.start + phase) % 2;
    (first < range.end).then_some(first)
}

/// The sites of one same-colour bin: starting at `(y0, x0)`, every other row and column of the
/// `2n×2n` super-block, cut at `rows.end` and `cols.end`.
fn bin_sites(
    (y0, x0): (usize, usize),
    n: usize,
    rows_end: usize,
    cols_end: usize,
) -> impl Iterator<Item = (usize, usize)> {
    (y0..(y0 + 2 * n).min(rows_end))
        .step_by(2)
        .flat_map(move |y| {
            (x0..(x0 + 2 * n).min(cols_end))
                .step_by(2)
                .map(move |x| (y, x))
        })
}

/// Reads a Bayer `frame` ROI by ROI, like [`super::binning::read_regions`], but a bin of side
/// `n` combines `n×n` sites of one colour (see the module docs).
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
    read_by_bands(frame, grid, roi_gain, roi_bin, |r, maps| {
        let BandMaps {
            est: mut e,
            sat: mut s,
            gain: mut g,
            bin: mut b,
        } = maps;

        let rows = grid.row_range(r);
        let y0 = rows.start;
        let (mut charges, mut posts, mut sites) = (Vec::new(), Vec::new(), Vec::new());
        for c in 0..grid.cols {
            let cols = grid.col_range(c);
            let (roi_g, n) = (roi_gain[[r, c]], roi_bin[[r, c]].max(1));
            for y in rows.clone() {
                for x in cols.clone() {
                    g[[y - y0, x]] = roi_g as f32;
                    b[[y - y0, x]] = bin_side(n);
                }
            }
            if n == 1 {
                // Unbinned: each site on its own, as on the monochrome sensor.
                for y in rows.clone() {
                    for x in cols.clone() {
                        let rd = read_pixel(
                            frame.charge_e[[y, x]].into(),
                            frame.post_noise_e[[y, x]].into(),
                            roi_g,
                            adc,
                        );
                        e[[y - y0, x]] = rd.estimate_e;
                        s[[y - y0, x]] = rd.saturated;
                    }
                }
                continue;
            }
            for (py, px) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (Some(ys), Some(xs)) = (first_of_phase(&rows, py), first_of_phase(&cols, px))
                else {
                    continue;
                };
                for by in (ys..rows.end).step_by(2 * n) {
                    for bx in (xs..cols.end).step_by(2 * n) {
                        sites.clear();
                        charges.clear();
                        posts.clear();
                        for (y, x) in bin_sites((by, bx), n, rows.end, cols.end) {
                            sites.push((y, x));
                            charges.push(f64::from(frame.charge_e[[y, x]]));
                            posts.push(f64::from(frame.post_noise_e[[y, x]]));
                        }
                        let amp = mode.amplifier_gain(roi_g, sites.len(), additive);
                        let read = read_bin(mode, amp, &charges, &posts, adc);
                        for (y, x) in &sites {
                            e[[y - y0, *x]] = read.estimate_e;
                            s[[y - y0, *x]] = read.saturated;
                        }
                    }
                }
            }
        }
    })
}

/// The two-shot snapshot of a Bayer sensor: like [`super::gain::take_snapshot`] (its own
/// exposure, base gain, 2×2 analog-average blocks), but each block holds 2×2 sites of **one**
/// colour, the top-left sites of a 4×4 super-block's phase. An ROI is summarised from the
/// blocks whose top-left site it holds: its peak is the brightest block of any colour, its mean
/// the mean of all its blocks.
pub fn take_snapshot(
    mosaic_e: ArrayView2<'_, f64>,
    sensor: &SensorSpec,
    grid: &RoiGrid,
    seed: u64,
) -> Snapshot {
    let adc = Adc::of(sensor);
    let n = SNAPSHOT_BLOCK_PX;
    let (h, w) = mosaic_e.dim();
    let span = 2 * n;
    // One ChaCha8 stream per (super-row, phase): the blocks of a super-row are drawn in order.
    let blocks: Vec<Vec<(usize, f64)>> = (0..h.div_ceil(span))
        .into_par_iter()
        .map(|sr| {
            let mut out = Vec::new();
            for (k, (py, px)) in [(0, 0), (0, 1), (1, 0), (1, 1)].into_iter().enumerate() {
                let mut rng = row_rng(seed, stream::SNAPSHOT, 4 * sr + k);
                let y0 = sr * span + py;
                if y0 >= h {
                    continue;
                }
                for x0 in (px..w).step_by(span) {
                    let sites: Vec<(usize, usize)> = bin_sites((y0, x0), n, h, w).collect();
                    let pixels = sites.len() as f64;
                    let mean: f64 = sites.iter().map(|p| mosaic_e[*p].max(0.0)).sum();
                    let l = photons(mean, pixels * sensor.full_well_e, &mut rng);
                    let z_pre: f64 = StandardNormal.sample(&mut rng);
                    let z_post: f64 = StandardNormal.sample(&mut rng);
                    let read = read_analog(
                        BinMode::AnalogAverage,
                        1.0,
                        l + sensor.sigma_pre_e * pixels.sqrt() * z_pre,
                        sites.len(),
                        sensor.sigma_post_e * z_post,
                        &adc,
                    );
                    let (r, c) = grid.roi_of(y0, x0);
                    out.push((r * grid.cols + c, read.estimate_e));
                }
            }
            out
        })
        .collect();
    let mut per_roi: Vec<Vec<f64>> = vec![Vec::new(); grid.rows * grid.cols];
    for (roi, v) in blocks.into_iter().flatten() {
        per_roi[roi].push(v);
    }
    Snapshot::of_blocks(grid, per_roi)
}

/// The single-shot per-pixel strategy on a Bayer sensor: along each row, site `x` is read at
/// the gain eq. 5.3 (with `eta`) gives for the readout of site `x − 2`, the previous site of
/// its colour; the first site of each colour in a row, and a site after a saturated one of its
/// colour, are read at base gain.
pub fn read_per_pixel(frame: &Frame, sensor: &SensorSpec, eta: f64) -> Readout {
    super::gain::read_per_pixel_interleaved(frame, sensor, eta, 2)
}

/// Alternating gains on a Bayer sensor (Hajisharif et al. 2014 in its dual-ISO form): row
/// pairs `{0, 1}`, `{4, 5}`, … at gain `low`, `{2, 3}`, `{6, 7}`, … at `high`, so each colour
/// has rows at both gains. The substitution of [`super::gain::read_alternating_rows`] uses the
/// same-colour rows two above and below (which are at the other gain): a high-gain site that
/// saturated takes their mean, a low-gain site whose same-colour neighbours are unsaturated
/// takes theirs.
pub fn read_alternating_rows(frame: &Frame, sensor: &SensorSpec, low: f64, high: f64) -> Readout {
    super::gain::read_alternating_row_groups(frame, sensor, (low, high), 2)
}
