//! The optimal-pitch analysis of §5.5.1 (conventions.md §8): contrast and noise (Fig. 5.3a), the
//! cutoff frequency, and the optimal pitch against light (Fig. 5.3b) with conventions.md's sanity
//! points.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use proptest::prelude::*;
use udc_core::sensor::SensorSpec;
use udc_core::sensor::pitch::{
    contrast_noise, cutoff_cyc_per_um, noise_sigma_e, nyquist_cyc_per_um, optimal_bin,
    optimal_pitch_curve, optimal_pitch_um,
};

/// The bin pitches of Table 5.4's sensor: 1, 2, 4 and 8 pixels of 0.5 µm.
const PITCHES: [f64; 4] = [0.5, 1.0, 2.0, 4.0];

#[test]
fn contrast_is_l0_p_sin_over_pi_f_and_noise_is_flat() {
    let s = SensorSpec::table54();
    let (l0, p, g) = (20.0, 2.0, 1.0);
    let freqs = [0.0, 0.1, 0.25, 0.5, 1.0 / p];
    let (c, n) = contrast_noise(l0, p, &s, g, &freqs);
    assert!((c[0] - l0 * p * p).abs() < 1e-12, "c(0) = l0 p²");
    let f = 0.1;
    let want = l0 * p * (std::f64::consts::PI * p * f).sin() / (std::f64::consts::PI * f);
    assert!((c[1] - want).abs() < 1e-9, "{} vs {want}", c[1]);
    assert!(c[4].abs() < 1e-9, "first zero at 1/p");
    let sigma = (0.33f64.powi(2) + 3.31f64.powi(2) / (g * g) + l0 * p * p / 2.0).sqrt();
    assert!(n.iter().all(|v| (v - sigma).abs() < 1e-12));
    assert_eq!(noise_sigma_e(l0, p, &s, g), sigma);
    assert_eq!(nyquist_cyc_per_um(p), 0.25);
}

#[test]
fn the_cutoff_is_where_contrast_over_noise_falls_to_snr_t() {
    let s = SensorSpec::table54();
    for (l0, p) in [(20.0, 2.0), (100.0, 0.5), (5.0, 4.0), (1000.0, 1.0)] {
        let f = cutoff_cyc_per_um(l0, p, &s, 1.0, 4.0);
        assert!(f > 0.0 && f < 1.0 / p, "{l0} {p}: {f}");
        let (c, n) = contrast_noise(l0, p, &s, 1.0, &[f]);
        assert!(
            (c[0] / n[0] - 4.0).abs() < 1e-6,
            "{l0} {p}: {}",
            c[0] / n[0]
        );
    }
    // Too dark for small pixels: even the mean level is below SNR_t.
    assert_eq!(cutoff_cyc_per_um(2.0, 0.5, &s, 1.0, 4.0), 0.0);
    // The cutoff is not clamped at Nyquist (as in the thesis): bright light passes it.
    let f = cutoff_cyc_per_um(1000.0, 1.0, &s, 1.0, 4.0);
    assert!(f > nyquist_cyc_per_um(1.0), "{f}");
}

#[test]
fn physics_md_sanity_points() {
    // σ_pre 0.33, σ_post 3.31, g 1: 4 µm at ~2–5 e⁻/µm², 2 µm at ~20, 0.5 µm above ~100.
    let s = SensorSpec::table54();
    for l0 in [2.0, 3.0, 5.0] {
        assert_eq!(optimal_pitch_um(l0, &PITCHES, &s, 1.0, 4.0), 4.0, "{l0}");
    }
    assert_eq!(optimal_pitch_um(20.0, &PITCHES, &s, 1.0, 4.0), 2.0);
    for l0 in [110.0, 200.0, 1000.0, 1e5] {
        assert_eq!(optimal_pitch_um(l0, &PITCHES, &s, 1.0, 4.0), 0.5, "{l0}");
    }
    assert_eq!(optimal_bin(20.0, &s, 1.0, 4.0), 4);
    assert_eq!(optimal_bin(500.0, &s, 1.0, 4.0), 1);
    // In the dark nothing is resolved: the largest pitch.
    assert_eq!(optimal_pitch_um(0.01, &PITCHES, &s, 1.0, 4.0), 4.0);
    assert!(optimal_pitch_um(1.0, &[], &s, 1.0, 4.0).is_nan());
}

#[test]
fn optimal_pitch_decreases_as_light_rises() {
    let s = SensorSpec::table54();
    let lights: Vec<f64> = (0..=60)
        .map(|k| 10f64.powf(-0.5 + k as f64 * 0.1))
        .collect();
    let fine: Vec<f64> = (5..=160).map(|k| k as f64 * 0.05).collect();
    for (gain, candidates) in [(1.0, &PITCHES[..]), (1.0, &fine[..]), (64.0, &fine[..])] {
        let curve = optimal_pitch_curve(&lights, candidates, &s, gain, 4.0);
        for w in curve.windows(2) {
            assert!(w[1] <= w[0], "g {gain}: {curve:?}");
        }
        assert!(curve[0] > curve[curve.len() - 1], "it moves");
    }
    // A higher gain lowers the read noise: the optimum is never larger.
    for l in &lights {
        assert!(
            optimal_pitch_um(*l, &fine, &s, 64.0, 4.0) <= optimal_pitch_um(*l, &fine, &s, 1.0, 4.0)
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, rng_seed: proptest::test_runner::RngSeed::Fixed(3), ..ProptestConfig::default() })]

    /// For any sensor noise, gain and threshold, the optimal pitch is non-increasing in light.
    #[test]
    fn optimal_pitch_is_monotone_for_any_sensor(
        pre in 0.0f64..3.0,
        post in 0.0f64..10.0,
        gain in 1.0f64..100.0,
        snr_t in 1.0f64..8.0,
        l in 0.1f64..1000.0,
        factor in 1.0f64..10.0,
    ) {
        let s = SensorSpec { sigma_pre_e: pre, sigma_post_e: post, ..SensorSpec::table54() };
        let fine: Vec<f64> = (1..=64).map(|k| k as f64 * 0.125).collect();
        let lo = optimal_pitch_um(l, &fine, &s, gain, snr_t);
        let hi = optimal_pitch_um(l * factor, &fine, &s, gain, snr_t);
        prop_assert!(hi <= lo, "{l} → {lo}, {} → {hi}", l * factor);
    }
}
