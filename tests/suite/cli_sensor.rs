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
    let cap = udc_studio::io::hdr::load_hdr(&out.join("vary-gain_vary-bin_capture.exr")).unwrap();
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
