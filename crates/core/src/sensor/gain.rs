//! Spatially-varying gain (§5.4): the gain rule of eq. 5.3, the two-shot snapshot, the
//! single-shot per-pixel readout, alternating rows, and dynamic range.

use ndarray::{Array2, ArrayView2, Axis};
use rayon::prelude::*;

use super::binning::Readout;
use rand_distr::{Distribution, StandardNormal};

use super::noise::{Adc, Frame, photons, read_analog, read_pixel, row_rng, stream};
use super::roi::RoiGrid;
use super::{BinMode, RoiLight, SensorSpec};

/// Eq. 5.3: the largest gain `g` with `g·l̂ + η·g·√l̂ ≤ l_wc`, i.e. `l_wc / (l̂ + η√l̂)`, clamped
/// to `[1, max_gain]`. A light level ≤ 0 (or NaN) gets the maximum gain. Never above
/// `max_gain` (nor below 1), and non-increasing in `light_e`.
pub fn gain_for_light(light_e: f64, eta: f64, full_well_e: f64, max_gain: f64) -> f64 {
    let top = max_gain.max(1.0);
    if !(light_e > 0.0) {
        return top;
    }
    let g = full_well_e / (light_e + eta.max(0.0) * light_e.sqrt());
    if g.is_nan() { 1.0 } else { g.clamp(1.0, top) }
}

/// §5.4.2: `l_wc / √(σ_pre² + σ_post²/g²)` at gain `g`, as a ratio (see [`ratio_db`]).
pub fn dynamic_range(sensor: &SensorSpec, gain: f64) -> f64 {
    let floor = (sensor.sigma_pre_e.powi(2) + (sensor.sigma_post_e / gain).powi(2)).sqrt();
    sensor.full_well_e / floor
}

/// `20 log10(ratio)`.
pub fn ratio_db(ratio: f64) -> f64 {
    20.0 * ratio.log10()
}

/// Side of the low-resolution snapshot's blocks: the snapshot is read in 2×2 bins (the thesis's
/// "low-resolution snapshot"), which halves its read noise and quarters its cost.
pub const SNAPSHOT_BLOCK_PX: usize = 2;

/// The two-shot strategies' first shot, summarised per ROI.
#[derive(Debug, Clone)]
pub struct Snapshot {
    /// Per ROI, the brightest 2×2 block of the base-gain snapshot, electrons per pixel (≥ 0):
    /// the `l̂` of eq. 5.3 by default ([`RoiLight::Brightest`]).
    pub roi_peak_e: Array2<f64>,
    /// Per ROI, the 99th percentile (nearest rank) of its 2×2 blocks, electrons per pixel (≥ 0).
    pub roi_p99_e: Array2<f64>,
    /// Per ROI, the mean of the snapshot, electrons per pixel (≥ 0): sets the ROI's bin.
    pub roi_mean_e: Array2<f64>,
}

impl Snapshot {
    /// Per ROI, the light level `which` picks: the `l̂` of eq. 5.3 for the ROI's gain.
    pub fn roi_light_e(&self, which: RoiLight) -> &Array2<f64> {
        match which {
            RoiLight::Brightest => &self.roi_peak_e,
            RoiLight::P99 => &self.roi_p99_e,
            RoiLight::Mean => &self.roi_mean_e,
        }
    }
}

/// Takes the snapshot: an exposure of its own (noise stream [`stream::SNAPSHOT`], one ChaCha8
/// stream per row of blocks) read at base gain in 2×2 analog-average bins aligned to the image
/// corner: per block one Poisson draw of the block's photons (clipped at its pixels' full
/// wells), its pixels' pre-amplifier noise and one post-amplifier draw, digitised like any
/// pixel. Each ROI is summarised from the blocks whose top-left pixel it holds.
pub fn take_snapshot(
    electrons: ArrayView2<'_, f64>,
    sensor: &SensorSpec,
    grid: &RoiGrid,
    seed: u64,
) -> Snapshot {
    let adc = Adc::of(sensor);
    let b = SNAPSHOT_BLOCK_PX;
    let (h, w) = electrons.dim();
    let (bh, bw) = (h.div_ceil(b), w.div_ceil(b));
    let mut blocks = Array2::<f64>::zeros((bh, bw));
    blocks
        .axis_iter_mut(Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(by, mut row)| {
            let mut rng = row_rng(seed, stream::SNAPSHOT, by);
            let ys = by * b..(by * b + b).min(h);
            for (bx, out) in row.iter_mut().enumerate() {
                let xs = bx * b..(bx * b + b).min(w);
                let pixels = ys.len() * xs.len();
                let mean: f64 = ys
                    .clone()
                    .map(|y| xs.clone().map(|x| electrons[[y, x]].max(0.0)).sum::<f64>())
                    .sum();
                let n = pixels as f64;
                let l = photons(mean, n * sensor.full_well_e, &mut rng);
                let z_pre: f64 = StandardNormal.sample(&mut rng);
                let z_post: f64 = StandardNormal.sample(&mut rng);
                let charge_sum = l + sensor.sigma_pre_e * n.sqrt() * z_pre;
                let read = read_analog(
                    BinMode::AnalogAverage,
                    1.0,
                    charge_sum,
                    pixels,
                    sensor.sigma_post_e * z_post,
                    &adc,
                );
                *out = read.estimate_e;
            }
        });
    let per_roi: Vec<Vec<f64>> = (0..grid.rows * grid.cols)
        .into_par_iter()
        .map(|k| {
            let (r, c) = (k / grid.cols, k % grid.cols);
            let (rows, cols) = (grid.row_range(r), grid.col_range(c));
            (rows.start.div_ceil(b)..rows.end.div_ceil(b))
                .flat_map(|by| {
                    (cols.start.div_ceil(b)..cols.end.div_ceil(b)).map(move |bx| (by, bx))
                })
                .map(|i| blocks[i])
                .collect()
        })
        .collect();
    Snapshot::of_blocks(grid, per_roi)
}

impl Snapshot {
    /// The snapshot of the ROIs of `grid` from each ROI's block readouts (row-major ROIs):
    /// the brightest block, the 99th percentile (nearest rank, as `scene::percentile_of`) and
    /// the mean, each at least 0.
    pub(super) fn of_blocks(grid: &RoiGrid, per_roi: Vec<Vec<f64>>) -> Snapshot {
        let stats: Vec<[f64; 3]> = per_roi
            .into_par_iter()
            .map(|mut values| {
                let n = values.len();
                let mean = (values.iter().sum::<f64>() / n.max(1) as f64).max(0.0);
                let peak = values.iter().copied().fold(0.0f64, f64::max);
                let p99 = match n {
                    0 => 0.0,
                    n => {
                        let rank = ((0.99 * n as f64).ceil() as usize).clamp(1, n);
                        let (_, x, _) = values.select_nth_unstable_by(rank - 1, f64::total_cmp);
                        x.max(0.0)
                    }
                };
                [peak, p99, mean]
            })
            .collect();
        let dim = (grid.rows, grid.cols);
        let map = |i: usize| Array2::from_shape_fn(dim, |(r, c)| stats[r * grid.cols + c][i]);
        Snapshot {
            roi_peak_e: map(0),
            roi_p99_e: map(1),
            roi_mean_e: map(2),
        }
    }
}

/// The single-shot per-pixel strategy (§5.4.1): along each row, left to right, pixel k+1 is
/// read at the gain eq. 5.3 (with `eta`) gives for pixel k's estimate; each row starts at base
/// gain, and a saturated pixel resets the next to base gain.
pub fn read_per_pixel(frame: &Frame, sensor: &SensorSpec, eta: f64) -> Readout {
    read_per_pixel_interleaved(frame, sensor, eta, 1)
}

/// The single-shot per-pixel gain along each row with `stride` interleaved chains: site `x`'s
/// gain comes from the readout of site `x − stride`. One chain is [`read_per_pixel`]; two is
/// the Bayer sensor's, where the sites two apart share a colour.
pub fn read_per_pixel_interleaved(
    frame: &Frame,
    sensor: &SensorSpec,
    eta: f64,
    stride: usize,
) -> Readout {
    let stride = stride.max(1);
    let adc = Adc::of(sensor);
    let dim = frame.charge_e.dim();
    let mut est = Array2::<f64>::zeros(dim);
    let mut sat = Array2::from_elem(dim, false);
    let mut gain = Array2::<f32>::zeros(dim);
    est.axis_iter_mut(Axis(0))
        .into_par_iter()
        .zip(sat.axis_iter_mut(Axis(0)).into_par_iter())
        .zip(gain.axis_iter_mut(Axis(0)).into_par_iter())
        .enumerate()
        .for_each(|(y, ((mut e_row, mut s_row), mut g_row))| {
            let mut next_gain = vec![1.0f64; stride];
            let (c_row, p_row) = (frame.charge_e.row(y), frame.post_noise_e.row(y));
            for x in 0..c_row.len() {
                let g = next_gain[x % stride];
                let r = read_pixel(c_row[x].into(), p_row[x].into(), g, &adc);
                e_row[x] = r.estimate_e;
                s_row[x] = r.saturated;
                g_row[x] = g as f32;
                next_gain[x % stride] = if r.saturated {
                    1.0
                } else {
                    gain_for_light(r.estimate_e, eta, sensor.full_well_e, sensor.max_gain)
                };
            }
        });
    Readout {
        estimate_e: est,
        saturated: sat,
        bin: Array2::ones(dim),
        gain,
    }
}

/// Alternating rows (Hajisharif et al. 2014): even rows at gain `low`, odd rows at `high`. A
/// high-gain pixel that saturated takes the mean of the low-gain pixels above and below; a
/// low-gain pixel whose high-gain neighbours above and below are unsaturated takes their mean
/// (in the dark only the high-gain rows are valid). Either way the vertical resolution halves
/// where the other rows are used. The saturation map marks pixels whose value still comes from
/// a saturated readout.
pub fn read_alternating_rows(frame: &Frame, sensor: &SensorSpec, low: f64, high: f64) -> Readout {
    read_alternating_row_groups(frame, sensor, (low, high), 1)
}

/// Alternating gains by groups of `group` rows: groups 0, 2, 4, … at `gains.0`, the others at
/// `gains.1`; a row's substitutes are the rows `group` above and below, in the neighbouring
/// groups (at the other gain). One row per group is [`read_alternating_rows`]; two is the
/// Bayer sensor's, where the rows two apart share a colour.
pub fn read_alternating_row_groups(
    frame: &Frame,
    sensor: &SensorSpec,
    (low, high): (f64, f64),
    group: usize,
) -> Readout {
    let group = group.max(1);
    let adc = Adc::of(sensor);
    let dim = frame.charge_e.dim();
    let (h, w) = dim;
    let is_high = |y: usize| (y / group) % 2 == 1;
    let row_gain = |y: usize| if is_high(y) { high } else { low };
    let raw: Vec<(Vec<f64>, Vec<bool>)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let g = row_gain(y);
            let (c_row, p_row) = (frame.charge_e.row(y), frame.post_noise_e.row(y));
            c_row
                .iter()
                .zip(p_row.iter())
                .map(|(c, p)| {
                    let r = read_pixel((*c).into(), (*p).into(), g, &adc);
                    (r.estimate_e, r.saturated)
                })
                .unzip()
        })
        .collect();
    let mut est = Array2::<f64>::zeros(dim);
    let mut sat = Array2::from_elem(dim, false);
    est.axis_iter_mut(Axis(0))
        .into_par_iter()
        .zip(sat.axis_iter_mut(Axis(0)).into_par_iter())
        .enumerate()
        .for_each(|(y, (mut e_row, mut s_row))| {
            let neighbours: Vec<usize> =
                [y.checked_sub(group), (y + group < h).then_some(y + group)]
                    .into_iter()
                    .flatten()
                    .collect();
            let (own_e, own_s) = &raw[y];
            for x in 0..w {
                let mean_of = |pick: &dyn Fn(usize) -> f64| {
                    neighbours.iter().map(|&n| pick(n)).sum::<f64>() / neighbours.len() as f64
                };
                let others_sat = neighbours.iter().any(|&n| raw[n].1[x]);
                let (value, saturated) = if neighbours.is_empty() {
                    (own_e[x], own_s[x])
                } else if is_high(y) && own_s[x] {
                    (mean_of(&|n| raw[n].0[x]), others_sat)
                } else if !is_high(y) && !others_sat {
                    (mean_of(&|n| raw[n].0[x]), false)
                } else {
                    (own_e[x], own_s[x])
                };
                e_row[x] = value;
                s_row[x] = saturated;
            }
        });
    Readout {
        estimate_e: est,
        saturated: sat,
        gain: Array2::from_shape_fn(dim, |(y, _)| row_gain(y) as f32),
        bin: Array2::ones(dim),
    }
}
