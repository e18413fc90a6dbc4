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
    let window_gpu = std::sync::Arc::new(std::sync::Mutex::new(None));
    let kept = window_gpu.clone();
    let mut h = Harness::builder()
        .with_size(egui::vec2(1440.0, 900.0))
        .with_max_steps(10_000)
        .wgpu()
        .build_eframe(move |cc| {
            let gpu = udc_studio::app::window_gpu(cc);
            *kept.lock().unwrap() = gpu.clone();
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

    // The jobs the studio runs by their parameters (a study, a quick reproduction) resolve
    // `gpu` on the window's device, not on a second one.
    let gpu = window_gpu
        .lock()
        .unwrap()
        .clone()
        .expect("the window's GPU");
    let shared = udc_gpu::Gpu::shared(udc_gpu::AdapterKind::Any).unwrap();
    assert!(std::sync::Arc::ptr_eq(&shared, &gpu), "one device");
    // A study started now computes its points there: its saved spec says so (a resume, here
    // or by `udc-studio sweep`, runs there too), and its rows land.
    h.state_mut().act(DisplayAction::NewStudy(None));
    h.run_steps(3);
    {
        let d = &mut h.state_mut().sweep_mut().study_dialog;
        d.axes.truncate(1);
        // The Fourier square's 6 DPI and a little finer.
        d.axes[0].text = "6, 8".into();
        assert_eq!(d.estimate().unwrap().expect("an estimate").points, 2);
    }
    h.run_steps(3);
    assert!(h.query_by_label_contains("2 points, about").is_some());
    h.get_by_label("Run").click();
    h.run_steps(2);
    let started = h.state().sweep().message().map(|m| m.text.clone());
    assert!(h.state().sweep().is_studying(), "{started:?}");
    step_until(&mut h, "the study's end", |app| {
        !app.sweep().is_studying() && app.sweep().is_idle()
    });
    let rows = h.state().sweep().table().map_or(0, |t| t.rows.len());
    assert_eq!(
        rows,
        2,
        "{started:?}, then {:?}",
        h.state().sweep().message().map(|m| m.text.clone())
    );
    let table = h.state().sweep().table().unwrap().dir.clone();
    let spec = std::fs::read_to_string(table.join("spec.toml")).unwrap();
    assert!(spec.contains("backend = \"gpu\""), "{spec}");
    // Help ▸ Reproduce thesis results runs there too, and its command line says so.
    h.state_mut().reproduce_mut().open = true;
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("--out DIR --backend gpu")
            .is_some(),
        "the reproduction's command names the backend"
    );
    h.state_mut().reproduce_mut().open = false;
    h.state_mut()
        .set_workspace(udc_studio::app::WorkspaceId::Display);

    // The Optimize panel's epochs run there too (a small T-OLED: f/5, a 128-pixel window), and
    // its outcome names the adapter.
    let mut small = udc_io::design::presets::load_preset("toled-150dpi").unwrap();
    small.optics.recipe = udc_studio::core::design::OpticsRecipe::Custom;
    small.optics.f_number = 5.0;
    small.optics.fine_sample_um = 1.0;
    small.optics.window_px = 128;
    h.state_mut().act(DisplayAction::Edit(Box::new(small)));
    step_until(&mut h, "the small T-OLED's result", display_up_to_date);
    h.state_mut()
        .display_mut()
        .show_left_tab(udc_studio::app::LeftTab::Optimize);
    {
        let s = h.state_mut().display_mut().optimizer_settings();
        s.epochs = 1;
        s.quality = udc_studio::core::analysis::analyze::Quality::Full;
    }
    h.run_steps(2);
    assert!(
        h.query_by_label_contains(&format!("Runs on {}", gpu.adapter()))
            .is_some(),
        "the panel says where it will run"
    );
    h.get_by_label("Run optimizer").click();
    h.run_steps(2);
    step_until(&mut h, "the optimizer's epoch", |app| {
        app.display().optimizer().finished().is_some()
    });
    let said = h
        .state()
        .display()
        .optimizer()
        .message()
        .unwrap()
        .text
        .clone();
    assert!(said.contains(&format!(" on {}", gpu.adapter())), "{said}");
}
