//! The `sensor` command's contract: JSON fields per strategy, output files, the table, one-line
//! errors and non-zero exits.
#![allow(clippy::unwrap_used, clippy::expect_used)]

const STILL_LIFE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/hdr/StillLife_620x423.exr"
);

use crate::common::run_cli as run;

#[test]
fn sensor_json_has_the_four_strategies_and_writes_the_maps() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (ok, stdout, stderr) = run(&[
        "sensor",
        "--hdr",
        STILL_LIFE,
        "--max-side-px",
        "240",
        "--roi",
        "48",
        "--seed",
        "3",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    assert_eq!(v["image_size_px"], serde_json::json!([240, 164]));
    assert_eq!(v["source_size_px"], serde_json::json!([620, 423]));
    assert_eq!(v["sensor"]["name"], "table54");
    assert_eq!(v["exposure"]["mean_fraction"], 0.05);
    assert_eq!(v["roi_px"], 48);
    let strategies = v["strategies"].as_array().unwrap();
    let names: Vec<&str> = strategies
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "const-gain/no-bin",
            "vary-gain/no-bin",
            "const-gain/vary-bin",
            "vary-gain/vary-bin"
        ]
    );
    for s in strategies {
        for key in [
            "worst_roi_ssim",
            "mean_ssim",
            "psnr_db",
            "saturated_fraction",
            "dynamic_range_db",
        ] {
            assert!(s[key].is_number(), "{key} in {s}");
        }
        for key in ["min", "max", "mean"] {
            assert!(s["gain_map"][key].is_number(), "gain_map.{key}");
            assert!(s["bin_map"][key].is_number(), "bin_map.{key}");
        }
        assert!(s["bin_map"]["fractions"]["1"].is_number());
        assert_eq!(s["roi_ssim"].as_array().unwrap().len(), 4);
    }
    assert_eq!(strategies[0]["gain_map"]["max"], 1.0);
    assert!(strategies[1]["gain_map"]["max"].as_f64().unwrap() > 1.0);
    let worst = |i: usize| strategies[i]["worst_roi_ssim"].as_f64().unwrap();
    assert!(worst(3) > worst(0), "{} vs {}", worst(3), worst(0));
    for name in [
        "truth.png",
        "truth.exr",
        "scene.exr",
        "vary-gain_vary-bin_capture.png",
        "vary-gain_vary-bin_capture.exr",
        "vary-gain_vary-bin_gain.png",
        "vary-gain_vary-bin_bins.png",
        "const-gain_no-bin_saturated.png",
    ] {
        assert!(out.join(name).is_file(), "missing {name}");
    }
    assert_eq!(v["outputs"].as_array().unwrap().len(), 23);
    let png = image::open(out.join("const-gain_vary-bin_bins.png")).unwrap();
    assert_eq!((png.width(), png.height()), (240, 164));
    // The capture EXR reads back as a one-plane scene of electrons.
    let cap =
        udc_studio::io::photo::hdr::load_hdr(&out.join("vary-gain_vary-bin_capture.exr")).unwrap();
    assert_eq!(cap.planes.len(), 1);
    assert_eq!(cap.dim(), (164, 240));
}

#[test]
fn sensor_prints_a_table_without_json() {
    let (ok, stdout, stderr) = run(&[
        "sensor",
        "--hdr",
        STILL_LIFE,
        "--max-side-px",
        "160",
        "--roi",
        "32",
        "--sensor",
        "nexus-6p",
        "--exposure",
        "p99.9:0.8",
        "--bin-mode",
        "additive",
    ]);
    assert!(ok, "{stderr}");
    for name in [
        "const-gain/no-bin",
        "vary-gain/vary-bin",
        "worst SSIM",
        "nexus-6p",
    ] {
        assert!(stdout.contains(name), "{name} missing in\n{stdout}");
    }
    assert!(stdout.contains("99.9th percentile"), "{stdout}");
}

#[test]
fn sensor_errors_are_one_line_and_exit_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let one_line = |args: &[&str], needle: &str| {
        let (ok, _, stderr) = run(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(stderr.contains(needle), "{needle} not in {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    };
    let missing = dir.path().join("nope.exr");
    one_line(&["sensor", "--hdr", missing.to_str().unwrap()], "nope.exr");
    let png = dir.path().join("photo.png");
    std::fs::write(&png, b"x").unwrap();
    one_line(&["sensor", "--hdr", png.to_str().unwrap()], "unsupported");
    let corrupt = dir.path().join("corrupt.exr");
    std::fs::write(&corrupt, b"\x76\x2f\x31\x01\x02\x00\x00\x00broken").unwrap();
    one_line(
        &["sensor", "--hdr", corrupt.to_str().unwrap()],
        "corrupt.exr",
    );
    one_line(
        &["sensor", "--hdr", STILL_LIFE, "--sensor", "canon"],
        "nikon-z5",
    );
    one_line(&["sensor", "--hdr", STILL_LIFE, "--roi", "2"], "--roi:");
    one_line(
        &["sensor", "--hdr", STILL_LIFE, "--exposure", "mean:-1"],
        "exposure",
    );
    one_line(&["sensor", "--hdr", STILL_LIFE, "--eta=-1"], "eta");
}

#[test]
fn sensor_json_names_the_gain_policy_and_counts_saturated_rois() {
    let args = |extra: &[&'static str]| {
        let mut a = vec![
            "sensor",
            "--hdr",
            STILL_LIFE,
            "--max-side-px",
            "200",
            "--roi",
            "40",
            "--json",
        ];
        a.extend_from_slice(extra);
        a
    };
    let (ok, stdout, stderr) = run(&args(&[]));
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(v["additive_gain"], "scaled");
    assert_eq!(v["roi_light"], "brightest");
    let rois = |v: &serde_json::Value, i: usize| {
        v["strategies"][i]["saturated_roi_fraction"]
            .as_f64()
            .unwrap()
    };
    for i in 0..4 {
        let f = rois(&v, i);
        assert!((0.0..=1.0).contains(&f), "{f}");
        // A saturated pixel puts its ROI among the saturated ones.
        let pixels = v["strategies"][i]["saturated_fraction"].as_f64().unwrap();
        assert_eq!(pixels > 0.0, f > 0.0);
    }
    let (ok, stdout, stderr) = run(&args(&[
        "--bin-mode",
        "additive",
        "--additive-gain",
        "same",
        "--roi-light",
        "mean",
    ]));
    assert!(ok, "{stderr}");
    let w: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(
        (&w["bin_mode"], &w["additive_gain"], &w["roi_light"]),
        (
            &serde_json::json!("additive"),
            &serde_json::json!("same"),
            &serde_json::json!("mean")
        )
    );
    // The mean light of an ROI gets a higher gain than its brightest block: more saturated ROIs.
    assert!(
        rois(&w, 1) >= rois(&v, 1),
        "{} vs {}",
        rois(&w, 1),
        rois(&v, 1)
    );
    // The table has the column.
    let (ok, stdout, _) = run(&[
        "sensor",
        "--hdr",
        STILL_LIFE,
        "--max-side-px",
        "120",
        "--roi",
        "32",
        "--gain-policy",
        "same",
        "--bin-mode",
        "additive",
    ]);
    assert!(ok);
    assert!(stdout.contains("sat. ROIs"), "{stdout}");
    assert!(stdout.contains("additive (same gain)"), "{stdout}");
}

#[test]
fn flat_patch_prints_measured_and_predicted_saturation() {
    let (ok, stdout, stderr) = run(&[
        "sensor",
        "flat-patch",
        "--light",
        "400",
        "--eta",
        "2",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    let f = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"));
    let (measured, predicted, se) = (f("saturated_fraction"), f("predicted"), f("standard_error"));
    assert!((measured - predicted).abs() < 3.0 * se, "{v}");
    // The thesis's Gaussian number, 1 − Φ(2).
    assert!((f("gaussian_tail") - 0.02275).abs() < 1e-5);
    assert_eq!(v["readouts"], 512 * 512);
    // The same patch in 2×2 additive bins: at the same gain the sum saturates N× sooner.
    let bins = |policy: &str| {
        let (ok, stdout, stderr) = run(&[
            "sensor",
            "flat-patch",
            "--light",
            "400",
            "--bin",
            "2",
            "--bin-mode",
            "additive",
            "--gain-policy",
            policy,
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
        assert_eq!(v["additive_gain"], policy);
        v["saturated_fraction"].as_f64().unwrap()
    };
    assert!(bins("same") > measured && measured > bins("scaled"));
    // Text output.
    let (ok, stdout, stderr) = run(&["sensor", "flat-patch", "--light", "100"]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("predicted"), "{stdout}");
}

#[test]
fn flat_patch_errors_are_one_line_and_exit_non_zero() {
    let one_line = |args: &[&str], needle: &str| {
        let (ok, _, stderr) = run(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(stderr.contains(needle), "{needle} not in {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    };
    one_line(&["sensor", "flat-patch", "--light", "-5"], "--light");
    one_line(&["sensor", "flat-patch", "--light", "NaN"], "--light");
    one_line(&["sensor", "flat-patch", "--light", "1e300"], "--light");
    one_line(
        &["sensor", "flat-patch", "--light", "10", "--eta=-1"],
        "--eta",
    );
    one_line(
        &["sensor", "flat-patch", "--light", "10", "--bin", "3"],
        "--bin",
    );
    one_line(
        &[
            "sensor",
            "flat-patch",
            "--light",
            "10",
            "--side-px",
            "100",
            "--bin",
            "8",
        ],
        "--side-px",
    );
    one_line(
        &["sensor", "flat-patch", "--light", "10", "--sensor", "canon"],
        "nikon-z5",
    );
    one_line(
        &[
            "sensor",
            "flat-patch",
            "--light",
            "10",
            "--gain-policy",
            "half",
        ],
        "scaled",
    );
    one_line(&["sensor", "flat-patch"], "--light");
    one_line(&["sensor"], "--hdr");
}

#[test]
fn sensor_cfa_rggb_reports_luminance_and_channels() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (ok, stdout, stderr) = run(&[
        "sensor",
        "--hdr",
        STILL_LIFE,
        "--max-side-px",
        "200",
        "--roi",
        "32",
        "--cfa",
        "rggb",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    assert_eq!(v["cfa"], "rggb");
    for s in v["strategies"].as_array().unwrap() {
        assert!(s["worst_roi_ssim"].is_number());
        for c in ["R", "G", "B"] {
            for key in ["worst_roi_ssim", "mean_ssim", "psnr_db"] {
                assert!(
                    s["channels"][c][key].is_number(),
                    "channels.{c}.{key} in {s}"
                );
            }
        }
    }
    // The colour captures: RGB PNGs, the luminance EXR the scores use, and RGB EXRs.
    let png = image::open(out.join("vary-gain_vary-bin_capture.png"))
        .unwrap()
        .to_rgb8();
    assert!(
        png.pixels().any(|p| p[0] != p[1] || p[1] != p[2]),
        "a colour capture"
    );
    let rgb = udc_studio::io::photo::hdr::load_hdr(&out.join("vary-gain_vary-bin_capture_rgb.exr"))
        .unwrap();
    assert_eq!(rgb.planes.len(), 3);
    let y =
        udc_studio::io::photo::hdr::load_hdr(&out.join("vary-gain_vary-bin_capture.exr")).unwrap();
    assert_eq!(y.planes.len(), 1);
    assert!(out.join("truth_rgb.exr").is_file());
    // Without the flag the run is monochrome and says so.
    let (ok, stdout, _) = run(&[
        "sensor",
        "--hdr",
        STILL_LIFE,
        "--max-side-px",
        "120",
        "--roi",
        "32",
        "--json",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(v["cfa"], "none");
    assert!(v["strategies"][0].get("channels").is_none());
    // The table names the colour path and prints the channels.
    let (ok, stdout, stderr) = run(&[
        "sensor",
        "--hdr",
        STILL_LIFE,
        "--max-side-px",
        "120",
        "--roi",
        "32",
        "--cfa",
        "rggb",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("RGGB Bayer mosaic") && stdout.contains("per channel"),
        "{stdout}"
    );
    // A bad value is one line naming the choices.
    let (ok, _, stderr) = run(&["sensor", "--hdr", STILL_LIFE, "--cfa", "cmyk"]);
    assert!(!ok);
    assert!(
        stderr.contains("cmyk") && stderr.contains("none") && stderr.contains("rggb"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}
