//! Tile orientations: the dihedral group D4 acting on an `N×N` pattern, and the seeded choice of
//! an orientation for every tile of a random tiling.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::design::TilingMode;

/// An element of D4 in canonical form: `flipud^flip_ud ∘ fliplr^flip_lr ∘ transpose^transpose`
/// (transpose first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct D4 {
    /// Transpose the pattern (applied first).
    pub transpose: bool,
    /// Then flip left-right (mirror the columns).
    pub flip_lr: bool,
    /// Then flip up-down (mirror the rows).
    pub flip_ud: bool,
}

impl D4 {
    /// The identity: the pattern as drawn.
    pub const IDENTITY: D4 = D4 {
        transpose: false,
        flip_lr: false,
        flip_ud: false,
    };

    /// All 8 elements.
    pub fn all() -> [D4; 8] {
        let mut out = [D4::IDENTITY; 8];
        for (i, e) in out.iter_mut().enumerate() {
            *e = D4 {
                transpose: i & 1 != 0,
                flip_lr: i & 2 != 0,
                flip_ud: i & 4 != 0,
            };
        }
        out
    }

    /// The result of the thesis's three coins: rotate 90° counter-clockwise (`rot90(P)` =
    /// `flipud(Pᵀ)`), then flip left-right, then flip up-down.
    pub fn from_coins(rotate_ccw: bool, flip_lr: bool, flip_ud: bool) -> D4 {
        D4 {
            transpose: rotate_ccw,
            flip_lr,
            flip_ud: rotate_ccw ^ flip_ud,
        }
    }

    /// The random-4 set {P, Pᵀ, fliplr P, flipud Pᵀ}, indexed 0..4.
    pub fn random4(index: u8) -> D4 {
        match index & 3 {
            0 => D4::IDENTITY,
            1 => D4 {
                transpose: true,
                ..D4::IDENTITY
            },
            2 => D4 {
                flip_lr: true,
                ..D4::IDENTITY
            },
            _ => D4 {
                transpose: true,
                flip_ud: true,
                flip_lr: false,
            },
        }
    }

    /// Source cell `(row, col)` of the original pattern that lands at `(row, col)` of the
    /// transformed `n×n` pattern.
    #[inline]
    pub fn source(self, row: usize, col: usize, n: usize) -> (usize, usize) {
        let r = if self.flip_ud { n - 1 - row } else { row };
        let c = if self.flip_lr { n - 1 - col } else { col };
        if self.transpose { (c, r) } else { (r, c) }
    }

    /// Applies the element to a square pattern.
    pub fn apply<T: Copy>(self, pattern: &[Vec<T>]) -> Vec<Vec<T>> {
        let n = pattern.len();
        (0..n)
            .map(|r| {
                (0..n)
                    .map(|c| {
                        let (sr, sc) = self.source(r, c, n);
                        pattern[sr][sc]
                    })
                    .collect()
            })
            .collect()
    }

    /// The frequency index that `|FT|²` of the transformed pattern reads from `|FT|²` of the
    /// original: flips negate a frequency axis, the transpose swaps them. Indices are signed
    /// offsets from DC, `(fy, fx)`.
    #[inline]
    pub fn source_frequency(self, fy: i64, fx: i64) -> (i64, i64) {
        let fy = if self.flip_ud { -fy } else { fy };
        let fx = if self.flip_lr { -fx } else { fx };
        if self.transpose { (fx, fy) } else { (fy, fx) }
    }
}

/// The orientations a tiling mode draws from, each equally likely.
pub fn orbit(mode: TilingMode) -> Vec<D4> {
    match mode {
        TilingMode::Repeat => vec![D4::IDENTITY],
        TilingMode::RandomD4 => D4::all().to_vec(),
        TilingMode::Random4 => (0..4).map(D4::random4).collect(),
    }
}

/// Interleaves a signed tile index pair into one stream number (zig-zag, then bit interleave is
/// unnecessary: 32 bits each is plenty for any display).
fn stream_key(tile_x: i64, tile_y: i64) -> u64 {
    let zz = |v: i64| ((v << 1) ^ (v >> 63)) as u64 & 0xFFFF_FFFF;
    (zz(tile_y) << 32) | zz(tile_x)
}

/// The orientation of tile `(tile_x, tile_y)` (tile `(0, 0)` holds the optical axis).
/// Depends only on `(mode, seed, tile_x, tile_y)`, never on the grid size, so every channel and
/// every quality level sees the same display.
pub fn tile_orientation(mode: TilingMode, seed: u64, tile_x: i64, tile_y: i64) -> D4 {
    match mode {
        TilingMode::Repeat => D4::IDENTITY,
        TilingMode::RandomD4 | TilingMode::Random4 => {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(stream_key(tile_x, tile_y));
            let bits: u32 = rng.random();
            if mode == TilingMode::RandomD4 {
                D4::from_coins(bits & 1 != 0, bits & 2 != 0, bits & 4 != 0)
            } else {
                D4::random4((bits & 3) as u8)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<Vec<u8>> {
        vec![vec![1, 2, 3], vec![4, 5, 6], vec![7, 8, 9]]
    }

    #[test]
    fn d4_has_eight_distinct_elements_on_an_asymmetric_pattern() {
        let p = sample();
        let mut seen: Vec<Vec<Vec<u8>>> = D4::all().iter().map(|g| g.apply(&p)).collect();
        seen.sort();
        seen.dedup();
        assert_eq!(seen.len(), 8);
    }

    #[test]
    fn coins_match_matlab_rot90_then_flips() {
        let p = sample();
        // rot90 counter-clockwise of [[1,2,3],[4,5,6],[7,8,9]] is [[3,6,9],[2,5,8],[1,4,7]].
        assert_eq!(
            D4::from_coins(true, false, false).apply(&p),
            vec![vec![3, 6, 9], vec![2, 5, 8], vec![1, 4, 7]]
        );
        // then fliplr
        assert_eq!(
            D4::from_coins(true, true, false).apply(&p),
            vec![vec![9, 6, 3], vec![8, 5, 2], vec![7, 4, 1]]
        );
        assert_eq!(
            D4::random4(3).apply(&p),
            vec![vec![3, 6, 9], vec![2, 5, 8], vec![1, 4, 7]],
            "flipud(Pᵀ) is the counter-clockwise rotation"
        );
    }

    #[test]
    fn orientations_are_reproducible_and_balanced() {
        let mut counts = std::collections::HashMap::new();
        for ty in -20..20 {
            for tx in -20..20 {
                let g = tile_orientation(TilingMode::RandomD4, 7, tx, ty);
                assert_eq!(g, tile_orientation(TilingMode::RandomD4, 7, tx, ty));
                *counts.entry(g).or_insert(0usize) += 1;
            }
        }
        assert_eq!(counts.len(), 8);
        // 1600 draws over 8 bins: each near 200 (binomial sd ≈ 13).
        assert!(
            counts.values().all(|&c| (140..260).contains(&c)),
            "{counts:?}"
        );
        let other: usize = (-20..20)
            .filter(|&t| {
                tile_orientation(TilingMode::RandomD4, 8, t, 0)
                    != tile_orientation(TilingMode::RandomD4, 7, t, 0)
            })
            .count();
        assert!(other > 20, "a different seed must give a different layout");
    }

    #[test]
    fn frequency_map_matches_pattern_map() {
        // |FT(g P)|²(f) = |FT(P)|²(source_frequency(f)) — checked on a 3×3 DFT.
        let p: Vec<Vec<f64>> = vec![
            vec![1.0, 0.0, 0.3],
            vec![0.2, 0.7, 0.0],
            vec![0.0, 0.9, 0.4],
        ];
        let dft2 = |q: &Vec<Vec<f64>>, fy: i64, fx: i64| {
            let n = q.len() as f64;
            let (mut re, mut im) = (0.0, 0.0);
            for (r, row) in q.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    let ph =
                        -2.0 * std::f64::consts::PI * (fy as f64 * r as f64 + fx as f64 * c as f64)
                            / n;
                    re += v * ph.cos();
                    im += v * ph.sin();
                }
            }
            re * re + im * im
        };
        for g in D4::all() {
            let gp = g.apply(&p);
            for fy in -1..=1 {
                for fx in -1..=1 {
                    let (sy, sx) = g.source_frequency(fy, fx);
                    assert!((dft2(&gp, fy, fx) - dft2(&p, sy, sx)).abs() < 1e-12);
                }
            }
        }
    }
}
