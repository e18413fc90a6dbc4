//! `udc-studio optimize`: the contract (loss history, AUC before and after, a loadable design).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use udc_studio::io::design::file::load_design;

use crate::common::run_cli as run;

#[test]
fn optimize_json_reports_history_and_auc_and_writes_the_design() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("new.json");
    let out_s = out.to_str().unwrap();
    let (ok, stdout, stderr) = run(&[
        "optimize",
        "--preset",
        "toled-150dpi",
        "--tiling",
        "random-4",
        "--epochs",
        "4",
        "--area",
        "0.3",
        "--preview",
        "--json",
        "--out",
        out_s,
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    let history = v["history"].as_array().unwrap();
    assert_eq!(history.len(), 4);
    for (k, h) in history.iter().enumerate() {
        assert_eq!(h["epoch"].as_u64(), Some(k as u64));
        assert!(h["loss_total"].as_f64().unwrap().is_finite());
        assert!(h["loss_inv"].as_f64().unwrap() < 0.0);
    }
    assert_eq!(v["auc_before"].as_array().unwrap().len(), 3);
    assert_eq!(v["auc_after"].as_array().unwrap().len(), 3);
    let saved = load_design(&out).unwrap();
    let open = saved
        .opening
        .cells
        .iter()
        .flatten()
        .filter(|c| **c == 1.0)
        .count();
    assert_eq!(
        open,
        (0.3f64 * 441.0).round() as usize,
        "binarised to the target area"
    );
    let after = v["open_fraction_after"].as_f64().unwrap();
    assert!((after - open as f64 / 441.0).abs() < 1e-9);
}

#[test]
fn optimize_rejects_bad_settings_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("new.json");
    let (ok, _, stderr) = run(&[
        "optimize",
        "--epochs",
        "5",
        "--area",
        "1.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("--area: must be in (0, 1]"), "{stderr}");
    assert!(!out.exists(), "nothing written on error");
    let (ok, _, stderr) = run(&[
        "optimize",
        "--data",
        "/nonexistent/photos",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("/nonexistent/photos"), "{stderr}");
}
