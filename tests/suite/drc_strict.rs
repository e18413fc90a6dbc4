//! The design-rule check of a phase plate, and `--strict` on both exports: a failing check
//! writes nothing, a lenient one warns in the export report.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common::run_cli;
use udc_studio::core::phase::PhaseDesign;
use udc_studio::io::phase::design::save_phase_design;

/// The thesis's 150-DPI plate at a 0.2-µm height step: its outer rings are under 200 nm.
fn stepped_plate(dir: &std::path::Path) -> std::path::PathBuf {
    let mut d = PhaseDesign::thesis(168.0, 1.0);
    d.height_step_um = Some(0.2);
    let path = dir.join("plate_design.json");
    save_phase_design(&path, &d).unwrap();
    path
}

fn files_in(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn drc_checks_a_phase_design_file_ring_by_ring() {
    let dir = tempfile::tempdir().unwrap();
    let plate = stepped_plate(dir.path());
    let p = plate.to_str().unwrap();
    let (ok, stdout, stderr) = run_cli(&["drc", p, "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(v["kind"], "phase");
    assert_eq!(v["clean"], false);
    let narrowest = v["report"]["min_feature_um"].as_f64().unwrap();
    assert!(narrowest > 0.0 && narrowest < 0.2, "{narrowest}");
    let first = &v["report"]["violations"][0];
    assert_eq!(first["kind"], "min-feature");
    assert!(
        first["place"].as_str().unwrap().contains("lenslet"),
        "{first}"
    );
    assert_eq!(v["report"]["rules"]["phase_min_feature_um"], 0.5);
    // The same rules file as a display mask's, with the plate's own key; flags override it.
    let rules = dir.path().join("fab.json");
    std::fs::write(
        &rules,
        r#"{"min_feature_um": 2, "min_gap_um": 2, "no_corner_contact": true,
            "min_angle_deg": 90, "phase_min_feature_um": 0.02}"#,
    )
    .unwrap();
    let r = rules.to_str().unwrap();
    let (ok, stdout, stderr) = run_cli(&["drc", p, "--rules", r, "--strict"]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("phase plate") && stdout.contains("no violation"),
        "{stdout}"
    );
    let (ok, _, stderr) = run_cli(&[
        "drc",
        p,
        "--rules",
        r,
        "--phase-min-feature-um",
        "1",
        "--strict",
    ]);
    assert!(!ok && stderr.contains("design-rule violations"), "{stderr}");
    // A display design's options make no sense on a plate.
    let (ok, _, stderr) = run_cli(&["drc", p, "--pitch-um", "42"]);
    assert!(!ok && stderr.contains("phase design"), "{stderr}");
}

#[test]
fn strict_phase_export_writes_nothing_and_lenient_warns() {
    let dir = tempfile::tempdir().unwrap();
    let plate = stepped_plate(dir.path());
    let before = files_in(dir.path());
    let out = dir.path().join("plate.gds");
    let (plate, out_s) = (plate.to_str().unwrap(), out.to_str().unwrap());
    let lenient = [
        "phase", "export", "--design", plate, "--format", "gds", "--out", out_s, "--json",
    ];
    let mut strict = lenient.to_vec();
    strict.push("--strict");
    let (ok, _, stderr) = run_cli(&strict);
    assert!(!ok && stderr.contains("design-rule violations"), "{stderr}");
    assert!(
        stderr.contains("lenslet"),
        "the violations are listed: {stderr}"
    );
    assert_eq!(
        files_in(dir.path()),
        before,
        "nothing written under --strict"
    );
    let (ok, stdout, stderr) = run_cli(&lenient);
    assert!(ok, "{stderr}");
    assert!(out.exists());
    assert!(
        stderr.contains("warning:") && stderr.contains("design-rule"),
        "{stderr}"
    );
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(v["drc"]["clean"], false);
    assert!(v["drc"]["report"]["counts"][0].as_u64().unwrap() > 0);
}

#[test]
fn strict_mask_export_writes_nothing_and_lenient_warns() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.svg");
    let o = out.to_str().unwrap();
    let base = [
        "export",
        "--preset",
        "l2inv-random",
        "--format",
        "svg",
        "--region",
        "pixel",
        "--out",
        o,
    ];
    let mut strict = base.to_vec();
    strict.push("--strict");
    let (ok, stdout, stderr) = run_cli(&strict);
    assert!(!ok && stderr.contains("design-rule violations"), "{stderr}");
    assert!(
        stdout.contains("corner contacts"),
        "the violations are listed: {stdout}"
    );
    assert!(
        files_in(dir.path()).is_empty(),
        "nothing written: {:?}",
        files_in(dir.path())
    );
    let (ok, stdout, stderr) = run_cli(&base);
    assert!(ok, "{stderr}");
    assert!(out.exists());
    assert!(
        stdout.contains("warning: ") && stdout.contains("corner contacts"),
        "{stdout}"
    );
    // A clean design exports under --strict, with no warning.
    let clean = dir.path().join("clean.svg");
    let (ok, stdout, stderr) = run_cli(&[
        "export",
        "--preset",
        "toled-150dpi",
        "--format",
        "svg",
        "--region",
        "pixel",
        "--out",
        clean.to_str().unwrap(),
        "--strict",
    ]);
    assert!(ok && clean.exists(), "{stderr}");
    assert!(!stdout.contains("warning"), "{stdout}");
}

#[test]
fn the_export_report_names_the_layer_of_every_role() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("layers.txt");
    std::fs::write(&map, "openings 10/3\noutline 11/0\nnotes 63/5\n").unwrap();
    let out = dir.path().join("m.gds");
    let (ok, stdout, stderr) = run_cli(&[
        "export",
        "--preset",
        "toled-150dpi",
        "--format",
        "gds",
        "--region",
        "pixel",
        "--out",
        out.to_str().unwrap(),
        "--layer-map",
        map.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("layers: openings 10/3, outline 11/0, notes 63/5"),
        "{stdout}"
    );
    assert!(
        !stdout.contains("notes and pupil outline on layer"),
        "{stdout}"
    );
}
