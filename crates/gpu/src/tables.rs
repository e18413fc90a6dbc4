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

/// The tables of one chirp-z "zoom" `X_q = Σ_{k<K} x_k ω^{(s+k)(t+q)}`, `q < Q`, with
/// `ω = exp(∓2πi/M)` (`conjugate`: the `+` sign): the input's pre-chirp `ω^{kt + k²/2}`, the
/// output's post-chirp `ω^{st + sq + q²/2} / N`, and the spectrum (length `N`, a power of two
/// `≥ K + Q − 1`) of the kernel `ω^{−j²/2}` at lags `j = −(K−1) … Q−1`. From
/// `(s+k)(t+q) = st + sq + kt + (k² + q² − (q−k)²)/2`; every angle is reduced exactly in
/// integers modulo `2M` before the `f64` sine and cosine.
pub struct Zoom {
    /// `K` pre-chirp factors.
    pub pre: Vec<C32>,
    /// `Q` post-chirp factors, `1/N` included.
    pub post: Vec<C32>,
    /// The kernel's spectrum, `N` values.
    pub kernel: Vec<C32>,
}

/// See [`Zoom`]; `s` and `t` may be negative (they are taken modulo `M`).
pub fn zoom(m: usize, (s, k_len): (i64, usize), (t, q_len): (i64, usize), conjugate: bool) -> Zoom {
    let n = conv_len(q_len.max(1), k_len);
    let period = 2 * m as i128;
    let sign = if conjugate { 1.0 } else { -1.0 };
    // exp(±iπ r / M) for an angle index r reduced modulo 2M.
    let phase = |r: i128| {
        let r = r.rem_euclid(period);
        Complex64::from_polar(1.0, sign * PI * r as f64 / m as f64)
    };
    let (s, t) = (
        i128::from(s).rem_euclid(m as i128),
        i128::from(t).rem_euclid(m as i128),
    );
    let pre = (0..k_len as i128)
        .map(|k| c32(phase(2 * k * t + k * k)))
        .collect();
    let post = (0..q_len as i128)
        .map(|q| c32(phase(2 * s * t + 2 * s * q + q * q) / n as f64))
        .collect();
    let mut v = vec![Complex64::new(0.0, 0.0); n];
    for (j, z) in v.iter_mut().enumerate().take(q_len) {
        *z = phase(-((j * j) as i128));
    }
    for j in 1..k_len {
        v[n - j] = phase(-((j * j) as i128));
    }
    udc_fft::complex_plan(n).process(&mut v);
    Zoom {
        pre,
        post,
        kernel: v.into_iter().map(c32).collect(),
    }
}
