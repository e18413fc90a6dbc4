//! The Field & depth view, driven headless: it opens, computes on its job and shows its numbers
//! with their units.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::{Duration, Instant};

use crate::common::Reach;
use crate::common::step_until;
use egui_kittest::kittest::Queryable;
use udc_studio::app::panels::views::ViewTab;
use udc_studio::app::panels::views::field_depth::Study;
use udc_studio::app::{DisplayAction, StudioApp};

/// Saves a picture of the studio when `UDC_SCREENSHOTS_DIR` is set (and a renderer exists).
fn capture(h: &mut egui_kittest::Harness<'_, StudioApp>, name: &str) {
    let Some(dir) = std::env::var_os("UDC_SCREENSHOTS_DIR").map(std::path::PathBuf::from) else {
        return;
    };
    match h.render() {
        Ok(img) => {
            std::fs::create_dir_all(&dir).unwrap();
            img.save(dir.join(format!("views-{name}.png"))).unwrap();
        }
        Err(e) => eprintln!("{name}: no renderer here ({e})"),
    }
}

fn wait_for_result(h: &mut egui_kittest::Harness<'_, StudioApp>, what: &str) {
    let start = Instant::now();
    // As common::step_until: a growing pause leaves the cores to the worker.
    let mut pause = Duration::from_millis(2);
    loop {
        h.step();
        let v = &h.state_mut().display_mut().views().field_depth;
        if !v.is_running() && !v.summary().is_empty() {
            h.step();
            return;
        }
        assert!(
            start.elapsed() < Duration::from_secs(90),
            "timed out waiting for {what}"
        );
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(100));
    }
}

#[test]
fn the_field_and_depth_view_shows_its_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let wgpu = std::env::var_os("UDC_SCREENSHOTS_DIR").is_some();
    let mut h = common::studio(dir.path(), wgpu, Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-random".into()));
    step_until(
        &mut h,
        "the design's result",
        crate::common::display_up_to_date,
    );
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::FieldDepth);
    wait_for_result(&mut h, "the field grid");
    let summary = h
        .state_mut()
        .display_mut()
        .views()
        .field_depth
        .summary()
        .to_string();
    assert!(
        summary.contains("max residual_rel") && summary.contains(" mm"),
        "{summary}"
    );
    assert_eq!(
        h.query_all_by_label_contains("residual ").count(),
        9 + 1,
        "9 insets and the note"
    );
    h.get_by_label("display to lens");
    // The studio computes on the CPU unless View ▸ Compute PSFs on says otherwise.
    let on = h
        .state_mut()
        .display_mut()
        .views()
        .field_depth
        .computed_on()
        .to_string();
    assert_eq!(on, "PSFs computed on the CPU (f64)");
    h.get_by_label(&on);
    capture(&mut h, "field");

    // The photo captured patch-wise through the field PSFs, restored with the centre PSF,
    // beside the shift-invariant capture: both scores on screen, the field one no better.
    h.state_mut()
        .display_mut()
        .views()
        .field_depth
        .set_capture_photo(true);
    h.step();
    wait_for_result(&mut h, "the field capture");
    let summary = h
        .state_mut()
        .display_mut()
        .views()
        .field_depth
        .summary()
        .to_string();
    assert!(
        summary.contains("field-dependent capture") && summary.contains("shift-invariant"),
        "{summary}"
    );
    let db = |key: &str| -> f64 {
        let at = summary.find(key).unwrap() + key.len();
        summary[at..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let (field_db, invariant_db) = (
        db("field-dependent capture "),
        db("shift-invariant capture "),
    );
    assert!(field_db <= invariant_db + 0.05, "{summary}");
    assert!(
        h.query_by_label_contains("field-dependent capture, restored")
            .is_some()
    );
    h.state_mut()
        .display_mut()
        .views()
        .field_depth
        .set_capture_photo(false);

    h.state_mut()
        .display_mut()
        .views()
        .field_depth
        .set_study(Study::Depth);
    h.step();
    wait_for_result(&mut h, "the depth PSFs");
    h.step();
    let summary = h
        .state_mut()
        .display_mut()
        .views()
        .field_depth
        .summary()
        .to_string();
    assert!(
        summary.contains("PSF scale z2/f") && summary.contains("waves"),
        "{summary}"
    );
    h.get_by_label("focused at infinity");
    h.get_by_label("object distance z1");
    capture(&mut h, "depth");

    // The photo at that depth, restored with the infinity PSF three ways.
    h.state_mut()
        .display_mut()
        .views()
        .field_depth
        .set_capture_photo(true);
    h.step();
    wait_for_result(&mut h, "the depth photos");
    let summary = h
        .state_mut()
        .display_mut()
        .views()
        .field_depth
        .summary()
        .to_string();
    assert!(
        summary.contains("refocused on it") && summary.contains("object at infinity"),
        "{summary}"
    );
    assert!(h.query_by_label_contains("refocused on it:").is_some());
    capture(&mut h, "depth-photo");
    h.state_mut()
        .display_mut()
        .views()
        .field_depth
        .set_capture_photo(false);

    h.state_mut()
        .display_mut()
        .views()
        .field_depth
        .set_study(Study::Saturation);
    h.step();
    wait_for_result(&mut h, "the saturation study");
    let summary = h
        .state_mut()
        .display_mut()
        .views()
        .field_depth
        .summary()
        .to_string();
    assert!(summary.contains("dB PSNR"), "{summary}");
    assert_eq!(h.query_all_by_label_contains("restored: PSNR").count(), 2);
    h.get_by_label("clipped");
    capture(&mut h, "saturation");
}
