//! Wall time of the sensor previewer, the job behind `udc-studio sensor` and the studio's sensor
//! panel.
//!
//! Cases (criterion ids):
//! - `sensor/table54/stilllife-1240x846`: Table 5.4's four strategies on a 1240×846 HDR scene
//!   (the committed 620×423 StillLife, each pixel repeated 2×2), maps and metrics included:
//!   everything [`run`] does. Goal ≤ 400 ms on 2 cores.
//! - `sensor/preview`: the same on the scene downscaled to the preview size
//!   ([`PREVIEW_MAX_SIDE_PX`], ROI scaled alike), what a parameter tweak in the panel reruns.
//!   Goal ≤ 100 ms.
//!
//! Each case prints its scores once. Run with `cargo bench --bench sensor -- --noplot`.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use ndarray::Array2;
use udc_studio::core::Progress;
use udc_studio::core::sensor::{PREVIEW_MAX_SIDE_PX, Scene, SensorRun, SensorSettings, run};
use udc_studio::io::photo::hdr::load_hdr;

const SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/hdr/StillLife_620x423.exr"
);

fn stilllife_1240x846() -> Scene {
    let small = match load_hdr(Path::new(SCENE)) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    };
    let planes = small
        .planes
        .iter()
        .map(|p| {
            let (h, w) = p.dim();
            Array2::from_shape_fn((2 * h, 2 * w), |(y, x)| p[[y / 2, x / 2]])
        })
        .collect();
    Scene { planes }
}

fn go(scene: &Scene, settings: &SensorSettings) -> SensorRun {
    match run(scene, settings, &Progress::new()) {
        Ok(r) => r,
        // A bench of a failing job would time the error path: stop loudly instead.
        Err(e) => panic!("sensor run failed: {e}"),
    }
}

fn bench_sensor(c: &mut Criterion) {
    let full = stilllife_1240x846();
    let settings = SensorSettings::default();
    let preview = full.downscaled(PREVIEW_MAX_SIDE_PX);
    let preview_settings = settings.for_preview(full.dim(), preview.dim());
    let cases = [
        ("table54/stilllife-1240x846", &full, &settings),
        ("preview", &preview, &preview_settings),
    ];
    // One untimed call per case: rayon's pool is built once per process.
    for (id, scene, s) in &cases {
        let r = go(scene, s);
        let (h, w) = scene.dim();
        let scores: Vec<String> = r
            .strategies
            .iter()
            .map(|st| format!("{} {:.3}/{:.3}", st.name, st.worst_roi_ssim, st.mean_ssim))
            .collect();
        println!(
            "sensor/{id}: {w}×{h}, ROI {} px; worst/mean SSIM {}; first call {:.1} ms",
            s.roi_px,
            scores.join(", "),
            r.elapsed_ms
        );
    }
    let mut group = c.benchmark_group("sensor");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    for (id, scene, s) in &cases {
        group.bench_function(*id, |b| {
            b.iter(|| black_box(go(black_box(scene), black_box(s))))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_sensor);
criterion_main!(benches);
