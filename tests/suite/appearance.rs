//! Display appearance (thesis §3.7, Fig. 3.27–3.28): the eye-blurred rendering, the display
//! quality numbers, the `appearance` CLI and the wiring-gap check.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use ndarray::Array2;
use udc_studio::core::Progress;
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::design::{Design, Opening, Subpixel, Subpixels};
use udc_studio::core::display::appearance::{AppearanceSettings, DisplayQuality, appearance};
use udc_studio::io::design::presets::load_preset;

use crate::common::run_cli as run;

fn quality(design: &Design, s: &AppearanceSettings) -> DisplayQuality {
    let grey = vec![Array2::from_elem((32, 32), 0.5)];
    appearance(design, &grey, s, &Progress::new())
        .expect("renders")
        .0
}

/// An opaque pixel with R, G, B in three 7-column stripes.
fn stripes() -> Design {
    let mut d = Design {
        opening: Opening::open(21, 168.0),
        ..Default::default()
    };
    d.opening.cells = vec![vec![0.0; 21]; 21];
    let mut sp = Subpixels::empty(21);
    for row in &mut sp.cells {
        for (c, s) in row.iter_mut().enumerate() {
            *s = Some(Subpixel::ALL[c / 7]);
        }
    }
    d.subpixels = Some(sp);
    d
}

#[test]
fn stripes_far_below_the_eyes_resolution_look_uniform() {
    // 2000 DPI: a 12.7 µm period against an 87 µm eye FWHM at 300 mm; the fundamental is
    // attenuated by exp(-2 pi^2 sigma^2 f^2) ~ e^-168.
    let s = AppearanceSettings {
        dpi: 2000.0,
        region_mm: 1.0,
        ..AppearanceSettings::default()
    };
    let q = quality(&stripes(), &s);
    assert!(q.nonuniformity < 1e-6, "{q:?}");
    assert!(q.aliasing < 1e-3, "{q:?}");
    // At 100 DPI the stripes are resolved.
    let q = quality(
        &stripes(),
        &AppearanceSettings {
            dpi: 100.0,
            ..AppearanceSettings::default()
        },
    );
    assert!(q.nonuniformity > 0.05, "{q:?}");
}

#[test]
fn a_periodic_layouts_flat_field_energy_sits_at_pixel_harmonics() {
    let s = AppearanceSettings {
        dpi: 150.0,
        ..AppearanceSettings::default()
    };
    let periodic = quality(&load_preset("l2inv-repeat").unwrap(), &s);
    let random = quality(&load_preset("l2inv-random").unwrap(), &s);
    println!("periodic {periodic:?}\nrandom {random:?}");
    assert!(periodic.harmonic_fraction > 0.999, "{periodic:?}");
    assert!(random.harmonic_fraction < 0.9, "{random:?}");
}

#[test]
fn a_longer_viewing_distance_lowers_nonuniformity_and_aliasing() {
    let d = load_preset("l2inv-random").unwrap();
    let near = quality(&d, &AppearanceSettings::default());
    let far = quality(
        &d,
        &AppearanceSettings {
            viewing_distance_mm: 600.0,
            ..AppearanceSettings::default()
        },
    );
    println!("near {near:?}\nfar {far:?}");
    assert!(far.nonuniformity < near.nonuniformity, "{near:?} {far:?}");
    assert!(far.aliasing < near.aliasing, "{near:?} {far:?}");
}

#[test]
fn appearance_cli_prints_quality_beside_the_camera_auc() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (ok, stdout, stderr) = run(&[
        "appearance",
        "--preset",
        "toled-150dpi",
        "--dpi",
        "300",
        "--viewing-distance-mm",
        "300",
        "--preview",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    let q = &v["display_quality"];
    for key in [
        "nonuniformity",
        "aliasing",
        "harmonic_fraction",
        "image_error",
    ] {
        assert!(q[key].as_f64().is_some_and(f64::is_finite), "{key}: {v}");
    }
    assert!(v["camera_auc"].as_f64().is_some_and(|a| a > 0.0), "{v}");
    assert!(out.join("appearance.png").is_file());
    // Fig. 3.27's pair: the periodic one is this (periodic) preset's own rendering, so its
    // numbers are the design's; both pictures are written.
    let t = v["tilings"].as_array().expect("tilings");
    assert_eq!(t.len(), 2, "{v}");
    assert_eq!(t[0]["tiling"], "periodic");
    assert_eq!(t[0]["nonuniformity"], q["nonuniformity"], "{v}");
    assert!(
        t[1]["tiling"].as_str().unwrap().starts_with("random"),
        "{v}"
    );
    assert!(out.join("appearance-periodic.png").is_file());
    assert!(out.join("appearance-random.png").is_file());
}

#[test]
fn appearance_cli_refuses_bad_values_naming_the_flag() {
    for (flag, value) in [
        ("--dpi", "0"),
        ("--viewing-distance-mm", "-5"),
        ("--region-mm", "NaN"),
    ] {
        let (ok, _, stderr) = run(&["appearance", "--preset", "toled-150dpi", flag, value]);
        assert!(!ok, "{flag} {value} accepted");
        assert!(stderr.contains(flag), "{flag}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    let (ok, _, stderr) = run(&["appearance", "--preset", "open-aperture"]);
    assert!(!ok);
    assert!(stderr.contains("subpixels"), "{stderr}");
}

fn rel_l2(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
    let diff: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let norm: f64 = a.iter().map(|x| x * x).sum();
    (diff / norm).sqrt()
}

/// Thesis Fig. 3.28: an 8 µm opaque wiring gap around the Top-10 L2+Inv random pixel has "a
/// negligible effect on the PSF" (a visual claim). Measured against the change a random layout
/// cannot avoid, drawing another realisation (seed), the gap is not negligible: the display
/// period grows 168 -> 176 µm, the diffraction orders move by `lambda f (1/168 - 1/176 µm)`
/// ~ 1.6 µm at 610 nm (0.8 of a 2 µm sensor pixel) and the opaque grid adds its own orders, so
/// the normalised PSFs differ by about 0.3 of their L2 norm (0.05 between seeds) and the AUC
/// drops by 14 / 8 / 28 % in R / G / B (under 1 % between seeds). The test pins the measured
/// size: less than half the PSF's norm and a third of the AUC (the PSF keeps its shape, as the
/// figure shows), and more than another seed changes.
#[test]
fn an_8um_wiring_gap_changes_the_psf_measurably_but_keeps_its_shape() {
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let p = Progress::new();
    let base = load_preset("l2inv-random").unwrap();
    let a = analyze_with(&base, &options, &p).unwrap();
    let b = analyze_with(&load_preset("l2inv-random-wiring8").unwrap(), &options, &p).unwrap();
    let mut seeds = Vec::new();
    for seed in 1..=3 {
        let mut d = base.clone();
        d.tiling.seed = seed;
        seeds.push(analyze_with(&d, &options, &p).unwrap());
    }
    for (k, (ca, cb)) in a.channels.iter().zip(&b.channels).enumerate() {
        let wiring_l2 = rel_l2(&ca.psf, &cb.psf);
        let wiring_auc =
            (cb.mtf.auc_radial_min - ca.mtf.auc_radial_min).abs() / ca.mtf.auc_radial_min;
        let seed_l2 = seeds
            .iter()
            .map(|s| rel_l2(&ca.psf, &s.channels[k].psf))
            .fold(0.0, f64::max);
        let seed_auc = seeds
            .iter()
            .map(|s| {
                (s.channels[k].mtf.auc_radial_min - ca.mtf.auc_radial_min).abs()
                    / ca.mtf.auc_radial_min
            })
            .fold(0.0, f64::max);
        println!(
            "wiring8 {}: PSF rel L2 {wiring_l2:.4} (seeds up to {seed_l2:.4}); AUC {:.5} -> \
             {:.5}, {:.2} % (seeds up to {:.2} %)",
            ca.name,
            ca.mtf.auc_radial_min,
            cb.mtf.auc_radial_min,
            wiring_auc * 100.0,
            seed_auc * 100.0
        );
        assert!(wiring_l2 < 0.5, "{}: {wiring_l2}", ca.name);
        assert!(wiring_auc < 0.35, "{}: {wiring_auc}", ca.name);
        assert!(wiring_l2 > seed_l2, "{}: {wiring_l2} vs {seed_l2}", ca.name);
    }
}
