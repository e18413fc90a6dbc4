//! Wall time of one `analyze` call, the job the studio runs on every edit.
//!
//! Cases (criterion ids):
//! - `analyze/iccp21/toled-repeat`: the default design at full quality; benches/numpy_reference.py
//!   does the same work in numpy and benches/report.sh compares the two.
//! - `analyze/iccp21/toled-random-d4`: the same pixel in a random-D4 tiling, with the expected PSF
//!   (the default options), i.e. the most work a chapter-3 design asks for.
//! - `analyze/preview/toled-repeat`: preview quality, the interactive path while drawing.
//! - `analyze/iccp21/open-aperture`: no display; its AUCs are the thesis's public check.
//!
//! Each case prints its AUCs and `L_inv` once, so a reader can compare them with the numpy
//! reference and the thesis, and writes them to `<target>/udc-bench/analyze-figures.json` for
//! benches/report.sh. Run with `cargo bench --bench analyze -- --noplot`.

mod common;

use std::collections::BTreeMap;
use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use udc_studio::core::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::design::{Opening, TilingMode};
use udc_studio::core::{Analysis, Design, Progress};

struct Case {
    id: &'static str,
    design: Design,
    options: AnalyzeOptions,
}

fn cases() -> Vec<Case> {
    let full = AnalyzeOptions::default();
    let preview = AnalyzeOptions {
        quality: Quality::Preview,
        ..full
    };
    let toled = Design::default_toled();
    let mut random = Design::default_toled();
    random.tiling.mode = TilingMode::RandomD4;
    // Built here rather than read from presets/: the bench must not move when a preset is
    // retuned. Same recipe and registration as the T-OLED, every cell open.
    let mut open = Design::default_toled();
    open.opening = Opening::open(open.opening.n(), open.opening.pitch_um);
    vec![
        Case {
            id: "iccp21/toled-repeat",
            design: toled.clone(),
            options: full,
        },
        Case {
            id: "iccp21/toled-random-d4",
            design: random,
            options: full,
        },
        Case {
            id: "preview/toled-repeat",
            design: toled,
            options: preview,
        },
        Case {
            id: "iccp21/open-aperture",
            design: open,
            options: full,
        },
    ]
}

fn run(case: &Case) -> Analysis {
    match analyze_with(&case.design, &case.options, &Progress::new()) {
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
    let mut figures = BTreeMap::new();
    // One untimed call per case first: it builds the process-wide FFT plans and ring tables and
    // starts rayon's pool, which every later call (like every edit in the studio) reuses.
    for case in &cases {
        let a = run(case);
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
        group.bench_function(case.id, |b| b.iter(|| black_box(run(black_box(case)))));
    }
    group.finish();
}

criterion_group!(benches, bench_analyze);
criterion_main!(benches);
