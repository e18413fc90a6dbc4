//! The pruned PSF route: `|DFT_M(a)|²` only where the sensor window and the aliasing measure
//! read it, with the same numbers as the full route ([`crate::psf::fft::binned_intensity`]).
//!
//! 1. Spectra of the field's nonzero rows (real FFTs of length `M`, or two rows per complex zoom
//!    when cheaper), keeping only the columns `kx` the window reads (`0 … kw`, negative columns
//!    by `|A(ky, −kx)| = |A(−ky, kx)|`) and the edge band `kx ≥ e = ⌈0.45 M⌉`.
//! 2. Per window column, a [`Zoom`] straight onto the window rows (chirp-z, a matrix DFT or a
//!    slice of a full FFT, whichever the operation count says is cheapest); only the window's
//!    samples are binned.
//! 3. The aliasing measure `edge = Σ |A|²` over the band `|kx| ≥ e or |ky| ≥ e`, exactly, by
//!    inclusion–exclusion: columns in the band by Parseval along `y` (`M Σ_y |R(y, kx)|²`),
//!    rows in the band by Parseval along `x` from zooms of the field's columns onto the band
//!    rows, minus the corner (band columns zoomed onto band rows). The total is `M² Σ|a|²`.
//!
//! Memory: the kept row spectra (`rows × (kw + band)` complex) instead of two `rows × M/2`
//! copies, and no `M`-long column per window column.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::SimError;
use crate::display::aperture::Field;
use crate::progress::Progress;
use crate::psf::fft::{Binned, check_grid};
use crate::psf::pruned_grid::Geometry;
use crate::psf::pruned_rows::{kept_row_spectra, row_pass_ops};
use crate::psf::sampling::Binning;
use crate::psf::zoom::{Zoom, ZoomKind, best_ops, cached, cheapest};

/// Columns gathered together from the row-major spectra (cache-friendly transposition).
const BLOCK: usize = 16;

/// Modelled cost of the pruned route (complex multiply-adds; the model is in the route module).
pub fn pruned_ops(field: &Field, m: usize, binning: &Binning) -> f64 {
    let g = Geometry::new(field, m, binning);
    let rows = row_pass_ops(field, &g);
    let window = (g.kw + 1) as f64 * best_ops(m, g.n_rows, g.window_zoom_len());
    let band_ops = best_ops(m, g.n_rows, g.band_len());
    let band_cols = g.kept.iter().filter(|&&k| k as i64 >= g.e).count();
    let corner = band_cols as f64 * band_ops;
    let rowband = g.n_cols.div_ceil(2) as f64 * band_ops;
    let copies = (g.n_rows * g.kept.len()) as f64 * 2.0;
    let wf = (g.x_range.1 - g.x_range.0 + 1).max(0) * (g.y_range.1 - g.y_range.0 + 1).max(0);
    rows + window + corner + rowband + copies + 2.0 * wf as f64
}

/// The zoom kinds the pruned route would run: onto the window rows, and onto the band rows.
pub fn zoom_kinds(field: &Field, m: usize, binning: &Binning) -> (ZoomKind, ZoomKind) {
    let g = Geometry::new(field, m, binning);
    (
        cheapest(m, g.n_rows, g.window_zoom_len()),
        cheapest(m, g.n_rows, g.band_len()),
    )
}

/// Per-chunk partial sums, merged in chunk order (deterministic whatever the scheduling).
struct Partial {
    /// Column-major `[jx][jy]` sensor sums.
    acc: Vec<f64>,
    /// `Σ |A|²` over band columns.
    band_cols: f64,
    /// `Σ |A|²` over band columns ∩ band rows.
    corner: f64,
}

/// `|DFT_M(a)|²` integrated over the window of `binning`, by the pruned route.
///
/// # Errors
/// [`SimError::Sampling`] if the field does not fit the grid; [`SimError::Cancelled`].
pub fn binned_pruned(
    field: &Field,
    m: usize,
    binning: &Binning,
    progress: &Progress,
) -> Result<Binned, SimError> {
    check_grid(field, m)?;
    progress.check()?;
    let g = Geometry::new(field, m, binning);
    let w = binning.window_px;
    let spectra = kept_row_spectra(field, &g);
    progress.check()?;
    let window_zoom = cached(m, g.iy0, g.n_rows, g.r_lo, g.window_zoom_len());
    let band_zoom = cached(m, g.iy0, g.n_rows, g.e, g.band_len());
    let runs = row_runs(&g, binning);
    let nk = g.kept.len();
    let chunk = nk.div_ceil(8).max(BLOCK);
    let starts: Vec<usize> = (0..nk).step_by(chunk).collect();
    let partials: Vec<Partial> = starts
        .par_iter()
        .map(|&first| {
            let mut p = Partial {
                acc: vec![0.0; w * w],
                band_cols: 0.0,
                corner: 0.0,
            };
            let mut col = vec![Complex64::new(0.0, 0.0); g.n_rows * BLOCK];
            let mut out = vec![Complex64::new(0.0, 0.0); g.window_zoom_len().max(g.band_len())];
            let mut inten = vec![0.0f64; g.window_zoom_len()];
            let (mut ws, mut bs) = (window_zoom.scratch(), band_zoom.scratch());
            let last = (first + chunk).min(nk);
            for b0 in (first..last).step_by(BLOCK) {
                if progress.is_cancelled() {
                    break;
                }
                let b1 = (b0 + BLOCK).min(last);
                for (r, row) in spectra.chunks(nk).enumerate() {
                    for (s, v) in row[b0..b1].iter().enumerate() {
                        col[s * g.n_rows + r] = *v;
                    }
                }
                for (s, &kx) in g.kept[b0..b1].iter().enumerate() {
                    let c = &col[s * g.n_rows..(s + 1) * g.n_rows];
                    if kx <= g.kw {
                        window_zoom.process(c, &mut out, &mut ws);
                        for (i, o) in inten.iter_mut().zip(&out) {
                            *i = o.norm_sqr();
                        }
                        bin_column(&g, binning, &runs, kx, &inten, &mut p.acc);
                    }
                    if kx as i64 >= g.e {
                        // Columns kx and −kx, except the self-mirrored Nyquist column.
                        let weight = if kx as i64 == g.h { 1.0 } else { 2.0 };
                        let energy: f64 = c.iter().map(Complex64::norm_sqr).sum();
                        p.band_cols += weight * m as f64 * energy;
                        band_zoom.process(c, &mut out, &mut bs);
                        let band: f64 = out[..g.band_len()].iter().map(Complex64::norm_sqr).sum();
                        p.corner += weight * band;
                    }
                }
            }
            p
        })
        .collect();
    progress.check()?;
    let band_rows = band_rows_energy(field, &g, &band_zoom);
    progress.check()?;
    let mut acc = vec![0.0; w * w];
    let (mut band_cols, mut corner) = (0.0, 0.0);
    for p in partials {
        acc.iter_mut().zip(&p.acc).for_each(|(a, b)| *a += b);
        band_cols += p.band_cols;
        corner += p.corner;
    }
    let sensor = ndarray::Array2::from_shape_fn((w, w), |(jy, jx)| acc[jx * w + jy]);
    Ok(Binned {
        sensor,
        total: (m * m) as f64 * field.energy(),
        edge: (band_cols + band_rows - corner).max(0.0),
    })
}

/// A run of window rows that fall in one sensor row: column `kx`'s intensities
/// `direct … direct + len − 1` for `kx`, and `mirror, mirror − 1, …` for `−kx`.
#[derive(Debug, Clone, Copy)]
struct Run {
    direct: usize,
    mirror: usize,
    jy: usize,
    len: usize,
}

/// The window's rows as runs (a sensor pixel's `spp` fine rows are one run, summed together).
fn row_runs(g: &Geometry, b: &Binning) -> Vec<Run> {
    let index = |v: i64| usize::try_from(g.wrap(v) - g.r_lo).ok();
    let mut runs: Vec<Run> = Vec::new();
    let rows = (g.y_range.0..=g.y_range.1)
        .filter_map(|ky| Some((index(ky)?, index(-ky)?, b.pixel_of(ky, 1)?)))
        .filter(|(d, m, _)| *d < g.window_zoom_len() && *m < g.window_zoom_len());
    for (direct, mirror, jy) in rows {
        match runs.last_mut() {
            Some(r) if r.jy == jy && r.direct + r.len == direct && r.mirror == mirror + r.len => {
                r.len += 1;
            }
            _ => runs.push(Run {
                direct,
                mirror,
                jy,
                len: 1,
            }),
        }
    }
    runs
}

/// Adds window column `kx` (and its mirror `−kx`) of the intensity into the sensor sums;
/// `inten[i]` holds signed row `r_lo + i` of column `kx`.
fn bin_column(g: &Geometry, b: &Binning, runs: &[Run], kx: usize, inten: &[f64], acc: &mut [f64]) {
    let w = b.window_px;
    let k = kx as i64;
    let mut add = |s: i64, mirrored: bool| {
        if s < g.x_range.0 || s > g.x_range.1 {
            return;
        }
        let Some(jx) = b.pixel_of(s, 0) else {
            return;
        };
        let out = &mut acc[jx * w..(jx + 1) * w];
        for r in runs {
            let first = if mirrored {
                r.mirror + 1 - r.len
            } else {
                r.direct
            };
            out[r.jy] += inten[first..first + r.len].iter().sum::<f64>();
        }
    };
    if k == g.h {
        // The Nyquist column is signed −M/2 and has no separate mirror.
        add(-g.h, false);
        return;
    }
    add(k, false);
    if k != 0 {
        add(-k, true);
    }
}

/// `Σ |A|²` over the band rows `|ky| ≥ e`, all columns: `M Σ_x Σ_band |C(ky, x)|²` with `C` the
/// DFT along `y` of field column `x` (Parseval along `x`). Two real columns `u`, `v` ride in one
/// complex zoom of `z = u + i v`: `|U(k)|² + |V(k)|² = (|Z(k)|² + |Z(−k)|²)/2`, and the band is
/// symmetric (`k` in it iff `−k` is), so the pair's band energy is `Σ_band |Z|²`.
fn band_rows_energy(field: &Field, g: &Geometry, band_zoom: &Zoom) -> f64 {
    let band = g.band_len();
    if band == 0 || g.n_cols == 0 {
        return 0.0;
    }
    let blocks: Vec<i64> = (0..g.n_cols as i64)
        .step_by(BLOCK)
        .map(|b| g.ix0 + b)
        .collect();
    let sums: Vec<f64> = blocks
        .par_iter()
        .map_init(
            || {
                (
                    vec![Complex64::new(0.0, 0.0); g.n_rows * BLOCK / 2],
                    vec![Complex64::new(0.0, 0.0); band],
                    band_zoom.scratch(),
                )
            },
            |(col, out, scratch), &x0| {
                col.iter_mut().for_each(|v| *v = Complex64::new(0.0, 0.0));
                for r in &field.rows {
                    let ri = (r.iy - g.iy0) as usize;
                    let lo = x0.max(r.ix0);
                    let hi = (x0 + BLOCK as i64).min(r.ix0 + r.values.len() as i64);
                    for x in lo..hi {
                        let dx = (x - x0) as usize;
                        let v = r.values[(x - r.ix0) as usize];
                        let slot = &mut col[(dx / 2) * g.n_rows + ri];
                        if dx.is_multiple_of(2) {
                            slot.re = v;
                        } else {
                            slot.im = v;
                        }
                    }
                }
                col.chunks(g.n_rows)
                    .map(|c| {
                        band_zoom.process(c, out, scratch);
                        out.iter().map(Complex64::norm_sqr).sum::<f64>()
                    })
                    .sum::<f64>()
            },
        )
        .collect();
    g.m as f64 * sums.iter().sum::<f64>()
}
