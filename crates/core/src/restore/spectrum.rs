//! Linear (not circular) 2-D convolution by FFT on a zero-padded grid, shared by the blur of the
//! capture, the Wiener filter and the conjugate-gradient solver.
//!
//! The image sits at the top-left corner of a `P×Q` grid; a kernel is placed with its centre pixel
//! (index `[W/2, W/2]` of a `W×W` kernel, the crate's optical-axis convention) at `[0, 0]`,
//! wrapping negative offsets to the far end. A product of spectra then gives the *'same'*
//! convolution directly in the top-left `H×W` corner: no shift, no phase ramp. That corner is free
//! of wrap-around as soon as `P ≥ H + max(c, W_k − 1 − c)` (`c` the centre index) — a kernel
//! row `u` maps an image row `j` to `i = j + u − c`, and an alias `u ± P` can only reach the corner
//! when `P` is smaller — even when the kernel is larger than the grid, so a photo much smaller
//! than its PSF still convolves linearly.
//!
//! Spectra are half spectra (`Q/2 + 1` columns, real input) stored column by column
//! (`data[kx · P + ky]`) so the column pass reads contiguous memory. The forward transform runs
//! its row FFTs over the image's rows only and the inverse its row FFTs over the cropped rows only.
//! Forward plans come from the crate-wide cache of [`crate::psf::fft`]; inverse plans are cached
//! here the same way. Rows and columns run in parallel on rayon's pool; every value is computed by
//! one thread in a fixed order, so results never depend on the thread count.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner};
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

use crate::psf::fft::{complex_plan, real_plan};
use crate::psf::sampling::next_fast_size;

struct InversePlans {
    real: RealFftPlanner<f64>,
    complex: FftPlanner<f64>,
    real_cache: HashMap<usize, Arc<dyn ComplexToReal<f64>>>,
    complex_cache: HashMap<usize, Arc<dyn Fft<f64>>>,
}

fn inverse_plans() -> &'static Mutex<InversePlans> {
    static PLANS: OnceLock<Mutex<InversePlans>> = OnceLock::new();
    PLANS.get_or_init(|| {
        Mutex::new(InversePlans {
            real: RealFftPlanner::new(),
            complex: FftPlanner::new(),
            real_cache: HashMap::new(),
            complex_cache: HashMap::new(),
        })
    })
}

/// A cached complex-to-real (inverse, unnormalised) plan of length `n`.
fn real_inverse_plan(n: usize) -> Arc<dyn ComplexToReal<f64>> {
    let mut p = inverse_plans().lock().unwrap_or_else(|e| e.into_inner());
    if let Some(plan) = p.real_cache.get(&n) {
        return plan.clone();
    }
    let plan = p.real.plan_fft_inverse(n);
    p.real_cache.insert(n, plan.clone());
    plan
}

/// A cached inverse (unnormalised) complex plan of length `n`.
fn complex_inverse_plan(n: usize) -> Arc<dyn Fft<f64>> {
    let mut p = inverse_plans().lock().unwrap_or_else(|e| e.into_inner());
    if let Some(plan) = p.complex_cache.get(&n) {
        return plan.clone();
    }
    let plan = p.complex.plan_fft_inverse(n);
    p.complex_cache.insert(n, plan.clone());
    plan
}

/// How far the grid extends beyond the image. The blur is exactly linear on either grid; only
/// Wiener's output near the borders changes, because the filter wraps around the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Padding {
    /// At least twice the image (conventions.md §5's "zero-padded to 2×"), and never less than
    /// [`Padding::Linear`]. The default: about 245 ms for a 1024×768 colour capture and Wiener
    /// restoration with the T-OLED PSFs on 2 cores (`benches/restore.rs`), inside the 300 ms
    /// budget.
    #[default]
    Double,
    /// The smallest fast FFT size free of wrap-around (`H + W_k/2`, see the module docs): about
    /// a third less time (165 ms for the case above) and the same PSNR within 0.02 dB there.
    /// Conjugate gradients give the same result on any grid, so this is the grid for them.
    Linear,
}

/// The padded FFT grid for an `H×W` image and a kernel of a given size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PadGrid {
    /// Padded rows `P` and columns `Q` (both even, 7-smooth).
    pub rows: usize,
    /// Padded columns `Q`.
    pub cols: usize,
    /// The image size `H×W`.
    pub image_rows: usize,
    /// Image columns `W`.
    pub image_cols: usize,
}

/// A half spectrum on a [`PadGrid`], column-major: `data[kx · rows + ky]`, `kx ≤ cols/2`.
#[derive(Debug, Clone)]
pub struct Spectrum {
    /// The grid the spectrum is laid out on.
    pub grid: PadGrid,
    /// The coefficients, column-major: `data[kx · rows + ky]`.
    pub data: Vec<Complex64>,
}

/// Rows processed together by the blocked transposes (32 complex = 512 bytes per read).
const BLOCK: usize = 32;

impl PadGrid {
    /// The grid for an image of `image_dim` (rows, cols) convolved with a kernel of `kernel_dim`.
    pub fn new(image_dim: (usize, usize), kernel_dim: (usize, usize), padding: Padding) -> Self {
        let size = |n: usize, k: usize| {
            let c = k / 2;
            let linear = n + c.max(k.saturating_sub(1 + c));
            let want = match padding {
                Padding::Linear => linear,
                Padding::Double => linear.max(2 * n),
            };
            next_fast_size(want.max(2))
        };
        PadGrid {
            rows: size(image_dim.0, kernel_dim.0),
            cols: size(image_dim.1, kernel_dim.1),
            image_rows: image_dim.0,
            image_cols: image_dim.1,
        }
    }

    /// Columns of a half spectrum.
    pub fn bins(&self) -> usize {
        self.cols / 2 + 1
    }

    /// Spectrum of the image at the top-left corner of the grid.
    ///
    /// # Panics
    /// If the image is not `image_rows × image_cols` (a caller bug, not user data).
    pub fn forward_image(&self, image: ArrayView2<'_, f64>) -> Spectrum {
        assert_eq!(image.dim(), (self.image_rows, self.image_cols));
        let rows: Vec<(usize, Vec<f64>)> = image
            .outer_iter()
            .enumerate()
            .map(|(y, row)| (y, row.to_vec()))
            .collect();
        self.forward_rows(&rows)
    }

    /// Spectrum of a kernel whose centre pixel `[H_k/2, W_k/2]` goes to `[0, 0]`, wrapping
    /// around the grid (kernels larger than the grid fold onto themselves, see the module docs).
    pub fn forward_kernel(&self, kernel: &Array2<f64>) -> Spectrum {
        let (kh, kw) = kernel.dim();
        let (cy, cx) = (kh / 2, kw / 2);
        let mut dense: Vec<Option<Vec<f64>>> = vec![None; self.rows];
        for (u, row) in kernel.outer_iter().enumerate() {
            let y = (u + self.rows - cy % self.rows) % self.rows;
            let out = dense[y].get_or_insert_with(|| vec![0.0; self.cols]);
            for (v, value) in row.iter().enumerate() {
                let x = (v + self.cols - cx % self.cols) % self.cols;
                out[x] += value;
            }
        }
        let rows: Vec<(usize, Vec<f64>)> = dense
            .into_iter()
            .enumerate()
            .filter_map(|(y, r)| r.map(|r| (y, r)))
            .collect();
        self.forward_rows(&rows)
    }

    /// Forward transform of the given grid rows (`(row index, values)`; values shorter than a
    /// grid row are zero-padded); every other row is zero.
    fn forward_rows(&self, rows: &[(usize, Vec<f64>)]) -> Spectrum {
        let (p, q, bins) = (self.rows, self.cols, self.bins());
        let plan = real_plan(q);
        let mut row_major = vec![Complex64::new(0.0, 0.0); rows.len() * bins];
        row_major
            .par_chunks_mut(bins)
            .zip(rows.par_iter())
            .for_each_init(
                || (plan.make_input_vec(), plan.make_scratch_vec()),
                |(input, scratch), (out, (_, values))| {
                    let n = values.len().min(q);
                    input[..n].copy_from_slice(&values[..n]);
                    input[n..].iter_mut().for_each(|v| *v = 0.0);
                    // Buffer lengths come from the plan itself, so this cannot fail.
                    let _ = plan.process_with_scratch(input, out, scratch);
                },
            );
        let mut data = vec![Complex64::new(0.0, 0.0); p * bins];
        data.par_chunks_mut(p * BLOCK)
            .enumerate()
            .for_each(|(b, chunk)| {
                let kx0 = b * BLOCK;
                let kx1 = (kx0 + BLOCK).min(bins);
                for ((y, _), spectrum) in rows.iter().zip(row_major.chunks(bins)) {
                    for (dk, v) in spectrum[kx0..kx1].iter().enumerate() {
                        chunk[dk * p + y] = *v;
                    }
                }
            });
        let plan = complex_plan(p);
        data.par_chunks_mut(p).for_each_init(
            || vec![Complex64::new(0.0, 0.0); plan.get_inplace_scratch_len()],
            |scratch, column| plan.process_with_scratch(column, scratch),
        );
        Spectrum { grid: *self, data }
    }

    /// Inverse transform, normalised by `1/(PQ)`, cropped to the top-left `H×W` corner.
    ///
    /// # Panics
    /// If the spectrum belongs to another grid (a caller bug).
    pub fn inverse_crop(&self, mut spectrum: Spectrum) -> Array2<f64> {
        assert_eq!(spectrum.grid, *self);
        let (p, q, bins) = (self.rows, self.cols, self.bins());
        let (h, w) = (self.image_rows, self.image_cols);
        let plan = complex_inverse_plan(p);
        spectrum.data.par_chunks_mut(p).for_each_init(
            || vec![Complex64::new(0.0, 0.0); plan.get_inplace_scratch_len()],
            |scratch, column| plan.process_with_scratch(column, scratch),
        );
        let data = &spectrum.data;
        let plan = real_inverse_plan(q);
        let scale = 1.0 / (p * q) as f64;
        let mut out = vec![0.0f64; h * w];
        out.par_chunks_mut(w * BLOCK).enumerate().for_each_init(
            || {
                (
                    vec![Complex64::new(0.0, 0.0); BLOCK * bins],
                    plan.make_output_vec(),
                    plan.make_scratch_vec(),
                )
            },
            |(rows_buf, real, scratch), (b, chunk)| {
                let y0 = b * BLOCK;
                let n = chunk.len() / w.max(1);
                for kx in 0..bins {
                    for (dy, v) in data[kx * p + y0..kx * p + y0 + n].iter().enumerate() {
                        rows_buf[dy * bins + kx] = *v;
                    }
                }
                for (dy, out_row) in chunk.chunks_mut(w).enumerate() {
                    let input = &mut rows_buf[dy * bins..(dy + 1) * bins];
                    // The spectrum is Hermitian up to round-off: the DC and Nyquist bins of a
                    // row of a real image are real.
                    input[0].im = 0.0;
                    if q.is_multiple_of(2) {
                        input[bins - 1].im = 0.0;
                    }
                    // Buffer lengths come from the plan itself, so this cannot fail.
                    let _ = plan.process_with_scratch(input, real, scratch);
                    for (o, v) in out_row.iter_mut().zip(real.iter()) {
                        *o = v * scale;
                    }
                }
            },
        );
        Array2::from_shape_vec((h, w), out).unwrap_or_else(|_| Array2::zeros((h, w)))
    }

    /// `inverse_crop(forward_image(image) · filter)`, the filter given per frequency.
    pub fn filter(
        &self,
        image: ArrayView2<'_, f64>,
        filter: impl Fn(usize, Complex64) -> Complex64 + Sync,
    ) -> Array2<f64> {
        let mut s = self.forward_image(image);
        s.data
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, v)| *v = filter(i, *v));
        self.inverse_crop(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direct 'same' convolution with the kernel centre at `[H_k/2, W_k/2]`, zero outside.
    fn direct_same(image: &Array2<f64>, kernel: &Array2<f64>) -> Array2<f64> {
        let (h, w) = image.dim();
        let (kh, kw) = kernel.dim();
        let (cy, cx) = ((kh / 2) as i64, (kw / 2) as i64);
        Array2::from_shape_fn((h, w), |(i, j)| {
            let mut acc = 0.0;
            for ((u, v), k) in kernel.indexed_iter() {
                let (y, x) = (i as i64 - (u as i64 - cy), j as i64 - (v as i64 - cx));
                if (0..h as i64).contains(&y) && (0..w as i64).contains(&x) {
                    acc += k * image[[y as usize, x as usize]];
                }
            }
            acc
        })
    }

    fn pseudo_random(dim: (usize, usize), salt: u64) -> Array2<f64> {
        Array2::from_shape_fn(dim, |(y, x)| {
            let s = (y as u64 * 7919 + x as u64 * 104_729 + salt * 15_485_863) % 1_000_003;
            s as f64 / 1_000_003.0
        })
    }

    #[test]
    fn fft_convolution_matches_the_direct_sum_even_for_kernels_larger_than_the_image() {
        for (img, ker) in [
            ((9, 13), (4, 6)),
            ((12, 7), (5, 3)),
            ((5, 6), (20, 18)),
            ((3, 3), (31, 30)),
        ] {
            let image = pseudo_random(img, 1);
            let kernel = pseudo_random(ker, 2);
            for padding in [Padding::Linear, Padding::Double] {
                let grid = PadGrid::new(img, ker, padding);
                let k = grid.forward_kernel(&kernel);
                let got = grid.filter(image.view(), |i, v| v * k.data[i]);
                let want = direct_same(&image, &kernel);
                for (a, b) in got.iter().zip(want.iter()) {
                    assert!((a - b).abs() < 1e-10, "{img:?} {ker:?}: {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn grid_sizes_are_fast_and_large_enough() {
        let g = PadGrid::new((768, 1024), (294, 294), Padding::Linear);
        assert!(g.rows >= 768 + 147 && g.cols >= 1024 + 147);
        assert!(g.rows < 1000 && g.cols < 1250, "{g:?}");
        let d = PadGrid::new((768, 1024), (294, 294), Padding::Double);
        assert!(d.rows >= 1536 && d.cols >= 2048);
    }
}
