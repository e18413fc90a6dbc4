//! Masks a mask house accepts without a phone call: DXF a strict reader does not repair, errors
//! that name the file once, the design's sampling caveats in the report, coordinates without
//! float noise, and `udc-studio import` reading exported masks back. DXF is checked by ezdxf
//! through `tests/mask_check.py` (python3 with ezdxf is required, as for `mask_export`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use udc_studio::core::Progress;
use udc_studio::core::design::{Design, Opening, TilingMode};
use udc_studio::core::mask::{BorderPolicy, MaskRegion, MaskSpec, Tone};
use udc_studio::core::phase::PhaseDesign;
use udc_studio::io::mask::{ExportOptions, MaskFormat, export_mask, sidecar_path};
use udc_studio::io::phase::export::height_csv_text;

use crate::common::run_cli;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs the independent reader; fails loudly when python3 or ezdxf is missing.
fn python_check(args: &[&str]) -> serde_json::Value {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mask_check.py");
    let out = Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 with ezdxf is required (pip install ezdxf; .ci/test installs it)");
    assert!(
        out.status.success(),
        "mask_check.py {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("mask_check.py prints JSON")
}

/// An 8×8 opening without D4 symmetry in a 64 µm pixel, registered off-centre, with a gap.
fn design(mode: TilingMode) -> Design {
    let rows = [
        "##..#..#", "..#.##..", "#..#...#", ".##..#.#", "#...##..", ".#.#..#.", "##.....#",
        "..#.#.##",
    ];
    let mut d = Design::default_toled();
    d.name = "fab test".into();
    d.opening = Opening {
        pitch_um: 64.0,
        cells: rows
            .iter()
            .map(|r| r.chars().map(|c| f64::from(u8::from(c == '#'))).collect())
            .collect(),
        polygons: Vec::new(),
    };
    d.tiling.mode = mode;
    d.tiling.seed = 5;
    d.tiling.origin_offset_cells = [3.0, 2.0];
    d.tiling.wiring_gap_um = 4.0;
    d
}

fn options(format: MaskFormat, region: MaskRegion, tone: Tone) -> ExportOptions {
    ExportOptions {
        format,
        spec: MaskSpec {
            region,
            tone,
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        ..ExportOptions::default()
    }
}

#[test]
fn dxf_needs_no_repair_and_states_its_extents() {
    let dir = tempfile::tempdir().unwrap();
    for (region, tone) in [
        (MaskRegion::Block { cols: 3, rows: 2 }, Tone::Open),
        (MaskRegion::Pupil, Tone::Chrome),
    ] {
        let path = dir.path().join("a.dxf");
        let o = options(MaskFormat::Dxf, region, tone);
        export_mask(&design(TilingMode::RandomD4), &o, &path, &Progress::new()).unwrap();
        let v = python_check(&["dxf-audit", s(&path)]);
        assert_eq!(v["errors"], serde_json::json!([]), "{region:?}: {v}");
        assert_eq!(v["fixes"], serde_json::json!([]), "{region:?}: {v}");
        let bbox: Vec<f64> = serde_json::from_value(v["bbox"].clone()).unwrap();
        let min: Vec<f64> = serde_json::from_value(v["extmin"].clone()).unwrap();
        let max: Vec<f64> = serde_json::from_value(v["extmax"].clone()).unwrap();
        assert_eq!([min[0], min[1], max[0], max[1]], bbox[..], "{region:?}");
    }
}

/// The longest run of digits after a decimal point among the numbers in `text`.
fn most_decimals(text: &str) -> usize {
    let mut most = 0;
    for token in text.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-')) {
        if let Some((_, frac)) = token.split_once('.') {
            most = most.max(frac.chars().take_while(char::is_ascii_digit).count());
        }
    }
    most
}

#[test]
fn svg_and_csv_coordinates_carry_no_float_noise() {
    let dir = tempfile::tempdir().unwrap();
    // 600 DPI: a 42.333 µm pitch, cells of 2.0159 µm: edges that are not round in µm.
    let mut d = udc_studio::io::design::presets::load_preset("toled-600dpi").unwrap();
    d.tiling.wiring_gap_um = 0.3;
    let path = dir.path().join("m.svg");
    export_mask(
        &d,
        &options(MaskFormat::Svg, MaskRegion::Pupil, Tone::Open),
        &path,
        &Progress::new(),
    )
    .unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    // Micrometres on a 1 nm grid: at most 3 decimals (mm sizes at most 6).
    assert!(most_decimals(&svg) <= 6, "float noise in the SVG");
    for d_attr in svg.split("<path d=\"M").skip(1).take(50) {
        let coords = d_attr.split('Z').next().unwrap();
        assert!(most_decimals(coords) <= 3, "{coords}");
    }
    let mut plate = PhaseDesign::thesis(168.0, 1.0);
    plate.height_step_um = Some(0.2);
    let csv = height_csv_text(&plate, 0.1, 0.0).unwrap();
    let rows: Vec<&str> = csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
        .collect();
    assert!(rows.len() > 1000);
    for row in &rows {
        let mut f = row.split(',');
        for v in [f.next().unwrap(), f.next().unwrap()] {
            assert!(most_decimals(v) <= 9, "{v} in `{row}`");
            let x: f64 = v.parse().unwrap();
            assert_eq!(format!("{x}"), v, "{v} round-trips");
        }
    }
    // The samples sit on the 0.1 µm grid (odd multiples of 0.05 when N is even).
    let x0: f64 = rows[0].split(',').next().unwrap().parse().unwrap();
    assert!(((x0 / 0.05).round() * 0.05 - x0).abs() < 1e-12, "{x0}");
}

#[test]
fn export_errors_name_the_path_once() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("plain");
    std::fs::write(&file, "x").unwrap();
    for out in [
        dir.path().join("missing-dir").join("m.dxf"),
        file.join("m.gds"),
    ] {
        let (ok, stdout, stderr) = run_cli(&[
            "export",
            "--preset",
            "toled-150dpi",
            "--format",
            "dxf",
            "--region",
            "pixel",
            "--out",
            s(&out),
        ]);
        assert!(!ok && stdout.is_empty(), "{stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert_eq!(stderr.matches(s(&out)).count(), 1, "{stderr}");
        let parent = s(out.parent().unwrap());
        assert_eq!(stderr.matches(parent).count(), 1, "{stderr}");
        assert!(!stderr.contains(".part"), "names the temp file: {stderr}");
        assert_eq!(stderr.matches("cannot").count(), 1, "{stderr}");
    }
}

#[test]
fn export_report_carries_the_designs_sampling_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t.gds");
    let (ok, stdout, stderr) = run_cli(&[
        "export",
        "--preset",
        "toled-150dpi",
        "--format",
        "gds",
        "--region",
        "pixel",
        "--out",
        s(&out),
    ]);
    assert!(ok, "{stderr}");
    let (ok, json, stderr) = run_cli(&["analyze", "--preset", "toled-150dpi", "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let advice = v["advice"].as_array().unwrap();
    assert!(!advice.is_empty(), "the preset has a sampling note");
    for a in advice {
        let line = format!(
            "sampling {}: {}",
            a["severity"].as_str().unwrap(),
            a["message"].as_str().unwrap()
        );
        assert!(stdout.contains(&line), "missing `{line}` in\n{stdout}");
    }
}

/// Exports `d` (saved as a design file) with the CLI, optionally drops the sidecar, imports
/// the mask and returns the imported design.
fn cli_round_trip(dir: &Path, d: &Design, ext: &str, keep_sidecar: bool) -> Design {
    let design_path = dir.join("d.json");
    udc_studio::io::design::file::save_design(&design_path, d).unwrap();
    let mask = dir.join(format!("m.{ext}"));
    let (ok, _, stderr) = run_cli(&[
        "export",
        s(&design_path),
        "--format",
        ext,
        "--region",
        "3x3",
        "--tone",
        "chrome",
        "--um-per-px",
        "0.5",
        "--png-bits",
        "1",
        "--out",
        s(&mask),
    ]);
    assert!(ok, "{stderr}");
    if !keep_sidecar {
        std::fs::remove_file(sidecar_path(&mask)).unwrap();
    }
    let out = dir.join(format!("imported-{ext}.json"));
    let (ok, stdout, stderr) = run_cli(&["import", s(&mask), "--out", s(&out)]);
    assert!(ok, "{ext}: {stderr}");
    assert!(stdout.contains("imported 8×8 cells"), "{stdout}");
    let (ok, _, stderr) = run_cli(&["analyze", s(&out), "--preview", "--json"]);
    assert!(ok, "analyze of the imported {ext}: {stderr}");
    udc_studio::io::design::file::load_design(&out).unwrap()
}

#[test]
fn cli_import_reads_gds_dxf_and_png_back_into_the_design() {
    let dir = tempfile::tempdir().unwrap();
    let d = design(TilingMode::RandomD4);
    for ext in ["gds", "dxf", "png"] {
        for keep_sidecar in [true, false] {
            let got = cli_round_trip(dir.path(), &d, ext, keep_sidecar);
            let what = format!("{ext}, sidecar {keep_sidecar}");
            assert_eq!(got.opening.cells, d.opening.cells, "{what}");
            assert_eq!(got.opening.pitch_um, d.opening.pitch_um, "{what}");
            assert_eq!(got.tiling.mode, d.tiling.mode, "{what}");
            assert_eq!(got.tiling.seed, d.tiling.seed, "{what}");
            assert_eq!(got.tiling.wiring_gap_um, d.tiling.wiring_gap_um, "{what}");
        }
    }
}

#[test]
fn cli_import_rejects_bad_input_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.json");
    let txt = dir.path().join("m.txt");
    std::fs::write(&txt, "x").unwrap();
    let junk = dir.path().join("m.gds");
    std::fs::write(&junk, "not a mask").unwrap();
    let missing = dir.path().join("none.dxf");
    for (args, needle) in [
        (vec!["import", s(&txt), "--out", s(&out)], ".txt"),
        (vec!["import", s(&junk), "--out", s(&out)], "m.gds"),
        (vec!["import", s(&missing), "--out", s(&out)], "none.dxf"),
        (
            vec!["import", s(&junk), "--layer", "1", "--out", s(&out)],
            "L/D",
        ),
    ] {
        let (ok, stdout, stderr) = run_cli(&args);
        assert!(!ok, "{args:?} must fail");
        assert!(stdout.is_empty(), "{args:?} printed {stdout}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        if !stderr.contains("--help") {
            assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        }
        assert!(!out.exists(), "{args:?} wrote the design");
    }
}
