//! Drawing operations on an opening's cell grid (`cells[row][col]`, amplitude transmittance in
//! `[0, 1]`, row 0 at the top), shared by the studio's editor, its commands and the tests.
//!
//! Every function is pure and never panics: cells outside the grid (including the brush or shape
//! parts that fall off an edge) are clipped, and ragged rows are tolerated (only existing cells
//! are touched). Cell coordinates are `(row, col)`.

use std::collections::VecDeque;

use crate::design::MAX_CELLS;

/// Mirror symmetry applied while drawing: every touched cell is also set at its mirror images.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Symmetry {
    /// No mirroring: only the touched cell changes.
    #[default]
    None,
    /// Mirror across the vertical centre line (left ↔ right): `(r, c) → (r, N−1−c)`.
    MirrorX,
    /// Mirror across the horizontal centre line (top ↔ bottom): `(r, c) → (N−1−r, c)`.
    MirrorY,
    /// Both mirrors (and so the 180° rotation).
    FourFold,
}

impl Symmetry {
    /// Every symmetry, in the order the UI lists them.
    pub const ALL: [Symmetry; 4] = [
        Symmetry::None,
        Symmetry::MirrorX,
        Symmetry::MirrorY,
        Symmetry::FourFold,
    ];

    /// How the UI names it.
    pub fn label(self) -> &'static str {
        match self {
            Symmetry::None => "none",
            Symmetry::MirrorX => "mirror x (left-right)",
            Symmetry::MirrorY => "mirror y (top-bottom)",
            Symmetry::FourFold => "4-fold (both mirrors)",
        }
    }
}

/// The cell `(r, c)` of an `n×n` grid and its mirror images under `sym`, without duplicates
/// (cells on a mirror line are their own image). Empty when `(r, c)` lies outside the grid.
pub fn symmetric_cells(n: usize, r: usize, c: usize, sym: Symmetry) -> Vec<(usize, usize)> {
    if r >= n || c >= n {
        return Vec::new();
    }
    let (mr, mc) = (n - 1 - r, n - 1 - c);
    let candidates: &[(usize, usize)] = match sym {
        Symmetry::None => &[(r, c)],
        Symmetry::MirrorX => &[(r, c), (r, mc)],
        Symmetry::MirrorY => &[(r, c), (mr, c)],
        Symmetry::FourFold => &[(r, c), (r, mc), (mr, c), (mr, mc)],
    };
    let mut out: Vec<(usize, usize)> = Vec::with_capacity(candidates.len());
    for &p in candidates {
        if !out.contains(&p) {
            out.push(p);
        }
    }
    out
}

/// Sets one cell and its mirror images (clipped to the grid).
fn set_sym(cells: &mut [Vec<f64>], r: usize, c: usize, value: f64, sym: Symmetry) {
    for (rr, cc) in symmetric_cells(cells.len(), r, c, sym) {
        if let Some(v) = cells.get_mut(rr).and_then(|row| row.get_mut(cc)) {
            *v = value;
        }
    }
}

/// The rows (or columns) covered by a brush of `brush_cells` centred on `centre`: an odd brush is
/// centred exactly, an even one extends one cell further towards higher indices. Clipped to `n`.
fn brush_span(centre: usize, brush_cells: usize, n: usize) -> std::ops::Range<usize> {
    let b = brush_cells.max(1);
    let before = (b - 1) / 2;
    let after = b - 1 - before;
    let lo = centre.saturating_sub(before);
    let hi = centre.saturating_add(after).saturating_add(1).min(n);
    lo..hi.max(lo)
}

/// Paints a square brush `brush_cells` wide (0 counts as 1) centred on `(r, c)` with `value`,
/// clipped to the grid, together with its mirror images under `sym`.
pub fn paint(
    cells: &mut [Vec<f64>],
    r: usize,
    c: usize,
    brush_cells: usize,
    value: f64,
    sym: Symmetry,
) {
    let n = cells.len();
    for rr in brush_span(r, brush_cells, n) {
        for cc in brush_span(c, brush_cells, n) {
            set_sym(cells, rr, cc, value, sym);
        }
    }
}

/// The cells of the Bresenham line from `a` to `b`, both ends included, in order from `a`.
pub fn line_cells(a: (usize, usize), b: (usize, usize)) -> Vec<(usize, usize)> {
    // Grid coordinates are at most MAX_CELLS in practice; i64 holds any usize the caller can
    // index with, so the casts below cannot wrap for real grids.
    let (mut r, mut c) = (a.0 as i64, a.1 as i64);
    let (r1, c1) = (b.0 as i64, b.1 as i64);
    let dr = (r1 - r).abs();
    let dc = -(c1 - c).abs();
    let sr = if r < r1 { 1 } else { -1 };
    let sc = if c < c1 { 1 } else { -1 };
    let mut err = dr + dc;
    let mut out = Vec::with_capacity((dr.max(-dc) + 1) as usize);
    loop {
        out.push((r as usize, c as usize));
        if r == r1 && c == c1 {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dc {
            err += dc;
            r += sr;
        }
        if e2 <= dr {
            err += dr;
            c += sc;
        }
    }
    out
}

/// Paints the brush at every step of the Bresenham line from `a` to `b` (both ends included).
/// Used for the line tool and to join successive pointer positions of a drag.
pub fn line(
    cells: &mut [Vec<f64>],
    a: (usize, usize),
    b: (usize, usize),
    brush_cells: usize,
    value: f64,
    sym: Symmetry,
) {
    for (r, c) in line_cells(a, b) {
        paint(cells, r, c, brush_cells, value, sym);
    }
}

/// Fills the rectangle with inclusive corners `a` and `b` (in any order), clipped to the grid.
pub fn rect(
    cells: &mut [Vec<f64>],
    a: (usize, usize),
    b: (usize, usize),
    value: f64,
    sym: Symmetry,
) {
    let n = cells.len();
    let (r0, r1) = (a.0.min(b.0), a.0.max(b.0).min(n.saturating_sub(1)));
    let (c0, c1) = (a.1.min(b.1), a.1.max(b.1).min(n.saturating_sub(1)));
    for r in r0..=r1 {
        for c in c0..=c1 {
            set_sym(cells, r, c, value, sym);
        }
    }
}

/// Fills the ellipse inscribed in the box of cells with inclusive corners `a` and `b` (in any
/// order): a cell is set when its centre lies inside (or on) the ellipse through the box's edges.
pub fn ellipse(
    cells: &mut [Vec<f64>],
    a: (usize, usize),
    b: (usize, usize),
    value: f64,
    sym: Symmetry,
) {
    let n = cells.len();
    if n == 0 {
        return;
    }
    let (r0, r1) = (a.0.min(b.0), a.0.max(b.0));
    let (c0, c1) = (a.1.min(b.1), a.1.max(b.1));
    // Box edges in cell units: [r0, r1 + 1] × [c0, c1 + 1].
    let (r0f, r1f, c0f, c1f) = (r0 as f64, r1 as f64 + 1.0, c0 as f64, c1 as f64 + 1.0);
    let (cr, cc) = ((r0f + r1f) / 2.0, (c0f + c1f) / 2.0);
    let (ar, ac) = ((r1f - r0f) / 2.0, (c1f - c0f) / 2.0);
    for r in r0..=r1.min(n - 1) {
        for c in c0..=c1.min(n - 1) {
            let y = (r as f64 + 0.5 - cr) / ar;
            let x = (c as f64 + 0.5 - cc) / ac;
            if x * x + y * y <= 1.0 + 1e-12 {
                set_sym(cells, r, c, value, sym);
            }
        }
    }
}

/// The 4-connected region of cells exactly equal to the value at `(r, c)`, as a mask.
fn region(cells: &[Vec<f64>], r: usize, c: usize, mask: &mut [Vec<bool>]) {
    let Some(&start) = cells.get(r).and_then(|row| row.get(c)) else {
        return;
    };
    let mut queue = VecDeque::from([(r, c)]);
    while let Some((r, c)) = queue.pop_front() {
        let same = cells.get(r).and_then(|row| row.get(c)) == Some(&start);
        if !same || mask[r][c] {
            continue;
        }
        mask[r][c] = true;
        if r > 0 {
            queue.push_back((r - 1, c));
        }
        if c > 0 {
            queue.push_back((r, c - 1));
        }
        queue.push_back((r + 1, c));
        queue.push_back((r, c + 1));
    }
}

/// Sets the 4-connected region of cells equal to the value at `(r, c)` (and, under `sym`, the
/// regions at its mirror images, as they were before the fill) to `value`.
pub fn flood_fill(cells: &mut [Vec<f64>], r: usize, c: usize, value: f64, sym: Symmetry) {
    let mut mask: Vec<Vec<bool>> = cells.iter().map(|row| vec![false; row.len()]).collect();
    for (sr, sc) in symmetric_cells(cells.len(), r, c, sym) {
        region(cells, sr, sc, &mut mask);
    }
    for (row, m) in cells.iter_mut().zip(&mask) {
        for (v, &hit) in row.iter_mut().zip(m) {
            if hit {
                *v = value;
            }
        }
    }
}

/// Swaps open and closed: every transmittance `v` becomes `1 − v`.
pub fn invert(cells: &mut [Vec<f64>]) {
    for v in cells.iter_mut().flatten() {
        *v = 1.0 - *v;
    }
}

/// Closes every cell (transmittance 0).
pub fn clear(cells: &mut [Vec<f64>]) {
    for v in cells.iter_mut().flatten() {
        *v = 0.0;
    }
}

/// The opening grown (`steps > 0`) or shrunk (`steps < 0`) by `|steps|` cells: each step gives
/// every cell the largest (growing) or smallest (shrinking) transmittance of itself and its four
/// neighbours within the pixel (grey-scale dilation or erosion). A full-height slit 5 cells wide
/// grows to 7 and shrinks to 3; the pixel's edge is not wrapped, as the editor draws it.
pub fn grow(cells: &[Vec<f64>], steps: i32) -> Vec<Vec<f64>> {
    let mut out = cells.to_vec();
    let pick: fn(f64, f64) -> f64 = if steps > 0 { f64::max } else { f64::min };
    for _ in 0..steps.unsigned_abs() {
        let prev = out.clone();
        for (r, row) in out.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                let neighbours = [
                    r.checked_sub(1)
                        .and_then(|r| prev.get(r))
                        .and_then(|x| x.get(c)),
                    prev.get(r + 1).and_then(|x| x.get(c)),
                    c.checked_sub(1).and_then(|c| prev[r].get(c)),
                    prev[r].get(c + 1),
                ];
                *v = neighbours
                    .into_iter()
                    .flatten()
                    .fold(*v, |a, b| pick(a, *b));
            }
        }
    }
    out
}

/// Source index of target index `i` when `n_from` samples are resampled to `n_to` by nearest
/// neighbour on cell centres: `floor((i + ½)·n_from / n_to)`, in exact integer arithmetic.
fn nearest(i: usize, n_from: usize, n_to: usize) -> usize {
    ((2 * i + 1) * n_from / (2 * n_to)).min(n_from.saturating_sub(1))
}

/// The grid resampled to `new_n × new_n` cells by nearest neighbour on cell centres (the opening
/// keeps its shape in µm when the pitch is kept). Doubling and halving back is the identity, e.g.
/// 21 → 42 → 21. An empty grid resamples to all-closed cells. The caller bounds `new_n`
/// (the studio allows at most [`MAX_CELLS`]).
pub fn resample(cells: &[Vec<f64>], new_n: usize) -> Vec<Vec<f64>> {
    let n = cells.len();
    (0..new_n)
        .map(|r| {
            let src = if n == 0 {
                None
            } else {
                cells.get(nearest(r, n, new_n))
            };
            (0..new_n)
                .map(|c| match src {
                    Some(row) if !row.is_empty() => row[nearest(c, row.len(), new_n)],
                    _ => 0.0,
                })
                .collect()
        })
        .collect()
}

/// The grid as text: one line per row, `#` for open cells (transmittance ≥ 0.5) and `.` for
/// closed ones, lines separated by `\n` (no trailing newline).
pub fn to_text(cells: &[Vec<f64>]) -> String {
    cells
        .iter()
        .map(|row| {
            row.iter()
                .map(|&v| if v >= 0.5 { '#' } else { '.' })
                .collect::<String>()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Why text rows do not read as an opening grid (rows and columns counted from 1, blank lines
/// not counted).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GridTextError {
    /// Nothing but blank lines.
    #[error("no rows found: expected rows of '#' (open) and '.' (closed) cells")]
    NoRows,
    /// More rows or columns than the studio supports.
    #[error(
        "{rows} rows of {cols} cells is more than the {MAX_CELLS} cells per side the studio supports"
    )]
    TooLarge {
        /// Rows given.
        rows: usize,
        /// Cells in the first row.
        cols: usize,
    },
    /// A character that is not a cell.
    #[error(
        "row {row}, column {column}: unexpected character {found:?} \
         (use '#' or '1' for open, '.' or '0' for closed)"
    )]
    Character {
        /// Its row.
        row: usize,
        /// Its column.
        column: usize,
        /// The character.
        found: char,
    },
    /// A row of another length than the first.
    #[error("row {row} has {cells} cells, expected {expected}")]
    RowLength {
        /// The row.
        row: usize,
        /// Its cells.
        cells: usize,
        /// The first row's cells.
        expected: usize,
    },
    /// As many rows as columns are needed.
    #[error("the grid must be square: {rows} rows of {cols} cells (expected {cols} rows)")]
    NotSquare {
        /// Rows given.
        rows: usize,
        /// Cells per row.
        cols: usize,
    },
}

/// Reads a grid written as text rows: `#` or `1` open, `.` or `0` closed. Whitespace around each
/// row and blank lines are ignored. Rows are counted from 1 (blank lines not counted).
///
/// # Errors
/// [`GridTextError`]: a character that is not one of `#1.0`, rows of different lengths, a grid
/// that is not square, no rows, or more than [`MAX_CELLS`] cells per side.
pub fn from_text(text: &str) -> Result<Vec<Vec<f64>>, GridTextError> {
    let rows: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let Some(first) = rows.first() else {
        return Err(GridTextError::NoRows);
    };
    let n = first.chars().count();
    if rows.len() > MAX_CELLS || n > MAX_CELLS {
        return Err(GridTextError::TooLarge {
            rows: rows.len(),
            cols: n,
        });
    }
    let mut cells = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        let parsed = row
            .chars()
            .enumerate()
            .map(|(j, ch)| match ch {
                '#' | '1' => Ok(1.0),
                '.' | '0' => Ok(0.0),
                found => Err(GridTextError::Character {
                    row: i + 1,
                    column: j + 1,
                    found,
                }),
            })
            .collect::<Result<Vec<f64>, GridTextError>>()?;
        if parsed.len() != n {
            return Err(GridTextError::RowLength {
                row: i + 1,
                cells: parsed.len(),
                expected: n,
            });
        }
        cells.push(parsed);
    }
    if cells.len() != n {
        return Err(GridTextError::NotSquare {
            rows: cells.len(),
            cols: n,
        });
    }
    Ok(cells)
}

/// Intensity transmittance of the opening, `Σv² / count` (the fraction of open cells for a
/// binary grid); the same number the analysis reports. 0 for an empty grid.
pub fn open_fraction(cells: &[Vec<f64>]) -> f64 {
    let n: usize = cells.iter().map(Vec::len).sum();
    if n == 0 {
        return 0.0;
    }
    cells.iter().flatten().map(|v| v * v).sum::<f64>() / n as f64
}

/// Bounding box `(r0, c0, r1, c1)` (inclusive) of the cells that transmit any light
/// (transmittance > 0), or `None` when every cell is closed.
pub fn open_extent(cells: &[Vec<f64>]) -> Option<(usize, usize, usize, usize)> {
    let mut extent: Option<(usize, usize, usize, usize)> = None;
    for (r, row) in cells.iter().enumerate() {
        for (c, &v) in row.iter().enumerate() {
            if v > 0.0 {
                extent = Some(match extent {
                    None => (r, c, r, c),
                    Some((r0, c0, r1, c1)) => (r0.min(r), c0.min(c), r1.max(r), c1.max(c)),
                });
            }
        }
    }
    extent
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> Vec<Vec<f64>> {
        vec![vec![0.0; n]; n]
    }

    fn count(cells: &[Vec<f64>]) -> usize {
        cells.iter().flatten().filter(|&&v| v == 1.0).count()
    }

    fn is_set(cells: &[Vec<f64>], r: usize, c: usize) -> bool {
        cells[r][c] == 1.0
    }

    #[test]
    fn symmetric_cells_mirror_and_dedupe() {
        assert_eq!(symmetric_cells(5, 1, 0, Symmetry::None), vec![(1, 0)]);
        assert_eq!(
            symmetric_cells(5, 1, 0, Symmetry::MirrorX),
            vec![(1, 0), (1, 4)]
        );
        assert_eq!(
            symmetric_cells(5, 1, 0, Symmetry::MirrorY),
            vec![(1, 0), (3, 0)]
        );
        assert_eq!(
            symmetric_cells(5, 1, 0, Symmetry::FourFold),
            vec![(1, 0), (1, 4), (3, 0), (3, 4)]
        );
        // The centre of an odd grid is its own image.
        assert_eq!(symmetric_cells(5, 2, 2, Symmetry::FourFold), vec![(2, 2)]);
        assert_eq!(
            symmetric_cells(5, 2, 0, Symmetry::FourFold),
            vec![(2, 0), (2, 4)]
        );
        assert!(symmetric_cells(5, 5, 0, Symmetry::None).is_empty());
    }

    #[test]
    fn paint_brush_is_centred_and_clipped() {
        let mut g = grid(7);
        paint(&mut g, 3, 3, 3, 1.0, Symmetry::None);
        assert_eq!(count(&g), 9);
        assert!(is_set(&g, 2, 2) && is_set(&g, 4, 4) && !is_set(&g, 1, 3));
        let mut g = grid(7);
        paint(&mut g, 0, 0, 3, 1.0, Symmetry::None);
        assert_eq!(count(&g), 4);
        let mut g = grid(7);
        paint(&mut g, 6, 6, 0, 1.0, Symmetry::None);
        assert_eq!(count(&g), 1);
        assert!(is_set(&g, 6, 6));
        // An even brush extends towards higher indices.
        let mut g = grid(7);
        paint(&mut g, 3, 3, 2, 1.0, Symmetry::None);
        assert!(is_set(&g, 3, 3) && is_set(&g, 4, 4) && !is_set(&g, 2, 2));
        assert_eq!(count(&g), 4);
    }

    #[test]
    fn paint_with_mirror_x_sets_the_mirror_column() {
        let mut g = grid(6);
        paint(&mut g, 1, 0, 1, 1.0, Symmetry::MirrorX);
        assert!(is_set(&g, 1, 0) && is_set(&g, 1, 5));
        assert_eq!(count(&g), 2);
    }

    #[test]
    fn line_is_bresenham_with_both_ends() {
        // One cell per column, ties (r = ½, 3⁄2) rounded up; no gaps between steps.
        assert_eq!(
            line_cells((0, 0), (2, 4)),
            vec![(0, 0), (1, 1), (1, 2), (2, 3), (2, 4)]
        );
        assert_eq!(
            line_cells((5, 1), (0, 3)),
            vec![(5, 1), (4, 1), (3, 2), (2, 2), (1, 3), (0, 3)]
        );
        for w in line_cells((7, 0), (1, 11)).windows(2) {
            let (a, b) = (w[0], w[1]);
            assert!(a.0.abs_diff(b.0) <= 1 && a.1.abs_diff(b.1) <= 1 && a != b);
        }
        assert_eq!(line_cells((3, 3), (3, 3)), vec![(3, 3)]);
        assert_eq!(line_cells((4, 0), (0, 0)).len(), 5);
        let mut g = grid(9);
        line(&mut g, (0, 0), (8, 8), 1, 1.0, Symmetry::None);
        assert_eq!(count(&g), 9);
        assert!((0..9).all(|i| is_set(&g, i, i)));
    }

    #[test]
    fn rect_accepts_corners_in_any_order() {
        let mut g = grid(8);
        rect(&mut g, (5, 6), (2, 1), 1.0, Symmetry::None);
        assert_eq!(count(&g), 4 * 6);
        assert!(is_set(&g, 2, 1) && is_set(&g, 5, 6) && !is_set(&g, 1, 1));
        let mut g = grid(4);
        rect(&mut g, (2, 2), (9, 9), 1.0, Symmetry::None);
        assert_eq!(count(&g), 4);
    }

    #[test]
    fn ellipse_counts_cell_centres_inside() {
        let cases = [
            ((0, 0), (0, 0), 1),
            ((0, 0), (1, 1), 4),
            ((0, 0), (4, 4), 21),
        ];
        for (a, b, want) in cases {
            let mut g = grid(9);
            ellipse(&mut g, a, b, 1.0, Symmetry::None);
            assert_eq!(count(&g), want, "{a:?}..{b:?}");
        }
        let mut g = grid(9);
        ellipse(&mut g, (4, 0), (4, 8), 1.0, Symmetry::None);
        assert_eq!(count(&g), 9);
    }

    #[test]
    fn flood_fill_stays_inside_walls() {
        let mut g = from_text("..#..\n..#..\n..#..\n..#..\n..#..").unwrap_or_default();
        flood_fill(&mut g, 0, 0, 1.0, Symmetry::None);
        assert_eq!(to_text(&g), "###..\n###..\n###..\n###..\n###..");
        // Filling with the value already there changes nothing and terminates.
        flood_fill(&mut g, 0, 0, 1.0, Symmetry::None);
        assert_eq!(count(&g), 15);
        // Mirror x also fills the region on the other side.
        let mut g = from_text(".#.#.\n.#.#.\n.#.#.\n.#.#.\n.#.#.").unwrap_or_default();
        flood_fill(&mut g, 0, 0, 1.0, Symmetry::MirrorX);
        assert_eq!(to_text(&g), "##.##\n##.##\n##.##\n##.##\n##.##");
    }

    #[test]
    fn invert_and_clear() {
        let mut g = vec![vec![0.0, 0.25], vec![1.0, 0.5]];
        invert(&mut g);
        assert_eq!(g, vec![vec![1.0, 0.75], vec![0.0, 0.5]]);
        clear(&mut g);
        assert_eq!(g, grid(2));
    }

    #[test]
    fn resample_nearest_on_centres() {
        let g = from_text("#..\n.#.\n..#").unwrap_or_default();
        let big = resample(&g, 6);
        assert_eq!(big[0][..2], [1.0, 1.0]);
        assert_eq!(big[1][..3], [1.0, 1.0, 0.0]);
        assert_eq!(big[5][5], 1.0);
        assert_eq!(resample(&big, 3), g);
        assert_eq!(resample(&g, 1), vec![vec![1.0]]);
        assert_eq!(resample(&[], 2), grid(2));
    }

    #[test]
    fn text_round_trip_and_errors() {
        let g = vec![vec![1.0, 0.0], vec![0.2, 0.7]];
        assert_eq!(to_text(&g), "#.\n.#");
        assert_eq!(
            from_text("  \n 10 \r\n\n .# \n").unwrap_or_default(),
            vec![vec![1.0, 0.0], vec![0.0, 1.0]]
        );
        assert_eq!(
            from_text("##\n#").map_err(|e| e.to_string()),
            Err("row 2 has 1 cells, expected 2".to_string())
        );
        assert!(from_text("#x\n##").is_err_and(|e| e.to_string().contains("row 1, column 2")));
        assert!(from_text("##\n##\n##").is_err_and(|e| e.to_string().contains("square")));
        assert!(from_text(" \n\n").is_err_and(|e| e.to_string().contains("no rows")));
        let huge = vec!["#".repeat(MAX_CELLS + 1); MAX_CELLS + 1].join("\n");
        assert!(from_text(&huge).is_err_and(|e| e.to_string().contains("512")));
    }

    #[test]
    fn open_fraction_and_extent() {
        let g = from_text(".....\n.##..\n.#...\n.....\n.....").unwrap_or_default();
        assert!((open_fraction(&g) - 3.0 / 25.0).abs() < 1e-12);
        assert_eq!(open_extent(&g), Some((1, 1, 2, 2)));
        assert_eq!(open_extent(&grid(3)), None);
        assert_eq!(open_fraction(&[]), 0.0);
    }

    #[test]
    fn a_slit_grows_and_shrinks_a_cell_a_side_per_step() {
        let n = 21;
        let slit: Vec<Vec<f64>> = (0..n)
            .map(|_| (0..n).map(|c| f64::from((8..13).contains(&c))).collect())
            .collect();
        let width = |g: &[Vec<f64>]| g[10].iter().filter(|v| **v > 0.5).count();
        assert_eq!(width(&grow(&slit, 1)), 7);
        assert_eq!(width(&grow(&slit, -2)), 1);
        assert_eq!(grow(&slit, 0), slit);
        assert!((open_fraction(&grow(&slit, -1)) - 3.0 / 21.0).abs() < 1e-12);
        // Shrinking past nothing leaves nothing; growing past everything opens every cell.
        assert_eq!(open_fraction(&grow(&slit, -3)), 0.0);
        assert_eq!(open_fraction(&grow(&slit, 10)), 1.0);
    }
}
