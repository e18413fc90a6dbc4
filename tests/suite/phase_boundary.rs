//! Thesis §4.4.1's 'full' boundary for the phase model: the operator gains directions beyond
//! the scene's edges, the capture still sees the scene alone, and the restoration solves for the
//! wider support and crops it back. The scene's own columns are the closed world's operator
//! exactly; a scene that goes on beyond the sensor restores better with the full boundary than
//! in a closed world that cannot explain the light its edges receive.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use ndarray::{Array2, Axis};
use udc_studio::core::Progress;
use udc_studio::core::design::Channel;
use udc_studio::core::phase::imaging::{
    PhaseBlur, capture, phase_blur, phase_blur_full, restore, scores,
};
use udc_studio::core::phase::{PhaseDesign, PhaseOptics, PhaseSampling};
use udc_studio::core::restore::Denoise;

use crate::common::run_cli;

const WIDTH: usize = 64;
const MARGIN: usize = 32;

fn design() -> PhaseDesign {
    let mut d = PhaseDesign::thesis(42.0, 1.0);
    d.camera.pixels = 128;
    d
}

fn blurs() -> (PhaseBlur, PhaseBlur) {
    let d = design();
    let s = PhaseSampling::preview();
    let peaks = Channel::rgb_peaks();
    let p = Progress::new();
    let closed = phase_blur(&d, &s, &peaks, PhaseOptics::DoubleMla, WIDTH, &p).unwrap();
    let full = phase_blur_full(&d, &s, &peaks, PhaseOptics::DoubleMla, WIDTH, MARGIN, &p).unwrap();
    (closed, full)
}

/// A smooth scene `cols` wide with detail everywhere, three channels.
fn scene(cols: usize) -> Vec<Array2<f64>> {
    (0..3)
        .map(|c| {
            Array2::from_shape_fn((16, cols), |(r, j)| {
                let x = j as f64 / 9.0 + c as f64;
                0.5 + 0.3 * x.sin() * (r as f64 / 5.0).cos()
            })
        })
        .collect()
}

#[test]
fn the_scene_columns_are_the_closed_operator_and_the_capture_sees_the_scene_alone() {
    let (closed, full) = blurs();
    assert_eq!(full.margin, MARGIN);
    assert_eq!(full.width(), WIDTH);
    assert_eq!(full.channels[0].dim(), (WIDTH, WIDTH + 2 * MARGIN));
    for c in 0..3 {
        assert_eq!(
            full.scene_operator(c),
            closed.channels[c].view(),
            "channel {c}"
        );
        // The margins' directions do reach the sensor: there is something to solve for.
        let left: f64 = full.channels[c]
            .slice_axis(Axis(1), (0..MARGIN).into())
            .sum();
        assert!(left > 0.0, "channel {c}");
    }
    assert_eq!(full.ltr, closed.ltr);
    assert_eq!(full.valid, closed.valid);
    assert_eq!(full.green_column_energy, closed.green_column_energy);
    let s = scene(WIDTH);
    assert_eq!(
        capture(&full, &s, 1600.0, 3).unwrap(),
        capture(&closed, &s, 1600.0, 3).unwrap()
    );
}

#[test]
fn a_scene_that_goes_on_restores_better_with_the_full_boundary() {
    let (closed, full) = blurs();
    // The scene continues beyond the sensor's edges: its light reaches the sensor through the
    // margins' directions. Noise-free capture on the gained scale (white ≈ 1).
    let wide = scene(WIDTH + 2 * MARGIN);
    let captured: Vec<Array2<f64>> = wide
        .iter()
        .zip(&full.channels)
        .map(|(x, k)| x.dot(&k.t()) / full.ltr)
        .collect();
    let truth: Vec<Array2<f64>> = wide
        .iter()
        .map(|x| {
            x.slice_axis(Axis(1), (MARGIN..MARGIN + WIDTH).into())
                .to_owned()
        })
        .collect();
    let p = Progress::new();
    let photons = 1.0e6;
    let with_full = restore(&full, &captured, photons, Denoise::None, &p).unwrap();
    let with_closed = restore(&closed, &captured, photons, Denoise::None, &p).unwrap();
    assert_eq!(with_full.restored[0].dim(), (16, WIDTH), "cropped back");
    let all = 0..WIDTH;
    let (psnr_full, _) = scores(&with_full.restored, &truth, &all).unwrap();
    let (psnr_closed, _) = scores(&with_closed.restored, &truth, &all).unwrap();
    assert!(
        psnr_full > psnr_closed + 1.0,
        "full {psnr_full:.2} dB vs closed {psnr_closed:.2} dB"
    );
}

#[test]
fn the_command_line_scales_the_scene_and_names_the_boundary() {
    let (ok, out, err) = run_cli(&[
        "phase",
        "restore",
        "--preview",
        "--bare",
        "--photons",
        "1600",
        "--denoise",
        "none",
        "--scene-px",
        "96",
        "--full-boundary",
        "--json",
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["width_px"], 96);
    assert_eq!(v["boundary"], "full");
    for bad in [["--scene-px", "7"], ["--scene-px", "1025"]] {
        let (ok, _, err) = run_cli(&["phase", "restore", "--preview", bad[0], bad[1]]);
        assert!(!ok);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("--scene-px"), "{err}");
    }
    let (ok, _, err) = run_cli(&["reproduce", "fig3.8", "--quick", "--thesis-geometry"]);
    assert!(!ok && err.contains("table4.1"), "{err}");
}
