//! The sensor previewer workspace, driven like a user: open an HDR scene, see the preview then
//! the full run with Table 5.4's four strategies, change a parameter and see it rerun, and a
//! broken file that changes nothing.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use crate::common::step_until;
use egui_kittest::kittest::Queryable;
use udc_studio::app::WorkspaceId;
use udc_studio::app::sensor::SensorView;

fn still_life() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/hdr/StillLife_620x423.exr")
}

#[test]
fn an_hdr_scene_runs_the_four_strategies_and_reruns_on_a_change() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sensor);
    h.step();
    assert!(h.query_by_label("Open HDR…").is_some());
    let ctx = h.ctx.clone();
    h.state_mut().sensor_mut().load_scene(still_life(), &ctx);
    step_until(&mut h, "the full run", |app| app.sensor().is_up_to_date());
    let run = h.state().sensor().shown().unwrap().run.clone();
    let names: Vec<&str> = run.strategies.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "const-gain/no-bin",
            "vary-gain/no-bin",
            "const-gain/vary-bin",
            "vary-gain/vary-bin"
        ]
    );
    assert_eq!(
        run.electrons.dim(),
        (423, 620),
        "the full scene, not the preview"
    );
    // The table shows every strategy's worst-ROI SSIM (4 decimals).
    for s in &run.strategies {
        let shown = format!("{:.4}", s.worst_roi_ssim);
        assert!(
            h.query_all_by_label(&shown).next().is_some(),
            "{shown} on screen"
        );
    }
    // A live parameter: a smaller ROI reruns and the ROI grid follows.
    h.state_mut().sensor_mut().settings_mut().roi_px = 64;
    step_until(&mut h, "the rerun", |app| {
        app.sensor().is_up_to_date() && app.sensor().shown().is_some_and(|s| s.run.roi_px == 64)
    });
    let rerun = h.state().sensor().shown().unwrap().run.clone();
    assert_eq!(
        rerun.strategies[0].roi_ssim.dim(),
        (423usize.div_ceil(64), 620usize.div_ceil(64))
    );
    // Every view draws.
    for (view, label) in [
        (SensorView::Compare, "A: worst ROI SSIM"),
        (SensorView::Curves, "(b) optimal pitch"),
        (SensorView::Maps, "Bin map:"),
    ] {
        h.state_mut().sensor_mut().show(view);
        h.step();
        h.step();
        assert!(
            h.query_all_by_label_contains(label).next().is_some(),
            "{label}"
        );
    }
    // The maps are figures: each picture is found by its title, with its colour bar's or key's
    // words beside it, and built once, not every frame.
    for title in [
        "Scene (ground truth, tone-mapped)",
        "Gain map: ",
        "Saturated: ",
    ] {
        assert!(
            h.query_all_by_label_contains(title).next().is_some(),
            "{title}"
        );
    }
    for key in ["1×1", "8×8", "yes"] {
        assert!(
            h.query_all_by_label_contains(key).next().is_some(),
            "the key {key}"
        );
    }
    let built = h.state().sensor().figure_builds();
    for _ in 0..3 {
        h.step();
    }
    assert_eq!(
        h.state().sensor().figure_builds(),
        built,
        "no rebuild per frame"
    );
}

#[test]
fn a_broken_hdr_file_shows_an_error_and_keeps_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.exr");
    std::fs::write(&bad, b"v/1\x01 definitely not an OpenEXR file").unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sensor);
    let ctx = h.ctx.clone();
    h.state_mut().sensor_mut().load_scene(still_life(), &ctx);
    step_until(&mut h, "the full run", |app| app.sensor().is_up_to_date());
    h.state_mut().sensor_mut().load_scene(bad.clone(), &ctx);
    step_until(&mut h, "the error", |app| {
        app.sensor().message().is_some_and(|m| m.is_error())
    });
    let notice = h.state().sensor().message().unwrap().clone();
    let (msg, _) = (notice.text.clone(), notice.is_error());
    assert!(msg.contains("broken.exr"), "{msg}");
    assert_eq!(
        h.state().sensor().scene_name(),
        Some("StillLife_620x423.exr")
    );
    assert!(h.state().sensor().is_up_to_date(), "the last result stays");
}

#[test]
fn the_gain_controls_check_eta_on_a_flat_patch_and_count_saturated_rois() {
    use udc_studio::core::sensor::{AdditiveGain, BinMode};
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sensor);
    h.step();
    assert!(h.query_by_label("Flat patch check (eq. 5.3)").is_some());
    let checked = |app: &udc_studio::app::StudioApp| {
        let s = app.sensor();
        let f = s.flat_patch_check_ref();
        f.is_up_to_date(s.settings()) && f.result().is_some()
    };
    step_until(&mut h, "the flat-patch check", checked);
    fn h_result(
        h: &egui_kittest::Harness<'_, udc_studio::app::StudioApp>,
    ) -> (
        udc_studio::core::sensor::FlatPatchSpec,
        udc_studio::core::sensor::FlatPatch,
    ) {
        h.state()
            .sensor()
            .flat_patch_check_ref()
            .result()
            .cloned()
            .unwrap()
    }
    let (spec, eta2) = h_result(&h);
    assert_eq!((spec.light_e, spec.eta, spec.bin_px), (400.0, 2.0, 1));
    for shown in [
        format!("{:.2} %", 100.0 * eta2.predicted),
        format!("{:.2} %", 100.0 * eta2.gaussian_tail),
    ] {
        assert!(
            h.query_all_by_label(&shown).next().is_some(),
            "{shown} on screen"
        );
    }
    // A new η reruns the check: more headroom, fewer saturated pixels.
    h.state_mut().sensor_mut().flat_patch_check().eta = 4.0;
    step_until(&mut h, "the η = 4 check", checked);
    let (spec, eta4) = h_result(&h);
    assert_eq!(spec.eta, 4.0);
    assert!(eta4.saturated_fraction < eta2.saturated_fraction);
    // Additive bins at the same gain: the sum of 2×2 pixels saturates sooner than one pixel.
    {
        let s = h.state_mut().sensor_mut();
        s.settings_mut().bin_mode = BinMode::AnalogAdditive;
        s.settings_mut().additive_gain = AdditiveGain::Same;
        s.flat_patch_check().bin_px = 2;
    }
    step_until(&mut h, "the binned check", checked);
    let (spec, same) = h_result(&h);
    assert_eq!(
        (spec.bin_px, spec.bin_mode, spec.additive_gain),
        (2, BinMode::AnalogAdditive, AdditiveGain::Same)
    );
    assert!(same.saturated_fraction > eta4.saturated_fraction);
    // The additive-gain row explains its choice with the sensor's numbers.
    assert!(
        h.query_by_label_contains("2x2 at gain 1: read noise")
            .is_some()
    );
    // The numbers table counts saturated ROIs once a run is on screen.
    step_until(&mut h, "a run", |app| app.sensor().shown().is_some());
    assert!(h.query_by_label("saturated ROIs").is_some());
}

/// The settings have an undo history: a change made in the panel (the exposure kind) goes
/// through the workspace's queue, is one undo step, and undo puts the controls back too.
#[test]
fn a_settings_change_in_the_panel_is_one_undo_step() {
    use udc_studio::core::sensor::Exposure;
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sensor);
    h.step();
    assert!(!h.state().sensor().can_undo());
    assert_eq!(
        h.state().sensor().settings().exposure,
        Exposure::MeanFraction(0.05)
    );
    h.get_by_label("percentile").click();
    h.step();
    h.step();
    assert_eq!(
        h.state().sensor().settings().exposure,
        Exposure::PercentileFill {
            percentile: 99.9,
            fill: 0.8
        }
    );
    assert!(h.state().sensor().can_undo());
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.step();
    h.step();
    assert_eq!(
        h.state().sensor().settings().exposure,
        Exposure::MeanFraction(0.05)
    );
    // The controls show the undone exposure: nothing is queued back on the next frame.
    h.step();
    h.step();
    assert_eq!(
        h.state().sensor().settings().exposure,
        Exposure::MeanFraction(0.05)
    );
    assert!(h.state().sensor().can_redo());
    h.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    h.step();
    h.step();
    assert!(matches!(
        h.state().sensor().settings().exposure,
        Exposure::PercentileFill { .. }
    ));
}
