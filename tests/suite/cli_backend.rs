//! `--backend cpu|gpu|auto`: the GPU gives the CPU's numbers to `f32` precision and says which
//! adapter it ran on; `auto` uses a hardware GPU or says in one line why not; a machine without
//! any adapter makes `gpu` a one-line error (this test then says it skipped that half). The
//! same for `restore` and for `phase restore`, whose operator runs the Bloch relay on the device.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common::run_cli as run;

fn analyze(backend: &str) -> (bool, serde_json::Value, String) {
    json_run(&[
        "analyze",
        "--preset",
        "fourier-square",
        "--preview",
        "--json",
        "--backend",
        backend,
    ])
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

/// A job on the CPU (which must say nothing of a backend) and on the GPU (which must name its
/// adapter), or `None` after printing why the GPU half was skipped (no adapter).
fn cpu_then_gpu(
    job: impl Fn(&str) -> (bool, serde_json::Value, String),
) -> Option<(serde_json::Value, serde_json::Value)> {
    let (ok, cpu, stderr) = job("cpu");
    assert!(ok, "{stderr}");
    assert!(cpu.get("backend").is_none(), "the default says nothing");
    let (ok, gpu, stderr) = job("gpu");
    if !ok {
        assert!(stderr.contains("no GPU adapter"), "{stderr}");
        eprintln!("skipped the comparison: {}", stderr.trim());
        return None;
    }
    assert!(
        gpu["backend"]["adapter"]
            .as_str()
            .is_some_and(|a| !a.is_empty())
    );
    // The device, not the CPU, computed them.
    assert!(
        gpu["backend"]["device_transforms"].as_u64().unwrap() > 0,
        "{}",
        gpu["backend"]
    );
    Some((cpu, gpu))
}

/// The first light level's PSNR of two restorations, to its second decimal.
fn same_first_psnr(cpu: &serde_json::Value, gpu: &serde_json::Value) {
    let psnr = |v: &serde_json::Value| v["runs"][0]["psnr_db"].as_f64().unwrap();
    let (c, g) = (psnr(cpu), psnr(gpu));
    assert!((c - g).abs() < 0.01, "{c} vs {g}");
}

/// A CLI run's success, its `--json` object (null if none) and its stderr.
fn json_run(args: &[&str]) -> (bool, serde_json::Value, String) {
    let (ok, stdout, stderr) = run(args);
    let json = serde_json::from_str(stdout.trim()).unwrap_or(serde_json::Value::Null);
    (ok, json, stderr)
}

fn phase_restore(backend: &str) -> (bool, serde_json::Value, String) {
    json_run(&[
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
    ])
}

/// A λ0 plan's restoration (its operator through the Bloch relay, the phase model's slowest
/// step) on the GPU: the CPU's LTR and PSNR to f32 precision, and the adapter named.
#[test]
fn a_phase_restoration_on_the_gpu_reads_as_the_cpus() {
    let Some((cpu, gpu)) = cpu_then_gpu(phase_restore) else {
        return;
    };
    let f = |v: &serde_json::Value, key: &str| v[key].as_f64().unwrap();
    assert!((f(&cpu, "ltr") - f(&gpu, "ltr")).abs() <= 1e-5 * f(&cpu, "ltr"));
    same_first_psnr(&cpu, &gpu);
}

/// `restore --backend gpu`: the design's PSFs from the device, the same restoration to the
/// PSNR's second decimal, the adapter named.
#[test]
fn a_restoration_on_the_gpu_reads_as_the_cpus() {
    let photo = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/photos/astronaut_256.png"
    );
    let restore = |backend: &str| {
        json_run(&[
            "restore",
            "--preset",
            "fourier-square",
            "--image",
            photo,
            "--max-side-px",
            "32",
            "--snr-db",
            "28",
            "--json",
            "--backend",
            backend,
        ])
    };
    let Some((cpu, gpu)) = cpu_then_gpu(restore) else {
        return;
    };
    assert_eq!(gpu["ltr"], cpu["ltr"]);
    same_first_psnr(&cpu, &gpu);
}

/// A sweep's points on one device: `backend = "gpu"` in a spec's base runs every `analyze`
/// point's PSFs there, each row the CPU sweep's to the AUC's tolerance and the same LTR.
#[test]
fn a_sweep_runs_its_points_on_the_gpu() {
    let dir = tempfile::tempdir().unwrap();
    let table = |backend: &str| -> Option<Vec<(f64, f64, Option<u64>)>> {
        let spec = dir.path().join(format!("{backend}.toml"));
        // The GPU's rows also say how many transforms the device computed.
        let extra = if backend == "gpu" {
            ", \"backend.device_transforms\""
        } else {
            ""
        };
        std::fs::write(
            &spec,
            format!(
                "job = \"analyze\"\nmetrics = [\"auc_radial_min_mean\", \"ltr\"{extra}]\n[base]\n\
                 preset = \"fourier-square\"\npreview = true\nbackend = \"{backend}\"\n\
                 [[axis]]\nparam = \"tiling\"\nvalues = [\"repeat\", \"random-4\"]\n"
            ),
        )
        .unwrap();
        let out = dir.path().join(backend);
        let (ok, _, stderr) = run(&[
            "sweep",
            spec.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        if !ok && backend == "gpu" && stderr.contains("no GPU adapter") {
            eprintln!("skipped the GPU sweep: {}", stderr.trim());
            return None;
        }
        assert!(ok, "{stderr}");
        let mut r = csv::Reader::from_path(out.join("results.csv")).unwrap();
        let header: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
        let col = |name: &str| header.iter().position(|h| h == name).unwrap();
        let (auc, ltr) = (col("auc_radial_min_mean"), col("ltr"));
        let on_device = header.iter().position(|h| h == "backend.device_transforms");
        // Rows arrive as points finish: in point order for the comparison.
        let mut rows: Vec<(u64, f64, f64, Option<u64>)> = r
            .records()
            .map(|rec| {
                let rec = rec.unwrap();
                let f = |i: usize| rec[i].parse::<f64>().unwrap();
                let n = on_device.map(|i| rec[i].parse::<u64>().unwrap());
                (rec[0].parse().unwrap(), f(auc), f(ltr), n)
            })
            .collect();
        rows.sort_by_key(|r| r.0);
        Some(rows.into_iter().map(|(_, a, l, n)| (a, l, n)).collect())
    };
    let cpu = table("cpu").unwrap();
    let Some(gpu) = table("gpu") else {
        return;
    };
    assert_eq!(cpu.len(), 2);
    assert_eq!(cpu.len(), gpu.len());
    for ((ca, cl, _), (ga, gl, n)) in cpu.iter().zip(&gpu) {
        assert!(
            n.is_some_and(|n| n > 0),
            "the device computed the point: {n:?}"
        );
        assert_eq!(cl, gl, "LTR");
        assert!((ca - ga).abs() <= 3e-3 * ca, "AUC {ca} vs {ga}");
    }
}

/// The commands that study a design outside the typed jobs take `--backend` too: `saturation`,
/// `depth` and `psf compare` on the GPU read as on the CPU (the device computing their PSFs);
/// `field`, `appearance` and `psf fit` with `auto` say where theirs ran; a bad value is clap's one line.
#[test]
fn the_studies_of_a_design_run_on_the_gpu_as_on_the_cpu() {
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("g.npy");
    crate::common::toled_green_set(&set, 168.0, 64);
    let with = |args: &[&str], backend: &str| {
        let mut all = args.to_vec();
        all.extend(["--json", "--backend", backend]);
        json_run(&all)
    };
    let saturation = |b: &str| {
        let args = [
            "saturation",
            "--preset",
            "fourier-square",
            "--max-side-px",
            "32",
        ];
        with(&args, b)
    };
    let Some((cpu, gpu)) = cpu_then_gpu(saturation) else {
        return;
    };
    for run in ["clipped", "bracketed"] {
        let psnr = |v: &serde_json::Value| v[run]["psnr_db"].as_f64().unwrap();
        assert!(
            (psnr(&cpu) - psnr(&gpu)).abs() < 0.01,
            "{run}: {cpu} vs {gpu}"
        );
    }
    let depth = |b: &str| {
        let args = [
            "depth",
            "--preset",
            "fourier-square",
            "--object-distance-mm",
            "1000",
        ];
        with(&args, b)
    };
    let (cpu, gpu) = cpu_then_gpu(depth).unwrap();
    for key in [
        "residual_rel_focused_at_object",
        "residual_rel_focused_at_infinity",
    ] {
        let (c, g) = (cpu[key].as_f64().unwrap(), gpu[key].as_f64().unwrap());
        assert!(c > 0.0 && (c - g).abs() <= 1e-4 * c, "{key}: {c} vs {g}");
    }
    let compare = |b: &str| {
        let args = [
            "psf",
            "compare",
            set.to_str().unwrap(),
            "--preset",
            "toled-150dpi",
        ];
        with(&args, b)
    };
    let (cpu, gpu) = cpu_then_gpu(compare).unwrap();
    let row = |v: &serde_json::Value, key: &str| v["channels"][0][key].as_f64().unwrap();
    let (c, g) = (row(&cpu, "auc_design"), row(&gpu, "auc_design"));
    assert!((c - g).abs() <= 3e-3 * c, "AUC {c} vs {g}");
    let (c, g) = (
        row(&cpu, "residual_energy_share"),
        row(&gpu, "residual_energy_share"),
    );
    assert!((c - g).abs() < 1e-4, "residual share {c} vs {g}");
    // `auto` (a software driver is not taken): the backend object says where the PSFs ran.
    for args in [
        &[
            "field",
            "--preset",
            "fourier-square",
            "--display-distance-mm",
            "1",
            "--grid",
            "2",
        ][..],
        &["appearance", "--preset", "toled-150dpi", "--preview"],
        // A fit on a software driver takes about a minute (its fine grids are read back whole); the
        // device's whole grid is held to the CPU's in crates/gpu/tests.
        &[
            "psf",
            "fit",
            set.to_str().unwrap(),
            "--preset",
            "toled-150dpi",
            "--no-search",
            "--window-px",
            "16",
        ],
    ] {
        let (ok, v, stderr) = with(args, "auto");
        assert!(ok, "{args:?}: {stderr}");
        assert_eq!(v["backend"]["requested"], "auto", "{args:?}");
        let (ok, _, stderr) = run(&[args, &["--backend", "cuda"]].concat());
        assert!(
            !ok && stderr.contains("possible values: cpu, gpu, auto"),
            "{stderr}"
        );
    }
}

/// `phase invertibility` and `phase optimize` take `--backend`; under the lenslet period (one
/// lenslet's samples, the default) no step runs on the device, so V is the CPU's to the bit and
/// the report says the CPU computed it instead of naming the adapter it was handed.
#[test]
fn a_phase_job_with_no_step_on_the_device_says_the_cpu_ran_it() {
    let v = |backend: &str| {
        let args = ["phase", "invertibility", "--preview", "--json"];
        json_run(&[&args[..], &["--backend", backend]].concat())
    };
    let (ok, cpu, stderr) = v("cpu");
    assert!(ok, "{stderr}");
    let (ok, gpu, stderr) = v("gpu");
    if !ok {
        assert!(stderr.contains("no GPU adapter"), "{stderr}");
        eprintln!("skipped the comparison: {}", stderr.trim());
        return;
    }
    assert_eq!(gpu["v"], cpu["v"]);
    assert_eq!(gpu["backend"]["device_transforms"], 0, "{}", gpu["backend"]);
    let (ok, text, stderr) = run(&["phase", "optimize", "--preview", "--backend", "gpu"]);
    assert!(ok, "{stderr}");
    assert!(
        text.contains("PSFs computed on the CPU: no step of this job runs on"),
        "{text}"
    );
    let (ok, _, stderr) = run(&["phase", "optimize", "--backend", "cuda"]);
    assert!(
        !ok && stderr.contains("possible values: cpu, gpu, auto"),
        "{stderr}"
    );
}

fn optimize_one_epoch(backend: &str) -> (bool, serde_json::Value, String) {
    let out = tempfile::tempdir().unwrap();
    let design = out.path().join("optimized.json");
    let mut run = json_run(&[
        "optimize",
        "--preset",
        "toled-150dpi",
        "--f-number",
        "5",
        "--preview",
        "--epochs",
        "1",
        "--sigmoid-relaxation",
        "--json",
        "--out",
        design.to_str().unwrap(),
        "--backend",
        backend,
    ]);
    // The saved opening, read before its folder goes.
    if let Ok(text) = std::fs::read_to_string(&design) {
        let saved: serde_json::Value = serde_json::from_str(&text).unwrap();
        run.1["saved_cells"] = saved["opening"]["cells"].clone();
    }
    run
}

/// `optimize --backend gpu`: the epoch's `L_inv` (the model's window transforms, forward) and
/// the saved design (their adjoints, through Adam's step) as the CPU's, the device's transforms
/// counted.
#[test]
fn an_optimization_on_the_gpu_reads_as_the_cpus() {
    let Some((cpu, gpu)) = cpu_then_gpu(optimize_one_epoch) else {
        return;
    };
    let first = |v: &serde_json::Value| v["history"][0]["loss_inv"].as_f64().unwrap();
    let (c, g) = (first(&cpu), first(&gpu));
    assert!((c - g).abs() <= 1e-4 * c.abs(), "L_inv {c} vs {g}");
    // Adam's first step moves each logit by about the sign of its gradient, so an adjoint
    // that is wrong on the device opens other cells; f32 may flip a gradient that is nearly 0.
    let cells = |v: &serde_json::Value| -> String {
        let rows = v["saved_cells"].as_array().expect("the saved opening");
        rows.iter().map(|r| r.as_str().unwrap()).collect()
    };
    let (c, g) = (cells(&cpu), cells(&gpu));
    assert_eq!(c.len(), g.len());
    let differ = c.chars().zip(g.chars()).filter(|(a, b)| a != b).count();
    assert!(
        differ * 100 <= c.len(),
        "{differ} of {} cells differ:\n{c}\n{g}",
        c.len()
    );
    let (c, g) = (
        cpu["invertibility_loss_after"].as_f64().unwrap(),
        gpu["invertibility_loss_after"].as_f64().unwrap(),
    );
    assert!((c - g).abs() <= 1e-3 * c.abs(), "L_inv after {c} vs {g}");
}
