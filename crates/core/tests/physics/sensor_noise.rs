//! Monte-Carlo checks of the sensor noise model (thesis §5.3–5.5, conventions.md §8): eq. 5.1's
//! mean and variance, Table 5.1's four binning variances, eq. 5.3's gain and its 2.2 %
//! saturation at η = 2, the per-pixel and alternating-row readouts, and dynamic range.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use ndarray::Array2;
use proptest::prelude::*;
use udc_core::sensor::binning::{read_regions, variance};
use udc_core::sensor::gain::{
    dynamic_range, gain_for_light, ratio_db, read_alternating_rows, read_per_pixel,
};
use udc_core::sensor::noise::{Adc, expose_frame, read_bin};
use udc_core::sensor::{AdditiveGain, BinMode, RoiGrid, SensorSpec};

/// Table 5.4's sensor with a 20-bit ADC: quantisation (≈ 1e-3 e⁻) vanishes from the variances.
fn fine_adc_sensor() -> SensorSpec {
    SensorSpec {
        adc_bits: 20,
        ..SensorSpec::table54()
    }
}

fn mean_var(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    (
        m,
        v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0),
    )
}

/// Mean within 5 standard errors and variance within 5 standard errors of the sample variance
/// (`σ² √(2/(n−1))`, nearly Gaussian data).
fn assert_moments(samples: &[f64], want_mean: f64, want_var: f64, what: &str) {
    let n = samples.len() as f64;
    let (m, v) = mean_var(samples);
    let se_mean = (want_var / n).sqrt();
    assert!(
        (m - want_mean).abs() < 5.0 * se_mean,
        "{what}: mean {m}, expected {want_mean} ± {se_mean}"
    );
    let se_var = want_var * (2.0 / (n - 1.0)).sqrt();
    assert!(
        (v - want_var).abs() < 5.0 * se_var,
        "{what}: variance {v}, expected {want_var} ± {se_var}"
    );
}

/// Reads a flat field of `light_e` per pixel at `gain`, one pixel at a time.
fn flat_readout(sensor: &SensorSpec, light_e: f64, gain: f64, side: usize, seed: u64) -> Vec<f64> {
    let electrons = Array2::from_elem((side, side), light_e);
    let frame = expose_frame(electrons.view(), sensor, seed, 1);
    let grid = RoiGrid::new((side, side), side);
    let r = read_regions(
        &frame,
        &grid,
        &Array2::from_elem((1, 1), gain),
        &Array2::from_elem((1, 1), 1),
        BinMode::Digital,
        AdditiveGain::Scaled,
        &Adc::of(sensor),
    );
    r.estimate_e.iter().copied().collect()
}

#[test]
fn eq_5_1_estimate_is_unbiased_with_the_stated_variance() {
    let sensor = fine_adc_sensor();
    for (light, gain) in [
        (0.5, 1.0),
        (5.0, 1.0),
        (5.0, 16.0),
        (50.0, 4.0),
        (300.0, 1.0),
    ] {
        let v = flat_readout(&sensor, light, gain, 256, 11);
        let want = light + sensor.sigma_pre_e.powi(2) + (sensor.sigma_post_e / gain).powi(2);
        assert_moments(&v, light, want, &format!("l* {light}, g {gain}"));
    }
    // With the 12-bit ADC the quantisation step q = l_wc / (4095 − 205) / g adds q²/12.
    let sensor = SensorSpec::table54();
    let adc = Adc::of(&sensor);
    assert_eq!((adc.max_code, adc.black_dn), (4095.0, 205.0));
    let (light, gain) = (3.0, 2.0);
    let q = adc.e_per_dn / gain;
    let v = flat_readout(&sensor, light, gain, 256, 12);
    let want = light + sensor.sigma_pre_e.powi(2) + (sensor.sigma_post_e / gain).powi(2);
    assert_moments(&v, light, want + q * q / 12.0, "12-bit ADC");
}

#[test]
fn the_black_level_keeps_dark_pixels_unbiased() {
    // Without a black level, negative read noise would clip at code 0 and bias the dark.
    let sensor = SensorSpec::table54();
    let v = flat_readout(&sensor, 0.2, 1.0, 256, 13);
    let (m, _) = mean_var(&v);
    assert!(v.iter().any(|x| *x < 0.0), "negative estimates exist");
    assert!((m - 0.2).abs() < 0.05, "mean {m}");
}

#[test]
fn table_5_1_variances_of_the_four_binning_modes() {
    let sensor = fine_adc_sensor();
    let adc = Adc::of(&sensor);
    let (light, gain, side) = (20.0, 4.0, 512);
    let electrons = Array2::from_elem((side, side), light);
    let frame = expose_frame(electrons.view(), &sensor, 21, 1);
    // 2×2 bins (N = 4): gather each bin's four charges and post-amplifier samples.
    let bins: Vec<(Vec<f64>, Vec<f64>)> = (0..side / 2)
        .flat_map(|by| (0..side / 2).map(move |bx| (by, bx)))
        .map(|(by, bx)| {
            let px = [(0, 0), (0, 1), (1, 0), (1, 1)].map(|(dy, dx)| (2 * by + dy, 2 * bx + dx));
            (
                px.iter().map(|p| f64::from(frame.charge_e[*p])).collect(),
                px.iter()
                    .map(|p| f64::from(frame.post_noise_e[*p]))
                    .collect(),
            )
        })
        .collect();
    let n = 4;
    let cases = [
        ("no binning", BinMode::Digital, gain, 1),
        ("additive, ĝ = g/N", BinMode::AnalogAdditive, gain / 4.0, n),
        ("additive, ĝ = g", BinMode::AnalogAdditive, gain, n),
        ("average", BinMode::AnalogAverage, gain, n),
        ("digital", BinMode::Digital, gain, n),
    ];
    for (what, mode, amp, pixels) in cases {
        let est: Vec<f64> = bins
            .iter()
            .map(|(c, p)| read_bin(mode, amp, &c[..pixels], &p[..pixels], &adc).estimate_e)
            .collect();
        let want = variance(mode, light, &sensor, amp, pixels);
        assert_moments(&est, light, want, what);
    }
    // The thesis's point (§5.5.2): with ĝ = g/N additive binning keeps σ_post²/g² (average
    // binning's), digital binning divides it by N.
    let add = variance(BinMode::AnalogAdditive, light, &sensor, gain / 4.0, n);
    let avg = variance(BinMode::AnalogAverage, light, &sensor, gain, n);
    let dig = variance(BinMode::Digital, light, &sensor, gain, n);
    assert!((add - avg).abs() < 1e-12 && dig < avg, "{add} {avg} {dig}");
}

#[test]
fn read_regions_bins_like_read_bin() {
    let sensor = SensorSpec::table54();
    let adc = Adc::of(&sensor);
    let electrons = Array2::from_shape_fn((40, 40), |(y, x)| (y * 40 + x) as f64 * 0.3);
    let frame = expose_frame(electrons.view(), &sensor, 5, 1);
    let grid = RoiGrid::new((40, 40), 20);
    for (mode, additive) in [
        (BinMode::AnalogAdditive, AdditiveGain::Scaled),
        (BinMode::AnalogAdditive, AdditiveGain::Same),
        (BinMode::AnalogAverage, AdditiveGain::Same),
        (BinMode::Digital, AdditiveGain::Same),
    ] {
        let r = read_regions(
            &frame,
            &grid,
            &Array2::from_elem((2, 2), 3.0),
            &Array2::from_elem((2, 2), 8),
            mode,
            additive,
            &adc,
        );
        // ROI (1, 1) starts at pixel (20, 20); its last bins are cut to 4 px by the ROI edge.
        for (y0, x0, side) in [(20, 20, 8), (36, 36, 4)] {
            let idx: Vec<(usize, usize)> = (y0..y0 + side)
                .flat_map(|y| (x0..x0 + side).map(move |x| (y, x)))
                .collect();
            let c: Vec<f64> = idx.iter().map(|p| f64::from(frame.charge_e[*p])).collect();
            let p: Vec<f64> = idx
                .iter()
                .map(|p| f64::from(frame.post_noise_e[*p]))
                .collect();
            let amp = mode.amplifier_gain(3.0, c.len(), additive);
            let want = read_bin(mode, amp, &c, &p, &adc).estimate_e;
            for q in &idx {
                assert_eq!(r.estimate_e[*q], want, "{mode:?} at {q:?}");
                assert_eq!(r.bin[*q], 8);
                assert_eq!(r.gain[*q], 3.0);
            }
        }
    }
}

#[test]
fn eta_2_saturates_about_2_2_percent_of_a_flat_field() {
    let sensor = SensorSpec::table54();
    let light = 400.0;
    let gain = gain_for_light(light, 2.0, sensor.full_well_e, sensor.max_gain);
    assert!((gain - 1000.0 / 440.0).abs() < 1e-12, "{gain}");
    let side = 512;
    let electrons = Array2::from_elem((side, side), light);
    let frame = expose_frame(electrons.view(), &sensor, 3, 1);
    let grid = RoiGrid::new((side, side), side);
    let r = read_regions(
        &frame,
        &grid,
        &Array2::from_elem((1, 1), gain),
        &Array2::from_elem((1, 1), 1),
        BinMode::Digital,
        AdditiveGain::Scaled,
        &Adc::of(&sensor),
    );
    let fraction = r.saturated_fraction();
    // 1 − Φ(2) = 2.28 %; the thesis says ≈ 2.2 %.
    assert!((0.018..0.028).contains(&fraction), "{fraction}");
    // η = 4 makes saturation rare.
    let g4 = gain_for_light(light, 4.0, sensor.full_well_e, sensor.max_gain);
    let r4 = read_regions(
        &frame,
        &grid,
        &Array2::from_elem((1, 1), g4),
        &Array2::from_elem((1, 1), 1),
        BinMode::Digital,
        AdditiveGain::Scaled,
        &Adc::of(&sensor),
    );
    assert!(r4.saturated_fraction() < 1e-3);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, rng_seed: proptest::test_runner::RngSeed::Fixed(5), ..ProptestConfig::default() })]

    /// Eq. 5.3 never exceeds the maximum (nor goes below base gain), is monotone in the light
    /// level, and where it is not clamped keeps `g l + η g √l` at the well capacity.
    #[test]
    fn eq_5_3_gain_is_bounded_and_monotone(
        l1 in 0.0f64..5000.0,
        dl in 0.0f64..5000.0,
        eta in 0.0f64..6.0,
        well in 10.0f64..20000.0,
        max_gain in 1.0f64..600.0,
    ) {
        let g1 = gain_for_light(l1, eta, well, max_gain);
        let g2 = gain_for_light(l1 + dl, eta, well, max_gain);
        prop_assert!((1.0..=max_gain).contains(&g1));
        prop_assert!(g2 <= g1);
        if g1 > 1.0 && g1 < max_gain {
            let filled = g1 * l1 + eta * g1 * l1.sqrt();
            prop_assert!((filled - well).abs() < 1e-9 * well);
        }
    }
}

#[test]
fn dynamic_range_goes_from_l_wc_over_sigma_post_to_l_wc_over_sigma_pre() {
    let s = SensorSpec::table54();
    let base = dynamic_range(&s, 1.0);
    let top = dynamic_range(&s, s.max_gain);
    // Constant base gain: ≈ l_wc / σ_post (σ_pre is a tenth of it).
    assert!(
        (base / (s.full_well_e / s.sigma_post_e) - 1.0).abs() < 0.01,
        "{base}"
    );
    // The maximum gain the varying strategies reach: ≈ l_wc / σ_pre.
    assert!(
        (top / (s.full_well_e / s.sigma_pre_e) - 1.0).abs() < 0.015,
        "{top}"
    );
    assert!(
        (ratio_db(top) - ratio_db(base) - 20.0).abs() < 0.3,
        "one decade more"
    );
}

#[test]
fn per_pixel_gain_follows_the_previous_pixel_and_resets_after_saturation() {
    let sensor = SensorSpec::table54();
    // One row: 40 dark pixels (1 e⁻), then 40 bright ones (900 e⁻).
    let electrons = Array2::from_shape_fn((4, 80), |(_, x)| if x < 40 { 1.0 } else { 900.0 });
    let frame = expose_frame(electrons.view(), &sensor, 9, 1);
    let r = read_per_pixel(&frame, &sensor, 4.0);
    for y in 0..4 {
        assert_eq!(r.gain[[y, 0]], 1.0, "each row starts at base gain");
        // In the dark the gain climbs to the maximum.
        assert!(r.gain[[y, 39]] > 30.0, "{}", r.gain[[y, 39]]);
        // The first bright pixel is read at that gain and saturates; the next is at base gain.
        assert!(r.saturated[[y, 40]]);
        assert_eq!(r.gain[[y, 41]], 1.0);
        for x in 1..80 {
            let prev = r.estimate_e[[y, x - 1]];
            let want = if r.saturated[[y, x - 1]] {
                1.0
            } else {
                gain_for_light(prev, 4.0, sensor.full_well_e, sensor.max_gain)
            };
            assert_eq!(r.gain[[y, x]], want as f32, "({y}, {x})");
        }
        // Bright pixels after the reset: gain ≈ 1000/(900 + 4·30) ≈ 0.98 → 1, unsaturated.
        assert!(r.saturated.row(y).iter().skip(42).all(|s| !*s));
    }
}

#[test]
fn alternating_rows_use_high_gain_rows_in_the_dark() {
    let sensor = SensorSpec::table54();
    let electrons = Array2::from_elem((256, 256), 2.0);
    let frame = expose_frame(electrons.view(), &sensor, 4, 1);
    let alt = read_alternating_rows(&frame, &sensor, 1.0, sensor.max_gain);
    assert_eq!(alt.gain[[0, 0]], 1.0);
    assert_eq!(f64::from(alt.gain[[1, 0]]), sensor.max_gain);
    // Even rows are interpolated from the high-gain rows: far less read noise than base gain.
    let even: Vec<f64> = (0..128)
        .flat_map(|k| alt.estimate_e.row(2 * k).to_vec())
        .collect();
    let (_, v_alt) = mean_var(&even);
    let base = flat_readout(&sensor, 2.0, 1.0, 256, 4);
    let (_, v_base) = mean_var(&base);
    assert!(v_alt < 0.3 * v_base, "{v_alt} vs {v_base}");
    assert!(alt.saturated.iter().all(|s| !*s));
}
