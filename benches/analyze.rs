//! Wall time of one `analyze` call, the job the studio runs on every edit.
//!
//! Cases (criterion ids):
//! - `analyze/iccp21/toled-repeat`: the default design at full quality; benches/numpy_reference.py
//!   does the same work in numpy and benches/report.sh compares the two.
//! - `analyze/iccp21/toled-random-d4`: the same pixel in a random-D4 tiling, with the expected PSF
//!   (the default options), i.e. the most work a chapter-3 design asks for.
//! - `analyze/preview/toled-repeat-f10`, `analyze/iccp21/toled-repeat-f10`: the default design
//!   at f/10, where the preview doubles the fine spacing (at the thesis's f/2.5 it is full
//!   quality, conventions.md §2), at preview and at full quality.
//! - `analyze/iccp21/open-aperture`: no display; its AUCs are the thesis's public check.
//! - `analyze/iccp21/toled-600dpi`: the `toled-600dpi` preset (FFTs of 6100/5300/4700 points,
//!   a 294-pixel window), the case the pruned PSF route exists for (goal ≤ 300 ms).
//! - `analyze/single-thread/toled-150dpi`, `analyze/single-thread/l2inv-random`: one analysis
//!   (no expected PSF, as a sweep runs it) inside a 1-thread rayon pool: the CPU cost per design
//!   of a sweep on 2 cores (goal ≤ 35 ms, i.e. ≥ 50 designs/s on 2 cores).
//!
//! Each case prints its AUCs and `L_inv` once, so a reader can compare them with the numpy
//! reference and the thesis, and writes them to `<target>/udc-bench/analyze-figures.json` for
//! benches/report.sh. Run with `cargo bench --bench analyze -- --noplot`.

mod common;

use std::collections::BTreeMap;
use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::design::{Opening, TilingMode};
use udc_studio::core::{Analysis, Design, Progress};
use udc_studio::io::design::presets::load_preset;

struct Case {
    id: &'static str,
    design: Design,
    options: AnalyzeOptions,
    /// Run inside a 1-thread pool (the sweep's per-design cost) instead of the global pool.
    single_thread: bool,
}

fn preset(name: &str) -> Design {
    match load_preset(name) {
        Ok(d) => d,
        Err(e) => panic!("preset {name}: {e}"),
    }
}

fn cases() -> Vec<Case> {
    let full = AnalyzeOptions::default();
    let preview = AnalyzeOptions {
        quality: Quality::Preview,
        ..full
    };
    let toled = Design::default_toled();
    let mut slow = Design::default_toled();
    slow.optics.f_number = 10.0;
    let mut random = Design::default_toled();
    random.tiling.mode = TilingMode::RandomD4;
    // Built here rather than read from presets/: the bench must not move when a preset is
    // retuned. Same recipe and registration as the T-OLED, every cell open.
    let mut open = Design::default_toled();
    open.opening = Opening::open(open.opening.n(), open.opening.pitch_um);
    let sweep = AnalyzeOptions {
        expected_psf: false,
        ..full
    };
    let case = |id, design, options, single_thread| Case {
        id,
        design,
        options,
        single_thread,
    };
    vec![
        case("iccp21/toled-repeat", toled.clone(), full, false),
        case("iccp21/toled-random-d4", random, full, false),
        case("preview/toled-repeat-f10", slow.clone(), preview, false),
        case("iccp21/toled-repeat-f10", slow, full, false),
        case("iccp21/open-aperture", open, full, false),
        // The preset itself: the number is `analyze --preset toled-600dpi`.
        case("iccp21/toled-600dpi", preset("toled-600dpi"), full, false),
        case(
            "single-thread/toled-150dpi",
            preset("toled-150dpi"),
            sweep,
            true,
        ),
        case(
            "single-thread/l2inv-random",
            preset("l2inv-random"),
            sweep,
            true,
        ),
    ]
}

fn run(case: &Case, pool: &rayon::ThreadPool) -> Analysis {
    let job = || analyze_with(&case.design, &case.options, &Progress::new());
    let result = if case.single_thread {
        pool.install(job)
    } else {
        job()
    };
    match result {
        Ok(a) => a,
        // A bench of a failing job would time the error path: stop loudly instead.
        Err(e) => panic!("analyze {} failed: {e}", case.id),
    }
}

/// The figures a reader compares, as JSON (hand-written: the bench needs no serde derive).
fn figures_json(a: &Analysis) -> String {
    let aucs: Vec<String> = a
        .channels
        .iter()
        .map(|c| format!("\"{}\": {:e}", c.name, c.mtf.auc_radial_min))
        .collect();
    format!(
        "{{\"auc_radial_min\": {{{}}}, \"l_inv\": {:e}, \"ltr\": {:e}, \"warnings\": {}}}",
        aucs.join(", "),
        a.invertibility_loss,
        a.ltr,
        a.warnings.len()
    )
}

fn print_figures(id: &str, a: &Analysis) {
    let aucs: Vec<String> = a
        .channels
        .iter()
        .map(|c| format!("{} {:.9}", c.name, c.mtf.auc_radial_min))
        .collect();
    println!(
        "analyze/{id}: AUC(radial min) {}; L_inv {:.9}; LTR {:.4}; first call {:.1} ms",
        aucs.join(", "),
        a.invertibility_loss,
        a.ltr,
        a.elapsed_ms
    );
    for w in &a.warnings {
        println!("  warning: {w}");
    }
}

fn write_figures(figures: &BTreeMap<&str, String>) {
    let body: Vec<String> = figures
        .iter()
        .map(|(id, f)| format!("  \"analyze/{id}\": {f}"))
        .collect();
    let text = format!("{{\n{}\n}}\n", body.join(",\n"));
    common::write_figures("analyze-figures.json", &text);
}

fn bench_analyze(c: &mut Criterion) {
    let cases = cases();
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => panic!("a 1-thread pool: {e}"),
    };
    let mut figures = BTreeMap::new();
    // One untimed call per case first: it builds the process-wide FFT plans and ring tables and
    // starts rayon's pool, which every later call (like every edit in the studio) reuses.
    for case in &cases {
        let a = run(case, &pool);
        print_figures(case.id, &a);
        figures.insert(case.id, figures_json(&a));
    }
    write_figures(&figures);

    let mut group = c.benchmark_group("analyze");
    // Each call takes tens to hundreds of ms on 2 cores: flat sampling with 10 samples keeps a
    // case to a few seconds while criterion still reports a median.
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for case in &cases {
        group.bench_function(case.id, |b| {
            b.iter(|| black_box(run(black_box(case), &pool)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_analyze);
criterion_main!(benches);
