//! What a sensor run holds at its peak, counted by the test's own allocator: every byte the
//! heap holds at once, the scene's planes included. The budget check refuses runs by
//! [`peak_bytes`]; these tests hold the run to that estimate, and to the Limits chapter's
//! promise that a 4096×4096 colour run fits in 1 GiB.
//!
//! One test binary of its own: the counting allocator is the whole binary's, and the tests run
//! one after another in it (nextest gives each its own process).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use ndarray::Array2;
use peak_alloc::PeakAlloc;
use udc_core::sensor::{Cfa, Held, Scene, SensorSettings, peak_bytes, run_with};
use udc_core::{Progress, SimError};

#[global_allocator]
static HEAP: PeakAlloc = PeakAlloc;

/// A 4096×4096 scene's pixels.
const PIXELS_4096: u64 = 4096 * 4096;

/// A textured HDR scene of `planes` planes over four decades, left to right.
fn scene(h: usize, w: usize, planes: usize) -> Scene {
    Scene {
        planes: (0..planes)
            .map(|c| {
                Array2::from_shape_fn((h, w), |(y, x)| {
                    let level = 10f64.powf(-3.0 + 4.0 * x as f64 / w as f64);
                    level
                        * (1.0 + 0.3 * c as f64)
                        * (1.0 + 0.5 * ((x as f64 * 0.3).sin() * (y as f64 * 0.2).cos()))
                })
            })
            .collect(),
    }
}

/// The most bytes per scene pixel the heap held at once while `run_with` ran on an owned
/// `scene` with `settings`, handing each strategy over and keeping one number (what the CLI
/// does while it writes images, less the writing). On two threads, as CI has: each thread's
/// working rows are a fixed cost that a small scene would otherwise count per pixel.
fn peak_bytes_per_pixel(scene: Scene, settings: &SensorSettings) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a pool");
    let (h, w) = scene.dim();
    let scene_bytes: usize = scene.planes.iter().map(|p| p.len() * 8).sum();
    let before = HEAP.current_usage() - scene_bytes;
    HEAP.reset_peak_usage();
    let run = pool
        .install(|| {
            run_with(scene, settings, &Progress::new(), Held::HandedOver, |s| {
                Ok::<_, SimError>(s.worst_roi_ssim)
            })
        })
        .expect("a valid scene");
    assert_eq!(run.strategies.len(), settings.strategies.len());
    (HEAP.peak_usage() - before) as f64 / (h * w) as f64
}

#[test]
fn a_colour_run_holds_less_than_its_budget_and_fits_4096_squared_in_a_gib() {
    let (h, w) = (768, 1024);
    let settings = SensorSettings {
        cfa: Cfa::Rggb,
        ..SensorSettings::default()
    };
    let measured = peak_bytes_per_pixel(scene(h, w, 3), &settings);
    let estimated = peak_bytes((h, w), 3, &settings, Held::HandedOver) as f64 / (h * w) as f64;
    assert!(
        measured <= estimated,
        "held {measured:.1} B/px, the budget counts {estimated:.1}"
    );
    // 1 GiB over a 4096² scene is 64 B/px; the program itself and the allocator's slack need
    // the rest, so the run may hold 60 (it held 70 when the draws were f64 and the mosaics
    // were kept beside their RGB).
    assert!(
        measured * PIXELS_4096 as f64 <= 60.0 * PIXELS_4096 as f64,
        "held {measured:.1} B/px: {:.0} MiB at 4096²",
        measured * PIXELS_4096 as f64 / f64::from(1 << 20)
    );
}

#[test]
fn a_monochrome_run_holds_less_than_its_budget() {
    let (h, w) = (768, 1024);
    let settings = SensorSettings::default();
    let measured = peak_bytes_per_pixel(scene(h, w, 1), &settings);
    let estimated = peak_bytes((h, w), 0, &settings, Held::HandedOver) as f64 / (h * w) as f64;
    assert!(
        measured <= estimated,
        "held {measured:.1} B/px, the budget counts {estimated:.1}"
    );
    // The exposed scene (8), the draws (8, f32) and one strategy's capture and maps (14), and
    // the scoring's rows: 34 B/px (it held 39 with f64 draws).
    assert!(measured <= 34.0, "held {measured:.1} B/px");
}
