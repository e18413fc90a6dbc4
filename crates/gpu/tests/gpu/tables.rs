//! The tables the kernels read, checked in f64 on the CPU.

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;
use udc_gpu::tables::{chirp64, conv_len, kernel_spectrum, twiddles};

/// The recipe the kernels follow, run in f64 on the CPU: Bluestein with these tables gives
/// the direct DFT of an input shorter than m, for lengths with large prime factors.
#[test]
fn bluestein_with_these_tables_is_the_dft() {
    for (m, l) in [(6usize, 6usize), (1324, 700), (3050, 3050), (998, 17)] {
        let x: Vec<f64> = (0..l).map(|i| ((i * 7919) % 13) as f64 / 13.0).collect();
        let n = conv_len(m, l);
        let c = chirp64(m, m);
        let mut u = vec![Complex64::new(0.0, 0.0); n];
        for (i, &a) in x.iter().enumerate() {
            u[i] = a * c[i].conj();
        }
        udc_fft::complex_plan(n).process(&mut u);
        let v: Vec<Complex64> = kernel_spectrum(m, l, n)
            .iter()
            .map(|k| Complex64::new(f64::from(k[0]), f64::from(k[1])))
            .collect();
        // The kernel is in f32; the product's error is the f32 rounding of the table.
        u.iter_mut().zip(&v).for_each(|(a, b)| *a *= b);
        udc_fft::complex_inverse_plan(n).process(&mut u);
        let norm: f64 = x.iter().sum();
        for k in [0usize, 1, m / 3, m / 2, m - 1] {
            let direct: Complex64 = x
                .iter()
                .enumerate()
                .map(|(i, &a)| {
                    let t = ((i * k) % m) as f64 / m as f64;
                    a * Complex64::from_polar(1.0, -2.0 * PI * t)
                })
                .sum();
            let got = c[k].conj() * u[k] / n as f64;
            assert!(
                (got - direct).norm() < 1e-6 * norm,
                "m {m} l {l} k {k}: {got} vs {direct}"
            );
        }
    }
}

#[test]
fn the_chirp_angle_is_reduced_exactly() {
    let m = 12_288;
    let big = chirp64(m, 3 * m);
    // c_{j+m} = c_j · exp(iπ(2jm + m²)/m) = c_j · (−1)^m for even m.
    for j in [1usize, 999, m - 1] {
        assert!((big[j + m] - big[j]).norm() < 1e-12);
    }
    assert!(
        twiddles(8)
            .iter()
            .all(|t| (t[0].hypot(t[1]) - 1.0).abs() < 1e-7)
    );
}
