//! Wall time of one BM3D denoise, the step every restoration runs before deblurring.
//!
//! Cases (criterion ids):
//! - `denoise/bm3d/grey-512`: the test set's camera (512×512, grey) with white Gaussian noise
//!   σ = 0.1. Goal ≤ 1 s on 2 cores.
//! - `denoise/cbm3d/rgb-512`: the test set's astronaut (512×512, RGB), σ = 0.1. Goal ≤ 3 s.
//!
//! Each case prints its PSNR once. The reference implementation's time on the same inputs comes
//! from `python3 benches/bm3d_reference.py` (the `bm3d` package); the benchmark table of the
//! book (`docs/src/benchmarks.md`) shows both. Run with `cargo bench --bench denoise -- --noplot`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use ndarray::Array2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use udc_studio::core::Progress;
use udc_studio::core::denoise::bm3d;
use udc_studio::core::restore::quality::psnr_db_planes;
use udc_studio::io::photo::testset::{load_testset_photo, testset_dir};

/// PSNR over every channel, peak 1.
fn psnr(a: &[Array2<f64>], b: &[Array2<f64>]) -> f64 {
    psnr_db_planes(a, b, 1.0).expect("same sizes")
}

const SIGMA: f64 = 0.1;

fn noisy(name: &str, seed: u64) -> (Vec<Array2<f64>>, Vec<Array2<f64>>) {
    let clean = match load_testset_photo(&testset_dir().join(name)) {
        Ok(p) => p,
        Err(e) => panic!("cannot read the test-set photo {name}: {e}"),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, SIGMA).unwrap_or_else(|e| panic!("{e}"));
    let noisy = clean
        .iter()
        .map(|p| p.mapv(|v| v + normal.sample(&mut rng)))
        .collect();
    (clean, noisy)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("denoise");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    for (id, photo) in [
        ("bm3d/grey-512", "camera.png"),
        ("cbm3d/rgb-512", "astronaut.png"),
    ] {
        let (clean, noisy) = noisy(photo, 1);
        let run = || match bm3d(&noisy, SIGMA * SIGMA, &Progress::new()) {
            Ok(out) => out,
            Err(e) => panic!("denoise {id} failed: {e}"),
        };
        let out = run();
        println!(
            "{id}: noisy {:.2} dB, denoised {:.2} dB",
            psnr(&noisy, &clean),
            psnr(&out, &clean)
        );
        group.bench_function(id, |b| b.iter(|| black_box(run())));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
