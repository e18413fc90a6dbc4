//! `--backend cpu|gpu|auto`: the GPU gives the CPU's numbers to `f32` precision and says which
//! adapter it ran on; `auto` uses a hardware GPU or says in one line why not; a machine without
//! any adapter makes `gpu` a one-line error (this test then says it skipped that half).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common::run_cli as run;

fn analyze(backend: &str) -> (bool, serde_json::Value, String) {
    let (ok, stdout, stderr) = run(&[
        "analyze",
        "--preset",
        "fourier-square",
        "--preview",
        "--json",
        "--backend",
        backend,
    ]);
    let json = serde_json::from_str(stdout.trim()).unwrap_or(serde_json::Value::Null);
    (ok, json, stderr)
}

fn aucs(v: &serde_json::Value) -> Vec<f64> {
    v["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["auc_radial_min"].as_f64().unwrap())
        .collect()
}

#[test]
fn the_gpu_backend_reads_as_the_cpu_and_names_its_adapter() {
    let (ok, cpu, stderr) = analyze("cpu");
    assert!(ok, "{stderr}");
    assert!(cpu.get("backend").is_none(), "the default says nothing");
    let (ok, gpu, stderr) = analyze("gpu");
    if !ok {
        assert!(stderr.contains("no GPU adapter"), "{stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        eprintln!("skipped the comparison: {}", stderr.trim());
        return;
    }
    assert!(
        gpu["backend"]["adapter"]
            .as_str()
            .is_some_and(|a| !a.is_empty())
    );
    assert_eq!(gpu["ltr"], cpu["ltr"]);
    for (c, g) in aucs(&cpu).iter().zip(aucs(&gpu)) {
        assert!((c - g).abs() <= 3e-3 * c, "AUC {c} vs {g}");
    }
}

#[test]
fn auto_runs_on_a_hardware_gpu_or_says_why_not() {
    let (ok, v, stderr) = analyze("auto");
    assert!(ok, "{stderr}");
    let b = &v["backend"];
    assert_eq!(b["requested"], "auto");
    match (b["adapter"].as_str(), b["note"].as_str()) {
        (Some(adapter), None) => assert!(!adapter.contains("software"), "{adapter}"),
        // No hardware adapter, or one that refused a transform (too large for it).
        (_, Some(note)) => assert!(note.ends_with("computing on the CPU"), "{note}"),
        other => panic!("adapter and note: {other:?}"),
    }
    let (ok, _, stderr) = run(&["analyze", "--backend", "cuda"]);
    assert!(
        !ok && stderr.contains("possible values: cpu, gpu, auto"),
        "{stderr}"
    );
}

fn phase_restore(backend: &str) -> (bool, serde_json::Value, String) {
    let (ok, stdout, stderr) = run(&[
        "phase",
        "restore",
        "--preview",
        "--peaks",
        "--lambda0",
        "uniform",
        "--relay",
        "wrapped-display",
        "--scene-px",
        "16",
        "--photons",
        "1000",
        "--denoise",
        "none",
        "--json",
        "--backend",
        backend,
    ]);
    let json = serde_json::from_str(stdout.trim()).unwrap_or(serde_json::Value::Null);
    (ok, json, stderr)
}

/// A λ0 plan's restoration (its operator through the Bloch relay, the phase model's slowest
/// step) on the GPU: the CPU's LTR and PSNR to f32 precision, and the adapter named.
#[test]
fn a_phase_restoration_on_the_gpu_reads_as_the_cpus() {
    let (ok, cpu, stderr) = phase_restore("cpu");
    assert!(ok, "{stderr}");
    assert!(cpu.get("backend").is_none(), "the default says nothing");
    let (ok, gpu, stderr) = phase_restore("gpu");
    if !ok {
        assert!(stderr.contains("no GPU adapter"), "{stderr}");
        eprintln!("skipped the comparison: {}", stderr.trim());
        return;
    }
    assert!(
        gpu["backend"]["adapter"]
            .as_str()
            .is_some_and(|a| !a.is_empty())
    );
    let f = |v: &serde_json::Value, key: &str| v[key].as_f64().unwrap();
    assert!((f(&cpu, "ltr") - f(&gpu, "ltr")).abs() <= 1e-5 * f(&cpu, "ltr"));
    let psnr = |v: &serde_json::Value| v["runs"][0]["psnr_db"].as_f64().unwrap();
    assert!(
        (psnr(&cpu) - psnr(&gpu)).abs() < 0.01,
        "{} vs {}",
        psnr(&cpu),
        psnr(&gpu)
    );
}
