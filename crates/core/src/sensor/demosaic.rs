//! Demosaicing an RGGB mosaic to three colour planes: Malvar, He and Cutler's gradient-corrected
//! linear interpolation (H. S. Malvar, L. He, R. Cutler, "High-quality linear interpolation for
//! demosaicing of Bayer-patterned color images", ICASSP 2004).
//!
//! Each missing colour is the bilinear interpolation of its nearest sites plus a gain times the
//! discrete Laplacian of the colour that *is* measured at the site (the paper's gains α = 1/2,
//! β = 5/8, γ = 3/4), i.e. four 5×5 kernels with coefficients in eighths:
//!
//! | at | estimates | kernel (centre, then by offset) |
//! |---|---|---|
//! | R or B | G | `4`; `±1` in x or y: `2`; `±2` in x or y: `−1` |
//! | G, same-colour neighbours left/right | R or B | `5`; `±1` in x: `4`; `±2` in x: `−1`; diagonals: `−1`; `±2` in y: `½` |
//! | G, same-colour neighbours above/below | R or B | the transpose |
//! | B or R | R or B | `6`; diagonals: `2`; `±2` in x or y: `−3/2` |
//!
//! Every kernel sums to one per colour it reads, so a flat field of any colour comes back
//! exactly, and its correction term vanishes on linear ramps, which come back exactly away from
//! the edges. At the image edge the mosaic is mirrored without repeating the edge site
//! (`−1 → 1`, `−2 → 2`): an offset of one or two keeps its parity, so every tap still reads a
//! site of the colour the kernel expects (padding by repetition would not). Values are `f64`;
//! the result is not clipped (overshoots at edges can be negative; the tone curve clips).
//!
//! The correction assumes the colours share their detail (as they mostly do in natural
//! images); where channels vary independently it is bilinear-accurate only (the tests measure
//! 1 % of the swing on independent smooth blobs, 2.5 % at the edge).
//!
//! Why not a crate: the `demosaic` crate (crates.io) implements the same kernels, but on `f32`
//! and with the edge sites repeated, which feeds the wrong colour into the kernels near the
//! border; the test suite uses it as an independent check of the interior.

use ndarray::{Array2, Axis};
use rayon::prelude::*;

use super::cfa::rggb_channel;
use crate::Sample;

/// A kernel: `(dy, dx, weight)` taps, weights in eighths.
type Kernel = &'static [(isize, isize, f64)];

/// G at an R or B site.
const G_AT_RB: Kernel = &[
    (0, 0, 4.0),
    (-1, 0, 2.0),
    (1, 0, 2.0),
    (0, -1, 2.0),
    (0, 1, 2.0),
    (-2, 0, -1.0),
    (2, 0, -1.0),
    (0, -2, -1.0),
    (0, 2, -1.0),
];

/// R (or B) at a G site whose row holds R (or B): neighbours left and right.
const ALONG_ROW: Kernel = &[
    (0, 0, 5.0),
    (0, -1, 4.0),
    (0, 1, 4.0),
    (0, -2, -1.0),
    (0, 2, -1.0),
    (-1, -1, -1.0),
    (-1, 1, -1.0),
    (1, -1, -1.0),
    (1, 1, -1.0),
    (-2, 0, 0.5),
    (2, 0, 0.5),
];

/// R (or B) at a G site whose column holds R (or B): neighbours above and below.
const ALONG_COLUMN: Kernel = &[
    (0, 0, 5.0),
    (-1, 0, 4.0),
    (1, 0, 4.0),
    (-2, 0, -1.0),
    (2, 0, -1.0),
    (-1, -1, -1.0),
    (-1, 1, -1.0),
    (1, -1, -1.0),
    (1, 1, -1.0),
    (0, -2, 0.5),
    (0, 2, 0.5),
];

/// R at a B site, or B at an R site: the four diagonal neighbours.
const DIAGONAL: Kernel = &[
    (0, 0, 6.0),
    (-1, -1, 2.0),
    (-1, 1, 2.0),
    (1, -1, 2.0),
    (1, 1, 2.0),
    (-2, 0, -1.5),
    (2, 0, -1.5),
    (0, -2, -1.5),
    (0, 2, -1.5),
];

/// `i + d` mirrored into `0..n` without repeating the edge sample (keeps parity for `|d| ≤ 2`
/// when `n ≥ 3`; clamped for the tinier images that cannot be mirrored).
fn mirror(i: usize, d: isize, n: usize) -> usize {
    let last = n as isize - 1;
    let mut j = i as isize + d;
    if j < 0 {
        j = -j;
    }
    if j > last {
        j = 2 * last - j;
    }
    j.clamp(0, last.max(0)) as usize
}

/// Demosaics an RGGB mosaic ([`super::cfa::rggb_channel`]) into R, G and B planes of its size
/// by Malvar–He–Cutler (see the module docs), in the mosaic's sample type (sums in `f64`). Rows
/// are computed in parallel.
pub fn demosaic_rggb<T: Sample>(mosaic: &Array2<T>) -> [Array2<T>; 3] {
    demosaic_rggb_to(mosaic)
}

/// [`demosaic_rggb`] into planes of sample type `U`, whatever the mosaic's: each site's own
/// sample is stored as the nearest `U`, so the mosaic read back from the planes
/// ([`super::cfa::mosaic_of`]) is the mosaic in `U`.
pub fn demosaic_rggb_to<T: Sample, U: Sample>(mosaic: &Array2<T>) -> [Array2<U>; 3] {
    let (h, w) = mosaic.dim();
    let standard = mosaic.as_standard_layout();
    let m = standard.as_slice().unwrap_or_default();
    let mut out: [Array2<U>; 3] = std::array::from_fn(|_| Array2::default((h, w)));
    let [r, g, b] = &mut out;
    r.axis_iter_mut(Axis(0))
        .into_par_iter()
        .zip(g.axis_iter_mut(Axis(0)).into_par_iter())
        .zip(b.axis_iter_mut(Axis(0)).into_par_iter())
        .enumerate()
        .for_each(|(y, ((mut r_row, mut g_row), mut b_row))| {
            // Two sites from every edge no tap needs the mirror: index directly.
            let inner_row = (2..h.saturating_sub(2)).contains(&y);
            let apply = |x: usize, k: Kernel| -> U {
                let sum: f64 = if inner_row && (2..w.saturating_sub(2)).contains(&x) {
                    k.iter()
                        .map(|(dy, dx, wt)| {
                            let v: f64 = m
                                [(y as isize + dy) as usize * w + (x as isize + dx) as usize]
                                .into();
                            wt * v
                        })
                        .sum()
                } else {
                    k.iter()
                        .map(|(dy, dx, wt)| {
                            let v: f64 = m[mirror(y, *dy, h) * w + mirror(x, *dx, w)].into();
                            wt * v
                        })
                        .sum()
                };
                U::from_f64(sum / 8.0)
            };
            for x in 0..w {
                let own = U::from_f64(m[y * w + x].into());
                let (rv, gv, bv) = match rggb_channel(y, x) {
                    0 => (own, apply(x, G_AT_RB), apply(x, DIAGONAL)),
                    2 => (apply(x, DIAGONAL), apply(x, G_AT_RB), own),
                    // Green on a red row (even y): red left and right, blue above and below.
                    _ if y % 2 == 0 => (apply(x, ALONG_ROW), own, apply(x, ALONG_COLUMN)),
                    _ => (apply(x, ALONG_COLUMN), own, apply(x, ALONG_ROW)),
                };
                r_row[x] = rv;
                g_row[x] = gv;
                b_row[x] = bv;
            }
        });
    out
}
