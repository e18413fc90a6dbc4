//! The `phase` command's contract: `psf`, `invertibility` and `optimize` JSON, output files and
//! one-line errors.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use serde_json::Value;
use udc_studio::core::Progress;
use udc_studio::core::phase::{
    PhaseDesign, PhaseSampling, Relay, invertibility_score, v_matrix_on, wavelength_grid_nm,
};

use crate::common::run_cli as run;

fn json_of(args: &[&str]) -> Value {
    let (ok, stdout, stderr) = run(args);
    assert!(ok, "{args:?}: {stderr}");
    serde_json::from_str(stdout.trim()).expect("one JSON object")
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn psf_json_has_each_channel_against_the_toled_and_writes_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("psf");
    let v = json_of(&[
        "phase",
        "psf",
        "--pitch-um",
        "42",
        "--fold",
        "1",
        "--lambda0",
        "fixed:530",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(v["lenslets"], 58);
    assert!((v["fov_deg"].as_f64().unwrap() - 13.6).abs() < 0.1);
    let channels = v["channels"].as_array().unwrap();
    let names: Vec<&str> = channels
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["R", "G", "B"]);
    for c in channels {
        let psf = floats(&c["psf"]);
        assert_eq!(psf.len(), 1024);
        assert!((psf.iter().sum::<f64>() - 1.0).abs() < 1e-4);
        // The reported numbers are the PSF's own.
        let peak = psf.iter().copied().fold(0.0, f64::max);
        assert!((c["peak"].as_f64().unwrap() - peak).abs() < 1e-5 * peak.max(1e-3));
        let inv = c["invertibility"].as_f64().unwrap();
        assert!((invertibility_score(&psf) - inv).abs() < 1e-3 * inv);
        let before = c["energy_vs_toled_before_polariser"].as_f64().unwrap();
        assert!((c["energy_vs_toled"].as_f64().unwrap() - before / 2.0).abs() < 1e-5 * before);
    }
    let g = &channels[1];
    assert_eq!(g["wavelength_nm"], 530.0);
    // At λ0 the arrays pass ≈ 1/0.238 the T-OLED's light, and focus it.
    assert!((g["energy_vs_toled_before_polariser"].as_f64().unwrap() - 4.2).abs() < 0.2);
    assert!(g["peak"].as_f64().unwrap() > 3.0 * g["toled_peak"].as_f64().unwrap());
    let csv = std::fs::read_to_string(out.join("psf.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "pixel_offset,R,toled_R,G,toled_G,B,toled_B"
    );
    assert_eq!(lines.count(), 1024);
}

#[test]
fn psf_off_axis_follows_the_image_point_and_the_field_of_view() {
    let at = |deg: &str| {
        json_of(&[
            "phase",
            "psf",
            "--fold",
            "5",
            "--preview",
            "--angle-deg",
            deg,
            "--json",
        ])
    };
    let inside = at("3");
    // Thesis sampling: 2.03 µm effective pixels with the axis on the left edge of the axis
    // pixel, so f sinθ = 4670 µm · sin 3° = 244.4 µm lies in pixel ⌊244.4 / 2.03⌋ = 120.
    assert_eq!(inside["image_pixel"], 120);
    let outside = at("12");
    let ltr = |v: &Value| v["ltr_with_polariser"].as_f64().unwrap();
    assert!(ltr(&inside) > 0.45, "{}", ltr(&inside));
    assert!(ltr(&outside) < 0.1, "{}", ltr(&outside));
    // The T-OLED does not care about the angle.
    let toled = |v: &Value| v["toled_ltr"].as_f64().unwrap();
    assert!((toled(&inside) - toled(&outside)).abs() < 0.01);
}

#[test]
fn invertibility_json_is_the_30_by_30_v_matrix_through_either_relay() {
    let args = [
        "phase",
        "invertibility",
        "--pitch-um",
        "84",
        "--preview",
        "--json",
    ];
    let grid = wavelength_grid_nm();
    let rows_of = |v: &Value| -> Vec<Vec<f64>> {
        assert_eq!(floats(&v["lambda_nm"]), grid);
        assert_eq!(floats(&v["lambda0_nm"]), grid);
        let rows: Vec<Vec<f64>> = v["v"].as_array().unwrap().iter().map(floats).collect();
        assert_eq!(rows.len(), 30);
        assert!(rows.iter().all(|r| r.len() == 30));
        rows
    };
    // The default relay is the lenslet period; `--relay whole-display` is the thesis code's.
    let period = rows_of(&json_of(&args));
    let whole = rows_of(&json_of(
        &[&args[..], &["--relay", "whole-display"]].concat(),
    ));
    // Rows are λ0 and columns λ: spot-check each against the core.
    for (rows, relay) in [
        (&period, Relay::LensletPeriod),
        (&whole, Relay::WholeDisplay),
    ] {
        let core = v_matrix_on(
            &PhaseDesign::thesis(84.0, 1.0),
            &PhaseSampling::preview().with_relay(relay),
            &[grid[3], grid[20]],
            &[grid[5], grid[20]],
            &Progress::new(),
        )
        .unwrap();
        for (a, j) in [3, 20].iter().enumerate() {
            for (b, k) in [5, 20].iter().enumerate() {
                let want = core.v[a][b];
                assert!(
                    (rows[*j][*k] - want).abs() < 1e-5 * want,
                    "{relay:?} V[{j}][{k}]"
                );
            }
        }
    }
    // Not the same computation, and the same V to a few 1e-3 at 300 DPI (the array reaches
    // 1.2 lenslets beyond the main lens, as at 600 DPI).
    assert_ne!(period, whole);
    let worst = period
        .iter()
        .flatten()
        .zip(whole.iter().flatten())
        .map(|(p, w)| ((p - w) / w).abs())
        .fold(0.0, f64::max);
    eprintln!("V at 84 µm, preview: worst relative difference {worst:e}");
    assert!(worst < 3e-3, "{worst:e}");
}

#[test]
fn optimize_json_allocates_every_lenslet_and_beats_fixed_530() {
    let v = json_of(&[
        "phase",
        "optimize",
        "--pitch-um",
        "168",
        "--preview",
        "--json",
    ]);
    assert_eq!(v["lenslets"], 17);
    let counts: Vec<u64> = v["counts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .collect();
    assert_eq!(counts.len(), 30);
    assert_eq!(counts.iter().sum::<u64>(), 17);
    let lambda0 = floats(&v["lambda0_nm"]);
    assert_eq!(lambda0.len(), 17);
    assert!(lambda0.windows(2).all(|w| w[0] <= w[1]));
    // λ0 repeats each grid wavelength by its count.
    let grid = wavelength_grid_nm();
    let expanded: Vec<f64> = counts
        .iter()
        .zip(&grid)
        .flat_map(|(&c, &l)| std::iter::repeat_n(l, c as usize))
        .collect();
    assert_eq!(lambda0, expanded);
    let inv = floats(&v["channel_invertibility"]);
    let fixed = floats(&v["fixed_530_invertibility"]);
    assert_eq!(inv.len(), 3);
    let worst = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(worst(&inv) > worst(&fixed), "{inv:?} vs {fixed:?}");
}

#[test]
fn bad_phase_arguments_are_one_line_errors() {
    for (args, needle) in [
        (vec!["phase", "psf", "--fold", "-1"], "--fold"),
        (vec!["phase", "psf", "--pitch-um", "NaN"], "--pitch-um"),
        (vec!["phase", "psf", "--lambda0", "blue"], "--lambda0"),
        (vec!["phase", "psf", "--lambda0", "fixed:abc"], "--lambda0"),
        (vec!["phase", "psf", "--lambda0", "fixed:5000"], "--lambda0"),
        (vec!["phase", "psf", "--angle-deg", "95"], "--angle-deg"),
        (
            vec!["phase", "invertibility", "--relay", "sideways"],
            "--relay",
        ),
        (
            vec![
                "phase",
                "optimize",
                "--spectral",
                "/nonexistent/response.csv",
            ],
            "/nonexistent/response.csv",
        ),
    ] {
        let (ok, stdout, stderr) = run(&args);
        assert!(!ok, "{args:?} succeeded: {stdout}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(stdout.is_empty(), "{args:?} printed {stdout}");
    }
}

#[test]
fn export_writes_each_format_and_reads_an_optimized_design() {
    let dir = tempfile::tempdir().unwrap();
    let gds = dir.path().join("plate.gds");
    let v = json_of(&[
        "phase",
        "export",
        "--format",
        "gds",
        "--height-step-um",
        "0.2",
        "--length-um",
        "100",
        "--json",
        "--out",
        gds.to_str().unwrap(),
    ]);
    // T = 1 at 530 nm: a 1.029 µm fold, floored to 0.2 µm steps: 0 … 1.0 µm = 6 levels. The
    // top one spans 29 nm of sag, a ring under 0.1 µm wide wherever it falls, narrower than the
    // default half-micron rule: it joins the next fold, leaving 5 levels, 4 above the substrate.
    assert_eq!(v["levels"], 5);
    assert_eq!(v["layers"].as_array().unwrap().len(), 4);
    assert!(v["ring_merge"]["merged_rings"].as_u64().unwrap() > 0, "{v}");
    assert!(std::fs::metadata(&gds).unwrap().len() > 1000);
    // The allocation saved by `optimize --out` is exported as it is.
    let opt_dir = dir.path().join("opt");
    let (ok, _, stderr) = run(&[
        "phase",
        "optimize",
        "--pitch-um",
        "168",
        "--preview",
        "--out",
        opt_dir.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let csv = dir.path().join("plate.csv");
    let design = opt_dir.join("phase_design.json");
    let v = json_of(&[
        "phase",
        "export",
        "--design",
        design.to_str().unwrap(),
        "--format",
        "csv",
        "--json",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(v["width_um"], 17.0 * 168.0);
    let text = std::fs::read_to_string(&csv).unwrap();
    let lambda0: std::collections::BTreeSet<String> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("x_um"))
        .map(|l| l.split(',').nth(3).unwrap().to_string())
        .collect();
    assert!(
        lambda0.len() > 1,
        "the optimized plate has several λ0: {lambda0:?}"
    );
    for (args, needle) in [
        (vec!["phase", "export", "--format", "stl"], "--out"),
        (
            vec![
                "phase",
                "export",
                "--format",
                "gds",
                "--out",
                "/tmp/never.gds",
            ],
            "--height-step-um",
        ),
        (
            vec![
                "phase",
                "export",
                "--format",
                "png",
                "--sample-um",
                "-2",
                "--out",
                "/tmp/never.png",
            ],
            "--sample-um",
        ),
    ] {
        let (ok, _, stderr) = run(&args);
        assert!(!ok && stderr.contains(needle), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
    assert!(!std::path::Path::new("/tmp/never.gds").exists());
}
