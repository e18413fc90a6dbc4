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

use ndarray::{Array2, ArrayView2, Axis};
use rayon::prelude::*;
use rustfft::num_complex::{Complex32, Complex64};
use udc_fft::{Fft, complex_inverse_plan, complex_plan, real_inverse_plan, real_plan};

use crate::Sample;
use crate::psf::sampling::next_fast_size;

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

/// Image rows [`PadGrid::convolve`] transforms before it files them into its column strip.
const ROW_BAND: usize = 128;

/// The most [`PadGrid::convolve`] holds of an image's row spectra at once: 64 MiB, a 2048 ×
/// 2048 image on the doubled grid (4 196 352 coefficients of 8 bytes is 32 MiB); a 4096 × 4096
/// one is done in three strips.
pub const STRIP_BYTES: usize = 64 << 20;

/// A kernel's row spectra on a grid ([`PadGrid::kernel_rows`]).
#[derive(Debug, Clone)]
pub struct KernelRows {
    grid: PadGrid,
    /// `(grid row, its Q/2+1 coefficients)`, in increasing row order.
    rows: Vec<(usize, Vec<Complex64>)>,
}

impl KernelRows {
    /// Column `kx` of the kernel's spectrum into `out` (`P` long), by one column transform.
    fn column(
        &self,
        kx: usize,
        out: &mut [Complex64],
        plan: &dyn Fft<f64>,
        scratch: &mut [Complex64],
    ) {
        out.iter_mut().for_each(|v| *v = Complex64::new(0.0, 0.0));
        for (y, spectrum) in &self.rows {
            out[*y] = spectrum[kx];
        }
        plan.process_with_scratch(out, scratch);
    }
}

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
        self.forward_rows(&self.kernel_grid_rows(kernel))
    }

    /// The grid rows a kernel occupies once its centre pixel is at `[0, 0]` and it wraps
    /// around the grid: `(row index, Q values)`, in increasing row order.
    fn kernel_grid_rows(&self, kernel: &Array2<f64>) -> Vec<(usize, Vec<f64>)> {
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
        dense
            .into_iter()
            .enumerate()
            .filter_map(|(y, r)| r.map(|r| (y, r)))
            .collect()
    }

    /// A kernel for [`PadGrid::convolve`]: the row spectra of the grid rows it occupies (placed
    /// as [`PadGrid::forward_kernel`] places it), from which each column of its spectrum is
    /// computed when needed instead of holding all `P × (Q/2+1)` coefficients.
    pub fn kernel_rows(&self, kernel: &Array2<f64>) -> KernelRows {
        let rows = self.kernel_grid_rows(kernel);
        let plan = real_plan(self.cols);
        let spectra: Vec<Vec<Complex64>> = rows
            .par_iter()
            .map_init(
                || (plan.make_input_vec(), plan.make_scratch_vec()),
                |(input, scratch), (_, values)| {
                    input.copy_from_slice(values);
                    let mut out = plan.make_output_vec();
                    // Buffer lengths come from the plan itself, so this cannot fail.
                    let _ = plan.process_with_scratch(input, &mut out, scratch);
                    out
                },
            )
            .collect();
        KernelRows {
            grid: *self,
            rows: rows.into_iter().map(|(y, _)| y).zip(spectra).collect(),
        }
    }

    /// `inverse_crop(forward_image(image) · f(Y, K))` for the kernel `kernel`, with the image's
    /// spectrum `Y` and the kernel's `K` at each frequency, computed column by column so that
    /// it never holds a whole padded spectrum: the row spectra of the image's `H` rows (8 bytes
    /// a coefficient), in strips of columns when even those would exceed [`STRIP_BYTES`] (each
    /// strip repeats the row transforms, and the rows' inverse transforms are summed). The
    /// kernel's column spectra are computed as each column needs them. Equal to the whole-grid
    /// route within the `f32` storage's rounding (about 1e-7 of the image's scale).
    ///
    /// # Panics
    /// If the image is not `image_rows × image_cols` or the kernel belongs to another grid (a
    /// caller bug, not user data).
    pub fn convolve<T: Sample>(
        &self,
        image: ArrayView2<'_, T>,
        kernel: &KernelRows,
        f: impl Fn(Complex64, Complex64) -> Complex64 + Sync,
    ) -> Array2<T> {
        self.convolve_in_strips(image, kernel, f, STRIP_BYTES)
    }

    /// [`PadGrid::convolve`] holding at most about `strip_bytes` of row spectra.
    fn convolve_in_strips<T: Sample>(
        &self,
        image: ArrayView2<'_, T>,
        kernel: &KernelRows,
        f: impl Fn(Complex64, Complex64) -> Complex64 + Sync,
        strip_bytes: usize,
    ) -> Array2<T> {
        assert_eq!(image.dim(), (self.image_rows, self.image_cols));
        assert_eq!(kernel.grid, *self);
        let (p, q, bins) = (self.rows, self.cols, self.bins());
        let (h, w) = (self.image_rows, self.image_cols);
        let blocks = bins.div_ceil(BLOCK);
        let strips = (h * bins * std::mem::size_of::<Complex32>())
            .div_ceil(strip_bytes.max(1))
            .clamp(1, blocks);
        let strip_bins = blocks.div_ceil(strips) * BLOCK;
        let mut out = Array2::<T>::default((h, w));
        let forward = real_plan(q);
        let inverse = real_inverse_plan(q);
        let (column, column_inverse) = (complex_plan(p), complex_inverse_plan(p));
        let column_scratch = column
            .get_inplace_scratch_len()
            .max(column_inverse.get_inplace_scratch_len());
        let scale = 1.0 / (p * q) as f64;
        for (s, b0) in (0..bins).step_by(strip_bins).enumerate() {
            let b1 = (b0 + strip_bins).min(bins);
            let nb = b1 - b0;
            // The strip, column-major (`strip[dk · H + y]`) so that each column is contiguous.
            let mut strip = vec![Complex32::new(0.0, 0.0); nb * h];
            let mut band = vec![Complex64::new(0.0, 0.0); ROW_BAND * nb];
            for y0 in (0..h).step_by(ROW_BAND) {
                let n = ROW_BAND.min(h - y0);
                band[..n * nb].par_chunks_mut(nb).enumerate().for_each_init(
                    || {
                        (
                            forward.make_input_vec(),
                            forward.make_output_vec(),
                            forward.make_scratch_vec(),
                        )
                    },
                    |(input, spectrum, scratch), (r, out)| {
                        for (i, v) in input.iter_mut().zip(image.row(y0 + r)) {
                            *i = (*v).into();
                        }
                        input[w..].iter_mut().for_each(|v| *v = 0.0);
                        let _ = forward.process_with_scratch(input, spectrum, scratch);
                        out.copy_from_slice(&spectrum[b0..b1]);
                    },
                );
                strip
                    .par_chunks_mut(h * BLOCK)
                    .enumerate()
                    .for_each(|(blk, chunk)| {
                        for (dk, col) in chunk.chunks_mut(h).enumerate() {
                            let k = blk * BLOCK + dk;
                            for (r, v) in col[y0..y0 + n].iter_mut().enumerate() {
                                let c = band[r * nb + k];
                                *v = Complex32::new(c.re as f32, c.im as f32);
                            }
                        }
                    });
            }
            strip.par_chunks_mut(h).enumerate().for_each_init(
                || {
                    (
                        vec![Complex64::new(0.0, 0.0); p],
                        vec![Complex64::new(0.0, 0.0); p],
                        vec![Complex64::new(0.0, 0.0); column_scratch],
                    )
                },
                |(buf, k, scratch), (dk, col)| {
                    for (b, v) in buf.iter_mut().zip(col.iter()) {
                        *b = Complex64::new(f64::from(v.re), f64::from(v.im));
                    }
                    buf[h..]
                        .iter_mut()
                        .for_each(|v| *v = Complex64::new(0.0, 0.0));
                    column.process_with_scratch(buf, scratch);
                    kernel.column(b0 + dk, k, column.as_ref(), scratch);
                    for (b, k) in buf.iter_mut().zip(k.iter()) {
                        *b = f(*b, *k);
                    }
                    column_inverse.process_with_scratch(buf, scratch);
                    for (v, b) in col.iter_mut().zip(buf.iter()) {
                        *v = Complex32::new(b.re as f32, b.im as f32);
                    }
                },
            );
            let strip = &strip;
            out.axis_chunks_iter_mut(Axis(0), BLOCK)
                .into_par_iter()
                .enumerate()
                .for_each_init(
                    || {
                        (
                            vec![Complex64::new(0.0, 0.0); BLOCK * bins],
                            inverse.make_output_vec(),
                            inverse.make_scratch_vec(),
                        )
                    },
                    |(rows, real, scratch), (b, mut chunk)| {
                        let y0 = b * BLOCK;
                        let n = chunk.nrows();
                        rows.iter_mut().for_each(|v| *v = Complex64::new(0.0, 0.0));
                        for dk in 0..nb {
                            for (r, v) in strip[dk * h + y0..dk * h + y0 + n].iter().enumerate() {
                                rows[r * bins + b0 + dk] =
                                    Complex64::new(f64::from(v.re), f64::from(v.im));
                            }
                        }
                        for (r, mut out_row) in chunk.outer_iter_mut().enumerate() {
                            let input = &mut rows[r * bins..(r + 1) * bins];
                            // The DC and Nyquist bins of a real row are real (see inverse_crop).
                            input[0].im = 0.0;
                            if q.is_multiple_of(2) {
                                input[bins - 1].im = 0.0;
                            }
                            let _ = inverse.process_with_scratch(input, real, scratch);
                            for (o, v) in out_row.iter_mut().zip(real.iter()) {
                                *o = if s == 0 {
                                    T::from_f64(v * scale)
                                } else {
                                    T::from_f64((*o).into() + v * scale)
                                };
                            }
                        }
                    },
                );
        }
        out
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
    fn the_column_by_column_convolution_equals_the_whole_spectrum_in_any_number_of_strips() {
        let image = pseudo_random((70, 150), 3);
        let kernel = pseudo_random((11, 9), 4);
        for padding in [Padding::Linear, Padding::Double] {
            let grid = PadGrid::new(image.dim(), kernel.dim(), padding);
            let k = grid.forward_kernel(&kernel);
            let want = grid.filter(image.view(), |i, v| v * k.data[i]);
            let rows = grid.kernel_rows(&kernel);
            // 1 strip, then strips of one and of three column blocks (the last one partial).
            for strip_bytes in [usize::MAX, 1, 70 * 96 * 8] {
                let got = grid.convolve_in_strips(image.view(), &rows, |y, k| y * k, strip_bytes);
                let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (a, b) in got.iter().zip(want.iter()) {
                    assert!(
                        (a - b).abs() < 1e-6 * scale,
                        "{padding:?} {strip_bytes}: {a} vs {b}"
                    );
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
