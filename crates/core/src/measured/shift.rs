//! A sub-pixel shift of a square array by a phase ramp in the Fourier domain: unlike an
//! interpolation it leaves the MTF as it is (a bilinear half-pixel shift would multiply it by
//! `cos(π f)`), which is what a measured PSF is compared by.

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use udc_fft::{complex_inverse_plan, complex_plan};

/// Transforms the rows, then the columns, of `data` (`n × n`, row-major) in place.
pub(crate) fn transform(data: &mut [Complex64], n: usize, inverse: bool) {
    let plan = if inverse {
        complex_inverse_plan(n)
    } else {
        complex_plan(n)
    };
    data.par_chunks_mut(n).for_each(|row| plan.process(row));
    let mut t = vec![Complex64::new(0.0, 0.0); n * n];
    for y in 0..n {
        for x in 0..n {
            t[x * n + y] = data[y * n + x];
        }
    }
    t.par_chunks_mut(n).for_each(|col| plan.process(col));
    for x in 0..n {
        for y in 0..n {
            data[y * n + x] = t[x * n + y];
        }
    }
}

/// `a` moved by `(dy, dx)` pixels (down and right positive), circularly: the sample at `[y, x]`
/// lands at `[y + dy, x + dx]`.
pub fn shifted(a: &Array2<f64>, dy: f64, dx: f64) -> Array2<f64> {
    let (n, cols) = a.dim();
    if n != cols || n == 0 || (dy == 0.0 && dx == 0.0) {
        return a.clone();
    }
    let mut data: Vec<Complex64> = a.iter().map(|v| Complex64::new(*v, 0.0)).collect();
    transform(&mut data, n, false);
    // The phase of DFT index k for a move of d samples. The even Nyquist index stands for
    // both +1/2 and −1/2 cycles per sample: it takes the mean of their ramps, cos(π d), which
    // is real (and exactly ±1 for a whole-pixel move).
    let ramp = |k: usize, d: f64| -> Complex64 {
        if 2 * k == n {
            Complex64::new((std::f64::consts::PI * d).cos(), 0.0)
        } else {
            let f = if 2 * k < n {
                k as f64 / n as f64
            } else {
                k as f64 / n as f64 - 1.0
            };
            Complex64::from_polar(1.0, -std::f64::consts::TAU * f * d)
        }
    };
    let ramp_x: Vec<Complex64> = (0..n).map(|k| ramp(k, dx)).collect();
    data.par_chunks_mut(n).enumerate().for_each(|(ky, row)| {
        let ry = ramp(ky, dy);
        for (v, rx) in row.iter_mut().zip(&ramp_x) {
            *v *= ry * rx;
        }
    });
    transform(&mut data, n, true);
    let scale = 1.0 / (n * n) as f64;
    Array2::from_shape_vec((n, n), data.iter().map(|c| c.re * scale).collect())
        .unwrap_or_else(|_| a.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_whole_pixel_shift_moves_every_sample() {
        let a = Array2::from_shape_fn((8, 8), |(y, x)| (y * 8 + x) as f64);
        let s = shifted(&a, 2.0, -3.0);
        for y in 0..8 {
            for x in 0..8 {
                let v = s[[(y + 2) % 8, (x + 5) % 8]];
                assert!((v - a[[y, x]]).abs() < 1e-9, "[{y}, {x}]");
            }
        }
    }

    #[test]
    fn a_half_pixel_shift_moves_the_centroid_and_keeps_the_sum() {
        let n = 32;
        let a = Array2::from_shape_fn((n, n), |(y, x)| {
            let (dy, dx) = (y as f64 - 16.0, x as f64 - 16.0);
            (-(dy * dy + dx * dx) / 6.0).exp()
        });
        let s = shifted(&a, 0.5, -0.25);
        let sum: f64 = s.sum();
        assert!((sum - a.sum()).abs() < 1e-9);
        let (mut cy, mut cx) = (0.0, 0.0);
        for ((y, x), v) in s.indexed_iter() {
            cy += y as f64 * v;
            cx += x as f64 * v;
        }
        assert!((cy / sum - 16.5).abs() < 1e-6, "{}", cy / sum);
        assert!((cx / sum - 15.75).abs() < 1e-6, "{}", cx / sum);
    }
}
