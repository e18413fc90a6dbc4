//! Fraunhofer intensity on an arbitrary sensor window by the chirp-z transform (Bluestein).
//!
//! A zero-padded FFT puts the sensor samples at `λf/(M δ1)`, which differs per wavelength and
//! needs M ≈ 10⁶; the chirp-z transform evaluates exactly the window's `W` samples at the spacing
//! we choose with three FFTs of about `N + W` points, so every wavelength shares one sensor grid.

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;

use crate::core::fft::{complex_inverse_plan, complex_plan};
use crate::core::sampling::next_fast_size;

/// A prepared transform for one wavelength, input length and output window.
pub struct Czt {
    n_out: usize,
    size: usize,
    /// `exp(−iα n²/2)` folded with the window's start frequency, per input sample.
    input_chirp: Vec<Complex64>,
    /// FFT of the convolution kernel `exp(+iα k²/2)`, k = −(N−1) … W−1.
    kernel_spectrum: Vec<Complex64>,
}

impl Czt {
    /// `|Σ_n a_n exp(−i 2π x_n u_m / (λ f))|²` for `x_n = x0 + n dx` (n < `n_in`) and
    /// `u_m = u0 + m du` (m < `n_out`); `lambda_f_um2` is λ·f in µm². Only intensities are
    /// returned, so the phase factors that depend on m alone are dropped.
    pub fn new(
        n_in: usize,
        n_out: usize,
        dx_um: f64,
        u0_um: f64,
        du_um: f64,
        lambda_f_um2: f64,
    ) -> Self {
        let beta = 2.0 * PI / lambda_f_um2;
        let alpha = beta * dx_um * du_um;
        let size = next_fast_size(n_in + n_out - 1);
        // exp(−iβ x_n u_m) = exp(−iβ(x0 u0 + x0 m du)) · exp(−iβ n dx u0) · exp(−iα n m), and
        // n m = (n² + m² − (m−n)²)/2. Phases are reduced before cis() to keep them accurate.
        let chirp = |k: f64| -> f64 { (0.5 * alpha * k * k).rem_euclid(2.0 * PI) };
        let input_chirp = (0..n_in)
            .map(|n| {
                let n = n as f64;
                let ramp = (beta * dx_um * u0_um * n).rem_euclid(2.0 * PI);
                Complex64::from_polar(1.0, -(ramp + chirp(n)))
            })
            .collect();
        let mut kernel = vec![Complex64::new(0.0, 0.0); size];
        for (m, slot) in kernel.iter_mut().enumerate().take(n_out) {
            *slot = Complex64::from_polar(1.0, chirp(m as f64));
        }
        for k in 1..n_in {
            kernel[size - k] = Complex64::from_polar(1.0, chirp(k as f64));
        }
        complex_plan(size).process(&mut kernel);
        Czt {
            n_out,
            size,
            input_chirp,
            kernel_spectrum: kernel,
        }
    }

    /// Intensities `|X_m|²` of `input` (length `n_in`), written into `out` (length `n_out`).
    /// `scratch` is resized as needed and can be reused between calls.
    pub fn intensity(&self, input: &[Complex64], scratch: &mut Vec<Complex64>, out: &mut [f64]) {
        scratch.clear();
        scratch.resize(self.size, Complex64::new(0.0, 0.0));
        for ((s, a), c) in scratch.iter_mut().zip(input).zip(&self.input_chirp) {
            *s = a * c;
        }
        let forward = complex_plan(self.size);
        let inverse = complex_inverse_plan(self.size);
        let len = forward
            .get_inplace_scratch_len()
            .max(inverse.get_inplace_scratch_len());
        super::chain::with_scratch(len, |fft_scratch| {
            forward.process_with_scratch(scratch, fft_scratch);
            for (s, k) in scratch.iter_mut().zip(&self.kernel_spectrum) {
                *s *= k;
            }
            inverse.process_with_scratch(scratch, fft_scratch);
        });
        let norm = 1.0 / self.size as f64;
        for (o, s) in out.iter_mut().zip(scratch.iter()).take(self.n_out) {
            *o = (s * norm).norm_sqr();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transform equals the direct sum it replaces.
    #[test]
    fn matches_the_direct_sum() {
        let n_in = 37;
        let n_out = 23;
        let (dx, u0, du, lf) = (0.3, -4.1, 0.45, 2.7);
        let input: Vec<Complex64> = (0..n_in)
            .map(|n| Complex64::new((n as f64 * 0.7).sin(), (n as f64 * 0.31).cos() - 0.2))
            .collect();
        let x0 = -5.0;
        let czt = Czt::new(n_in, n_out, dx, u0, du, lf);
        let mut out = vec![0.0; n_out];
        czt.intensity(&input, &mut Vec::new(), &mut out);
        for (m, got) in out.iter().enumerate() {
            let u = u0 + m as f64 * du;
            let direct: Complex64 = input
                .iter()
                .enumerate()
                .map(|(n, a)| {
                    let x = x0 + n as f64 * dx;
                    a * Complex64::from_polar(1.0, -2.0 * PI * x * u / lf)
                })
                .sum();
            assert!(
                (got - direct.norm_sqr()).abs() < 1e-9 * (1.0 + direct.norm_sqr()),
                "m={m}"
            );
        }
    }
}
