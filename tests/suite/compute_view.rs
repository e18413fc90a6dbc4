//! View ▸ Compute PSFs on: the studio computes the display's PSFs on the GPU its window draws
//! with (a device of its own on eframe's adapter), names it, keeps the choice in its settings, and shows the
//! CPU's numbers to `f32` precision, and hands the phase workspace's operators to the same
//! device; without a wgpu window the GPU choice is greyed out.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use udc_studio::app::{DisplayAction, StudioApp, StudioOptions};

use crate::common::{Reach, display_up_to_date, step_until};

fn aucs(app: &StudioApp) -> Vec<f64> {
    app.display()
        .shown()
        .expect("a result")
        .analysis
        .channels
        .iter()
        .map(|c| c.mtf.auc_radial_min)
        .collect()
}

#[test]
fn without_a_wgpu_window_the_gpu_choice_is_greyed_out() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = crate::common::studio(dir.path(), false, Duration::from_secs(600));
    h.get_by_label("View").click();
    h.run();
    let gpu = h.get_by_label_contains("GPU (none");
    assert!(
        gpu.accesskit_node().is_disabled(),
        "the GPU choice is disabled"
    );
    h.get_by_label("CPU (f64, the reference)");
}

#[test]
fn the_studio_computes_on_the_windows_gpu_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let dirs = udc_studio::app::AppDirs::at(dir.path());
    let mut h = Harness::builder()
        .with_size(egui::vec2(1440.0, 900.0))
        .with_max_steps(10_000)
        .wgpu()
        .build_eframe(move |cc| {
            let gpu = udc_studio::app::window_gpu(cc);
            StudioApp::new(
                &cc.egui_ctx,
                StudioOptions {
                    dirs,
                    design_path: None,
                    native_dialogs: false,
                    autosave_every: Duration::from_secs(600),
                    gpu,
                },
            )
        });
    h.state_mut()
        .act(DisplayAction::LoadPreset("fourier-square".into()));
    step_until(&mut h, "the CPU result", display_up_to_date);
    let cpu = aucs(h.state());
    h.get_by_label("View").click();
    h.run();
    if h.query_by_label_contains("GPU (none").is_some() {
        eprintln!("skipped: the test window has no wgpu device");
        return;
    }
    assert_eq!(h.state().phase().operators_on(), None, "the CPU at first");
    h.get_by_label_contains("GPU: ").click();
    h.run();
    // The phase workspace's operators follow the same choice (their propagations' Bloch relay).
    assert!(
        h.state().phase().operators_on().is_some(),
        "the phase operators run on the GPU too"
    );
    step_until(&mut h, "the GPU result", display_up_to_date);
    let gpu = aucs(h.state());
    for (c, g) in cpu.iter().zip(&gpu) {
        assert!(
            (c - g).abs() <= 3e-3 * c,
            "AUC {c} on the CPU, {g} on the GPU"
        );
    }
    // Computed again, not the CPU's result kept: f32 leaves its mark in the last digits.
    assert_ne!(cpu, gpu, "the result was recomputed on the GPU");
    let settings = std::fs::read_to_string(dir.path().join("settings.json")).unwrap();
    assert!(settings.contains("\"backend\": \"gpu\""), "{settings}");
}
