//! Wall time of one capture-and-restore, the job behind `udc-studio restore`.
//!
//! Cases (criterion ids):
//! - `restore/wiener/toled-1024x768`: a 1024×768 colour photo (the committed astronaut, scaled
//!   up) blurred by the T-OLED 150-DPI PSFs (294×294 per channel), exposed at 28 dB with noise and
//!   restored by Wiener on the default 2×-padded grid (conventions.md §5), PSNR and SSIM included:
//!   everything [`simulate`] does. Goal ≤ 300 ms on 2 cores.
//! - `restore/wiener-linear/toled-1024x768`: the same on the smallest linear grid, to show what
//!   the 2× padding costs.
//! - `restore/cg/toled-256x256`: the conjugate-gradient restoration (default settings) of the
//!   256×256 photo.
//!
//! The PSFs are computed once, outside the timing. Each case prints its PSNR and SSIM once.
//! Run with `cargo bench --bench restore -- --noplot`.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use image::imageops::FilterType;
use ndarray::Array2;
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::restore::{
    CgSettings, Denoise, Light, Method, Padding, Recipe, RestoreResult, RestoreSettings, simulate,
};
use udc_studio::core::{Design, Progress};
use udc_studio::io::photo::{load_photo, planes_of};

const PHOTO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/photos/astronaut_256.png"
);

fn photo_1024x768() -> Vec<Array2<f64>> {
    let img = match image::open(Path::new(PHOTO)) {
        Ok(img) => img,
        Err(e) => panic!("cannot read {PHOTO}: {e}"),
    };
    let big = image::DynamicImage::ImageRgb32F(img.to_rgb32f()).resize_exact(
        1024,
        768,
        FilterType::Triangle,
    );
    planes_of(&big.to_rgb32f())
}

struct Case {
    id: &'static str,
    photo: Vec<Array2<f64>>,
    settings: RestoreSettings,
}

fn run(case: &Case, psfs: &[&Array2<f64>]) -> RestoreResult {
    match simulate(&case.photo, psfs, &case.settings, &Progress::new()) {
        Ok(r) => r,
        // A bench of a failing job would time the error path: stop loudly instead.
        Err(e) => panic!("restore {} failed: {e}", case.id),
    }
}

fn bench_restore(c: &mut Criterion) {
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let analysis = match analyze_with(&Design::default_toled(), &options, &Progress::new()) {
        Ok(a) => a,
        Err(e) => panic!("analyze failed: {e}"),
    };
    let psfs: Vec<&Array2<f64>> = analysis.channels.iter().map(|c| &c.psf).collect();
    let small = match load_photo(Path::new(PHOTO), None) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let big = photo_1024x768();
    // The deblurring alone, so its figures compare with earlier runs; BM3D has its own case.
    let mut wiener = RestoreSettings {
        denoise: Denoise::None,
        ..RestoreSettings::default()
    };
    wiener.capture.light = Light::SnrDb(28.0);
    let bm3d = RestoreSettings {
        denoise: Denoise::authors_table(Recipe::Iccp21),
        padding: Padding::Linear,
        ..wiener.clone()
    };
    let linear = RestoreSettings {
        padding: Padding::Linear,
        ..wiener.clone()
    };
    let cg = RestoreSettings {
        method: Method::Cg(CgSettings::default()),
        padding: Padding::Linear,
        ..wiener.clone()
    };
    let cases = [
        Case {
            id: "wiener/toled-1024x768",
            photo: big.clone(),
            settings: wiener,
        },
        Case {
            id: "wiener-linear/toled-1024x768",
            photo: big,
            settings: linear,
        },
        Case {
            id: "cg/toled-256x256",
            photo: small.clone(),
            settings: cg,
        },
        Case {
            id: "bm3d-wiener-linear/toled-256x256",
            photo: small,
            settings: bm3d,
        },
    ];
    // One untimed call per case: FFT plans and rayon's pool are built once per process.
    for case in &cases {
        let r = run(case, &psfs);
        let iterations = r.channels.iter().filter_map(|c| c.cg.as_ref());
        let its: Vec<String> = iterations.map(|c| c.iterations.to_string()).collect();
        println!(
            "restore/{}: PSNR {:.2} dB (capture {:.2} dB), SSIM {:.4}, grid {}×{}, first call \
             {:.1} ms{}",
            case.id,
            r.psnr_db,
            r.captured_psnr_db,
            r.ssim,
            r.grid.rows,
            r.grid.cols,
            r.elapsed_ms,
            if its.is_empty() {
                String::new()
            } else {
                format!(", CG iterations {}", its.join("/"))
            }
        );
    }
    let mut group = c.benchmark_group("restore");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    for case in &cases {
        group.bench_function(case.id, |b| {
            b.iter(|| black_box(run(black_box(case), black_box(&psfs))))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_restore);
criterion_main!(benches);
