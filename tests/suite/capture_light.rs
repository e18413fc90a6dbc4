//! A capture conserves light (conventions.md §5): a restoration whose PSF window holds less than
//! 97 % of a channel's light says so in one line, with the fix, from the core, the CLI (text and
//! JSON) alike; a window that holds the light says nothing. Fig. 3.9's shipped designs hold it
//! for every layout.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use udc_studio::core::Progress;
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::analysis::light::{capture_light_warning, channels_losing_light};
use udc_studio::core::restore::light::MIN_CAPTURE_ENERGY_IN_WINDOW;
use udc_studio::io::design::file::{parse_design, to_json};
use udc_studio::io::design::pattern::load_pattern_png;

use crate::common::run_cli;

fn reproduce(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("presets/reproduce")
        .join(rel)
}

/// Fig. 3.9's 80-DPI base with its window set to `window_px`.
fn base_80dpi(window_px: usize) -> udc_studio::core::Design {
    let text = std::fs::read_to_string(reproduce("designs/fig3.9/base-80dpi.json")).unwrap();
    let mut d = parse_design(&text).unwrap();
    d.optics.window_px = window_px;
    d
}

/// The same with the P-OLED pattern, as `--pattern` puts it.
fn poled_80dpi(window_px: usize) -> udc_studio::core::Design {
    let mut d = base_80dpi(window_px);
    d.opening.cells = load_pattern_png(&reproduce("patterns/poled-42.png")).unwrap();
    d.opening.polygons.clear();
    d.reconcile_subpixels();
    d
}

fn analysis(d: &udc_studio::core::Design) -> udc_studio::core::Analysis {
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    analyze_with(d, &options, &Progress::new()).unwrap()
}

#[test]
fn a_window_that_drops_light_is_warned_in_one_line_with_the_fix() {
    // The thesis's 294-pixel window at 80 DPI drops about 3 % of the P-OLED's red light.
    let narrow = analysis(&poled_80dpi(294));
    let losing = channels_losing_light(&narrow);
    assert!(losing.iter().any(|(n, _)| *n == "R"), "{losing:?}");
    for (_, share) in &losing {
        assert!(*share < MIN_CAPTURE_ENERGY_IN_WINDOW);
    }
    let w = capture_light_warning(&narrow).expect("a warning");
    assert_eq!(w.lines().count(), 1, "{w}");
    assert!(
        w.contains("294-pixel") && w.contains("optics.window_px"),
        "{w}"
    );
    let r = losing.iter().find(|(n, _)| *n == "R").unwrap().1;
    assert!(w.contains(&format!("{:.1} % in R", 100.0 * r)), "{w}");
    // The shipped window (the whole FFT grid at 470 nm) holds it: no warning.
    let shipped = analysis(&poled_80dpi(622));
    assert!(channels_losing_light(&shipped).is_empty());
    assert_eq!(capture_light_warning(&shipped), None);
}

#[test]
fn restore_says_so_in_text_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let narrow = dir.path().join("narrow.json");
    std::fs::write(&narrow, to_json(&base_80dpi(294))).unwrap();
    let pattern = reproduce("patterns/poled-42.png");
    let photo = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/testset/coffee.png");
    let args = [
        "restore",
        narrow.to_str().unwrap(),
        "--pattern",
        pattern.to_str().unwrap(),
        "--image",
        photo,
        "--max-side-px",
        "32",
        "--snr-db",
        "32",
        "--denoise",
        "none",
    ];
    let (ok, out, err) = run_cli(&args);
    assert!(ok, "{err}");
    let lines: Vec<&str> = out.lines().filter(|l| l.contains("capture: the")).collect();
    assert_eq!(lines.len(), 1, "{out}");
    assert!(lines[0].starts_with("warning: "), "{}", lines[0]);
    let mut json_args = args.to_vec();
    json_args.push("--json");
    let (ok, out, err) = run_cli(&json_args);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let held: Vec<f64> = v["energy_in_window"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(held.len(), 3);
    let least = v["energy_in_window_min"].as_f64().unwrap();
    assert_eq!(least, held.iter().copied().fold(f64::INFINITY, f64::min));
    assert!(least < MIN_CAPTURE_ENERGY_IN_WINDOW, "{least}");
    let warned = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w.as_str().unwrap().starts_with("capture: the"))
        .count();
    assert_eq!(warned, 1, "{out}");
}
