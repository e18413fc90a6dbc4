//! Stage 1 of the pruned PSF route: the spectra of the field's rows at the
//! kept columns only (`0 … kw` and the band `e … M/2`), by the cheaper of two exact ways:
//!
//! - a real FFT of length `M` per row: `fft(M)/2` each;
//! - two rows `u`, `v` at once as `z = u + i v`, zoomed onto `k ∈ [−kw, kw]` and onto the band
//!   (which holds `−k` for every `k` in it), then split: `U(k) = (Z(k) + conj Z(−k))/2`,
//!   `V(k) = (Z(k) − conj Z(−k))/(2i)`: `(zoom(window) + zoom(band))/2` per row. For the awkward
//!   sizes the physics asks for (6100 = 4·25·61) this is ~3× cheaper than rustfft's real FFT.
//!
//! The two ways differ by a phase per column (where the grid origin sits), which no intensity
//! sees; one call uses one way for every row.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::display::aperture::{Field, SparseRow};
use crate::psf::pruned_grid::Geometry;
use crate::psf::zoom::{best_ops, cached, fft_ops};
use udc_fft::real_plan;

/// Modelled cost of the cheaper row pass, complex multiply-adds.
pub(crate) fn row_pass_ops(field: &Field, g: &Geometry) -> f64 {
    real_ops(field, g).min(pair_ops(g))
}

fn real_ops(field: &Field, g: &Geometry) -> f64 {
    field.rows.len() as f64 * 0.5 * fft_ops(g.m)
}

fn pair_ops(g: &Geometry) -> f64 {
    g.n_rows.div_ceil(2) as f64
        * (best_ops(g.m, g.n_cols, 2 * g.kw + 1) + best_ops(g.m, g.n_cols, g.band_len()))
}

/// Row spectra of every grid row `iy0 … iy0 + n_rows − 1` (zero rows stay zero), keeping only
/// the columns of `g.kept`, row-major `[row][kept]`.
pub(crate) fn kept_row_spectra(field: &Field, g: &Geometry) -> Vec<Complex64> {
    let nk = g.kept.len().max(1);
    let mut by_row: Vec<Option<&SparseRow>> = vec![None; g.n_rows];
    for r in &field.rows {
        by_row[(r.iy - g.iy0) as usize] = Some(r);
    }
    let mut out = vec![Complex64::new(0.0, 0.0); g.n_rows * nk];
    if pair_ops(g) < real_ops(field, g) {
        paired(g, &by_row, &mut out);
    } else {
        real(g, &by_row, &mut out);
    }
    out
}

fn real(g: &Geometry, by_row: &[Option<&SparseRow>], out: &mut [Complex64]) {
    let plan = real_plan(g.m);
    let nk = g.kept.len().max(1);
    out.par_chunks_mut(nk).zip(by_row.par_iter()).for_each_init(
        || {
            (
                plan.make_input_vec(),
                plan.make_output_vec(),
                plan.make_scratch_vec(),
            )
        },
        |(input, spectrum, scratch), (dst, row)| {
            let Some(row) = row else {
                return;
            };
            input.iter_mut().for_each(|v| *v = 0.0);
            let start = (row.ix0 + g.h) as usize;
            input[start..start + row.values.len()].copy_from_slice(&row.values);
            // Lengths come from the plan itself, so this cannot fail.
            let _ = plan.process_with_scratch(input, spectrum, scratch);
            for (d, &kx) in dst.iter_mut().zip(&g.kept) {
                *d = spectrum[kx];
            }
        },
    );
}

fn paired(g: &Geometry, by_row: &[Option<&SparseRow>], out: &mut [Complex64]) {
    let nk = g.kept.len().max(1);
    let kw = g.kw as i64;
    let window = cached(g.m, g.ix0, g.n_cols, -kw, 2 * g.kw + 1);
    let band = cached(g.m, g.ix0, g.n_cols, g.e, g.band_len());
    let m = g.m as i64;
    // Where Z(k) and Z(−k) sit in the two zoom outputs, per kept column: (window?, index, mirror).
    let source: Vec<(bool, usize, usize)> = g
        .kept
        .iter()
        .map(|&kx| {
            let k = kx as i64;
            if k <= kw {
                (true, (kw + k) as usize, (kw - k) as usize)
            } else {
                (false, (k - g.e) as usize, (m - k - g.e) as usize)
            }
        })
        .collect();
    out.par_chunks_mut(2 * nk)
        .zip(by_row.par_chunks(2))
        .for_each_init(
            || {
                (
                    vec![Complex64::new(0.0, 0.0); g.n_cols],
                    vec![Complex64::new(0.0, 0.0); 2 * g.kw + 1],
                    vec![Complex64::new(0.0, 0.0); g.band_len()],
                    window.scratch(),
                    band.scratch(),
                )
            },
            |(z, zw, zb, sw, sb), (dst, rows)| {
                if rows.iter().all(Option::is_none) {
                    return;
                }
                z.iter_mut().for_each(|v| *v = Complex64::new(0.0, 0.0));
                for (part, row) in rows.iter().enumerate() {
                    let Some(row) = row else {
                        continue;
                    };
                    let start = (row.ix0 - g.ix0) as usize;
                    for (d, v) in z[start..start + row.values.len()]
                        .iter_mut()
                        .zip(&row.values)
                    {
                        if part == 0 {
                            d.re = *v;
                        } else {
                            d.im = *v;
                        }
                    }
                }
                window.process(z, zw, sw);
                band.process(z, zb, sb);
                let (first, second) = dst.split_at_mut(nk);
                for (j, &(in_window, at, mirror)) in source.iter().enumerate() {
                    let (zk, zm) = if in_window {
                        (zw[at], zw[mirror].conj())
                    } else {
                        (zb[at], zb[mirror].conj())
                    };
                    first[j] = (zk + zm) * 0.5;
                    if let Some(s) = second.get_mut(j) {
                        // (Z(k) − conj Z(−k)) / (2i)
                        let d = (zk - zm) * 0.5;
                        *s = Complex64::new(d.im, -d.re);
                    }
                }
            },
        );
}
