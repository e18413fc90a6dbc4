//! The preview agrees with full quality (conventions.md §4, "Preview"): on every preset and on
//! three random tilings of each, at the preset's own f-number and at f/10, the preview's AUC is
//! within 3 % of full quality's per channel and its `L_inv` within 10 %. Where the preview
//! keeps the design's sampling it is the full-quality computation itself (same plan); where
//! it doubles the spacing both are run and compared.

use rayon::prelude::*;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_core::design::TilingMode;
use udc_core::{Analysis, Design, Progress};
use udc_io::design::presets::{PRESETS, load_preset};

/// Per-channel AUC tolerance, relative.
const AUC_TOLERANCE: f64 = 0.03;
/// `L_inv` tolerance, relative; `L_inv` lies in [−1, 0], and below 0.005 in size (a design
/// whose Wiener response is nearly 1 everywhere) an absolute 0.0005 stands in.
const LINV_TOLERANCE: f64 = 0.10;
const LINV_FLOOR: f64 = 0.005;

fn variants() -> Vec<(String, Design)> {
    let mut out = Vec::new();
    for p in PRESETS {
        let own = load_preset(p.name).unwrap_or_else(|e| panic!("{}: {e}", p.name));
        let mut tilings = vec![(p.name.to_owned(), own.clone())];
        for seed in 1..=3 {
            let mut d = own.clone();
            d.tiling.mode = TilingMode::RandomD4;
            d.tiling.seed = seed;
            tilings.push((format!("{} random-d4 seed {seed}", p.name), d));
        }
        for (label, d) in tilings {
            let mut slow = d.clone();
            slow.optics.f_number = 10.0;
            out.push((label.clone(), d));
            out.push((format!("{label} at f/10"), slow));
        }
    }
    out
}

fn run(design: &Design, quality: Quality) -> Analysis {
    let options = AnalyzeOptions {
        quality,
        expected_psf: false,
    };
    analyze_with(design, &options, &Progress::default())
        .unwrap_or_else(|e| panic!("{quality:?}: {e}"))
}

#[test]
fn the_preview_agrees_with_full_quality_on_every_preset_and_random_tiling() {
    let cases = variants();
    let doubled: Vec<_> = cases
        .iter()
        .filter(|(_, d)| Quality::Preview.doubles_spacing(d))
        .collect();
    // Where the preview keeps the spacing it must plan exactly what full quality plans (no
    // faster FFT size either: that alone moved a periodic layout's AUC by up to 56 %).
    for (label, d) in cases
        .iter()
        .filter(|(_, d)| !Quality::Preview.doubles_spacing(d))
    {
        let plan = |q: Quality| {
            q.plan(d, &mut Vec::new())
                .unwrap_or_else(|e| panic!("{label}: {e}"))
        };
        assert_eq!(plan(Quality::Preview), plan(Quality::Full), "{label}");
    }
    // Every preset is f/2.5, where the doubled spacing would alias; at f/10 every one doubles.
    assert_eq!(doubled.len(), cases.len() / 2, "which cases double");
    assert!(doubled.iter().all(|(l, _)| l.ends_with("at f/10")));
    let failures: Vec<String> = doubled
        .par_iter()
        .filter_map(|(label, d)| {
            let (full, preview) = (run(d, Quality::Full), run(d, Quality::Preview));
            assert!(preview.channels[0].fine_um > 1.9 * full.channels[0].fine_um);
            let mut bad = Vec::new();
            for (f, p) in full.channels.iter().zip(&preview.channels) {
                let (a, b) = (f.mtf.auc_radial_min, p.mtf.auc_radial_min);
                if (b - a).abs() > AUC_TOLERANCE * a {
                    bad.push(format!("AUC {} {a:.5} → {b:.5}", f.name));
                }
            }
            let (a, b) = (full.invertibility_loss, preview.invertibility_loss);
            let allowed = (LINV_TOLERANCE * a.abs()).max(LINV_TOLERANCE * LINV_FLOOR);
            if (b - a).abs() > allowed {
                bad.push(format!("L_inv {a:.5} → {b:.5}"));
            }
            (!bad.is_empty()).then(|| format!("{label}: {}", bad.join(", ")))
        })
        .collect();
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn the_preview_doubles_only_where_the_intensity_is_oversampled() {
    let mut d = load_preset("toled-150dpi").expect("preset");
    // δ2 = 0.5 µm, shortest wavelength 470 nm: doubled 1 µm must be ≤ half of λN/2.
    for (n, doubles) in [(2.5, false), (8.0, false), (8.6, true), (16.0, true)] {
        d.optics.f_number = n;
        assert_eq!(Quality::Preview.doubles_spacing(&d), doubles, "f/{n}");
        assert!(!Quality::Full.doubles_spacing(&d));
    }
    // An odd number of fine samples per pixel cannot be halved.
    d.optics.fine_sample_um = 2.0 / 3.0;
    assert!(!Quality::Preview.doubles_spacing(&d));
}
