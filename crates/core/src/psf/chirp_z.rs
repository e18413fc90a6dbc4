//! The chirp-z transform (Bluestein's algorithm), the one implementation behind both callers:
//! the display PSF's partial DFTs (`psf::zoom`, double precision, phases reduced
//! exactly in integers) and the phase mask's Fraunhofer window (`phase::czt`, single
//! precision FFTs). Each caller writes its own chirps; this module runs the convolution
//!
//! `y_j = Σ_i x_i · pre_i · kernel(j − i)`, for `j < n_out`,
//!
//! with two FFTs of a free, fast length `L ≥ n_in + n_out − 1`: a sum `Σ_n x_n w^{n m}` becomes
//! that convolution through `n m = (n² + m² − (m − n)²)/2` (the callers' docs derive their
//! chirps). The kernel is transformed once, in double precision, and rounded to the FFT's
//! precision once.

use std::sync::Arc;

use rustfft::num_complex::{Complex, Complex64};
use rustfft::{Fft, FftNum};

use crate::psf::sampling::next_fast_size_235;
use udc_fft::{complex_inverse_plan, complex_plan, complex_plan_f32};

/// The precision a [`ChirpZ`] runs its FFTs in (`f64` or `f32`); inputs and chirps stay `f64`.
pub trait Precision: FftNum {
    /// The cached forward and inverse plans of length `len`.
    fn plans(len: usize) -> (Arc<dyn Fft<Self>>, Arc<dyn Fft<Self>>);
    /// `v` rounded to this precision.
    fn narrow(v: Complex64) -> Complex<Self>;
}

impl Precision for f64 {
    fn plans(len: usize) -> (Arc<dyn Fft<f64>>, Arc<dyn Fft<f64>>) {
        (complex_plan(len), complex_inverse_plan(len))
    }
    fn narrow(v: Complex64) -> Complex<f64> {
        v
    }
}

impl Precision for f32 {
    fn plans(len: usize) -> (Arc<dyn Fft<f32>>, Arc<dyn Fft<f32>>) {
        (complex_plan_f32(len, false), complex_plan_f32(len, true))
    }
    fn narrow(v: Complex64) -> Complex<f32> {
        Complex::new(v.re as f32, v.im as f32)
    }
}

/// The convolution length for `n_in` inputs and `n_out` outputs: 2·3·5-smooth, so rustfft runs
/// it at full speed.
pub fn convolution_len(n_in: usize, n_out: usize) -> usize {
    next_fast_size_235((n_in + n_out).saturating_sub(1).max(2))
}

/// A prepared chirp-z convolution (see the module docs). Build once, run on many inputs.
pub struct ChirpZ<T: Precision> {
    len: usize,
    n_out: usize,
    forward: Arc<dyn Fft<T>>,
    inverse: Arc<dyn Fft<T>>,
    /// Per input sample, the chirp the input is multiplied by.
    pre: Vec<Complex64>,
    /// FFT of `kernel(d)`, d = −(n_in − 1) … n_out − 1, wrapped onto `len` points, over `len`.
    kernel_hat: Vec<Complex<T>>,
}

/// The reusable buffers of [`ChirpZ::convolve`]: they grow on first use.
pub struct ChirpWork<T> {
    padded: Vec<Complex<T>>,
    scratch: Vec<Complex<T>>,
}

impl<T> ChirpWork<T> {
    /// Empty buffers.
    pub const fn new() -> Self {
        ChirpWork {
            padded: Vec::new(),
            scratch: Vec::new(),
        }
    }
}

impl<T> Default for ChirpWork<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Precision> ChirpZ<T> {
    /// The convolution with input chirp `pre` (its length is the input length) and
    /// `kernel(d)` for `d = −(pre.len() − 1) … n_out − 1`.
    pub fn new(pre: Vec<Complex64>, n_out: usize, kernel: impl Fn(i64) -> Complex64) -> Self {
        let n_in = pre.len();
        let len = convolution_len(n_in, n_out);
        let mut wrapped = vec![Complex64::new(0.0, 0.0); len];
        for d in -(n_in as i64 - 1)..n_out as i64 {
            wrapped[d.rem_euclid(len as i64) as usize] = kernel(d);
        }
        complex_plan(len).process(&mut wrapped);
        let scale = 1.0 / len as f64;
        let (forward, inverse) = T::plans(len);
        ChirpZ {
            len,
            n_out,
            forward,
            inverse,
            pre,
            kernel_hat: wrapped.iter().map(|k| T::narrow(k * scale)).collect(),
        }
    }

    /// The convolution's (FFT) length `L ≥ n_in + n_out − 1`.
    pub fn fft_len(&self) -> usize {
        self.len
    }

    /// Outputs kept, `n_out`.
    pub fn n_out(&self) -> usize {
        self.n_out
    }

    /// The kernel's spectrum over `L`: `FFT(kernel)/L`, in this precision. The outputs are the
    /// first `n_out` samples of `IFFT(FFT(x·pre) · kernel_hat)` (unnormalised inverse).
    pub fn kernel_hat(&self) -> &[Complex<T>] {
        &self.kernel_hat
    }

    /// The input chirp: sample `n` of the input is multiplied by `pre()[n]`.
    pub fn pre(&self) -> &[Complex64] {
        &self.pre
    }

    /// [`ChirpZ::convolve`] of an input the caller writes already multiplied by the input
    /// chirp ([`ChirpZ::pre`]): `fill` gets the first `n_in` (at most the chirp's length)
    /// samples of the FFT buffer, in this precision, so a caller that keeps a product with the
    /// chirp across many inputs forms each input in one vectorisable pass.
    pub fn convolve_filled<'w>(
        &self,
        n_in: usize,
        fill: impl FnOnce(&mut [Complex<T>]),
        work: &'w mut ChirpWork<T>,
    ) -> &'w [Complex<T>] {
        let zero = Complex::new(T::zero(), T::zero());
        let n_in = n_in.min(self.pre.len());
        let padded = &mut work.padded;
        padded.resize(self.len, zero);
        padded[n_in..].fill(zero);
        fill(&mut padded[..n_in]);
        self.transform(work)
    }

    /// The FFT, the kernel's product and the inverse FFT of the filled buffer.
    fn transform<'w>(&self, work: &'w mut ChirpWork<T>) -> &'w [Complex<T>] {
        let zero = Complex::new(T::zero(), T::zero());
        let scratch_len = self
            .forward
            .get_inplace_scratch_len()
            .max(self.inverse.get_inplace_scratch_len());
        let ChirpWork { padded, scratch } = work;
        scratch.resize(scratch_len, zero);
        self.forward.process_with_scratch(padded, scratch);
        for (s, k) in padded.iter_mut().zip(&self.kernel_hat) {
            *s = *s * *k;
        }
        self.inverse.process_with_scratch(padded, scratch);
        &padded[..self.n_out]
    }

    /// The convolution of the inputs `input(0), input(1), …` (each called once, in order, for
    /// as many samples as the input chirp has, or `n_in` if fewer): the first `n_out` values,
    /// before any output chirp.
    pub fn convolve<'w>(
        &self,
        n_in: usize,
        mut input: impl FnMut(usize) -> Complex64,
        work: &'w mut ChirpWork<T>,
    ) -> &'w [Complex<T>] {
        let zero = Complex::new(T::zero(), T::zero());
        let padded = &mut work.padded;
        padded.clear();
        padded.resize(self.len, zero);
        for (n, (s, c)) in padded.iter_mut().zip(&self.pre).take(n_in).enumerate() {
            *s = T::narrow(input(n) * c);
        }
        self.transform(work)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both precisions equal the direct convolution they replace.
    #[test]
    fn matches_the_direct_convolution_in_both_precisions() {
        let (n_in, n_out) = (13usize, 9usize);
        let pre: Vec<Complex64> = (0..n_in)
            .map(|i| Complex64::from_polar(1.0, 0.37 * (i * i) as f64))
            .collect();
        let kernel = |d: i64| Complex64::from_polar(1.0 + 0.1 * d as f64, -0.21 * (d * d) as f64);
        let x = |i: usize| Complex64::new((i as f64 * 0.7).sin(), 0.3 * i as f64 - 1.0);
        let want: Vec<Complex64> = (0..n_out as i64)
            .map(|j| {
                (0..n_in)
                    .map(|i| x(i) * pre[i] * kernel(j - i as i64))
                    .sum()
            })
            .collect();
        let wide = ChirpZ::<f64>::new(pre.clone(), n_out, kernel);
        let got = wide.convolve(n_in, x, &mut ChirpWork::new()).to_vec();
        let narrow = ChirpZ::<f32>::new(pre, n_out, kernel);
        let got32 = narrow.convolve(n_in, x, &mut ChirpWork::new()).to_vec();
        for ((a, b), w) in got.iter().zip(&got32).zip(&want) {
            assert!((a - w).norm() < 1e-12, "{a} vs {w}");
            let b = Complex64::new(f64::from(b.re), f64::from(b.im));
            assert!((b - w).norm() < 1e-5 * (1.0 + w.norm()), "{b} vs {w}");
        }
    }

    /// An input written already chirped gives the same convolution, in a reused buffer whose
    /// earlier, longer contents must not leak into the zeros beyond the input.
    #[test]
    fn a_prechirped_input_convolves_as_the_plain_one() {
        let n_in = 11usize;
        let pre: Vec<Complex64> = (0..n_in)
            .map(|i| Complex64::from_polar(1.0, 0.29 * (i * i) as f64))
            .collect();
        let kernel = |d: i64| Complex64::from_polar(1.0, -0.17 * (d * d) as f64);
        let z = ChirpZ::<f32>::new(pre, 7, kernel);
        let x = |i: usize| Complex64::new((i as f64).cos(), 0.5 - 0.1 * i as f64);
        let mut work = ChirpWork::new();
        for n in [n_in, 4] {
            let plain = z.convolve(n, x, &mut ChirpWork::new()).to_vec();
            let filled = z
                .convolve_filled(
                    n,
                    |buf| {
                        for (i, b) in buf.iter_mut().enumerate() {
                            *b = f32::narrow(x(i) * z.pre()[i]);
                        }
                    },
                    &mut work,
                )
                .to_vec();
            assert_eq!(plain, filled, "{n} inputs");
        }
    }

    /// A shorter input reads as zeros beyond its end.
    #[test]
    fn a_shorter_input_is_zero_padded() {
        let pre = vec![Complex64::new(1.0, 0.0); 6];
        let z = ChirpZ::<f64>::new(pre, 4, |d| Complex64::new(d as f64, 0.0));
        let got = z
            .convolve(
                2,
                |i| Complex64::new(1.0 + i as f64, 0.0),
                &mut ChirpWork::new(),
            )
            .to_vec();
        // y_j = 1·j + 2·(j − 1).
        for (j, y) in got.iter().enumerate() {
            let want = 3.0 * j as f64 - 2.0;
            assert!(
                (y.re - want).abs() < 1e-12 && y.im.abs() < 1e-12,
                "j={j}: {y}"
            );
        }
    }
}
