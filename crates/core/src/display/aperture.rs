//! Rasterising the effective aperture `a = p · o` (conventions.md §1) onto the pupil grid.
//!
//! Samples sit at `x = ix·δ1`, `y = iy·δ1` (signed offsets from the optical axis) and represent
//! the `δ1×δ1` square around them. The display is box-filtered (area-weighted amplitude) onto that
//! square, which is exact when cells are whole multiples of δ1 and aligned, as in the thesis
//! recipe. The lens pupil is binary: a sample is inside when its centre is within `D/2`.

use crate::design::{Design, Opening, Polygon, TilingMode};
use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::display::tiling::{D4, tile_orientation};

/// One row of a field on the pupil grid, stored densely between its first and last nonzero
/// samples: real amplitudes, or complex ones for a field with a phase ([`Field::with_phase`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SparseRow<T = f64> {
    /// Signed row offset from the axis, in samples (`y = iy·δ1`).
    pub iy: i64,
    /// Signed column offset of `values[0]`.
    pub ix0: i64,
    /// Consecutive samples from column `ix0` on.
    pub values: Vec<T>,
}

/// A field on the pupil grid: a real one (amplitude transmittance), or a complex one (the
/// aperture with a phase across it, as a defocused pupil).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Field<T = f64> {
    /// Rows with any nonzero sample, in ascending `iy`.
    pub rows: Vec<SparseRow<T>>,
}

impl<T> Field<T> {
    /// Largest `|offset|` of any sample, in samples (the field fits a grid of `M` when
    /// `-M/2 <= offset < M/2`).
    pub fn extent(&self) -> (i64, i64) {
        let mut lo = 0i64;
        let mut hi = 0i64;
        for r in &self.rows {
            lo = lo.min(r.iy).min(r.ix0);
            hi = hi.max(r.iy).max(r.ix0 + r.values.len() as i64 - 1);
        }
        (lo, hi)
    }
}

impl Field<Complex64> {
    /// `Σ |a|²`.
    pub fn energy(&self) -> f64 {
        self.rows
            .iter()
            .flat_map(|r| r.values.iter())
            .map(Complex64::norm_sqr)
            .sum()
    }
}

impl Field {
    /// `Σ |a|²`.
    pub fn energy(&self) -> f64 {
        self.rows
            .iter()
            .flat_map(|r| r.values.iter())
            .map(|v| v * v)
            .sum()
    }

    /// Each sample `a` at `(ix, iy)` times `exp(i·phase(ix, iy))`, the phase in radians and
    /// reduced mod 2π in `f64` before the exponential (a defocus's is many waves at the rim).
    pub fn with_phase(&self, phase: impl Fn(i64, i64) -> f64 + Sync) -> Field<Complex64> {
        let rows = self
            .rows
            .par_iter()
            .map(|r| SparseRow {
                iy: r.iy,
                ix0: r.ix0,
                values: r
                    .values
                    .iter()
                    .enumerate()
                    .map(|(j, &v)| {
                        let ph = phase(r.ix0 + j as i64, r.iy).rem_euclid(std::f64::consts::TAU);
                        Complex64::from_polar(v, ph)
                    })
                    .collect(),
            })
            .collect();
        Field { rows }
    }

    /// Dense `[row, col]` copy on an `m×m` grid (axis at `m/2`), for tests and views.
    pub fn to_dense(&self, m: usize) -> Vec<Vec<f64>> {
        let mut out = vec![vec![0.0; m]; m];
        let h = (m / 2) as i64;
        for r in &self.rows {
            let y = r.iy + h;
            if !(0..m as i64).contains(&y) {
                continue;
            }
            for (k, v) in r.values.iter().enumerate() {
                let x = r.ix0 + k as i64 + h;
                if (0..m as i64).contains(&x) {
                    out[y as usize][x as usize] = *v;
                }
            }
        }
        out
    }
}

/// The display layout in physical terms, independent of any grid.
#[derive(Debug, Clone)]
pub struct Display<'a> {
    /// `N×N` effective cell transmittance (see [`effective_cells`]).
    pub cells: &'a [Vec<f64>],
    /// Display pixel pitch `T`, µm.
    pub pitch_um: f64,
    /// Opaque wiring gap around every pixel, µm; the tiling period is `pitch_um + gap_um`.
    pub gap_um: f64,
    /// Cell `[x, y]` of its tile that the optical axis sits on (see `Tiling::origin_offset_cells`).
    pub origin_offset_cells: [f64; 2],
    /// How the pixel pattern is laid out (repeat or random orientations).
    pub mode: TilingMode,
    /// Seed of the random tile orientations.
    pub seed: u64,
}

impl<'a> Display<'a> {
    /// The display of `design`, with `cells` as its effective cell transmittance.
    pub fn from_design(design: &'a Design, cells: &'a [Vec<f64>]) -> Self {
        Display {
            cells,
            pitch_um: design.opening.pitch_um,
            gap_um: design.tiling.wiring_gap_um,
            origin_offset_cells: design.tiling.origin_offset_cells,
            mode: design.tiling.mode,
            seed: design.tiling.seed,
        }
    }

    fn n(&self) -> usize {
        self.cells.len()
    }

    fn cell_um(&self) -> f64 {
        self.pitch_um / self.n() as f64
    }

    fn period_um(&self) -> f64 {
        self.pitch_um + self.gap_um
    }
}

/// Which part of the display to rasterise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Extent {
    /// Everything inside a circular pupil of this diameter (µm).
    Pupil {
        /// Pupil diameter `D`, µm.
        diameter_um: f64,
    },
    /// Only the tile holding the optical axis, unclipped (for the expected-PSF terms).
    SingleTile,
    /// Everything within a square of half-side `half_um` around the axis (previews).
    Square {
        /// Half the side of the square, µm.
        half_um: f64,
    },
}

/// A run of one axis of a sample square that falls in one tile and one cell (`None` = gap).
#[derive(Debug, Clone, Copy)]
struct Segment {
    tile: i64,
    cell: Option<usize>,
    weight: f64,
}

/// Splits `[x - δ/2, x + δ/2]` (µm from the axis) at cell and period boundaries.
fn segments(display: &Display, x_um: f64, delta_um: f64, axis: usize) -> Vec<Segment> {
    let n = display.n();
    let cell = display.cell_um();
    let period = display.period_um();
    let shift = (display.origin_offset_cells[axis] + 0.5) * cell;
    let a = x_um - 0.5 * delta_um + shift;
    let b = x_um + 0.5 * delta_um + shift;
    let eps = 1e-9 * delta_um.max(period);
    let mut out = Vec::with_capacity(2);
    let mut pos = a;
    while pos < b - eps {
        let tile = (pos / period).floor();
        let local = pos - tile * period;
        let (cell_idx, end) = if local >= display.pitch_um - eps {
            (None, (tile + 1.0) * period)
        } else {
            let c = ((local / cell).floor().max(0.0) as usize).min(n - 1);
            let end = if c == n - 1 {
                tile * period + display.pitch_um
            } else {
                tile * period + (c + 1) as f64 * cell
            };
            (Some(c), end)
        };
        let end = end.min(b).max(pos + eps);
        out.push(Segment {
            tile: tile as i64,
            cell: cell_idx,
            weight: (end - pos) / delta_um,
        });
        pos = end;
    }
    out
}

/// Rasterises the display (clipped by `extent`) on a grid of spacing `delta_um`, its rows in
/// parallel (a fit rasterises a display at every step of its pitch and edges, a pupil of
/// millions of samples).
pub fn rasterise(display: &Display, extent: Extent, delta_um: f64) -> Field {
    let Some(walker) = Walker::new(display, extent, delta_um) else {
        return Field::default();
    };
    let n = display.n();
    // The pattern each tile shows, flattened: one copy per orientation the tiles use (eight at
    // most), so a sample reads its cell without turning its indices.
    let mut kinds: Vec<D4> = Vec::new();
    let tile_kind: Vec<usize> = walker
        .orientations
        .iter()
        .map(|g| match kinds.iter().position(|k| k == g) {
            Some(i) => i,
            None => {
                kinds.push(*g);
                kinds.len() - 1
            }
        })
        .collect();
    let patterns: Vec<Vec<f64>> = kinds
        .iter()
        .map(|g| {
            (0..n * n)
                .map(|k| {
                    let (sr, sc) = g.source(k / n, k % n, n);
                    display.cells[sr][sc]
                })
                .collect()
        })
        .collect();
    // Each sample column's pieces as runs of consecutive cells in one tile (a refined opening
    // puts a dozen cells under a sample), their weights back to back.
    let mut run_starts = Vec::with_capacity(walker.segs_x.len() + 1);
    let mut runs: Vec<Run> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    run_starts.push(0);
    for segs in &walker.segs_x {
        let column_start = runs.len();
        for sx in segs {
            let Some(cx) = sx.cell else { continue };
            if extent == Extent::SingleTile && sx.tile != 0 {
                continue;
            }
            let tile = (sx.tile - walker.tx0) as usize;
            let in_column = runs.len() > column_start;
            match runs.last_mut() {
                Some(r) if in_column && r.tile == tile && r.c0 + r.len == cx => {
                    r.len += 1;
                }
                _ => runs.push(Run {
                    tile,
                    c0: cx,
                    w0: weights.len(),
                    len: 1,
                }),
            }
            weights.push(sx.weight);
        }
        run_starts.push(runs.len());
    }
    let rows = (walker.lo..=walker.hi)
        .into_par_iter()
        .filter_map(|iy| {
            let (first, last) = walker.inside(iy)?;
            let ky = (iy - walker.lo) as usize;
            let k0 = (first - walker.lo) as usize;
            let mut values = vec![0.0f64; (last - first + 1) as usize];
            // Row pieces outer, column pieces inner: each sample sums its terms in the order
            // the cell map lists them.
            for sy in &walker.segs_y[ky] {
                let Some(cy) = sy.cell else { continue };
                if extent == Extent::SingleTile && sy.tile != 0 {
                    continue;
                }
                let base = (sy.tile - walker.ty0) as usize * walker.tiles_x;
                for (k, v) in values.iter_mut().enumerate() {
                    let kx = k0 + k;
                    for r in &runs[run_starts[kx]..run_starts[kx + 1]] {
                        let at = cy * n + r.c0;
                        let cells = &patterns[tile_kind[base + r.tile]][at..at + r.len];
                        for (wx, cell) in weights[r.w0..r.w0 + r.len].iter().zip(cells) {
                            *v += sy.weight * wx * cell;
                        }
                    }
                }
            }
            let lead = values.iter().position(|v| *v != 0.0)?;
            let tail = values.iter().rposition(|v| *v != 0.0).unwrap_or(lead);
            values.truncate(tail + 1);
            values.drain(..lead);
            Some(SparseRow {
                iy,
                ix0: first + lead as i64,
                values,
            })
        })
        .collect();
    Field { rows }
}

/// `len` consecutive cells of one row of a tile from cell `c0`, under one sample column, with
/// their weights at `w0..w0 + len`.
struct Run {
    tile: usize,
    c0: usize,
    w0: usize,
    len: usize,
}

/// The display as a linear map from the `N×N` cell transmittances (flattened row-major) to the
/// samples of the pupil grid: sample `k` at `(iy[k], ix[k])` holds `Σ weight · cell` over its
/// terms. The optimizer needs this to send gradients from samples back to cells.
#[derive(Debug, Clone, Default)]
pub struct CellMap {
    /// Cells per side `N` of the opening.
    pub n: usize,
    /// Signed sample offsets from the axis of every sample inside the extent, row by row.
    pub iy: Vec<i64>,
    /// Signed column offsets from the axis, one per sample (pairs with `iy`).
    pub ix: Vec<i64>,
    /// Terms of sample `k` are `terms[starts[k]..starts[k + 1]]` as `(cell, weight)`.
    pub starts: Vec<usize>,
    /// `(cell, weight)` terms of all samples back to back, cells flattened row-major.
    pub terms: Vec<(usize, f64)>,
}

impl CellMap {
    /// Builds the map of `display` (its cell values are ignored, only its geometry counts).
    pub fn new(display: &Display, extent: Extent, delta_um: f64) -> Self {
        let mut map = CellMap {
            n: display.n(),
            starts: vec![0],
            ..CellMap::default()
        };
        walk(display, extent, delta_um, |iy, ix, terms| {
            map.iy.push(iy);
            map.ix.push(ix);
            map.terms.extend_from_slice(terms);
            map.starts.push(map.terms.len());
        });
        map
    }

    /// Sample values for the flattened cells.
    pub fn apply(&self, cells: &[f64]) -> Vec<f64> {
        self.starts
            .windows(2)
            .map(|w| {
                self.terms[w[0]..w[1]]
                    .iter()
                    .map(|&(c, wt)| wt * cells[c])
                    .sum()
            })
            .collect()
    }

    /// The adjoint: `∂L/∂cell = Σ_samples weight · ∂L/∂sample`.
    pub fn adjoint(&self, sample_grad: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n * self.n];
        for (w, g) in self.starts.windows(2).zip(sample_grad) {
            for &(c, wt) in &self.terms[w[0]..w[1]] {
                out[c] += wt * g;
            }
        }
        out
    }
}

/// Visits every sample inside `extent`, row by row and left to right, with the `(cell, weight)`
/// terms of its box-filtered display value (cells flattened row-major; empty in a wiring gap).
fn walk(
    display: &Display,
    extent: Extent,
    delta_um: f64,
    mut visit: impl FnMut(i64, i64, &[(usize, f64)]),
) {
    let Some(walker) = Walker::new(display, extent, delta_um) else {
        return;
    };
    let n = display.n();
    let mut flat = Vec::with_capacity(4);
    for iy in walker.lo..=walker.hi {
        walker.row(iy, |ix, terms| {
            flat.clear();
            flat.extend(terms.iter().map(|&(r, c, w)| (r * n + c, w)));
            visit(iy, ix, &flat);
        });
    }
}

/// What every row of a rasterisation shares: each sample column's and row's cuts at cell and
/// period boundaries, and each tile's orientation.
struct Walker<'d, 'a> {
    display: &'d Display<'a>,
    extent: Extent,
    delta_um: f64,
    /// First and last sample offset on each axis.
    lo: i64,
    hi: i64,
    segs_x: Vec<Vec<Segment>>,
    segs_y: Vec<Vec<Segment>>,
    /// Orientation per tile in a dense table (a ChaCha stream per tile is not free, and a hash
    /// lookup per sample would dominate the rasterisation), from tile `(tx0, ty0)` on.
    orientations: Vec<D4>,
    tx0: i64,
    ty0: i64,
    tiles_x: usize,
    /// Squared pupil radius, µm² (infinite for the other extents).
    r2: f64,
}

impl<'d, 'a> Walker<'d, 'a> {
    /// `None` for a display without cells.
    fn new(display: &'d Display<'a>, extent: Extent, delta_um: f64) -> Option<Self> {
        if display.n() == 0 {
            return None;
        }
        let (lo, hi) = match extent {
            Extent::Pupil { diameter_um } => {
                let r = (0.5 * diameter_um / delta_um).floor() as i64;
                (-r, r)
            }
            Extent::Square { half_um } => {
                let r = (half_um / delta_um).floor() as i64;
                (-r, r)
            }
            Extent::SingleTile => {
                let shift_x = (display.origin_offset_cells[0] + 0.5) * display.cell_um();
                let shift_y = (display.origin_offset_cells[1] + 0.5) * display.cell_um();
                let lo = ((-shift_x.max(shift_y)) / delta_um).floor() as i64 - 1;
                let hi = ((display.pitch_um - shift_x.min(shift_y)) / delta_um).ceil() as i64 + 1;
                (lo, hi)
            }
        };
        let axis_segments = |axis: usize| -> Vec<Vec<Segment>> {
            (lo..=hi)
                .map(|i| segments(display, i as f64 * delta_um, delta_um, axis))
                .collect()
        };
        let segs_x = axis_segments(0);
        let segs_y = axis_segments(1);
        let tile_range = |segs: &[Vec<Segment>]| {
            let mut it = segs.iter().flatten().map(|s| s.tile);
            let first = it.next().unwrap_or(0);
            it.fold((first, first), |(a, b), t| (a.min(t), b.max(t)))
        };
        let (tx0, tx1) = tile_range(&segs_x);
        let (ty0, ty1) = tile_range(&segs_y);
        let orientations: Vec<D4> = (ty0..=ty1)
            .flat_map(|ty| (tx0..=tx1).map(move |tx| (tx, ty)))
            .map(|(tx, ty)| tile_orientation(display.mode, display.seed, tx, ty))
            .collect();
        let r2 = match extent {
            Extent::Pupil { diameter_um } => (0.5 * diameter_um).powi(2),
            Extent::SingleTile | Extent::Square { .. } => f64::INFINITY,
        };
        Some(Walker {
            display,
            extent,
            delta_um,
            lo,
            hi,
            segs_x,
            segs_y,
            orientations,
            tx0,
            ty0,
            tiles_x: (tx1 - tx0 + 1) as usize,
            r2,
        })
    }

    /// The first and last sample of row `iy` inside the extent (a disc's samples in a row are
    /// consecutive), or `None`.
    fn inside(&self, iy: i64) -> Option<(i64, i64)> {
        let y = iy as f64 * self.delta_um;
        let within = |ix: i64| {
            let x = ix as f64 * self.delta_um;
            x * x + y * y <= self.r2
        };
        let first = (self.lo..=self.hi).find(|&ix| within(ix))?;
        let last = (first..=self.hi).rev().find(|&ix| within(ix))?;
        Some((first, last))
    }

    /// Visits the samples of row `iy` inside the extent, left to right, with the
    /// `(cell row, cell column, weight)` terms of each one's box-filtered value.
    fn row(&self, iy: i64, mut visit: impl FnMut(i64, &[(usize, usize, f64)])) {
        let n = self.display.n();
        let ky = (iy - self.lo) as usize;
        let Some((first, last)) = self.inside(iy) else {
            return;
        };
        let mut terms = Vec::with_capacity(4);
        for ix in first..=last {
            let kx = (ix - self.lo) as usize;
            terms.clear();
            for sy in &self.segs_y[ky] {
                let Some(cy) = sy.cell else { continue };
                for sx in &self.segs_x[kx] {
                    let Some(cx) = sx.cell else { continue };
                    if self.extent == Extent::SingleTile && (sx.tile != 0 || sy.tile != 0) {
                        continue;
                    }
                    let g = self.orientations[(sy.tile - self.ty0) as usize * self.tiles_x
                        + (sx.tile - self.tx0) as usize];
                    let (sr, sc) = g.source(cy, cx, n);
                    terms.push((sr, sc, sy.weight * sx.weight));
                }
            }
            visit(ix, &terms);
        }
    }
}

/// Number of pupil samples (`Σ p²`) for a binary disc of diameter `d_um` on a `δ1` grid.
pub fn pupil_sample_count(diameter_um: f64, delta_um: f64) -> f64 {
    let r = (0.5 * diameter_um / delta_um).floor() as i64;
    let r2 = (0.5 * diameter_um).powi(2);
    let mut count = 0u64;
    for iy in -r..=r {
        for ix in -r..=r {
            let (x, y) = (ix as f64 * delta_um, iy as f64 * delta_um);
            if x * x + y * y <= r2 {
                count += 1;
            }
        }
    }
    count as f64
}

/// The cells the simulation uses: the drawn cells united with the rasterised polygons.
pub fn effective_cells(opening: &Opening) -> Vec<Vec<f64>> {
    let mut cells = opening.cells.clone();
    if opening.polygons.is_empty() {
        return cells;
    }
    let n = opening.n();
    let cell = opening.cell_um();
    for (r, row) in cells.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            let rect = [
                c as f64 * cell,
                r as f64 * cell,
                (c + 1) as f64 * cell,
                (r + 1) as f64 * cell,
            ];
            let covered: f64 = opening
                .polygons
                .iter()
                .map(|p| clipped_area(p, rect))
                .sum::<f64>()
                / (cell * cell);
            *v = v.max(covered.clamp(0.0, 1.0));
        }
    }
    debug_assert_eq!(cells.len(), n);
    cells
}

/// Area of `polygon ∩ rect` (`rect = [x0, y0, x1, y1]`), by Sutherland–Hodgman clipping against
/// the convex rectangle and the shoelace formula.
pub fn clipped_area(polygon: &Polygon, rect: [f64; 4]) -> f64 {
    let mut pts: Vec<[f64; 2]> = polygon.vertices_um.clone();
    // Each clip edge: keep points with sign * (coord - bound) >= 0.
    for (axis, bound, keep_greater) in [
        (0usize, rect[0], true),
        (0, rect[2], false),
        (1, rect[1], true),
        (1, rect[3], false),
    ] {
        if pts.is_empty() {
            return 0.0;
        }
        let inside = |p: &[f64; 2]| {
            if keep_greater {
                p[axis] >= bound
            } else {
                p[axis] <= bound
            }
        };
        let mut out = Vec::with_capacity(pts.len() + 4);
        for i in 0..pts.len() {
            let cur = pts[i];
            let prev = pts[(i + pts.len() - 1) % pts.len()];
            let (ci, pi) = (inside(&cur), inside(&prev));
            if ci != pi {
                let t = (bound - prev[axis]) / (cur[axis] - prev[axis]);
                out.push([
                    prev[0] + t * (cur[0] - prev[0]),
                    prev[1] + t * (cur[1] - prev[1]),
                ]);
            }
            if ci {
                out.push(cur);
            }
        }
        pts = out;
    }
    let mut twice = 0.0;
    for i in 0..pts.len() {
        let a = pts[i];
        let b = pts[(i + 1) % pts.len()];
        twice += a[0] * b[1] - b[0] * a[1];
    }
    0.5 * twice.abs()
}

/// The display around the pupil as a dense square image for previews: `(side, values)` with the
/// axis at `side / 2`, covering 1.15 pupil diameters, sampled at δ1 or coarser so that the side
/// stays within `max_side`. Returns the sample spacing used.
pub fn display_preview(design: &Design, max_side: usize) -> (usize, Vec<f32>, f64) {
    let cells = effective_cells(&design.opening);
    let display = Display::from_design(design, &cells);
    let half_um = 0.575 * design.optics.pupil_diameter_um();
    let mut delta = design.optics.pupil_sample_um;
    while (2.0 * half_um / delta) as usize + 1 > max_side.max(16) {
        delta *= 2.0;
    }
    let field = rasterise(&display, Extent::Square { half_um }, delta);
    let r = (half_um / delta).floor() as usize;
    let side = 2 * r + 2;
    let dense = field.to_dense(side);
    (
        side,
        dense.into_iter().flatten().map(|v| v as f32).collect(),
        delta,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn display(cells: &[Vec<f64>], pitch: f64, offset: [f64; 2]) -> Display<'_> {
        Display {
            cells,
            pitch_um: pitch,
            gap_um: 0.0,
            origin_offset_cells: offset,
            mode: TilingMode::Repeat,
            seed: 0,
        }
    }

    #[test]
    fn thesis_registration_puts_the_axis_on_cell_6() {
        // Mark only cell (6, 6): with cells = δ1 it must land exactly on the axis sample.
        let mut cells = vec![vec![0.0; 21]; 21];
        cells[6][6] = 1.0;
        let d = display(&cells, 168.0, [6.0, 6.0]);
        let f = rasterise(&d, Extent::Pupil { diameter_um: 400.0 }, 8.0);
        let dense = f.to_dense(64);
        assert_eq!(dense[32][32], 1.0);
        assert_eq!(dense[32][31], 0.0);
        assert_eq!(dense[32][32 + 21], 1.0, "period of 21 samples");
        assert_eq!(dense[32 - 21][32], 1.0);
    }

    #[test]
    fn area_coverage_is_exact_for_half_cells() {
        // Cells of 16 µm on an 8 µm grid, shifted by a tenth of a cell: samples straddle cell
        // boundaries; the mean transmittance is preserved.
        let cells = vec![vec![1.0, 0.0], vec![0.0, 0.0]];
        let d = display(&cells, 32.0, [0.1, 0.1]);
        let f = rasterise(
            &d,
            Extent::Pupil {
                diameter_um: 4000.0,
            },
            8.0,
        );
        let dense = f.to_dense(512);
        // mean over a whole number of periods (16 samples = 4 periods) near the centre
        let mut s = 0.0;
        for row in dense.iter().skip(256 - 8).take(16) {
            s += row[256 - 8..256 + 8].iter().sum::<f64>();
        }
        assert!((s / 256.0 - 0.25).abs() < 1e-12, "mean {}", s / 256.0);
        assert!(
            dense.iter().flatten().any(|&v| v > 0.0 && v < 1.0),
            "partial coverage expected"
        );
    }

    #[test]
    fn pupil_count_matches_disc_area() {
        let n = pupil_sample_count(4000.0, 8.0);
        let area = std::f64::consts::PI * 250.0 * 250.0;
        assert!((n - area).abs() / area < 0.005, "{n} vs {area}");
    }

    #[test]
    fn polygon_coverage_of_a_triangle() {
        let tri = Polygon {
            vertices_um: vec![[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]],
        };
        assert!((clipped_area(&tri, [0.0, 0.0, 10.0, 10.0]) - 50.0).abs() < 1e-12);
        assert!((clipped_area(&tri, [0.0, 0.0, 5.0, 5.0]) - 25.0).abs() < 1e-12);
        assert!((clipped_area(&tri, [5.0, 5.0, 10.0, 10.0])).abs() < 1e-12);
        assert!((clipped_area(&tri, [0.0, 5.0, 5.0, 10.0]) - 12.5).abs() < 1e-12);
    }

    #[test]
    fn wiring_gap_is_opaque_and_lengthens_the_period() {
        let cells = vec![vec![1.0; 21]; 21];
        let mut d = display(&cells, 168.0, [0.0, 0.0]);
        d.gap_um = 8.0;
        let f = rasterise(
            &d,
            Extent::Pupil {
                diameter_um: 2000.0,
            },
            8.0,
        );
        let dense = f.to_dense(256);
        let row = &dense[128];
        // tile starts half a cell before the axis: samples 0..=20 open, 21 gap, period 22.
        assert_eq!(row[128 + 20], 1.0);
        assert_eq!(row[128 + 21], 0.0);
        assert_eq!(row[128 + 22], 1.0);
        assert_eq!(row[128 + 43], 0.0);
    }
}
