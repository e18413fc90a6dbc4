//! The `restore` command's contract: JSON fields per run, output files, one-line errors and
//! non-zero exits.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

const ASTRONAUT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/photos/astronaut_256.png"
);

use crate::common::run_cli as run;

#[test]
fn restore_json_has_one_run_per_light_level() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A small grey photo made here: the command reads any image the `image` crate decodes.
    let photo = dir.path().join("scene.png");
    image::GrayImage::from_fn(64, 48, |x, y| image::Luma([((x * 4) ^ (y * 5)) as u8]))
        .save(&photo)
        .expect("save");
    let out = dir.path().join("out");
    let (ok, stdout, stderr) = run(&[
        "restore",
        "--preset",
        "open-aperture",
        "--image",
        photo.to_str().expect("utf-8"),
        "--snr-db",
        "24",
        "--snr-db",
        "32",
        "--json",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    assert_eq!(v["design"], "Open aperture");
    assert!(v["image"].as_str().expect("path").ends_with("scene.png"));
    // The open aperture passes 21/5 times the reference T-OLED's light.
    let rel = v["ltr_relative"].as_f64().expect("number");
    assert!((rel - 4.2).abs() < 0.01, "{rel}");
    let runs = v["runs"].as_array().expect("runs");
    assert_eq!(runs.len(), 2);
    for key in ["light_e", "snr_db", "psnr_db", "ssim", "channels"] {
        assert!(runs[0].get(key).is_some(), "run missing {key}");
    }
    assert!((runs[0]["light_e"].as_f64().expect("number") - 273.0).abs() < 0.5);
    assert_eq!(runs[1]["snr_db"], 32.0);
    // 1608 e⁻ × 4.2 stays below the full well: nothing saturates.
    assert_eq!(runs[1]["channels"][0]["saturated_fraction"], 0.0);
    let names: Vec<&str> = runs[0]["channels"]
        .as_array()
        .expect("channels")
        .iter()
        .map(|c| c["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["R", "G", "B"]);
    let psnr = |i: usize| runs[i]["psnr_db"].as_f64().expect("number");
    assert!(
        psnr(1) > psnr(0),
        "more light, better PSNR: {} vs {}",
        psnr(1),
        psnr(0)
    );
    for stem in ["snr-24db", "snr-32db"] {
        for suffix in [
            "captured.png",
            "restored.png",
            "difference.png",
            "captured.exr",
            "restored.exr",
        ] {
            let p = out.join(format!("{stem}_{suffix}"));
            assert!(p.is_file(), "missing {}", p.display());
        }
    }
    let restored = image::open(out.join("snr-32db_restored.png")).expect("PNG");
    assert_eq!((restored.width(), restored.height()), (64, 48));
}

#[test]
fn restore_prints_a_table_for_the_committed_photo() {
    assert!(Path::new(ASTRONAUT).is_file());
    let (ok, stdout, stderr) = run(&[
        "restore",
        "--preset",
        "toled-150dpi",
        "--image",
        ASTRONAUT,
        "--max-side-px",
        "64",
        "--light",
        "654",
        "--method",
        "cg",
        "--iterations",
        "5",
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("PSNR"), "{stdout}");
    assert!(stdout.contains("654"), "{stdout}");
}

#[test]
fn restore_errors_are_one_line_and_exit_non_zero() {
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("nope.png");
    let (ok, _, stderr) = run(&[
        "restore",
        "--image",
        missing.to_str().expect("utf-8"),
        "--snr-db",
        "28",
    ]);
    assert!(!ok);
    assert!(stderr.contains("nope.png"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    // No light level at all is a usage error.
    let (ok, _, stderr) = run(&["restore", "--image", ASTRONAUT]);
    assert!(!ok);
    assert!(
        stderr.contains("--light") || stderr.contains("--snr-db"),
        "{stderr}"
    );
    // A bad parameter names itself.
    let (ok, _, stderr) = run(&[
        "restore",
        "--image",
        ASTRONAUT,
        "--max-side-px",
        "32",
        "--snr-db",
        "28",
        "--nsr=-1",
    ]);
    assert!(!ok);
    assert!(stderr.contains("nsr"), "{stderr}");
}
