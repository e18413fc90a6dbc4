//! The FFT plans of `udc-fft`: cached per length and direction, and each transforms as named.
//! (Here rather than as the crate's unit tests: a test build of that crate would compile every
//! rustfft algorithm a second time.)

use std::sync::Arc;

use rustfft::num_complex::{Complex, Complex64};
use udc_fft::{
    FftDirection, complex_inverse_plan, complex_plan, complex_plan_f32, real_inverse_plan,
    real_plan,
};

/// Plans are made once per length and direction, and each transforms as its name says: a
/// unit impulse at sample 1 has the spectrum `exp(∓2πik/n)`, and the inverse undoes the
/// forward up to the factor `n`.
#[test]
fn plans_are_cached_and_transform_as_named() {
    let n = 12;
    assert!(Arc::ptr_eq(&complex_plan(n), &complex_plan(n)));
    assert!(!Arc::ptr_eq(&complex_plan(n), &complex_inverse_plan(n)));
    assert!(Arc::ptr_eq(
        &complex_plan_f32(n, true),
        &complex_plan_f32(n, true)
    ));
    assert_eq!(complex_plan(n).fft_direction(), FftDirection::Forward);
    assert_eq!(
        complex_inverse_plan(n).fft_direction(),
        FftDirection::Inverse
    );
    assert_eq!(
        complex_plan_f32(n, false).fft_direction(),
        FftDirection::Forward
    );
    let mut x = vec![Complex64::new(0.0, 0.0); n];
    x[1] = Complex64::new(1.0, 0.0);
    complex_plan(n).process(&mut x);
    for (k, v) in x.iter().enumerate() {
        let want = Complex64::from_polar(1.0, -2.0 * std::f64::consts::PI * k as f64 / n as f64);
        assert!((v - want).norm() < 1e-12, "k={k}: {v}");
    }
    complex_inverse_plan(n).process(&mut x);
    assert!((x[1] - Complex64::new(n as f64, 0.0)).norm() < 1e-12);
    let mut y = vec![Complex::<f32>::new(0.0, 0.0); n];
    y[1] = Complex::new(1.0, 0.0);
    complex_plan_f32(n, false).process(&mut y);
    assert!((y[3] - Complex::new(0.0, -1.0)).norm() < 1e-6, "{}", y[3]);
}

/// The real plans: a cosine of frequency 2 puts n/2 into bin 2 and comes back times n.
#[test]
fn real_plans_round_trip() {
    let n = 16;
    let forward = real_plan(n);
    assert!(Arc::ptr_eq(&forward, &real_plan(n)));
    let mut input: Vec<f64> = (0..n)
        .map(|i| (2.0 * std::f64::consts::PI * 2.0 * i as f64 / n as f64).cos())
        .collect();
    let original = input.clone();
    let mut spectrum = forward.make_output_vec();
    forward.process(&mut input, &mut spectrum).unwrap();
    assert!((spectrum[2].re - n as f64 / 2.0).abs() < 1e-12);
    assert!(spectrum[1].norm() < 1e-12);
    let inverse = real_inverse_plan(n);
    let mut back = inverse.make_output_vec();
    inverse.process(&mut spectrum, &mut back).unwrap();
    for (b, o) in back.iter().zip(&original) {
        assert!((b / n as f64 - o).abs() < 1e-12);
    }
}
