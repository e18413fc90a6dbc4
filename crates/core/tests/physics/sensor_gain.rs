//! Additive binning's two gain policies (Table 5.1, Fig. 5.4b, §5.6) and the flat-patch check of
//! eq. 5.3's η (conventions.md §8), by seeded Monte Carlo against the formulas. Tolerances come
//! from the sample sizes: a sample variance is compared within 3 standard errors (from the
//! sample's own fourth moment), a saturated fraction within 3 (one case) or 4 (a sweep of many
//! cases) binomial standard errors.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use ndarray::Array2;
use udc_core::Progress;
use udc_core::sensor::binning::{read_regions, read_sigma_e, variance};
use udc_core::sensor::flat::predicted_saturation;
use udc_core::sensor::gain::gain_for_light;
use udc_core::sensor::noise::{Adc, expose_frame};
use udc_core::sensor::{AdditiveGain, BinMode, FlatPatchSpec, RoiGrid, SensorSpec, flat_patch};

/// Table 5.4's sensor with a 20-bit ADC: Table 5.1 leaves quantisation out, and so do these
/// variances (≈ 1e-3 e⁻ steps).
fn fine_adc_sensor() -> SensorSpec {
    SensorSpec {
        adc_bits: 20,
        ..SensorSpec::table54()
    }
}

/// A flat 512×512 exposure at `light_e` read at pixel gain `gain` in `bin`-wide bins: one
/// estimate per bin (its top-left pixel carries it) and whether any bin saturated.
fn bin_estimates(
    frame: &udc_core::sensor::noise::Frame,
    sensor: &SensorSpec,
    gain: f64,
    bin: usize,
    mode: BinMode,
    additive: AdditiveGain,
) -> (Vec<f64>, bool) {
    let dim = frame.charge_e.dim();
    let grid = RoiGrid::new(dim, 64);
    let rois = (grid.rows, grid.cols);
    let r = read_regions(
        frame,
        &grid,
        &Array2::from_elem(rois, gain),
        &Array2::from_elem(rois, bin),
        mode,
        additive,
        &Adc::of(sensor),
    );
    let est = r
        .estimate_e
        .indexed_iter()
        .filter(|((y, x), _)| y % bin == 0 && x % bin == 0)
        .map(|(_, v)| *v)
        .collect();
    (est, r.saturated.iter().any(|s| *s))
}

/// `var(x) − var(y)` for paired samples (one exposure read two ways) and its standard error, from
/// the per-sample differences of squared deviations: common random numbers cancel.
fn variance_excess(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let d: Vec<f64> = x
        .iter()
        .zip(y)
        .map(|(a, b)| (a - mx).powi(2) - (b - my).powi(2))
        .collect();
    let md = d.iter().sum::<f64>() / n;
    let var_d = d.iter().map(|v| (v - md).powi(2)).sum::<f64>() / (n - 1.0);
    (md * n / (n - 1.0), (var_d / n).sqrt())
}

/// Sample mean, variance, and the standard error of the variance, `√((m4 − s⁴)/n)` from the
/// sample's fourth central moment (no Gaussian assumption: Poisson light is skewed).
fn moments(v: &[f64]) -> (f64, f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    let m4 = v.iter().map(|x| (x - m).powi(4)).sum::<f64>() / n;
    (m, var, ((m4 - var * var).max(0.0) / n).sqrt())
}

#[test]
fn table_5_1_additive_binning_at_both_gain_policies() {
    let sensor = fine_adc_sensor();
    // Dim light at low gain (Fig. 5.4b's setting), brighter light at higher gain, bigger bins.
    for (k, (light, gain, bin)) in [(2.0, 1.0, 2), (20.0, 4.0, 2), (2.0, 4.0, 4)]
        .into_iter()
        .enumerate()
    {
        let electrons = Array2::from_elem((512, 512), light);
        let frame = expose_frame(electrons.view(), &sensor, 40 + k as u64, 1);
        let n = bin * bin;
        for (mode, additive) in [
            (BinMode::AnalogAdditive, AdditiveGain::Scaled),
            (BinMode::AnalogAdditive, AdditiveGain::Same),
            (BinMode::AnalogAverage, AdditiveGain::Scaled),
            (BinMode::Digital, AdditiveGain::Scaled),
        ] {
            let what = format!("{mode:?} {additive:?} at {light} e⁻, g {gain}, N {n}");
            let (est, saturated) = bin_estimates(&frame, &sensor, gain, bin, mode, additive);
            assert!(!saturated, "{what}: Table 5.1 assumes nothing saturates");
            let amp = mode.amplifier_gain(gain, n, additive);
            let want = variance(mode, light, &sensor, amp, n);
            let (m, v, se_v) = moments(&est);
            let se_m = (want / est.len() as f64).sqrt();
            assert!((m - light).abs() < 3.0 * se_m, "{what}: mean {m} ± {se_m}");
            assert!(
                (v - want).abs() < 3.0 * se_v,
                "{what}: variance {v}, Table 5.1 {want} ± {se_v}"
            );
        }
    }
}

#[test]
fn with_the_same_gain_digital_binning_is_worse_than_additive() {
    // §5.6: "With the same gain, digital binning is slightly worse than analog additive binning."
    // Table 5.1 at ĝ = g: the read-noise terms are σ_post²/(N g²) against σ_post²/(N² g²).
    let sensor = fine_adc_sensor();
    for (k, (light, gain)) in [(2.0, 1.0), (20.0, 4.0)].into_iter().enumerate() {
        let electrons = Array2::from_elem((512, 512), light);
        let frame = expose_frame(electrons.view(), &sensor, 50 + k as u64, 1);
        let read = |mode, additive| bin_estimates(&frame, &sensor, gain, 2, mode, additive).0;
        // All read the same exposure: they differ only by how they combine it.
        let digital = read(BinMode::Digital, AdditiveGain::Same);
        let same = read(BinMode::AnalogAdditive, AdditiveGain::Same);
        let scaled = read(BinMode::AnalogAdditive, AdditiveGain::Scaled);
        let (excess, se) = variance_excess(&digital, &same);
        assert!(
            excess > 3.0 * se,
            "same gain {gain} at {light} e⁻: digital exceeds additive by {excess} ± {se}"
        );
        // At ĝ = g/N the order turns (§5.5.2): additive keeps σ_post²/g², digital divides it by N.
        let (excess, se) = variance_excess(&scaled, &digital);
        assert!(
            excess > 3.0 * se,
            "ĝ = g/N at {light} e⁻: additive exceeds digital by {excess} ± {se}"
        );
    }
    // The formulas behind both statements, for any bin and gain.
    for n in [4usize, 16, 64] {
        for gain in [1.0, 2.5, 16.0] {
            let s = &sensor;
            let read = |mode, additive| read_sigma_e(mode, additive, s, gain, n).powi(2);
            let pre = s.sigma_pre_e.powi(2) / n as f64;
            let post = |v: f64| v - pre;
            let digital = read(BinMode::Digital, AdditiveGain::Same);
            let same = read(BinMode::AnalogAdditive, AdditiveGain::Same);
            let scaled = read(BinMode::AnalogAdditive, AdditiveGain::Scaled);
            let average = read(BinMode::AnalogAverage, AdditiveGain::Same);
            let nf = n as f64;
            // ĝ = g: additive's post-amplifier term is N× below digital's.
            assert!((post(digital) / post(same) - nf).abs() < 1e-9 * nf);
            // ĝ = g/N: σ_post²/(N² ĝ²) = σ_post²/g², average's, N× digital's.
            assert!((scaled - average).abs() < 1e-12 * average);
            assert!((post(scaled) / post(digital) - nf).abs() < 1e-9 * nf);
            assert!((post(scaled) - (s.sigma_post_e / gain).powi(2)).abs() < 1e-12);
        }
    }
}

/// `|measured − predicted| ≤ k` binomial standard errors (plus one readout, for p at 0 or 1).
fn assert_close(r: &udc_core::sensor::FlatPatch, k: f64, what: &str) {
    let slack = k * r.standard_error + 1.0 / r.readouts as f64;
    assert!(
        (r.saturated_fraction - r.predicted).abs() <= slack,
        "{what}: measured {}, predicted {} ± {}",
        r.saturated_fraction,
        r.predicted,
        r.standard_error
    );
}

#[test]
fn the_flat_patch_measures_what_the_model_predicts() {
    let sensor = SensorSpec::table54();
    // Dark (gain near the maximum, few electrons: discreteness), mid, bright (gain clamped to 1
    // at η = 4). With the bins below, 18 cases: 4 standard errors each.
    for light_e in [10.0, 100.0, 400.0, 900.0] {
        for eta in [2.0, 4.0] {
            let spec = FlatPatchSpec {
                light_e,
                eta,
                seed: 7,
                ..FlatPatchSpec::default()
            };
            let r = flat_patch(&spec, &sensor, &Progress::new()).unwrap();
            assert_eq!(r.readouts, 512 * 512);
            let g = gain_for_light(light_e, eta, sensor.full_well_e, sensor.max_gain);
            assert_eq!(r.gain, g);
            assert_close(&r, 4.0, &format!("{light_e} e⁻, η {eta}"));
        }
    }
    // Bins: digital (any of N pixels saturates), analog sums at both gain policies, average.
    for (bin_px, bin_mode, additive_gain) in [
        (2, BinMode::Digital, AdditiveGain::Scaled),
        (2, BinMode::AnalogAdditive, AdditiveGain::Scaled),
        (2, BinMode::AnalogAdditive, AdditiveGain::Same),
        (2, BinMode::AnalogAverage, AdditiveGain::Same),
        (4, BinMode::Digital, AdditiveGain::Same),
    ] {
        for light_e in [25.0, 400.0] {
            let spec = FlatPatchSpec {
                light_e,
                bin_px,
                bin_mode,
                additive_gain,
                seed: 8,
                ..FlatPatchSpec::default()
            };
            let r = flat_patch(&spec, &sensor, &Progress::new()).unwrap();
            assert_eq!(r.readouts, (512 / bin_px).pow(2));
            let what = format!("{bin_px}x{bin_px} {bin_mode:?} {additive_gain:?} at {light_e} e⁻");
            assert_close(&r, 4.0, &what);
        }
    }
}

#[test]
fn eta_2_saturates_about_2_2_percent_of_a_flat_patch() {
    // Eq. 5.3's "2.2 %" is 1 − Φ(2) = 2.28 %, from a Gaussian of variance g² l̂. The model's
    // Poisson tail is heavier: to first order in 1/√l̂ the threshold moves down by the skewness
    // term (η² − 1)/(6√l̂) and at most a half-electron continuity step 1/(2√l̂), so the excess
    // over 1 − Φ(η) is at most φ(η)·((η² − 1)/6 + 1/2)/√l̂ (20 % kept for higher orders).
    let cases = [
        (SensorSpec::table54(), 400.0),
        // A large well reaches large l̂ at gains above 1: the excess shrinks as 1/√l̂.
        (SensorSpec::named("nikon-z5").unwrap(), 10_000.0),
    ];
    let eta: f64 = 2.0;
    let phi = (-eta * eta / 2.0).exp() / (2.0 * std::f64::consts::PI).sqrt();
    for (sensor, light_e) in cases {
        let spec = FlatPatchSpec {
            light_e,
            eta,
            seed: 11,
            ..FlatPatchSpec::default()
        };
        let r = flat_patch(&spec, &sensor, &Progress::new()).unwrap();
        let what = format!("{} at {light_e} e⁻", sensor.name);
        assert!(
            r.gain > 1.0 && r.gain < sensor.max_gain,
            "{what}: unclamped"
        );
        assert_close(&r, 3.0, &what);
        assert!((r.gaussian_tail - 0.022_750_13).abs() < 1e-7);
        let excess = r.predicted - r.gaussian_tail;
        let bound = 1.2 * phi * ((eta * eta - 1.0) / 6.0 + 0.5) / light_e.sqrt();
        assert!(
            excess > 0.0 && excess < bound,
            "{what}: predicted {} vs 1 − Φ(η) {}: excess {excess}, bound {bound}",
            r.predicted,
            r.gaussian_tail
        );
    }
}

#[test]
fn an_additive_sum_at_the_same_gain_saturates_n_times_sooner() {
    let sensor = SensorSpec::table54();
    let (light_e, eta) = (400.0, 2.0);
    let g = gain_for_light(light_e, eta, sensor.full_well_e, sensor.max_gain);
    let pixel = predicted_saturation(
        light_e,
        g,
        1,
        BinMode::Digital,
        AdditiveGain::Scaled,
        &sensor,
    );
    for bin in [2usize, 4] {
        let n = (bin * bin) as f64;
        let at = |light: f64, additive| {
            predicted_saturation(light, g, bin, BinMode::AnalogAdditive, additive, &sensor)
        };
        // At ĝ = g a bin at l/N holds the charge one pixel at l holds, read at the same gain:
        // the same tail, but for the N pixels' pre-amplifier noise (g²(N − 1)σ_pre² against
        // g² l̂: under 1 % of the spread).
        let same = at(light_e / n, AdditiveGain::Same);
        assert!((same / pixel - 1.0).abs() < 0.02, "{same} vs {pixel}");
        // At ĝ = g/N the bin at l saturates less than one pixel at l: no extra saturation.
        assert!(at(light_e, AdditiveGain::Scaled) < pixel);
        // Measured: a flat patch at l/N read in additive bins at the gain for l.
        let electrons = Array2::from_elem((512, 512), light_e / n);
        let frame = expose_frame(electrons.view(), &sensor, 12, 1);
        let grid = RoiGrid::new((512, 512), 64);
        let rois = (grid.rows, grid.cols);
        let r = read_regions(
            &frame,
            &grid,
            &Array2::from_elem(rois, g),
            &Array2::from_elem(rois, bin),
            BinMode::AnalogAdditive,
            AdditiveGain::Same,
            &Adc::of(&sensor),
        );
        let readouts = (512 / bin).pow(2) as f64;
        let measured = r.saturated_fraction();
        let se = (same * (1.0 - same) / readouts).sqrt();
        assert!(
            (measured - same).abs() < 3.0 * se,
            "{measured} vs {same} ± {se}"
        );
    }
}

#[test]
fn bad_flat_patches_name_their_field() {
    let sensor = SensorSpec::table54();
    let d = FlatPatchSpec::default();
    let cases = [
        (
            FlatPatchSpec {
                light_e: -1.0,
                ..d.clone()
            },
            "light_e",
        ),
        (
            FlatPatchSpec {
                light_e: f64::NAN,
                ..d.clone()
            },
            "light_e",
        ),
        (
            FlatPatchSpec {
                eta: f64::INFINITY,
                ..d.clone()
            },
            "eta",
        ),
        (
            FlatPatchSpec {
                bin_px: 3,
                ..d.clone()
            },
            "bin_px",
        ),
        (
            FlatPatchSpec {
                side_px: 100,
                bin_px: 8,
                ..d.clone()
            },
            "side_px",
        ),
        (
            FlatPatchSpec {
                side_px: 8,
                ..d.clone()
            },
            "side_px",
        ),
    ];
    for (spec, field) in cases {
        match flat_patch(&spec, &sensor, &Progress::new()) {
            Err(udc_core::SimError::InvalidSetting { path: f, .. }) => assert_eq!(f, field),
            other => panic!("{field}: {other:?}"),
        }
    }
    // A black patch is valid: maximum gain, nothing saturates, as predicted.
    let dark = FlatPatchSpec {
        light_e: 0.0,
        side_px: 64,
        ..d
    };
    let r = flat_patch(&dark, &sensor, &Progress::new()).unwrap();
    assert_eq!(r.gain, sensor.max_gain);
    assert_eq!((r.saturated_fraction, r.predicted), (0.0, 0.0));
}
