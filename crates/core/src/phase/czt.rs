//! Fraunhofer intensity on an arbitrary sensor window by the chirp-z transform (Bluestein).
//!
//! A zero-padded FFT puts the sensor samples at `λf/(M δ1)`, which differs per wavelength and
//! needs M ≈ 10⁶; the chirp-z transform evaluates exactly the window's `W` samples at the spacing
//! we choose with three FFTs of about `N + W` points, so every wavelength shares one sensor grid.
//! The transform itself is the one in [`crate::psf::chirp_z`]; this module writes its chirps.

use std::f64::consts::PI;

use rustfft::num_complex::{Complex32, Complex64};

use crate::psf::chirp_z::{ChirpWork, ChirpZ};
use crate::psf::fft::quadratic_phase;

/// A prepared transform for one wavelength, input length and output window. Its FFTs run in
/// single precision (the chirps are computed in double and rounded once): intensities keep
/// ~1e-6 of the peak, and the transform costs half as much.
pub struct Czt {
    n_in: usize,
    chirp: ChirpZ<f32>,
}

/// The reusable buffers of [`Czt::intensity`].
pub type CztWork = ChirpWork<f32>;

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
        // exp(−iβ x_n u_m) = exp(−iβ(x0 u0 + x0 m du)) · exp(−iβ n dx u0) · exp(−iα n m), and
        // n m = (n² + m² − (m−n)²)/2.
        let input_chirp = quadratic_phase(-0.5 * alpha, -beta * dx_um * u0_um, 0, 1.0)
            .take(n_in)
            .collect();
        let kernel: Vec<Complex64> = quadratic_phase(0.5 * alpha, 0.0, 0, 1.0)
            .take(n_in.max(n_out))
            .collect();
        Czt {
            n_in,
            chirp: ChirpZ::new(input_chirp, n_out, |d| kernel[d.unsigned_abs() as usize]),
        }
    }

    /// Intensities `|X_m|²` of `input` (length `n_in`), written into `out` (length `n_out`).
    /// `work` holds the padded array and the FFT scratch; it is resized as needed and can be
    /// reused between calls.
    pub fn intensity(&self, input: &[Complex64], work: &mut CztWork, out: &mut [f64]) {
        self.intensity_with(work, |n| input[n], out);
    }

    /// The transform of the first `n` inputs (`n ≤ n_in`; the rest taken as zero), up to
    /// phase factors that depend on the output sample alone and not on `n`: the transforms of
    /// parts of one input can therefore be added with phases of their own before the intensity
    /// is taken.
    pub fn partial_with<'w>(
        &self,
        work: &'w mut CztWork,
        n: usize,
        input: impl FnMut(usize) -> Complex64,
    ) -> &'w [Complex32] {
        self.chirp.convolve(n.min(self.n_in), input, work)
    }

    /// The convolution itself (its length, kernel spectrum and outputs), for a transform that
    /// runs elsewhere.
    pub fn convolution(&self) -> &ChirpZ<f32> {
        &self.chirp
    }

    /// The chirp each input sample is multiplied by before the convolution (length `n_in`).
    pub fn input_chirp(&self) -> &[Complex64] {
        self.chirp.pre()
    }

    /// [`Czt::intensity`] of an input that `fill` writes already multiplied by
    /// [`Czt::input_chirp`], in single precision, all `n_in` samples.
    pub fn intensity_filled(
        &self,
        work: &mut CztWork,
        fill: impl FnOnce(&mut [Complex32]),
        out: &mut [f64],
    ) {
        for (o, s) in out
            .iter_mut()
            .zip(self.chirp.convolve_filled(self.n_in, fill, work))
        {
            *o = f64::from(s.norm_sqr());
        }
    }

    /// [`Czt::intensity`] of the input `input(0), input(1), … input(n_in − 1)`, called once each
    /// in order: a caller forms its field in the same pass.
    pub fn intensity_with(
        &self,
        work: &mut CztWork,
        input: impl FnMut(usize) -> Complex64,
        out: &mut [f64],
    ) {
        for (o, s) in out
            .iter_mut()
            .zip(self.chirp.convolve(self.n_in, input, work))
        {
            *o = f64::from(s.norm_sqr());
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
        czt.intensity(&input, &mut CztWork::new(), &mut out);
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
                (got - direct.norm_sqr()).abs() < 1e-5 * (1.0 + direct.norm_sqr()),
                "m={m}"
            );
        }
    }
}
