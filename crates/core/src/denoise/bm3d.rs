//! BM3D's two stages (Dabov et al. 2007): block matching, a collaborative hard-threshold filter
//! that gives a basic estimate, then block matching on the basic estimate and a collaborative
//! Wiener filter of the noisy image that uses it as its pilot. Both stages aggregate the
//! filtered blocks with a Kaiser window and the paper's per-group weights.
//!
//! **Speed.** Matching compares every reference block (a grid of step 3, plus the last row and
//! column) with every block of its 39×39 search window. Instead of one block pair at a time, the
//! distances are computed one displacement at a time for a tile of reference blocks (12 rows by
//! 86 columns of them): the squared difference of the image and its shifted copy, summed over 8
//! rows and then 8 columns, gives that displacement's distance for every reference block of the
//! tile at ~2 operations per pixel. Tiles are fixed (not one per thread), filtered in parallel
//! and added to the output in tile order, so the result does not depend on the number of threads.
//!
//! **Memory.** Beyond its input the denoiser holds two `f32` planes per channel, the noisy one
//! and the estimate, and per thread the transformed blocks of one tile's reach: the sums of the
//! tiles are added a round at a time into a window of rows, and a row leaves the window for the
//! estimate once no later tile reaches it. The Wiener stage writes its output over the basic
//! estimate the same way, since a finished row is no longer anyone's pilot. A 4096 × 4096
//! colour image thus denoises in about 400 MB besides itself (48 bytes a pixel and channel
//! before tiles and windows).

use ndarray::Array2;
use rayon::prelude::*;

use super::colour;
use super::transforms::{
    BLOCK, BLOCK_LEN, Block, BlockTransform, Transform2d, haar_forward, haar_inverse, kaiser_block,
};
use crate::Sample;
use crate::{Progress, SimError};

/// The parameters of both stages. The defaults are the reference implementation's profile
/// `'np'` (its `bm3d` package, v4: blocks of 8, step 3, window 39, groups of 16 and 32, τ 3000
/// and 400, λ = 3.0) with the paper's Wiener shrinkage (μ² = 1; the package's μ² = 0.4 goes
/// with its own transform scaling and loses 0.1–0.3 dB here); distances and thresholds are on
/// images of range [0, 1].
#[derive(Debug, Clone, PartialEq)]
pub struct Bm3dProfile {
    /// Step between reference blocks, pixels (both stages).
    pub step_px: usize,
    /// Side of the square search window centred on each reference block, pixels (odd).
    pub search_px: usize,
    /// Most blocks in a hard-threshold group (a power of two).
    pub max_group_ht: usize,
    /// Most blocks in a Wiener group (a power of two).
    pub max_group_wiener: usize,
    /// Block-matching threshold of the hard-threshold stage, as the mean squared difference per
    /// pixel on the 8-bit scale (the paper's τ_match; the reference's 3000).
    pub tau_match_ht_8bit: f64,
    /// The same for the Wiener stage (the reference's 400).
    pub tau_match_wiener_8bit: f64,
    /// Hard threshold in units of σ (the paper's λ_3D).
    pub lambda_ht: f64,
    /// Multiplier of σ² in the Wiener shrinkage `|B|² / (|B|² + μ² σ²)`.
    pub mu2: f64,
    /// Shape parameter of the Kaiser aggregation window.
    pub kaiser_beta: f64,
    /// 2-D block transform of the hard-threshold stage (the reference: bior1.5).
    pub transform_ht: BlockTransform,
    /// 2-D block transform of the Wiener stage (the reference: DCT).
    pub transform_wiener: BlockTransform,
}

impl Default for Bm3dProfile {
    fn default() -> Self {
        Bm3dProfile {
            step_px: 3,
            search_px: 39,
            max_group_ht: 16,
            max_group_wiener: 32,
            tau_match_ht_8bit: 3000.0,
            tau_match_wiener_8bit: 400.0,
            lambda_ht: 3.0,
            mu2: 1.0,
            kaiser_beta: 2.0,
            transform_ht: BlockTransform::Bior15,
            transform_wiener: BlockTransform::Dct,
        }
    }
}

impl Bm3dProfile {
    fn validate(&self) -> Result<(), SimError> {
        let pow2 = |name: &str, v: usize| {
            if v.is_power_of_two() && v <= 256 {
                Ok(())
            } else {
                Err(SimError::invalid(
                    format!("bm3d.{name}"),
                    format!("must be a power of two ≤ 256 (got {v})"),
                ))
            }
        };
        pow2("max_group_ht", self.max_group_ht)?;
        pow2("max_group_wiener", self.max_group_wiener)?;
        if self.step_px == 0 || self.step_px > BLOCK {
            return Err(SimError::invalid(
                "bm3d.step_px",
                format!("must be 1 … {BLOCK} pixels (got {})", self.step_px),
            ));
        }
        if self.search_px.is_multiple_of(2) || self.search_px > 255 {
            return Err(SimError::invalid(
                "bm3d.search_px",
                format!("must be odd and ≤ 255 pixels (got {})", self.search_px),
            ));
        }
        for (name, v) in [
            ("tau_match_ht_8bit", self.tau_match_ht_8bit),
            ("tau_match_wiener_8bit", self.tau_match_wiener_8bit),
            ("lambda_ht", self.lambda_ht),
            ("mu2", self.mu2),
            ("kaiser_beta", self.kaiser_beta),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SimError::invalid(
                    format!("bm3d.{name}"),
                    format!("must be a finite number ≥ 0 (got {v:?})"),
                ));
            }
        }
        Ok(())
    }
}

/// Bytes per pixel and channel the denoiser holds besides its input: the `f32` noisy plane
/// and the estimate (basic, then final), for the memory budget.
const BYTES_PER_PIXEL_CHANNEL: u64 = 8;

/// Bytes each worker thread holds at most: two caches of transformed blocks over a tile's
/// reach ([`TILE_REF_COLS`] wide) and the tile's sums; the rows of the tiles in flight.
const BYTES_PER_WORKER: u64 = 32 << 20;

/// Denoises `planes` corrupted by white Gaussian noise of variance `sigma2` with the default
/// profile: one plane is a grey image (BM3D), three planes are R, G, B (CBM3D: opponent colour
/// space, groups found on the luminance and shared by the chrominances), any other count is
/// denoised plane by plane.
///
/// ```
/// use ndarray::Array2;
/// use udc_core::{Progress, denoise::bm3d};
///
/// let clean = Array2::from_shape_fn((32, 32), |(y, x)| ((x / 8 + y / 8) % 2) as f64);
/// let noisy = clean.mapv(|v| v + 0.05) + Array2::from_shape_fn((32, 32), |(y, x)| {
///     0.1 * (((y * 31 + x * 17) % 7) as f64 / 3.0 - 1.0)
/// });
/// let out = bm3d(&[noisy.clone()], 0.01, &Progress::new())?;
/// let mse = |a: &Array2<f64>| (a - &clean.mapv(|v| v + 0.05)).mapv(|d| d * d).mean().unwrap();
/// assert!(mse(&out[0]) < mse(&noisy));
/// # Ok::<(), udc_core::SimError>(())
/// ```
///
/// # Errors
/// [`SimError::InvalidSetting`] for no planes, planes of different sizes, a plane under 8×8
/// pixels or holding a non-finite value (`planes[c]`), or a `sigma2` that is not a finite
/// positive number; [`SimError::TooLarge`] over the memory budget; [`SimError::Cancelled`].
pub fn bm3d<T: Sample>(
    planes: &[Array2<T>],
    sigma2: f64,
    progress: &Progress,
) -> Result<Vec<Array2<T>>, SimError> {
    bm3d_with(planes, sigma2, &Bm3dProfile::default(), progress)
}

/// [`bm3d`] of planes the caller gives up: `f32` planes become the denoiser's working planes
/// and its output, so a colour image costs 8 bytes per pixel and channel beyond itself
/// instead of 12 (what a camera-size restoration needs to fit in memory).
///
/// # Errors
/// As [`bm3d`].
pub fn bm3d_owned<T: Sample>(
    planes: Vec<Array2<T>>,
    sigma2: f64,
    progress: &Progress,
) -> Result<Vec<Array2<T>>, SimError> {
    let profile = Bm3dProfile::default();
    check(&planes, sigma2, &profile, 0)?;
    run(planes, sigma2, &profile, progress)
}

/// Checks the planes, the variance and the profile, and the memory the run would take beyond
/// `held_bytes_per_value` more per value; returns the size.
fn check<T: Sample>(
    planes: &[Array2<T>],
    sigma2: f64,
    profile: &Bm3dProfile,
    held_bytes_per_value: u64,
) -> Result<(usize, usize), SimError> {
    let dim = validate(planes, sigma2)?;
    profile.validate()?;
    let values = (dim.0 * dim.1 * planes.len()) as u64;
    crate::budget::check(
        &format!("denoising a {}×{} image", dim.1, dim.0),
        values * (BYTES_PER_PIXEL_CHANNEL + held_bytes_per_value)
            + BYTES_PER_WORKER * rayon::current_num_threads() as u64,
        "denoise a smaller image",
    )?;
    Ok(dim)
}

/// [`bm3d`] with a chosen profile.
///
/// # Errors
/// As [`bm3d`], and [`SimError::InvalidSetting`] for a profile out of range (`bm3d.…`).
pub fn bm3d_with<T: Sample>(
    planes: &[Array2<T>],
    sigma2: f64,
    profile: &Bm3dProfile,
    progress: &Progress,
) -> Result<Vec<Array2<T>>, SimError> {
    // The caller keeps its planes, so the run copies them.
    check(planes, sigma2, profile, std::mem::size_of::<T>() as u64)?;
    run(planes.to_vec(), sigma2, profile, progress)
}

fn run<T: Sample>(
    planes: Vec<Array2<T>>,
    sigma2: f64,
    profile: &Bm3dProfile,
    progress: &Progress,
) -> Result<Vec<Array2<T>>, SimError> {
    let dim = planes.first().map_or((0, 0), Array2::dim);
    progress.set(0.0);
    if planes.len() == 3 {
        let (opp, stretch, sigmas) = colour::to_opponent(planes, sigma2);
        let sigmas = sigmas.map(|s| s as f32);
        let out = denoise(opp, &sigmas, dim, profile, progress, (0.0, 1.0))?;
        return Ok(colour::from_opponent(out, &stretch, dim));
    }
    let n = planes.len() as f32;
    let sigma = sigma2.sqrt() as f32;
    let mut out = Vec::with_capacity(planes.len());
    for (c, plane) in planes.into_iter().enumerate() {
        let span = (c as f32 / n, (c + 1) as f32 / n);
        let data = T::plane_into_f32(plane);
        let mut d = denoise(vec![data], &[sigma], dim, profile, progress, span)?;
        let d = T::vec_from_f32(d.pop().unwrap_or_default());
        out.push(Array2::from_shape_vec(dim, d).map_err(|e| SimError::Sampling(e.to_string()))?);
    }
    Ok(out)
}

/// The largest noise variance the denoiser takes: images are in [0, 1], so σ = 1 is noise as
/// large as the whole range (the thesis's σ² are 1e-4 to 0.04).
pub const MAX_SIGMA2: f64 = 1.0;

/// The smallest: σ = 1e-6, far below a 16-bit step (1.5e-5); at 1e-300 the Wiener weights
/// overflow and the output is silently black.
pub const MIN_SIGMA2: f64 = 1e-12;

/// Whether `sigma2` is a noise variance the denoiser takes: finite, from [`MIN_SIGMA2`] to
/// [`MAX_SIGMA2`].
pub fn sigma2_in_range(sigma2: f64) -> bool {
    sigma2.is_finite() && (MIN_SIGMA2..=MAX_SIGMA2).contains(&sigma2)
}

fn validate<T: Sample>(planes: &[Array2<T>], sigma2: f64) -> Result<(usize, usize), SimError> {
    if !sigma2_in_range(sigma2) {
        return Err(SimError::invalid(
            "sigma2",
            format!(
                "the noise variance must be a finite number > 0, at least {MIN_SIGMA2:e} and at \
                 most {MAX_SIGMA2} (images are in [0, 1]; got {sigma2:?})"
            ),
        ));
    }
    let Some(first) = planes.first() else {
        return Err(SimError::invalid("planes", "no image planes to denoise"));
    };
    let dim = first.dim();
    for (c, p) in planes.iter().enumerate() {
        if p.dim() != dim {
            return Err(SimError::invalid(
                format!("planes[{c}]"),
                format!("is {:?}, plane 0 is {dim:?}", p.dim()),
            ));
        }
        if p.nrows() < BLOCK || p.ncols() < BLOCK {
            return Err(SimError::invalid(
                format!("planes[{c}]"),
                format!(
                    "is {}×{} pixels; BM3D needs at least {BLOCK}×{BLOCK}",
                    p.ncols(),
                    p.nrows()
                ),
            ));
        }
        if let Some(v) = p.iter().find(|v| !(**v).into().is_finite()) {
            return Err(SimError::invalid(
                format!("planes[{c}]"),
                format!("holds {v}; values must be finite"),
            ));
        }
    }
    Ok(dim)
}

/// The two stages over channels that share their groups (found on channel 0). The basic
/// estimate is written into one set of planes, and the final estimate over it as its rows
/// become final.
fn denoise(
    noisy: Vec<Vec<f32>>,
    sigmas: &[f32],
    dim: (usize, usize),
    profile: &Bm3dProfile,
    progress: &Progress,
    span: (f32, f32),
) -> Result<Vec<Vec<f32>>, SimError> {
    let geom = Geometry::new(dim, profile, Cut::default());
    let mid = span.0 + 0.45 * (span.1 - span.0);
    let mut estimate = vec![vec![0f32; dim.0 * dim.1]; noisy.len()];
    let ctx = StageContext {
        noisy: &noisy,
        sigmas,
        geom: &geom,
        profile,
        progress,
    };
    stage(Stage::HardThreshold, &ctx, &mut estimate, (span.0, mid))?;
    stage(Stage::Wiener, &ctx, &mut estimate, (mid, span.1))?;
    Ok(estimate)
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    HardThreshold,
    Wiener,
}

/// Where the reference blocks are and how the work is cut into tiles.
struct Geometry {
    h: usize,
    w: usize,
    rows: Vec<usize>,
    cols: Vec<usize>,
    /// Half the search window, pixels.
    half: usize,
    cut: Cut,
}

/// How the work is cut: it changes what is in memory at once, not the result (but for the
/// order of the sums' roundings).
#[derive(Debug, Clone, Copy)]
struct Cut {
    /// Reference columns per tile.
    tile_ref_cols: usize,
    /// Tiles filtered in parallel before their sums are added and finished rows written.
    tiles_per_round: usize,
}

impl Default for Cut {
    fn default() -> Self {
        Cut {
            tile_ref_cols: TILE_REF_COLS,
            tiles_per_round: 4 * rayon::current_num_threads().max(1),
        }
    }
}

/// Reference rows per band: large enough that the band's extra rows (a block's height) cost
/// little, small enough to give the pool work to share on a 256-pixel image.
const BAND_REF_ROWS: usize = 12;

/// Reference columns per tile (about 256 pixels at step 3): a band is cut into tiles so that a
/// worker's caches of transformed blocks cover a tile's reach, not the image's width (a
/// 4096-pixel-wide band's would be 83 MB each).
const TILE_REF_COLS: usize = 86;

/// One unit of work: a band of reference rows by a run of reference columns.
struct Tile<'a> {
    rows: &'a [usize],
    cols: &'a [usize],
}

impl Tile<'_> {
    /// The pixel rows `y0..y1` and columns `x0..x1` the tile's groups can reach.
    fn reach(&self, geom: &Geometry) -> (usize, usize, usize, usize) {
        let y0 = self.rows[0].saturating_sub(geom.half);
        let y1 = (self.rows[self.rows.len() - 1] + BLOCK + geom.half).min(geom.h);
        let x0 = self.cols[0].saturating_sub(geom.half);
        let x1 = (self.cols[self.cols.len() - 1] + BLOCK + geom.half).min(geom.w);
        (y0, y1, x0, x1)
    }
}

impl Geometry {
    fn new((h, w): (usize, usize), profile: &Bm3dProfile, cut: Cut) -> Self {
        Geometry {
            h,
            w,
            rows: ref_positions(h, profile.step_px),
            cols: ref_positions(w, profile.step_px),
            half: profile.search_px / 2,
            cut,
        }
    }

    /// The tiles, band by band, left to right.
    fn tiles(&self) -> Vec<Tile<'_>> {
        self.rows
            .chunks(BAND_REF_ROWS)
            .flat_map(|rows| {
                self.cols
                    .chunks(self.cut.tile_ref_cols.max(1))
                    .map(move |cols| Tile { rows, cols })
            })
            .collect()
    }
}

/// Block origins `0, step, 2·step, …` and the last possible one, so every pixel is covered.
fn ref_positions(len: usize, step: usize) -> Vec<usize> {
    let last = len - BLOCK;
    let mut v: Vec<usize> = (0..=last).step_by(step).collect();
    if v.last() != Some(&last) {
        v.push(last);
    }
    v
}

/// The best matches of one reference block: at most `cap`, each within `tau`.
#[derive(Clone)]
struct TopK {
    items: Vec<(f32, u32)>,
    bound: f32,
    cap: usize,
}

impl TopK {
    fn new(cap: usize, tau: f32) -> Self {
        TopK {
            items: Vec::with_capacity(cap),
            bound: tau,
            cap,
        }
    }

    /// Offers a candidate; once full, the items are a binary max-heap on distance, so the
    /// worst is at the root and a better candidate replaces it in O(log cap).
    #[inline]
    fn offer(&mut self, d: f32, pos: u32) {
        let items = &mut self.items;
        if items.len() < self.cap {
            if d > self.bound {
                return;
            }
            items.push((d, pos));
            if items.len() == self.cap {
                // Heapify once, bottom-up.
                for i in (0..self.cap / 2).rev() {
                    sift_down(items, i);
                }
                self.bound = items[0].0;
            }
        } else {
            if d >= self.bound {
                return;
            }
            items[0] = (d, pos);
            sift_down(items, 0);
            self.bound = items[0].0;
        }
    }

    /// Positions sorted by distance (the reference block, at distance 0, first), cut to the
    /// largest power of two the Haar transform takes.
    fn group(mut self, reference: u32) -> Vec<u32> {
        self.items.sort_by(|a, b| {
            a.0.total_cmp(&b.0)
                .then_with(|| (b.1 == reference).cmp(&(a.1 == reference)))
        });
        let n = prev_power_of_two(self.items.len().max(1));
        let mut v: Vec<u32> = self.items.iter().take(n).map(|it| it.1).collect();
        if v.is_empty() {
            v.push(reference);
        }
        v
    }
}

/// Restores the max-heap property below `i`.
#[inline]
fn sift_down(items: &mut [(f32, u32)], mut i: usize) {
    let n = items.len();
    loop {
        let l = 2 * i + 1;
        if l >= n {
            return;
        }
        let r = l + 1;
        let c = if r < n && items[r].0 > items[l].0 {
            r
        } else {
            l
        };
        if items[c].0 <= items[i].0 {
            return;
        }
        items.swap(i, c);
        i = c;
    }
}

fn prev_power_of_two(n: usize) -> usize {
    1 << (usize::BITS - 1 - n.leading_zeros())
}

/// Finds the groups of a tile's reference blocks on `img` (see the module docs for the
/// displacement-at-a-time distance).
fn match_tile(
    img: &[f32],
    geom: &Geometry,
    tile: &Tile<'_>,
    cap: usize,
    tau: f32,
) -> Vec<Vec<u32>> {
    let (h, w, half) = (geom.h as isize, geom.w, geom.half as isize);
    let (rows, cols) = (tile.rows, tile.cols);
    let ncols = cols.len();
    let mut tops = vec![TopK::new(cap, tau); rows.len() * ncols];
    let band_rows = rows[rows.len() - 1] + BLOCK - rows[0];
    let tw = cols[ncols - 1] + BLOCK - cols[0];
    // Column-wise running sums of the squared differences down the band's rows: the distance of
    // a reference row is then one subtraction of two rows of it, then 8 columns summed.
    let mut prefix = vec![0f32; (band_rows + 1) * tw];
    let mut vsum = vec![0f32; tw];
    let mut sum2 = vec![0f32; tw];
    let mut sum4 = vec![0f32; tw];
    // Nearest displacements first: near blocks tend to be the most alike, so the groups fill with
    // good matches early and most later candidates fail the first comparison.
    let mut shifts: Vec<(isize, isize)> = (-half..=half)
        .flat_map(|dy| (-half..=half).map(move |dx| (dy, dx)))
        .collect();
    shifts.sort_by_key(|&(dy, dx)| (dy * dy + dx * dx, dy, dx));
    for (dy, dx) in shifts {
        // The reference rows whose block, moved by dy, stays inside the image (a contiguous run).
        let lo = rows.partition_point(|&r| (r as isize) + dy < 0);
        let hi = rows.partition_point(|&r| (r as isize) + dy <= h - BLOCK as isize);
        if lo >= hi {
            continue;
        }
        let ya = rows[lo];
        let yb = rows[hi - 1] + BLOCK;
        // The same for the tile's reference columns and dx.
        let xlo = ((-dx).max(0) as usize).max(cols[0]);
        let xhi = (w as isize - BLOCK as isize - dx).min(cols[ncols - 1] as isize);
        if xhi < xlo as isize {
            continue;
        }
        let xhi = xhi as usize;
        let span = xhi + BLOCK - xlo;
        let c_lo = cols.partition_point(|&c| c < xlo);
        let c_hi = cols.partition_point(|&c| c <= xhi);
        prefix[..span].fill(0.0);
        for y in ya..yb {
            let k = y - ya;
            let (done, rest) = prefix.split_at_mut((k + 1) * tw);
            let prev = &done[k * tw..k * tw + span];
            let cur = &mut rest[..span];
            let a = &img[y * w + xlo..y * w + xlo + span];
            let s = ((y as isize + dy) * w as isize + xlo as isize + dx) as usize;
            let b = &img[s..s + span];
            for (((c, p), a), b) in cur.iter_mut().zip(prev).zip(a).zip(b) {
                let e = a - b;
                *c = p + e * e;
            }
        }
        for (ri, &r) in rows.iter().enumerate().take(hi).skip(lo) {
            let k = r - ya;
            let top = &prefix[(k + BLOCK) * tw..(k + BLOCK) * tw + span];
            let bottom = &prefix[k * tw..k * tw + span];
            for ((v, t), b) in vsum[..span].iter_mut().zip(top).zip(bottom) {
                *v = t - b;
            }
            // 8-column sums by doubling: pairs, fours, eights.
            for (i, s) in sum2[..span - 1].iter_mut().enumerate() {
                *s = vsum[i] + vsum[i + 1];
            }
            for (i, s) in sum4[..span - 3].iter_mut().enumerate() {
                *s = sum2[i] + sum2[i + 2];
            }
            // May be negative (dx < 0 on row 0); each candidate's own position is not.
            let base = (r as isize + dy) * w as isize + dx;
            let row_tops = &mut tops[ri * ncols..(ri + 1) * ncols];
            for (top, &c) in row_tops[c_lo..c_hi].iter_mut().zip(&cols[c_lo..c_hi]) {
                let i = c - xlo;
                top.offer(sum4[i] + sum4[i + 4], (base + c as isize) as u32);
            }
        }
    }
    tops.into_iter()
        .enumerate()
        .map(|(i, t)| {
            let (r, c) = (rows[i / ncols], cols[i % ncols]);
            t.group((r * w + c) as u32)
        })
        .collect()
}

/// What a tile adds to the output: weighted sums and weights over its reach, rows `y0..` and
/// columns `x0..x0 + rw`, of each channel.
struct TileSums {
    y0: usize,
    x0: usize,
    rw: usize,
    num: Vec<Vec<f32>>,
    den: Vec<Vec<f32>>,
}

/// What both stages read.
struct StageContext<'a> {
    noisy: &'a [Vec<f32>],
    sigmas: &'a [f32],
    geom: &'a Geometry,
    profile: &'a Bm3dProfile,
    progress: &'a Progress,
}

/// One stage over the whole image: tiles matched and filtered in parallel a round at a time,
/// their sums added in tile order (so the result does not depend on the number of threads),
/// and each row written to `estimate` once no later tile can reach it. The hard-threshold
/// stage fills `estimate` with the basic estimate; the Wiener stage reads it as its pilot and
/// overwrites it row by row with the final estimate (a row is final only once every tile that
/// reads it is done).
fn stage(
    kind: Stage,
    ctx: &StageContext<'_>,
    estimate: &mut [Vec<f32>],
    span: (f32, f32),
) -> Result<(), SimError> {
    let StageContext {
        noisy,
        sigmas,
        geom,
        profile,
        progress,
    } = *ctx;
    let (cap, tau_8bit) = match kind {
        Stage::HardThreshold => (profile.max_group_ht, profile.tau_match_ht_8bit),
        Stage::Wiener => (profile.max_group_wiener, profile.tau_match_wiener_8bit),
    };
    // Distances between noisy blocks carry the noise's own 2 N² σ² on average; the threshold
    // is set for clean blocks, so the hard-threshold stage (which matches on the noisy image)
    // adds it back, or at high noise no block but the reference itself would ever match.
    let noise_bias = match kind {
        Stage::HardThreshold => 2.0 * BLOCK_LEN as f64 * f64::from(sigmas[0]).powi(2),
        Stage::Wiener => 0.0,
    };
    let tau = (tau_8bit * (BLOCK_LEN as f64) / (255.0 * 255.0) + noise_bias) as f32;
    let tiles = geom.tiles();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let filter = Filter::new(kind, sigmas, profile);
    let (w, channels) = (geom.w, noisy.len());
    let per_round = geom.cut.tiles_per_round.max(1);
    // The sums of rows `base..` so far; rows above `base` are written.
    let mut base = 0;
    let mut num = vec![Vec::<f32>::new(); channels];
    let mut den = vec![Vec::<f32>::new(); channels];
    for (round, batch) in tiles.chunks(per_round).enumerate() {
        let sums: Vec<Result<TileSums, SimError>> = {
            let pilot: Option<&[Vec<f32>]> = (kind == Stage::Wiener).then_some(&*estimate);
            let guide: &[f32] = pilot.map_or(&noisy[0], |p| &p[0]);
            batch
                .par_iter()
                .map_init(Scratch::default, |scratch, tile| {
                    progress.check()?;
                    let groups = match_tile(guide, geom, tile, cap, tau);
                    let out = filter.tile(noisy, pilot, geom, tile, &groups, scratch);
                    let d = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                    progress.set(span.0 + (span.1 - span.0) * d as f32 / tiles.len() as f32);
                    Ok(out)
                })
                .collect()
        };
        for s in sums {
            let s = s?;
            let rows = s.num[0].len() / s.rw.max(1);
            let end = (s.y0 + rows - base) * w;
            for c in 0..channels {
                if num[c].len() < end {
                    num[c].resize(end, 0.0);
                    den[c].resize(end, 0.0);
                }
                for r in 0..rows {
                    let o = (s.y0 + r - base) * w + s.x0;
                    let from = r * s.rw..(r + 1) * s.rw;
                    for (o, v) in num[c][o..o + s.rw].iter_mut().zip(&s.num[c][from.clone()]) {
                        *o += v;
                    }
                    for (o, v) in den[c][o..o + s.rw].iter_mut().zip(&s.den[c][from]) {
                        *o += v;
                    }
                }
            }
        }
        let next = tiles
            .get((round + 1) * per_round)
            .map_or(geom.h, |t| t.reach(geom).0);
        for c in 0..channels {
            let rows = base * w..next * w;
            let out = &mut estimate[c][rows.clone()];
            for (i, (o, z)) in out.iter_mut().zip(&noisy[c][rows]).enumerate() {
                let d = den[c].get(i).copied().unwrap_or(0.0);
                *o = if d > 0.0 { num[c][i] / d } else { *z };
            }
            let cut = ((next - base) * w).min(num[c].len());
            num[c].drain(..cut);
            den[c].drain(..cut);
        }
        base = next;
    }
    Ok(())
}

/// The collaborative filter of one stage.
struct Filter {
    kind: Stage,
    transform: Transform2d,
    /// Noise standard deviation per coefficient over σ (see [`Transform2d::noise_scale`]).
    noise_scale: Block,
    kaiser: Block,
    sigmas: Vec<f32>,
    lambda: f32,
    mu2: f32,
}

impl Filter {
    fn new(kind: Stage, sigmas: &[f32], profile: &Bm3dProfile) -> Self {
        let transform = Transform2d::new(match kind {
            Stage::HardThreshold => profile.transform_ht,
            Stage::Wiener => profile.transform_wiener,
        });
        let noise_scale = transform.noise_scale();
        Filter {
            kind,
            transform,
            noise_scale,
            kaiser: kaiser_block(profile.kaiser_beta),
            sigmas: sigmas.to_vec(),
            lambda: profile.lambda_ht as f32,
            mu2: profile.mu2 as f32,
        }
    }

    /// Filters every group of a tile and aggregates it into the tile's sums. Channel by channel,
    /// so that one pair of transform caches serves all of a tile's groups.
    fn tile(
        &self,
        noisy: &[Vec<f32>],
        basic: Option<&[Vec<f32>]>,
        geom: &Geometry,
        tile: &Tile<'_>,
        groups: &[Vec<u32>],
        scratch: &mut Scratch,
    ) -> TileSums {
        let w = geom.w;
        let (y0, y1, x0, x1) = tile.reach(geom);
        let rw = x1 - x0;
        let len = (y1 - y0) * rw;
        let channels = noisy.len();
        let mut num = vec![vec![0f32; len]; channels];
        let mut den = vec![vec![0f32; len]; channels];
        let max = groups.iter().map(Vec::len).max().unwrap_or(1);
        let mut g = vec![[0f32; BLOCK_LEN]; max];
        let mut pilot = vec![[0f32; BLOCK_LEN]; max];
        let mut tmp = vec![[0f32; BLOCK_LEN]; max];
        for c in 0..channels {
            let sigma = self.sigmas[c];
            scratch.noisy.reset((y0, x0, rw, w), len);
            scratch.basic.reset((y0, x0, rw, w), len);
            let (num, den) = (&mut num[c], &mut den[c]);
            for group in groups {
                let n = group.len();
                let g = &mut g[..n];
                for (blk, &p) in g.iter_mut().zip(group) {
                    *blk = *scratch.noisy.get(&self.transform, &noisy[c], p as usize);
                }
                haar_forward(g, &mut tmp);
                let weight = match (self.kind, basic) {
                    (Stage::Wiener, Some(basic)) => {
                        let pilot = &mut pilot[..n];
                        for (blk, &p) in pilot.iter_mut().zip(group) {
                            *blk = *scratch.basic.get(&self.transform, &basic[c], p as usize);
                        }
                        haar_forward(pilot, &mut tmp);
                        wiener_shrink(g, pilot, &self.noise_scale, self.mu2, sigma)
                    }
                    _ => hard_threshold(g, &self.noise_scale, self.lambda * sigma, sigma),
                };
                haar_inverse(g, &mut tmp);
                let wk: Block = std::array::from_fn(|k| weight * self.kaiser[k]);
                for (blk, &p) in g.iter().zip(group) {
                    let px = self.transform.inverse(blk);
                    let (gy, gx) = (p as usize / w, p as usize % w);
                    let p = (gy - y0) * rw + gx - x0;
                    for i in 0..BLOCK {
                        let o = p + i * rw;
                        let wr = &wk[i * BLOCK..(i + 1) * BLOCK];
                        let pr = &px[i * BLOCK..(i + 1) * BLOCK];
                        for ((n, &a), &b) in num[o..o + BLOCK].iter_mut().zip(wr).zip(pr) {
                            *n += a * b;
                        }
                        for (d, &a) in den[o..o + BLOCK].iter_mut().zip(wr) {
                            *d += a;
                        }
                    }
                }
            }
        }
        TileSums {
            y0,
            x0,
            rw,
            num,
            den,
        }
    }
}

/// The hard-threshold filter of a transformed group, in place (coefficient k is kept when
/// `|z| ≥ λ σ scale_k`); returns the aggregation weight `1 / (σ² N_kept)` (the paper's weight
/// of the basic estimate).
fn hard_threshold(g: &mut [Block], scale: &Block, lambda_sigma: f32, sigma: f32) -> f32 {
    let thr: Block = std::array::from_fn(|k| lambda_sigma * scale[k]);
    let mut kept = 0u32;
    for z in g.iter_mut() {
        for (v, t) in z.iter_mut().zip(&thr) {
            let keep = v.abs() >= *t;
            kept += u32::from(keep);
            if !keep {
                *v = 0.0;
            }
        }
    }
    1.0 / (sigma * sigma * kept.max(1) as f32).max(f32::MIN_POSITIVE)
}

/// The empirical Wiener filter of a transformed group given its pilot, in place:
/// `W = |B|² / (|B|² + μ² σ_k²)`; returns the aggregation weight `1 / (σ² ‖W‖²)`.
fn wiener_shrink(g: &mut [Block], pilot: &[Block], scale: &Block, mu2: f32, sigma: f32) -> f32 {
    let noise: Block = std::array::from_fn(|k| mu2 * (sigma * scale[k]).powi(2));
    let mut energy = 0f32;
    for (z, b) in g.iter_mut().zip(pilot) {
        let mut e = [0f32; BLOCK_LEN];
        for k in 0..BLOCK_LEN {
            let b2 = b[k] * b[k];
            let gain = b2 / (b2 + noise[k]);
            z[k] *= gain;
            e[k] = gain * gain;
        }
        energy += e.iter().sum::<f32>();
    }
    1.0 / (sigma * sigma * energy).max(f32::MIN_POSITIVE)
}

/// Transformed blocks of one image over a tile's reach, each computed at most once per tile
/// (a block joins the groups of many neighbouring reference blocks). Stamps mark what the
/// current tile computed, so the buffer is reused without clearing.
#[derive(Default)]
struct BlockCache {
    blocks: Vec<Block>,
    stamp: Vec<u32>,
    generation: u32,
    /// The reach's first row and column, its width, and the image's width.
    origin: (usize, usize, usize, usize),
}

impl BlockCache {
    fn reset(&mut self, origin: (usize, usize, usize, usize), len: usize) {
        if self.blocks.len() < len {
            self.blocks.resize(len, [0f32; BLOCK_LEN]);
            self.stamp.resize(len, 0);
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.stamp.fill(0);
            self.generation = 1;
        }
        self.origin = origin;
    }

    #[inline]
    fn get(&mut self, transform: &Transform2d, img: &[f32], pos: usize) -> &Block {
        let (y0, x0, rw, w) = self.origin;
        let i = (pos / w - y0) * rw + pos % w - x0;
        if self.stamp[i] != self.generation {
            let mut b = [0f32; BLOCK_LEN];
            for r in 0..BLOCK {
                b[r * BLOCK..(r + 1) * BLOCK]
                    .copy_from_slice(&img[pos + r * w..pos + r * w + BLOCK]);
            }
            self.blocks[i] = transform.forward(&b);
            self.stamp[i] = self.generation;
        }
        &self.blocks[i]
    }
}

/// A worker's reusable buffers.
#[derive(Default)]
struct Scratch {
    noisy: BlockCache,
    basic: BlockCache,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_positions_cover_every_pixel() {
        for len in [8usize, 9, 10, 11, 20, 31, 512] {
            let v = ref_positions(len, 3);
            assert_eq!(v[0], 0);
            assert_eq!(*v.last().unwrap(), len - BLOCK);
            for px in 0..len {
                assert!(v.iter().any(|&p| p <= px && px < p + BLOCK), "{len} {px}");
            }
        }
    }

    #[test]
    fn top_k_keeps_the_closest_within_tau() {
        let mut t = TopK::new(4, 10.0);
        for (d, p) in [
            (5.0, 1),
            (11.0, 2),
            (0.0, 3),
            (7.0, 4),
            (1.0, 5),
            (2.0, 6),
            (9.0, 7),
        ] {
            t.offer(d, p);
        }
        assert_eq!(t.group(3), vec![3, 5, 6, 1]);
        let mut t = TopK::new(16, 1.0);
        for p in 0..3 {
            t.offer(0.5, p);
        }
        // Three matches make a group of two (the Haar transform needs a power of two).
        assert_eq!(t.group(9).len(), 2);
    }

    /// Tiles and rounds only cut the work: one tile per band and one round give the same
    /// estimates as tiles of 7 block columns finished one at a time (rows written as soon as no
    /// later tile reaches them), up to the order of the sums' roundings. The basic estimate
    /// agrees to float precision; the final one almost everywhere too, but where the basic
    /// estimates' last bits flip a near-tie of the Wiener stage's block matching (on the basic
    /// estimate) by up to 1e-4.
    #[test]
    fn the_cut_of_the_work_does_not_change_the_result() {
        let dim = (90, 130);
        let clean = |i: usize| {
            let (y, x) = (i / dim.1, i % dim.1);
            if (x / 16 + y / 16) % 2 == 0 { 0.2 } else { 0.7 }
        };
        // Uniform noise of σ ≈ 0.03 from a hash of the pixel and channel.
        let noise = |i: usize, c: usize| {
            let mut z = (i as u64 * 3 + c as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            z = (z ^ (z >> 31)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            ((z >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.1
        };
        let noisy: Vec<Vec<f32>> = (0..3)
            .map(|c| (0..dim.0 * dim.1).map(|i| clean(i) + noise(i, c)).collect())
            .collect();
        let profile = Bm3dProfile::default();
        let run = |cut: Cut, stages: &[Stage]| {
            let geom = Geometry::new(dim, &profile, cut);
            let mut estimate = vec![vec![0f32; dim.0 * dim.1]; 3];
            let ctx = StageContext {
                noisy: &noisy,
                sigmas: &[0.03, 0.03, 0.03],
                geom: &geom,
                profile: &profile,
                progress: &Progress::new(),
            };
            for kind in stages {
                stage(*kind, &ctx, &mut estimate, (0.0, 1.0)).unwrap();
            }
            estimate
        };
        let whole = Cut {
            tile_ref_cols: usize::MAX,
            tiles_per_round: usize::MAX,
        };
        let pieces = Cut {
            tile_ref_cols: 7,
            tiles_per_round: 1,
        };
        let differences = |a: &[Vec<f32>], b: &[Vec<f32>]| {
            let d: Vec<f32> = a
                .iter()
                .flatten()
                .zip(b.iter().flatten())
                .map(|(a, b)| (a - b).abs())
                .collect();
            let largest = d.iter().fold(0f32, |m, v| m.max(*v));
            (largest, d.iter().sum::<f32>() / d.len() as f32)
        };
        let basic = [Stage::HardThreshold];
        let (largest, _) = differences(&run(whole, &basic), &run(pieces, &basic));
        assert!(largest < 1e-5, "basic estimates differ by {largest}");
        let both = [Stage::HardThreshold, Stage::Wiener];
        let final_whole = run(whole, &both);
        let (largest, mean) = differences(&final_whole, &run(pieces, &both));
        assert!(
            largest < 1e-3 && mean < 1e-5,
            "final estimates differ by {largest} (mean {mean})"
        );
        // And the estimate is a denoised image, not the noisy one passed through.
        let mse = |p: &[f32]| {
            let sum: f32 = p
                .iter()
                .enumerate()
                .map(|(i, v)| (v - clean(i)).powi(2))
                .sum();
            sum / p.len() as f32
        };
        let (denoised, before) = (mse(&final_whole[0]), mse(&noisy[0]));
        assert!(denoised < 0.25 * before, "{denoised} vs {before}");
    }

    #[test]
    fn a_constant_image_stays_constant() {
        let flat = Array2::from_elem((20, 27), 0.3);
        let out = bm3d(&[flat], 0.01, &Progress::new()).unwrap();
        // Uniform, and at the input's level but for the Wiener gain on the group's mean,
        // |B|² / (|B|² + σ²) with |B| ≥ 0.3 · 8 (a block's DC): at most 1.7e-3 low.
        let (lo, hi) = out[0]
            .iter()
            .fold((f64::INFINITY, 0f64), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        assert!(hi - lo < 1e-5, "{lo} … {hi}");
        assert!(hi <= 0.3 + 1e-6 && lo > 0.3 * (1.0 - 1.8e-3), "{lo} … {hi}");
    }

    /// σ² outside [1e-12, 1] is refused before any work, naming the field; both ends are taken.
    #[test]
    fn the_noise_variance_must_be_positive_and_at_most_one() {
        let img = vec![Array2::from_elem((16, 16), 0.5)];
        for bad in [0.0, -0.01, f64::NAN, f64::INFINITY, 1.5, 1e308, 1e-300] {
            let e = validate(&img, bad).expect_err("refused");
            assert!(
                matches!(&e, SimError::InvalidSetting { path: field, .. } if field == "sigma2"),
                "{bad}: {e}"
            );
        }
        assert!(validate(&img, MAX_SIGMA2).is_ok());
        assert!(validate(&img, MIN_SIGMA2).is_ok());
        assert!(validate(&img, 1e-4).is_ok());
    }
}
