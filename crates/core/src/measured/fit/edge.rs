//! The opening with its edges moved out or in by a bias: an over- or under-etched prototype,
//! whose open fraction differs from the drawing while its shape stays.
//!
//! The opening is refined to about 256 cells a side, made binary (cells ≥ 0.5 open) and given
//! the signed distance of every cell centre to the nearest edge (positive inside, in cells).
//! A bias of `b` cells then gives each cell the transmittance `clamp(0.5 + d + b, 0, 1)`: the
//! drawing itself at `b = 0`, and a transmittance that moves smoothly with `b`, so the fit has
//! a derivative to follow. The tile's border is not an edge (an opening that runs into the next
//! tile keeps running), and the bias stops there.

/// The refined opening and its signed distances.
#[derive(Debug, Clone)]
pub struct EdgeField {
    /// Cells a side of the refined grid.
    n: usize,
    /// How many refined cells one drawn cell spans.
    refine: usize,
    /// Signed distance of each refined cell to the edge, cells, row-major.
    distance: Vec<f64>,
}

/// Above this many cells a side the opening is used as drawn.
const REFINED_CELLS: usize = 256;

impl EdgeField {
    /// The field of a drawn opening (`N×N` cells, row 0 at the top).
    pub fn new(cells: &[Vec<f64>]) -> Self {
        let drawn = cells.len().max(1);
        let refine = (REFINED_CELLS / drawn).max(1);
        let n = drawn * refine;
        let open: Vec<bool> = (0..n * n)
            .map(|k| {
                let (r, c) = (k / n / refine, k % n / refine);
                cells
                    .get(r)
                    .and_then(|row| row.get(c))
                    .is_some_and(|v| *v >= 0.5)
            })
            .collect();
        // The distance to the nearest cell of the other kind, less half a cell: the edge runs
        // between the two centres.
        let to_open = squared_distances(&open, n, true);
        let to_closed = squared_distances(&open, n, false);
        let distance = open
            .iter()
            .zip(to_open.iter().zip(&to_closed))
            .map(|(&o, (&d_open, &d_closed))| {
                if o {
                    d_closed.sqrt() - 0.5
                } else {
                    0.5 - d_open.sqrt()
                }
            })
            .collect();
        EdgeField {
            n,
            refine,
            distance,
        }
    }

    /// Cells a side of the refined grid.
    pub fn n(&self) -> usize {
        self.n
    }

    /// How many refined cells one drawn cell spans (the axis's registration scales by it).
    pub fn refine(&self) -> usize {
        self.refine
    }

    /// The refined opening with its edges moved out by `bias_cells` (in by a negative bias).
    pub fn cells(&self, bias_cells: f64) -> Vec<Vec<f64>> {
        self.distance
            .chunks(self.n)
            .map(|row| {
                row.iter()
                    .map(|d| (0.5 + d + bias_cells).clamp(0.0, 1.0))
                    .collect()
            })
            .collect()
    }

    /// The open fraction (the mean intensity transmittance) at `bias_cells`.
    pub fn open_fraction(&self, bias_cells: f64) -> f64 {
        self.distance
            .iter()
            .map(|d| (0.5 + d + bias_cells).clamp(0.0, 1.0).powi(2))
            .sum::<f64>()
            / self.distance.len().max(1) as f64
    }
}

/// The squared distance (cells) from each cell of the `n × n` grid to the nearest cell whose
/// state is `target`; `f64::MAX / 4` where there is none. Two passes of the exact 1-D squared
/// distance transform (Felzenszwalb and Huttenlocher), rows then columns.
fn squared_distances(open: &[bool], n: usize, target: bool) -> Vec<f64> {
    let far = f64::MAX / 4.0;
    let mut grid: Vec<f64> = open
        .iter()
        .map(|&o| if o == target { 0.0 } else { far })
        .collect();
    let mut line = vec![0.0; n];
    let mut out = vec![0.0; n];
    for r in 0..n {
        line.copy_from_slice(&grid[r * n..(r + 1) * n]);
        transform_1d(&line, &mut out);
        grid[r * n..(r + 1) * n].copy_from_slice(&out);
    }
    for c in 0..n {
        for r in 0..n {
            line[r] = grid[r * n + c];
        }
        transform_1d(&line, &mut out);
        for r in 0..n {
            grid[r * n + c] = out[r];
        }
    }
    grid
}

/// `out[q] = min_p (q − p)² + f[p]`: the lower envelope of the parabolas rooted at each `p`.
fn transform_1d(f: &[f64], out: &mut [f64]) {
    let n = f.len();
    let far = f64::MAX / 4.0;
    // Only the finite samples root a parabola.
    let roots: Vec<usize> = (0..n).filter(|&p| f[p] < far).collect();
    if roots.is_empty() {
        out.fill(far);
        return;
    }
    let mut v: Vec<usize> = Vec::with_capacity(roots.len());
    let mut z: Vec<f64> = Vec::with_capacity(roots.len() + 1);
    let cross = |p: usize, q: usize| {
        ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q as f64 - p as f64))
    };
    for &q in &roots {
        while let Some(&p) = v.last() {
            let s = cross(p, q);
            if z.last().is_some_and(|&zl| s <= zl) {
                v.pop();
                z.pop();
            } else {
                z.push(s);
                break;
            }
        }
        if v.is_empty() {
            z.clear();
        }
        v.push(q);
    }
    // `z[k]` is where parabola `v[k + 1]` takes over from `v[k]`.
    let mut k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while k < z.len() && z[k] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *o = (q as f64 - p as f64).powi(2) + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(open: &[bool], n: usize, target: bool) -> Vec<f64> {
        (0..n * n)
            .map(|k| {
                (0..n * n)
                    .filter(|&j| open[j] == target)
                    .map(|j| {
                        let (dy, dx) = (
                            (k / n) as f64 - (j / n) as f64,
                            (k % n) as f64 - (j % n) as f64,
                        );
                        dy * dy + dx * dx
                    })
                    .fold(f64::MAX / 4.0, f64::min)
            })
            .collect()
    }

    #[test]
    fn the_transform_equals_the_brute_force_distances() {
        let n = 13;
        let mut state = 7u64;
        let open: Vec<bool> = (0..n * n)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1);
                state >> 61 == 0
            })
            .collect();
        for target in [true, false] {
            assert_eq!(squared_distances(&open, n, target), brute(&open, n, target));
        }
    }

    #[test]
    fn no_bias_gives_the_drawing_and_a_bias_moves_a_square_opening_edges() {
        // An 8×8 opening in a 32×32 tile, refined 8×: 64 cells open a side of 256.
        let drawn: Vec<Vec<f64>> = (0..32)
            .map(|r| {
                (0..32)
                    .map(|c| f64::from(u8::from((12..20).contains(&r) && (12..20).contains(&c))))
                    .collect()
            })
            .collect();
        let field = EdgeField::new(&drawn);
        assert_eq!((field.n(), field.refine()), (256, 8));
        let open0 = field.open_fraction(0.0);
        assert!((open0 - 64.0 / 1024.0).abs() < 1e-12, "{open0}");
        // Out by 2 refined cells on every side: (64 + 4)² of 256², less the corners' rounding
        // (at most the 2×2 corner squares).
        let grown = field.open_fraction(2.0) * 65536.0;
        assert!(
            (68.0 * 68.0 - 16.0..=68.0 * 68.0).contains(&grown),
            "{grown}"
        );
        let shrunk = field.open_fraction(-2.0) * 65536.0;
        assert!((shrunk - 60.0 * 60.0).abs() < 1e-9, "{shrunk}");
        // Smooth and rising in between.
        let mut last = field.open_fraction(-3.0);
        for k in -29..30 {
            let f = field.open_fraction(f64::from(k) / 10.0);
            assert!(f > last, "not rising at {k}");
            last = f;
        }
    }

    #[test]
    fn the_tile_border_is_not_an_edge() {
        // A slit running from the top of the tile to the bottom widens, but does not grow in rows.
        let drawn: Vec<Vec<f64>> = (0..16)
            .map(|_| {
                (0..16)
                    .map(|c| f64::from(u8::from((6..10).contains(&c))))
                    .collect()
            })
            .collect();
        let field = EdgeField::new(&drawn);
        let cells = field.cells(3.0);
        let n = field.n();
        let open_cols = |r: usize| cells[r].iter().filter(|v| **v > 0.99).count();
        assert_eq!(open_cols(0), open_cols(n / 2));
        assert_eq!(open_cols(0), 4 * field.refine() + 6);
    }
}
