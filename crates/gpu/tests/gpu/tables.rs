//! The tables the kernels read, checked in f64 on the CPU.

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;
use udc_gpu::tables::{chirp64, conv_len, kernel_spectrum, twiddles, zoom};

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

/// The zoom the optimizer's window stages run, in f64 on the CPU with the `f32` tables:
/// `Σ_k x_k ω^{(s+k)(t+q)}` for negative and positive offsets, both signs of ω, a large prime
/// factor in `M` (1324 = 4·331) and offsets far past `M` (taken modulo `M`).
#[test]
fn the_zoom_tables_make_the_offset_dft() {
    let c = |v: &[f32; 2]| Complex64::new(f64::from(v[0]), f64::from(v[1]));
    for (m, (s, k_len), (t, q_len), conjugate) in [
        (1324usize, (-41i64, 83usize), (-150i64, 301usize), false),
        (1324, (-41, 83), (500, 290), true),
        (12, (-3, 5), (-6, 12), false),
        (998, (2000, 17), (-3001, 64), true),
    ] {
        let x: Vec<Complex64> = (0..k_len)
            .map(|i| Complex64::new(((i * 7919) % 13) as f64 / 13.0, ((i * 31) % 7) as f64 / 7.0))
            .collect();
        let z = zoom(m, (s, k_len), (t, q_len), conjugate);
        let n = z.kernel.len();
        assert!(n.is_power_of_two() && n >= k_len + q_len - 1);
        let mut u = vec![Complex64::new(0.0, 0.0); n];
        for (i, a) in x.iter().enumerate() {
            u[i] = a * c(&z.pre[i]);
        }
        udc_fft::complex_plan(n).process(&mut u);
        u.iter_mut().zip(&z.kernel).for_each(|(a, b)| *a *= c(b));
        udc_fft::complex_inverse_plan(n).process(&mut u);
        let norm: f64 = x.iter().map(|a| a.norm()).sum();
        let sign = if conjugate { 1.0 } else { -1.0 };
        for (q, (post, y)) in z.post.iter().zip(&u).enumerate() {
            let direct: Complex64 = x
                .iter()
                .enumerate()
                .map(|(k, a)| {
                    let e = ((s + k as i64) * (t + q as i64)).rem_euclid(m as i64);
                    a * Complex64::from_polar(1.0, sign * 2.0 * PI * e as f64 / m as f64)
                })
                .sum();
            // The post-chirp carries 1/N.
            let got = c(post) * y;
            assert!(
                (got - direct).norm() < 1e-6 * norm,
                "m {m} s {s} t {t} q {q}: {got} vs {direct}"
            );
        }
    }
}
