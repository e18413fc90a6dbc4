//! The opening optimizer's speed (issue 7): one epoch (forward and adjoint through the FFTs of
//! all three channels) as a criterion bench, and one complete 150-epoch `L_inv` run of the
//! thesis recipe (T-OLED geometry, random-4 tiling, iccp21 optics), timed once: a run takes tens
//! of seconds, too long for criterion's ten samples. The run's wall time and result go to
//! `<target>/udc-bench/optimize.json` for benches/report.sh (goal: ≤ 60 s on 2 cores).
//! Run with `cargo bench --bench optimize -- --noplot`.

mod common;

use std::hint::black_box;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::design::TilingMode;
use udc_studio::core::optimize::{Objective, OptimizeSettings, optimize};
use udc_studio::core::psf::route::PsfRoute;
use udc_studio::core::{Design, Progress};

fn design() -> Design {
    let mut d = Design::default_toled();
    d.tiling.mode = TilingMode::Random4;
    d
}

/// One full run, timed once, with the AUC before and after.
fn full_run() {
    let d = design();
    let settings = OptimizeSettings::default();
    let start = Instant::now();
    let result = optimize(
        &d,
        &settings,
        None,
        &PsfRoute::Auto,
        &Progress::new(),
        |_| ControlFlow::Continue(()),
    );
    let seconds = start.elapsed().as_secs_f64();
    let Ok(result) = result else {
        eprintln!("the optimizer failed: {result:?}");
        return;
    };
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let auc = |d: &Design| -> Vec<f64> {
        analyze_with(d, &options, &Progress::new())
            .map(|a| a.channels.iter().map(|c| c.mtf.auc_radial_min).collect())
            .unwrap_or_default()
    };
    let (before, after) = (auc(&d), auc(&result.design));
    println!("150 epochs, iccp21, L_inv only: {seconds:.1} s; AUC {before:.4?} -> {after:.4?}");
    let text = format!(
        "{{\"epochs\": {}, \"seconds\": {seconds:.3}, \"auc_before\": {before:?}, \"auc_after\": {after:?}}}\n",
        result.history.len()
    );
    common::write_figures("optimize.json", &text);
}

fn bench_optimize(c: &mut Criterion) {
    let d = design();
    let settings = OptimizeSettings::default();
    let objective = Objective::new(
        &d,
        Quality::Full,
        settings.weights,
        settings.relaxation,
        None,
        &PsfRoute::Auto,
    );
    let Ok(objective) = objective else {
        eprintln!("cannot build the objective");
        return;
    };
    let logits = vec![0.5; 441];
    let mut group = c.benchmark_group("optimize");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    group.bench_function("iccp21/epoch", |b| {
        b.iter(|| black_box(objective.step(black_box(&logits), 0.2)))
    });
    group.finish();
    full_run();
}

criterion_group!(benches, bench_optimize);
criterion_main!(benches);
