//! The tables the kernels read, computed in `f64` on the CPU and rounded once to `f32`: the
//! power-of-two FFT's twiddles, the chirp `c_j = exp(iπ j²/M)` and the spectrum of the
//! Bluestein convolution kernel. WGSL's `sin`/`cos` are promised to only about 5e-4, so no angle
//! is evaluated on the device.

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;

/// `[re, im]` in `f32`, as the shaders' `vec2<f32>`.
pub type C32 = [f32; 2];

fn c32(c: Complex64) -> C32 {
    [c.re as f32, c.im as f32]
}

/// `exp(−2πi t / n)` for `t < n/2`: the twiddles of a radix-2 FFT of length `n`.
pub fn twiddles(n: usize) -> Vec<C32> {
    (0..n / 2)
        .map(|t| c32(Complex64::from_polar(1.0, -2.0 * PI * t as f64 / n as f64)))
        .collect()
}

/// `exp(−2πi t / n)` for every `t < n`: a mixed-radix FFT's twiddles and roots of unity.
pub fn roots(n: usize) -> Vec<C32> {
    (0..n)
        .map(|t| c32(Complex64::from_polar(1.0, -2.0 * PI * t as f64 / n as f64)))
        .collect()
}

/// `c_j = exp(iπ j² / m)` for `j < len`, the angle reduced exactly in integers
/// (`j² mod 2m`), so that large `j` lose no digits.
pub fn chirp64(m: usize, len: usize) -> Vec<Complex64> {
    let period = 2 * m as u64;
    (0..len as u64)
        .map(|j| {
            let r = (j * j) % period;
            Complex64::from_polar(1.0, PI * r as f64 / m as f64)
        })
        .collect()
}

/// The chirp of [`chirp64`] for `j < m`, in `f32`.
pub fn chirp(m: usize) -> Vec<C32> {
    chirp64(m, m).into_iter().map(c32).collect()
}

/// The convolution length for a DFT of length `m` of inputs `l` samples long: the power of two
/// `N ≥ m + l − 1`, so the circular convolution does not wrap onto the outputs kept.
pub fn conv_len(m: usize, l: usize) -> usize {
    (m + l.max(1) - 1).next_power_of_two()
}

/// The FFT (length `n`) of the convolution kernel `v`: `v_j = c_j` for `0 ≤ j < m`,
/// `v_{n−j} = c_j` for `0 < j < l` (the negative lags an input of `l` samples reaches), zero
/// elsewhere.
pub fn kernel_spectrum(m: usize, l: usize, n: usize) -> Vec<C32> {
    let c = chirp64(m, m.max(l));
    let mut v = vec![Complex64::new(0.0, 0.0); n];
    v[..m].copy_from_slice(&c[..m]);
    for j in 1..l {
        v[n - j] = c[j];
    }
    udc_fft::complex_plan(n).process(&mut v);
    v.into_iter().map(c32).collect()
}
