//! Peak resident memory of one full `analyze` call, each case in a fresh process.
//!
//! `VmHWM` (from /proc/self/status) is a process-wide high-water mark that never goes down, so
//! a second job in the same process would only show the larger of the two. The bench therefore
//! re-runs its own executable once per case (`--case NAME`) and each child reports:
//! - the baseline `VmHWM` after building the design, before the call;
//! - the peak `VmHWM` after the call (FFT scratch, rayon's per-thread accumulators, results).
//!
//! The parent writes `<target>/udc-bench/memory.json` for benches/report.sh. On a system without
//! /proc the numbers print as "unavailable" (JSON `null`). Run with `cargo bench --bench memory`.

mod common;

use std::path::PathBuf;
use std::process::Command;

use udc_studio::core::analysis::analyze::{AnalyzeOptions, analyze_with};
use udc_studio::core::design::TilingMode;
use udc_studio::core::{Design, Progress};
use udc_studio::io::design::presets::load_preset;

const CASES: [&str; 3] = [
    "iccp21/toled-repeat",
    "iccp21/toled-random-d4",
    "iccp21/toled-600dpi",
];

fn design(case: &str) -> Option<Design> {
    let mut d = Design::default_toled();
    match case {
        "iccp21/toled-repeat" => {}
        "iccp21/toled-random-d4" => d.tiling.mode = TilingMode::RandomD4,
        // The preset the issue quotes (`analyze --preset toled-600dpi`; goal ≤ 150 MB).
        "iccp21/toled-600dpi" => d = load_preset("toled-600dpi").ok()?,
        _ => return None,
    }
    Some(d)
}

/// `VmHWM` in MB (10⁶ bytes), or `None` without /proc or the field.
fn vm_hwm_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    // "VmHWM:   123456 kB"
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0 / 1e6)
}

fn show(mb: Option<f64>) -> String {
    mb.map_or_else(|| "unavailable".to_string(), |v| format!("{v:.1} MB"))
}

fn json_number(mb: Option<f64>) -> String {
    mb.map_or_else(|| "null".to_string(), |v| format!("{v:.3}"))
}

/// Child: one analyze, then one JSON line on stdout.
fn child(case: &str) -> i32 {
    let Some(d) = design(case) else {
        eprintln!("unknown case {case}");
        return 2;
    };
    let baseline = vm_hwm_mb();
    // Default options: full quality and, for the random tiling, the expected PSF too.
    let result = analyze_with(&d, &AnalyzeOptions::default(), &Progress::new());
    let peak = vm_hwm_mb();
    match result {
        Ok(a) => {
            println!(
                "{{\"baseline_mb\": {}, \"peak_mb\": {}, \"elapsed_ms\": {:.1}}}",
                json_number(baseline),
                json_number(peak),
                a.elapsed_ms
            );
            0
        }
        Err(e) => {
            eprintln!("analyze {case} failed: {e}");
            1
        }
    }
}

/// Parent: one fresh process per case; returns the case's JSON object (numbers or `null`).
fn measure(case: &str) -> String {
    // current_exe reads /proc/self/exe on Linux; argv[0] (a full path under cargo) is the
    // fallback so that a system without /proc still runs the cases and prints "unavailable".
    let exe = match std::env::current_exe()
        .or_else(|e| std::env::args_os().next().map(PathBuf::from).ok_or(e))
    {
        Ok(p) => p,
        Err(e) => {
            println!("memory/{case}: unavailable (cannot find own executable: {e})");
            return "{\"baseline_mb\": null, \"peak_mb\": null}".into();
        }
    };
    let out = Command::new(exe).args(["--case", case]).output();
    let line = match &out {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
            .lines()
            .last()
            .unwrap_or("")
            .to_string(),
        Ok(o) => {
            println!(
                "memory/{case}: child failed ({}): {}",
                o.status,
                String::from_utf8_lossy(&o.stderr).trim()
            );
            return "{\"baseline_mb\": null, \"peak_mb\": null}".into();
        }
        Err(e) => {
            println!("memory/{case}: unavailable (cannot start a child process: {e})");
            return "{\"baseline_mb\": null, \"peak_mb\": null}".into();
        }
    };
    // The child's line is tiny and fixed-format; read its two numbers back for the human print.
    let field = |name: &str| -> Option<f64> {
        let rest = line.split(&format!("\"{name}\": ")).nth(1)?;
        rest.split([',', '}']).next()?.trim().parse().ok()
    };
    println!(
        "memory/{case}: baseline VmHWM {}, peak VmHWM {}",
        show(field("baseline_mb")),
        show(field("peak_mb"))
    );
    line
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--case") {
        let case = args.get(i + 1).map_or("", String::as_str);
        std::process::exit(child(case));
    }
    // `cargo bench` passes `--bench` and any filter after `--`; a filter picks cases by substring.
    let filter: Vec<&str> = args
        .iter()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .map(String::as_str)
        .collect();
    let mut body = Vec::new();
    for case in CASES {
        if filter.is_empty() || filter.iter().any(|f| case.contains(f)) {
            body.push(format!("  \"memory/{case}\": {}", measure(case)));
        }
    }
    let text = format!("{{\n{}\n}}\n", body.join(",\n"));
    common::write_figures("memory.json", &text);
}
