//! Throughput of one in-process sweep, the job behind `udc-studio sweep`.
//!
//! Cases (criterion ids), each a fresh sweep of 16 points into a new folder on 2 worker threads
//! (plots off), so the median divided by 16 is the cost of a point:
//! - `sweep/analyze/toled-150dpi-seeds`: the periodic T-OLED at 150 DPI, R, G, B, full quality.
//! - `sweep/analyze/l2inv-random-seeds`: the thesis's random-tiled layout at 150 DPI, 16 seeds.
//!
//! Goal: ≥ 50 analysed 150-DPI three-channel designs per second on 2 cores (≥ 4× a shell loop
//! over the CLI; `benches/sweep.sh` measures the loop and the sweep's memory). Run with
//! `cargo bench --bench sweep -- --noplot`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use udc_studio::core::Progress;
use udc_studio::core::sweep::Shard;
use udc_studio::io::sweep::parse_spec;
use udc_studio::jobs::sweep::{RunOptions, run_sweep};

/// The binary's allocator (src/main.rs), so the bench measures what `udc-studio sweep` does.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn spec(preset: &str) -> String {
    format!(
        "job = \"analyze\"\n[base]\npreset = \"{preset}\"\n[[axis]]\nparam = \"seed\"\nrange = {{ start = 0, stop = 15 }}\n"
    )
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("sweep/analyze");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .measurement_time(Duration::from_secs(20));
    let options = RunOptions {
        shard: Shard::WHOLE,
        threads: Some(2),
        plots: false,
        check_values: true,
        hold_after_points: None,
    };
    for (id, preset) in [
        ("toled-150dpi-seeds", "toled-150dpi"),
        ("l2inv-random-seeds", "l2inv-random"),
    ] {
        let spec = match parse_spec(&spec(preset), true) {
            Ok(s) => s,
            Err(e) => panic!("bench spec: {e}"),
        };
        group.bench_function(id, |b| {
            b.iter_with_setup(
                || match tempfile::tempdir() {
                    Ok(d) => d,
                    Err(e) => panic!("temp dir: {e}"),
                },
                |dir| {
                    let summary = run_sweep(
                        &spec,
                        &dir.path().join("r"),
                        &options,
                        &Progress::new(),
                        &mut |_| {},
                    );
                    black_box(summary.map(|s| s.computed).unwrap_or(0))
                },
            );
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
