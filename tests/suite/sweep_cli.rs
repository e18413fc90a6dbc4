//! `udc-studio sweep`: results equal the single-point commands', Parquet equals CSV, resuming
//! skips finished points, Ctrl-C keeps them, shards merge into the whole, bad specs and values
//! are refused with the field named (issue 19).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeMap;
use std::path::Path;

use crate::common::run_cli;
use udc_studio::core::sweep::ParamValue;
use udc_studio::io::design::hash::design_hash;
use udc_studio::jobs::FromParams;
use udc_studio::jobs::display::DesignSelection;

const TINY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/sweep/tiny.toml");

/// Data rows of a results.csv keyed by point, as field lists.
fn rows(dir: &Path) -> (Vec<String>, BTreeMap<u64, Vec<String>>) {
    let mut r = csv::Reader::from_path(dir.join("results.csv")).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    let mut out = BTreeMap::new();
    for rec in r.records() {
        let rec = rec.unwrap();
        let fields: Vec<String> = rec.iter().map(str::to_string).collect();
        let point: u64 = fields[0].parse().unwrap();
        assert!(out.insert(point, fields).is_none(), "point {point} twice");
    }
    (header, out)
}

fn sweep(args: &[&str]) -> (bool, String, String) {
    let mut all = vec!["sweep"];
    all.extend_from_slice(args);
    run_cli(&all)
}

#[test]
fn a_sweep_row_holds_what_analyze_prints_for_that_point() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    let (ok, _, err) = sweep(&[TINY, "--out", out.to_str().unwrap(), "--quiet"]);
    assert!(ok, "{err}");
    let (header, table) = rows(&out);
    assert_eq!(table.len(), 8);
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    for point in [0u64, 6] {
        let row = &table[&point];
        let (tiling, seed) = (&row[col("tiling")], &row[col("seed")]);
        let (ok, json, err) = run_cli(&[
            "analyze",
            "--preset",
            "toled-150dpi",
            "--preview",
            "--tiling",
            tiling,
            "--seed",
            seed,
            "--json",
        ]);
        assert!(ok, "{err}");
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        let ltr = v["ltr"].as_f64().unwrap();
        assert_eq!(row[col("ltr")].parse::<f64>().unwrap(), ltr);
        for (i, c) in ["R", "G", "B"].iter().enumerate() {
            let auc = v["channels"][i]["auc_radial_min"].as_f64().unwrap();
            let name = format!("channels.{c}.auc_radial_min");
            assert_eq!(
                row[col(&name)].parse::<f64>().unwrap(),
                auc,
                "{name} at point {point}"
            );
        }
        // The row's design hash is the design the studio would open for it.
        let choice = DesignSelection::from_params(&udc_studio::jobs::params_of([
            ("preset", &ParamValue::Text("toled-150dpi".into())),
            ("tiling", &ParamValue::Text(tiling.clone())),
            ("seed", &ParamValue::Int(seed.parse().unwrap())),
        ]))
        .unwrap();
        assert_eq!(
            design_hash(&choice.resolve().unwrap()),
            row[col("design_hash")]
        );
    }
    // Random tilings beat the periodic one in AUC (thesis Fig. 3.10), seed by seed.
    for s in 0..4u64 {
        let a = |p: u64| {
            table[&p][col("auc_radial_min_mean")]
                .parse::<f64>()
                .unwrap()
        };
        assert!(
            a(4 + s) > 3.0 * a(s),
            "seed {s}: random {} vs repeat {}",
            a(4 + s),
            a(s)
        );
    }
    // Plots beside the results: PNG and SVG of the default metric-vs-axis and Pareto plots.
    for stem in [
        "auc_radial_min_mean-vs-tiling",
        "pareto-auc_radial_min_mean-ltr",
    ] {
        let png = image::open(out.join("plots").join(format!("{stem}.png"))).unwrap();
        assert_eq!((png.width(), png.height()), (960, 600));
        let svg = std::fs::read_to_string(out.join("plots").join(format!("{stem}.svg"))).unwrap();
        assert!(svg.contains("<svg"), "{stem}.svg is not an SVG");
        let x_label = if stem.starts_with("pareto") {
            "ltr"
        } else {
            "tiling"
        };
        assert!(
            svg.contains(x_label),
            "{stem}.svg has no {x_label} axis label"
        );
    }
    // The Parquet file holds the same table, typed.
    check_parquet_equals_csv(&out);
}

fn check_parquet_equals_csv(out: &Path) {
    use arrow_array::Array;
    use arrow_array::cast::AsArray;
    use arrow_array::types::{Float64Type, UInt64Type};
    let (header, table) = rows(out);
    let file = std::fs::File::open(out.join("results.parquet")).unwrap();
    let reader = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap()
        .build()
        .unwrap();
    let mut n = 0;
    for batch in reader {
        let batch = batch.unwrap();
        let names: Vec<String> = batch
            .schema()
            .fields()
            .iter()
            .map(|f| f.name().clone())
            .collect();
        assert_eq!(names, header);
        let points = batch.column(0).as_primitive::<UInt64Type>();
        let ltr_col = header.iter().position(|h| h == "ltr").unwrap();
        let ltr = batch.column(ltr_col).as_primitive::<Float64Type>();
        for i in 0..batch.num_rows() {
            let row = &table[&points.value(i)];
            assert!(!ltr.is_null(i));
            assert_eq!(ltr.value(i), row[ltr_col].parse::<f64>().unwrap());
            n += 1;
        }
    }
    assert_eq!(n, table.len());
}

#[test]
fn resuming_skips_finished_points_and_repairs_a_cut_row() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    let o = out.to_str().unwrap();
    assert!(sweep(&[TINY, "--out", o, "--quiet"]).0);
    let (_, full) = rows(&out);
    // Keep the header and three rows, and half of a fourth, as a kill would.
    let text = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let cut = format!("{}\n{}", lines[..4].join("\n"), &lines[4][..20]);
    std::fs::write(out.join("results.csv"), cut).unwrap();
    let (ok, _, err) = sweep(&[TINY, "--out", o]);
    assert!(ok, "{err}");
    assert!(err.contains("5 computed"), "{err}");
    assert!(err.contains("3 already done"), "{err}");
    let (_, again) = rows(&out);
    assert_eq!(again, full, "the resumed table is the table");
    check_parquet_equals_csv(&out);
    // A third run computes nothing.
    let (ok, _, err) = sweep(&[TINY, "--out", o]);
    assert!(
        ok && err.contains("0 computed") && err.contains("8 already done"),
        "{err}"
    );
    // Another sweep in the same folder is refused, and the folder is untouched.
    let other = dir.path().join("other.toml");
    std::fs::write(
        &other,
        std::fs::read_to_string(TINY)
            .unwrap()
            .replace("stop = 3", "stop = 4"),
    )
    .unwrap();
    let (ok, _, err) = sweep(&[other.to_str().unwrap(), "--out", o]);
    assert!(!ok && err.contains("another sweep"), "{err}");
    assert_eq!(rows(&out).1, full);
}

#[test]
fn shards_merge_into_the_local_table_and_gaps_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let local = dir.path().join("local");
    assert!(sweep(&[TINY, "--out", local.to_str().unwrap(), "--quiet"]).0);
    let mut shard_dirs = Vec::new();
    for i in 0..3 {
        let d = dir.path().join(format!("s{i}"));
        let (ok, _, err) = sweep(&[
            TINY,
            "--out",
            d.to_str().unwrap(),
            "--shard",
            &format!("{i}/3"),
            "--threads",
            "1",
            "--quiet",
        ]);
        assert!(ok, "{err}");
        let (_, t) = rows(&d);
        assert!(
            t.keys().all(|p| p % 3 == i),
            "shard {i} holds {:?}",
            t.keys()
        );
        shard_dirs.push(d.to_str().unwrap().to_string());
    }
    let merged = dir.path().join("merged");
    let mut args: Vec<&str> = vec!["merge"];
    args.extend(shard_dirs.iter().map(String::as_str));
    args.extend(["--out", merged.to_str().unwrap()]);
    let (ok, _, err) = sweep(&args);
    assert!(ok, "{err}");
    assert_eq!(rows(&merged), rows(&local));
    // Rows come out sorted by point.
    let text = std::fs::read_to_string(merged.join("results.csv")).unwrap();
    let order: Vec<u64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(order, (0..8).collect::<Vec<_>>());
    // Without shard 1 the merge fails and names its points.
    let (ok, _, err) = sweep(&[
        "merge",
        &shard_dirs[0],
        &shard_dirs[2],
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("3 of 8 points are missing (points 1, 4, 7)"),
        "{err}"
    );
    // A shard given twice holds the same results: each point once.
    let (ok, _, err) = sweep(&[
        "merge",
        &shard_dirs[0],
        &shard_dirs[1],
        &shard_dirs[0],
        &shard_dirs[2],
        "--out",
        merged.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{err}");
    assert_eq!(rows(&merged), rows(&local));
    // A copy of shard 0 whose point 3 has another result, and a row cut halfway at its end.
    let copy = dir.path().join("s0-changed");
    std::fs::create_dir_all(&copy).unwrap();
    for entry in std::fs::read_dir(&shard_dirs[0]).unwrap() {
        let p = entry.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, copy.join(p.file_name().unwrap())).unwrap();
        }
    }
    let csv = copy.join("results.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut changed: String = text
        .lines()
        .map(|l| match l.strip_prefix("3,") {
            Some(rest) => format!("3,{}{}\n", "0".repeat(32), &rest[32..]),
            None => format!("{l}\n"),
        })
        .collect();
    changed.push_str("6,abc");
    std::fs::write(&csv, changed).unwrap();
    let (ok, _, err) = sweep(&[
        "merge",
        copy.to_str().unwrap(),
        &shard_dirs[0],
        &shard_dirs[1],
        &shard_dirs[2],
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("point 3 has two different results") && err.lines().count() == 1,
        "{err}"
    );
}

#[test]
fn bad_specs_and_values_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let spec = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let out = dir.path().join("o");
    let o = out.to_str().unwrap();
    let cases = [
        (
            spec(
                "tiling.toml",
                "job = \"analyze\"\n[[axis]]\nparam = \"tiling\"\nvalues = [\"repeat\", \"diagonal\"]",
            ),
            "axis `tiling` value `diagonal`",
        ),
        (
            spec(
                "flag.toml",
                "job = \"analyze\"\n[[axis]]\nparam = \"pitch\"\nvalues = [1]",
            ),
            "unknown parameter `pitch`",
        ),
        (
            spec(
                "neg.toml",
                "job = \"analyze\"\n[[axis]]\nparam = \"pitch-um\"\nvalues = [168, -5]",
            ),
            "axis `pitch-um` value `-5`",
        ),
        (spec("syntax.toml", "job = analyze"), "line 1"),
        (
            spec("j.json", "{\"job\": \"analyze\", \"axis\": 3}"),
            "axis",
        ),
    ];
    for (path, needle) in &cases {
        let (ok, _, err) = sweep(&[path, "--out", o]);
        assert!(!ok, "{path} was accepted");
        assert!(err.contains(needle), "{path}: `{err}` lacks `{needle}`");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            !out.exists(),
            "{path}: nothing is written for a refused spec"
        );
    }
    for shard in ["3/3", "x", "1/0"] {
        let (ok, _, err) = sweep(&[TINY, "--out", o, "--shard", shard]);
        assert!(!ok && err.contains("shard"), "{shard}: {err}");
    }
    let (ok, _, err) = sweep(&["/nonexistent/spec.toml", "--out", o]);
    assert!(!ok && err.contains("/nonexistent/spec.toml"), "{err}");
    let (ok, stdout, _) = sweep(&[TINY, "--check"]);
    assert!(ok && stdout.contains("8 points"), "{stdout}");
}

#[test]
fn a_point_that_fails_is_a_row_with_its_error_and_the_rest_run() {
    let dir = tempfile::tempdir().unwrap();
    // The check parses every value, but only running a point reads its photo: a corrupt photo
    // fails that point alone.
    let bad = dir.path().join("bad.png");
    std::fs::write(&bad, b"not a png").unwrap();
    let good = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/photos/astronaut_256.png"
    );
    let p = dir.path().join("s.toml");
    std::fs::write(
        &p,
        format!(
            "job = \"restore\"\n[base]\npreset = \"toled-150dpi\"\nsnr-db = 32\nmax-side-px = 48\n[[axis]]\nparam = \"image\"\nvalues = [{good:?}, {:?}]\n",
            bad.to_str().unwrap()
        ),
    )
    .unwrap();
    let out = dir.path().join("o");
    let (ok, _, err) = sweep(&[p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(err.contains("1 failed"), "{err}");
    let (header, t) = rows(&out);
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    assert!(t[&0][col("error")].is_empty());
    assert!(t[&0][col("runs.0.psnr_db")].parse::<f64>().unwrap() > 10.0);
    assert!(t[&1][col("error")].contains("bad.png"), "{:?}", t[&1]);
    assert!(t[&1][col("runs.0.psnr_db")].is_empty());
    // A failed point is finished: a re-run does not retry it.
    let (ok, _, err) = sweep(&[p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(ok && err.contains("0 computed"), "{err}");
}

#[test]
fn slurm_scripts_run_each_shard_as_an_array_task_then_merge() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cluster");
    let (ok, stdout, err) = run_cli(&[
        "sweep",
        "slurm",
        TINY,
        "--shards",
        "3",
        "--out",
        out.to_str().unwrap(),
        "--partition",
        "debug",
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("submit.sh"), "{stdout}");
    let array = std::fs::read_to_string(out.join("slurm/array.sbatch")).unwrap();
    assert!(array.contains("#SBATCH --array=0-2"), "{array}");
    assert!(array.contains("#SBATCH --partition=debug"));
    assert!(
        array.contains("--shard \"$SLURM_ARRAY_TASK_ID\"/3"),
        "{array}"
    );
    let merge = std::fs::read_to_string(out.join("slurm/merge.sbatch")).unwrap();
    assert!(merge.contains("sweep merge"), "{merge}");
    let submit = std::fs::read_to_string(out.join("slurm/submit.sh")).unwrap();
    assert!(submit.contains("--dependency=afterok:"), "{submit}");
    // The copied spec is the same sweep: a shard run from it merges with the original's.
    let (ok, _, err) = run_cli(&[
        "sweep",
        out.join("spec.toml").to_str().unwrap(),
        "--out",
        dir.path().join("x").to_str().unwrap(),
        "--check",
    ]);
    assert!(ok, "{err}");
    for bad in [["--time", "1h"], ["--shards", "0"], ["--partition", "a;b"]] {
        let mut args = vec![
            "sweep",
            "slurm",
            TINY,
            "--out",
            out.to_str().unwrap(),
            "--shards",
            "2",
        ];
        args.extend(bad);
        let (ok, _, err) = run_cli(&args);
        assert!(!ok, "{bad:?} accepted");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}

#[test]
fn ctrl_c_keeps_every_finished_point_and_a_rerun_completes() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("s.toml");
    std::fs::write(
        &spec,
        "job = \"analyze\"\n[base]\npreset = \"l2inv-random\"\n[[axis]]\nparam = \"seed\"\nrange = { start = 0, stop = 59 }\n",
    )
    .unwrap();
    let out = dir.path().join("o");
    // The run holds after 6 new points (the first, computed for the columns, and 5 more) until
    // the signal: it is interrupted midway however fast the machine.
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_udc-studio"))
        .args([
            "sweep",
            spec.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--threads",
            "2",
        ])
        .env("UDC_SWEEP_HOLD_AFTER_POINTS", "5")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once the held points are in the journal (a header and 6 rows).
    let csv = out.join("results.csv");
    let t0 = std::time::Instant::now();
    while std::fs::read_to_string(&csv).map_or(0, |t| t.lines().count()) < 7 {
        assert!(t0.elapsed().as_secs() < 120, "no rows after 2 minutes");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let (_, kept) = rows(&out);
    assert!(!output.status.success(), "the held run cannot finish");
    assert!(stderr.contains("interrupted"), "{stderr}");
    assert_eq!(kept.len(), 6, "every finished point kept, no more");
    // The Parquet file was finished too, with the same rows.
    check_parquet_equals_csv(&out);
    let (ok, _, err) = sweep(&[
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{err}");
    let (_, all) = rows(&out);
    assert_eq!(all.len(), 60, "every point exactly once after the re-run");
    for (p, r) in &kept {
        assert_eq!(&all[p], r, "point {p} changed");
    }
}

/// Every flag a sweep can set is a flag of some command: clap's own consistency check over the
/// whole command line (two arguments named alike in one command, e.g. a flattened `--dpi`,
/// only panic when that command runs).
#[test]
fn the_command_line_definition_is_consistent() {
    use clap::CommandFactory;
    udc_studio::cli::Cli::command().debug_assert();
}

/// `kill -9` at 20 moments spread over a run (seeded: each restart is killed once the journal
/// holds 0 or 1 more line than it did, then up to a millisecond later, so the cut falls before
/// the header, between points or in the middle of a write): every restart resumes from what
/// the journal holds, and the final table equals an uninterrupted run's, row for row. The kills
/// follow the journal, not the clock, so the run cannot finish before them however fast the
/// machine.
#[test]
fn a_sweep_killed_at_twenty_moments_resumes_to_the_uninterrupted_table() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("k.toml");
    std::fs::write(
        &spec,
        "job = \"analyze\"\nmetrics = [\"auc_radial_min_mean\", \"ltr\"]\n[base]\n\
         preset = \"toled-150dpi\"\ntiling = \"random-d4\"\n[[axis]]\nparam = \"seed\"\n\
         range = { start = 0, stop = 29 }\n",
    )
    .unwrap();
    let whole = dir.path().join("whole");
    let (ok, _, err) = sweep(&[
        spec.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
        "--quiet",
        "--no-plots",
    ]);
    assert!(ok, "{err}");
    let (header, want) = rows(&whole);
    assert_eq!(want.len(), 30);

    let out = dir.path().join("killed");
    let journal = out.join("results.csv");
    let lines = || std::fs::read_to_string(&journal).map_or(0, |t| t.lines().count());
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut killed_midway = 0;
    for _ in 0..20 {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let target = lines() + usize::from(state >> 63 == 1);
        let after_us = (state >> 33) % 1000;
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_udc-studio"))
            .args(["sweep", spec.to_str().unwrap(), "--out"])
            .arg(&out)
            .args(["--quiet", "--no-plots", "--threads", "2"])
            // Each run computes at most one new point past the first and then holds until
            // the kill: twenty runs cannot finish thirty points, however fast the machine.
            .env("UDC_SWEEP_HOLD_AFTER_POINTS", "1")
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let t0 = std::time::Instant::now();
        while lines() < target && child.try_wait().unwrap().is_none() {
            assert!(t0.elapsed().as_secs() < 120, "no new row after 2 minutes");
            std::thread::sleep(std::time::Duration::from_micros(200));
        }
        std::thread::sleep(std::time::Duration::from_micros(after_us));
        if child.try_wait().unwrap().is_none() {
            killed_midway += 1;
        }
        // SIGKILL: no handler runs, the journal is cut wherever the write was.
        let _ = child.kill();
        let _ = child.wait();
    }
    // The hold keeps every run unfinished: each kill lands midway.
    assert_eq!(
        killed_midway, 20,
        "only {killed_midway} kills landed midway"
    );
    assert!(lines() < 31, "the held runs finished the sweep");
    let (ok, _, err) = sweep(&[
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--no-plots",
    ]);
    assert!(ok, "{err}");
    let (got_header, got) = rows(&out);
    assert_eq!(got_header, header);
    assert_eq!(got, want, "the resumed table equals the uninterrupted one");
    check_parquet_equals_csv(&out);
}
