//! The transforms the optimizer differentiates through, each with its adjoint.
//!
//! [`WindowDft`] is `A = DFT_M(a)` restricted to the frequencies that land in the sensor window,
//! for a real field `a` that is nonzero only inside a small box (the pupil): rows first over the
//! box's rows, then columns over the window's columns, so no `M×M` array is ever formed. Its
//! adjoint is the unnormalised inverse DFT scattered from the window and gathered on the box.
//!
//! Complex gradients follow one convention throughout: for a real loss `L` of a complex `z`,
//! `∂L/∂z := ∂L/∂Re z + i ∂L/∂Im z`. With it, the gradient of a real input `x` of `z = F x` is
//! `Re(Fᴴ ∂L/∂z)`.

use std::sync::Mutex;

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use udc_fft::{complex_inverse_plan, complex_plan};

const ZERO: Complex64 = Complex64::new(0.0, 0.0);

/// Large complex buffers handed back after use. An epoch needs some 100 MB of temporaries; fresh
/// allocations of that size are mapped and unmapped every time, and the page faults cost about
/// as much as the FFTs themselves.
#[derive(Debug, Default)]
pub struct Pool {
    free: Mutex<Vec<Vec<Complex64>>>,
}

impl Clone for Pool {
    fn clone(&self) -> Self {
        Pool::default()
    }
}

impl Pool {
    /// A zeroed buffer of `len`.
    pub fn take(&self, len: usize) -> Vec<Complex64> {
        let reused = self
            .free
            .lock()
            .map(|mut f| {
                let best = f
                    .iter()
                    .enumerate()
                    .filter(|(_, v)| v.capacity() >= len)
                    .min_by_key(|(_, v)| v.capacity())
                    .map(|(i, _)| i);
                best.map(|i| f.swap_remove(i))
            })
            .ok()
            .flatten();
        let mut v = reused.unwrap_or_default();
        v.clear();
        v.resize(len, ZERO);
        v
    }

    /// Returns a buffer for reuse (a bounded number are kept).
    pub fn give(&self, v: Vec<Complex64>) {
        if let Ok(mut f) = self.free.lock()
            && f.len() < 16
        {
            f.push(v);
        }
    }
}

/// A contiguous run of signed offsets `start, start + 1, …, start + len − 1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Span {
    /// First offset.
    pub start: i64,
    /// Number of offsets.
    pub len: usize,
}

impl Span {
    fn index(self, k: usize, m: usize) -> usize {
        (self.start + k as i64).rem_euclid(m as i64) as usize
    }
}

/// `DFT_M` of a real field on the sample box `rows × cols`, kept on the frequency box
/// `freq_rows × freq_cols`. Frequencies are stored column-major: `out[j * freq_rows.len + i]`.
#[derive(Debug, Clone)]
pub struct WindowDft {
    /// DFT size `M`.
    pub m: usize,
    /// Signed row offsets of the field's sample box.
    pub rows: Span,
    /// Signed column offsets of the field's sample box.
    pub cols: Span,
    /// Signed frequency rows kept (taken modulo `M`).
    pub freq_rows: Span,
    /// Signed frequency columns kept (taken modulo `M`).
    pub freq_cols: Span,
}

impl WindowDft {
    /// `a` is row-major `rows.len × cols.len`; temporaries come from (and go back to) `pool`.
    pub fn forward(&self, a: &[f64], pool: &Pool) -> Vec<Complex64> {
        let (m, ny, nx) = (self.m, self.rows.len, self.cols.len);
        let (nfy, nfx) = (self.freq_rows.len, self.freq_cols.len);
        let plan = complex_plan(m);
        // Stage 1: a DFT per field row, keeping the window's columns; stored `[kx][row]`.
        let mut row_spectra = pool.take(nfx * ny);
        let mut by_row = pool.take(ny * nfx);
        by_row.par_chunks_mut(nfx).enumerate().for_each_init(
            || (vec![ZERO; m], vec![ZERO; plan.get_inplace_scratch_len()]),
            |(buf, scratch), (r, out)| {
                buf.fill(ZERO);
                for (c, v) in a[r * nx..(r + 1) * nx].iter().enumerate() {
                    buf[self.cols.index(c, m)] = Complex64::new(*v, 0.0);
                }
                plan.process_with_scratch(buf, scratch);
                for (j, o) in out.iter_mut().enumerate() {
                    *o = buf[self.freq_cols.index(j, m)];
                }
            },
        );
        transpose(&by_row, ny, nfx, &mut row_spectra);
        pool.give(by_row);
        // Stage 2: a DFT per kept column, keeping the window's rows.
        let mut out = pool.take(nfx * nfy);
        out.par_chunks_mut(nfy)
            .zip(row_spectra.par_chunks(ny))
            .for_each_init(
                || (vec![ZERO; m], vec![ZERO; plan.get_inplace_scratch_len()]),
                |(buf, scratch), (col_out, col_in)| {
                    buf.fill(ZERO);
                    for (r, v) in col_in.iter().enumerate() {
                        buf[self.rows.index(r, m)] = *v;
                    }
                    plan.process_with_scratch(buf, scratch);
                    for (i, o) in col_out.iter_mut().enumerate() {
                        *o = buf[self.freq_rows.index(i, m)];
                    }
                },
            );
        pool.give(row_spectra);
        out
    }

    /// `Re(Fᴴ g)` on the sample box, for `g` laid out as [`WindowDft::forward`]'s output.
    pub fn adjoint(&self, g: &[Complex64], pool: &Pool) -> Vec<f64> {
        let (m, ny, nx) = (self.m, self.rows.len, self.cols.len);
        let (nfy, nfx) = (self.freq_rows.len, self.freq_cols.len);
        let plan = complex_inverse_plan(m);
        // Stage 2ᴴ: per kept column, scatter the window rows, inverse DFT, gather the box rows.
        let mut cols = pool.take(nfx * ny);
        cols.par_chunks_mut(ny)
            .zip(g.par_chunks(nfy))
            .for_each_init(
                || (vec![ZERO; m], vec![ZERO; plan.get_inplace_scratch_len()]),
                |(buf, scratch), (out, col_in)| {
                    buf.fill(ZERO);
                    for (i, v) in col_in.iter().enumerate() {
                        buf[self.freq_rows.index(i, m)] = *v;
                    }
                    plan.process_with_scratch(buf, scratch);
                    for (r, o) in out.iter_mut().enumerate() {
                        *o = buf[self.rows.index(r, m)];
                    }
                },
            );
        let mut by_row = pool.take(ny * nfx);
        transpose(&cols, nfx, ny, &mut by_row);
        pool.give(cols);
        // Stage 1ᴴ: per box row, scatter the kept columns, inverse DFT, gather the box columns.
        let mut out = vec![0.0; ny * nx];
        out.par_chunks_mut(nx)
            .zip(by_row.par_chunks(nfx))
            .for_each_init(
                || (vec![ZERO; m], vec![ZERO; plan.get_inplace_scratch_len()]),
                |(buf, scratch), (row_out, row_in)| {
                    buf.fill(ZERO);
                    for (j, v) in row_in.iter().enumerate() {
                        buf[self.freq_cols.index(j, m)] = *v;
                    }
                    plan.process_with_scratch(buf, scratch);
                    for (c, o) in row_out.iter_mut().enumerate() {
                        *o = buf[self.cols.index(c, m)].re;
                    }
                },
            );
        pool.give(by_row);
        out
    }
}

/// `dst[c * rows + r] = src[r * cols + c]`, in cache-friendly blocks.
fn transpose(src: &[Complex64], rows: usize, cols: usize, dst: &mut [Complex64]) {
    const BLOCK: usize = 32;
    dst.par_chunks_mut(rows * BLOCK)
        .enumerate()
        .for_each(|(b, chunk)| {
            let c0 = b * BLOCK;
            for r in 0..rows {
                let row = &src[r * cols..(r + 1) * cols];
                for (dc, v) in row[c0..(c0 + BLOCK).min(cols)].iter().enumerate() {
                    chunk[dc * rows + r] = *v;
                }
            }
        });
}

/// Unnormalised 2-D DFT of a complex array (`inverse`: the `e^{+iθ}` kernel, no `1/N`).
pub fn dft2_complex(a: &Array2<Complex64>, inverse: bool) -> Array2<Complex64> {
    let (h, w) = a.dim();
    let plan = |n| {
        if inverse {
            complex_inverse_plan(n)
        } else {
            complex_plan(n)
        }
    };
    let mut data: Vec<Complex64> = a.iter().copied().collect();
    let row_plan = plan(w);
    data.par_chunks_mut(w).for_each(|row| row_plan.process(row));
    let mut t = vec![ZERO; h * w];
    transpose(&data, h, w, &mut t);
    let col_plan = plan(h);
    t.par_chunks_mut(h).for_each(|col| col_plan.process(col));
    transpose(&t, w, h, &mut data);
    Array2::from_shape_vec((h, w), data).unwrap_or_else(|_| Array2::zeros((h, w)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The window DFT equals the brute-force DFT, and its adjoint satisfies
    /// `⟨F a, g⟩ = ⟨a, Fᴴ g⟩` (real parts) for random data.
    #[test]
    fn window_dft_matches_brute_force_and_is_adjoint() {
        let w = WindowDft {
            m: 12,
            rows: Span { start: -3, len: 5 },
            cols: Span { start: -2, len: 4 },
            freq_rows: Span { start: -4, len: 7 },
            freq_cols: Span { start: -6, len: 12 },
        };
        let mut seed = 1u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let a: Vec<f64> = (0..20).map(|_| rnd()).collect();
        let pool = Pool::default();
        let got = w.forward(&a, &pool);
        for j in 0..12 {
            for i in 0..7 {
                let (ky, kx) = (-4 + i as i64, -6 + j as i64);
                let mut want = ZERO;
                for r in 0..5 {
                    for c in 0..4 {
                        let (y, x) = (-3 + r as i64, -2 + c as i64);
                        let th = -2.0 * std::f64::consts::PI * ((ky * y + kx * x) as f64) / 12.0;
                        want += a[r * 4 + c] * Complex64::from_polar(1.0, th);
                    }
                }
                assert!((got[j * 7 + i] - want).norm() < 1e-12);
            }
        }
        let g: Vec<Complex64> = (0..84).map(|_| Complex64::new(rnd(), rnd())).collect();
        let lhs: f64 = got
            .iter()
            .zip(&g)
            .map(|(z, h)| z.re * h.re + z.im * h.im)
            .sum();
        let back = w.adjoint(&g, &pool);
        let rhs: f64 = a.iter().zip(&back).map(|(x, y)| x * y).sum();
        assert!((lhs - rhs).abs() < 1e-10, "{lhs} vs {rhs}");
    }

    #[test]
    fn dft2_inverse_undoes_forward() {
        let a = Array2::from_shape_fn((6, 10), |(y, x)| {
            Complex64::new((y * 3 + x) as f64, y as f64)
        });
        let back = dft2_complex(&dft2_complex(&a, false), true);
        for (p, q) in a.iter().zip(back.iter()) {
            assert!((p * 60.0 - q).norm() < 1e-9);
        }
    }
}
