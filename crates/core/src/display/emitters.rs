//! Automatic placement of the R, G, B subpixels in a pixel's opaque area (thesis §3.7,
//! Fig. 3.26): three equal-area rectangles, as large as the closed cells allow. The presets'
//! placements and the optimizer's "reserve subpixels" constraint come from here.

use crate::design::{Opening, Subpixel, Subpixels};
use crate::display::aperture::effective_cells;

/// Grids larger than this per side are not auto-placed (the exhaustive rectangle search grows
/// with N⁴); every thesis layout has 21 cells.
pub const MAX_AUTO_PLACE_CELLS: usize = 128;

/// The cells an emitter may cover: closed (transmittance 0) after the polygons are rasterised.
pub fn closed_cells(opening: &Opening) -> Vec<Vec<bool>> {
    effective_cells(opening)
        .iter()
        .map(|r| r.iter().map(|&v| v <= 0.0).collect())
        .collect()
}

/// Three equal-area emitter rectangles (R, G, B) in the closed area of `opening`, each at least
/// `min_area_um2`, as large as a greedy search finds; `None` when they do not fit.
pub fn auto_place(opening: &Opening, min_area_um2: f64) -> Option<Subpixels> {
    let cell = opening.cell_um();
    let min_cells = if min_area_um2 > 0.0 && cell > 0.0 {
        (min_area_um2 / (cell * cell)).ceil().max(1.0) as usize
    } else {
        1
    };
    auto_place_cells(&closed_cells(opening), min_cells)
}

/// As [`auto_place`] on a grid of free cells, with the minimum area in cells.
///
/// For each candidate area `A`, from a third of the free cells down to `min_cells`, the colours
/// are placed one after the other: the first rectangle of area exactly `A` (most compact shape
/// first, then row-major position) whose cells are all free. The first `A` for which all three
/// fit wins. Greedy, so it may miss a packing an exhaustive search would find.
pub fn auto_place_cells(free: &[Vec<bool>], min_cells: usize) -> Option<Subpixels> {
    let n = free.len();
    if n == 0 || n > MAX_AUTO_PLACE_CELLS || free.iter().any(|r| r.len() != n) {
        return None;
    }
    let total: usize = free.iter().flatten().filter(|&&f| f).count();
    let max_area = total / 3;
    let min_cells = min_cells.max(1);
    if max_area < min_cells {
        return None;
    }
    for area in candidate_areas(max_area, min_cells, n) {
        if let Some(sp) = place_three(free, area) {
            return Some(sp);
        }
    }
    None
}

/// Every area from `max` down to `min` on small grids; on larger ones a 1 %-step ladder (plus
/// the exact tail) keeps the search short.
fn candidate_areas(max: usize, min: usize, n: usize) -> Vec<usize> {
    if n <= 32 || max - min < 400 {
        return (min..=max).rev().collect();
    }
    let mut out = Vec::new();
    let mut a = max as f64;
    while a.floor() as usize >= min {
        let v = a.floor() as usize;
        if out.last() != Some(&v) {
            out.push(v);
        }
        a *= 0.99;
    }
    out
}

/// Rectangle shapes `(rows, cols)` of exactly `area` cells that fit an `n×n` grid, most
/// compact first.
fn shapes(area: usize, n: usize) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = (1..=n.min(area))
        .filter(|h| area.is_multiple_of(*h) && area / h <= n)
        .map(|h| (h, area / h))
        .collect();
    out.sort_by_key(|&(h, w)| (h.abs_diff(w), h));
    out
}

fn place_three(free: &[Vec<bool>], area: usize) -> Option<Subpixels> {
    let n = free.len();
    let mut avail: Vec<Vec<bool>> = free.to_vec();
    let mut sp = Subpixels::empty(n);
    let shapes = shapes(area, n);
    for colour in Subpixel::ALL {
        let sums = prefix_sums(&avail);
        let (r0, c0, h, w) = shapes.iter().find_map(|&(h, w)| {
            (0..=n - h).find_map(|r| {
                (0..=n - w)
                    .find(|&c| rect_sum(&sums, r, c, h, w) == h * w)
                    .map(|c| (r, c, h, w))
            })
        })?;
        for (row, sp_row) in avail.iter_mut().zip(&mut sp.cells).skip(r0).take(h) {
            row[c0..c0 + w].fill(false);
            sp_row[c0..c0 + w].fill(Some(colour));
        }
    }
    Some(sp)
}

fn prefix_sums(avail: &[Vec<bool>]) -> Vec<Vec<usize>> {
    let n = avail.len();
    let mut s = vec![vec![0usize; n + 1]; n + 1];
    for r in 0..n {
        for c in 0..n {
            s[r + 1][c + 1] = s[r][c + 1] + s[r + 1][c] - s[r][c] + usize::from(avail[r][c]);
        }
    }
    s
}

fn rect_sum(s: &[Vec<usize>], r: usize, c: usize, h: usize, w: usize) -> usize {
    s[r + h][c + w] + s[r][c] - s[r][c + w] - s[r + h][c]
}
