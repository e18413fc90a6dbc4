//! Renders the studio headless (egui_kittest + wgpu on lavapipe) in the states the README shows.
//! Each scenario also asserts its state, so it is a test even where no renderer exists. With
//! `UDC_SCREENSHOTS_DIR` set (see `screenshots/make.sh`) the images are saved there.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use udc_studio::app::{DisplayAction, StudioApp};
use udc_studio::core::design::TilingMode;

fn harness(dir: &std::path::Path) -> Harness<'static, StudioApp> {
    common::studio(dir, true, Duration::from_secs(3600))
}

fn settle(h: &mut Harness<'_, StudioApp>) {
    common::step_until(h, "the worker", crate::common::display_up_to_date);
    for _ in 0..4 {
        h.step();
    }
}

/// Renders and saves when asked; checks the picture is not blank when a renderer exists.
pub fn capture(h: &mut Harness<'_, StudioApp>, name: &str) {
    match h.render() {
        Ok(img) => {
            let first = *img.get_pixel(0, 0);
            assert!(
                img.pixels().any(|p| *p != first),
                "{name}: rendered a blank image"
            );
            if let Ok(dir) = std::env::var("UDC_SCREENSHOTS_DIR") {
                std::fs::create_dir_all(&dir).unwrap();
                img.save(std::path::Path::new(&dir).join(format!("{name}.png")))
                    .unwrap();
            }
        }
        Err(e) => eprintln!("{name}: no renderer here ({e}); state checked, picture skipped"),
    }
}

#[test]
fn main_window_on_toled_then_random_tiling() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    settle(&mut h);
    h.get_by_label("log-PSF").click();
    settle(&mut h);
    capture(&mut h, "main-toled-repeat");
    h.get_by_label("Tiling").click();
    h.step();
    h.get_by_label("Random D4").click();
    settle(&mut h);
    assert_eq!(
        h.state().display().design().tiling.mode,
        TilingMode::RandomD4
    );
    capture(&mut h, "main-toled-random");
    h.get_by_label("MTF plots").click();
    settle(&mut h);
    capture(&mut h, "mtf-plots-random");
}

#[test]
fn compare_view() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    settle(&mut h);
    h.state_mut().act(DisplayAction::PinCompare);
    h.step();
    assert!(h.state().display().pinned().is_some());
    let mut d = h.state().display().design().clone();
    d.tiling.mode = TilingMode::RandomD4;
    h.state_mut().act(DisplayAction::Edit(Box::new(d)));
    settle(&mut h);
    // The menu bar also has a "Compare" menu: the tab is the last one.
    h.get_all_by_label("Compare")
        .last()
        .expect("the Compare tab")
        .click();
    settle(&mut h);
    capture(&mut h, "compare");
}

#[test]
fn editor_mid_drawing() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-random".into()));
    settle(&mut h);
    let before = h.state().display().design().clone();
    h.state_mut()
        .act(DisplayAction::SetTool(udc_studio::app::Tool::Ellipse));
    h.step();
    let rect = h
        .state()
        .display()
        .editor()
        .grid_rect()
        .expect("editor drawn");
    let a = rect.left_top() + rect.size() * 0.2;
    let b = rect.left_top() + rect.size() * 0.7;
    common::press_and_move(&mut h, a, b, 5);
    // Mid-drag: nothing is committed yet.
    assert_eq!(h.state().display().design(), &before);
    capture(&mut h, "editor-mid-drawing");
}

#[test]
fn optimizer_after_a_run() {
    use udc_studio::app::LeftTab;
    use udc_studio::core::analysis::analyze::Quality;
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    let mut d = h.state().display().design().clone();
    d.tiling.mode = TilingMode::Random4;
    h.state_mut().act(DisplayAction::Edit(Box::new(d)));
    settle(&mut h);
    h.state_mut().display_mut().show_left_tab(LeftTab::Optimize);
    // The README's picture shows a full run; the test needs only a finished one to apply (the
    // optimizer's gains are checked in optimize.rs and optimize_panel.rs).
    let epochs = if std::env::var_os("UDC_SCREENSHOTS_DIR").is_some() {
        100
    } else {
        10
    };
    {
        let s = h.state_mut().display_mut().optimizer_settings();
        s.epochs = epochs;
        s.quality = Quality::Preview;
    }
    h.step();
    h.get_by_label("Run optimizer").click();
    common::step_until(&mut h, "the optimizer", |app| {
        app.display().optimizer().finished().is_some()
    });
    h.get_by_label("MTF plots").click();
    settle(&mut h);
    capture(&mut h, "optimizer-run");
    h.get_by_label("Apply as new design").click();
    settle(&mut h);
    assert!(h.state().display().design().name.contains("optimized"));
    capture(&mut h, "optimizer-applied");
}

#[test]
fn restore_view_with_a_pinned_design() {
    use udc_studio::app::panels::views::ViewTab;
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    settle(&mut h);
    h.state_mut().act(DisplayAction::PinCompare);
    common::step_until(&mut h, "the pin", |app| app.display().pinned().is_some());
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-random".into()));
    settle(&mut h);
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::Restore);
    common::step_until(&mut h, "both restorations", |app| {
        let v = app.display().restore_view();
        !v.is_running() && v.current().is_some() && v.pinned().is_some()
    });
    for _ in 0..4 {
        h.step();
    }
    let v = h.state().display().restore_view();
    assert!(v.current().unwrap().psnr_db > v.pinned().unwrap().psnr_db);
    capture(&mut h, "restore");
}

#[test]
fn sensor_previewer_maps_and_split_compare() {
    use udc_studio::app::WorkspaceId;
    use udc_studio::app::sensor::{CompareMode, SensorView};
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut().set_workspace(WorkspaceId::Sensor);
    let ctx = h.ctx.clone();
    let scene =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/hdr/StillLife_620x423.exr");
    h.state_mut().sensor_mut().load_scene(scene, &ctx);
    common::step_until(&mut h, "the sensor run", |app| app.sensor().is_up_to_date());
    for _ in 0..4 {
        h.step();
    }
    assert_eq!(h.state().sensor().shown().unwrap().run.strategies.len(), 4);
    capture(&mut h, "sensor-maps");
    h.state_mut().sensor_mut().show(SensorView::Compare);
    h.state_mut()
        .sensor_mut()
        .set_compare(0, 3, CompareMode::Split, 0.5);
    for _ in 0..4 {
        h.step();
    }
    capture(&mut h, "sensor-compare");
    h.state_mut().sensor_mut().show(SensorView::Curves);
    for _ in 0..4 {
        h.step();
    }
    capture(&mut h, "sensor-curves");
    h.state_mut().sensor_mut().show(SensorView::Study);
    h.step();
    let ctx = h.ctx.clone();
    let app = h.state_mut();
    let settings = app.sensor().settings().clone();
    let scene = app.sensor().scene().cloned();
    if let Some(scene) = scene {
        app.sensor_mut()
            .study
            .start(scene.as_ref(), &settings, &ctx);
    }
    common::step_until(&mut h, "the bin-size study", |app| {
        app.sensor().study.study().is_some()
    });
    for _ in 0..4 {
        h.step();
    }
    capture(&mut h, "sensor-bin-study");
}

#[test]
fn phase_masks_psfs_plate_and_optimizer() {
    use udc_studio::app::WorkspaceId;
    use udc_studio::app::phase::{PhaseView, Quality};
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut().set_workspace(WorkspaceId::Phase);
    common::step_until(&mut h, "the phase PSFs", |app| app.phase().is_up_to_date());
    for _ in 0..4 {
        h.step();
    }
    assert_eq!(h.state().phase().shown().unwrap().psfs.lenslets, 58);
    capture(&mut h, "phase-psf");
    h.state_mut().phase_mut().show(PhaseView::Geometry);
    for _ in 0..4 {
        h.step();
    }
    capture(&mut h, "phase-plate");
    // The optimizer at preview sampling keeps the scenario quick.
    h.state_mut().phase_mut().quality = Quality::Preview;
    h.state_mut().phase_mut().show(PhaseView::Optimizer);
    common::step_until(&mut h, "the preview PSFs", |app| {
        app.phase().is_up_to_date()
    });
    h.get_by_label("Run optimizer").click();
    common::step_until(&mut h, "the phase optimizer", |app| {
        app.phase().optimized().is_some()
    });
    for _ in 0..4 {
        h.step();
    }
    let o = h.state().phase().optimized().unwrap();
    assert_eq!(o.allocation.counts.iter().sum::<usize>(), 58);
    capture(&mut h, "phase-optimizer");
}

#[test]
fn phase_capture_and_compare() {
    use udc_studio::app::WorkspaceId;
    use udc_studio::app::phase::{ChannelSet, PhaseView, Quality};
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut().set_workspace(WorkspaceId::Phase);
    // For the README's picture, full sampling through the peak wavelengths: the real view, ten
    // times quicker than the spectral channels. Otherwise preview sampling: the same rows and
    // states, a sixth of the work.
    let for_readme = std::env::var_os("UDC_SCREENSHOTS_DIR").is_some();
    h.state_mut().phase_mut().quality = if for_readme {
        Quality::Full
    } else {
        Quality::Preview
    };
    common::choose_capture(h.state_mut().phase_mut(), |c| {
        c.channels = ChannelSet::Peaks
    });
    h.state_mut().phase_mut().show(PhaseView::Capture);
    common::step_until(&mut h, "the capture", |app| {
        app.phase().capture_is_current()
    });
    for _ in 0..4 {
        h.step();
    }
    let rows = h.state().phase().capture_rows();
    assert_eq!(rows.len(), 2);
    assert!(rows[0].ltr > 1.5 * rows[1].ltr);
    // The bare T-OLED's slits pass no light at some horizontal frequencies (on the whole
    // 1024-pixel sensor its diffraction orders are all there); the double MLA (here T = 1, its
    // plate wrapping many times) passes nearly all of them. Each row with such frequencies
    // says what the photo keeps without them.
    assert!(
        rows[1].unpassed_mse > 10.0 * rows[0].unpassed_mse,
        "T-OLED {}, double MLA {}",
        rows[1].unpassed_mse,
        rows[0].unpassed_mse
    );
    assert_eq!(
        h.query_all_by_label_contains("passes < 1 % of").count(),
        rows.iter().filter(|r| r.unpassed_mse > 0.0).count()
    );
    capture(&mut h, "phase-capture");
    // Bare T-OLED, T = 1 fixed and uniform, T = 5 fixed and uniform (no optimizer run); the
    // test alone compares three of them (a row per setup and light level either way).
    let setups: &[usize] = if for_readme {
        &[0, 1, 2, 4, 5]
    } else {
        &[0, 1, 5]
    };
    h.state_mut().phase_mut().select_compare_setups(setups);
    h.get_by_label("Run comparison").click_accesskit();
    common::step_until(&mut h, "the comparison", |app| {
        !app.phase().compare().is_running()
    });
    assert_eq!(h.state().phase().compare().rows().len(), setups.len() * 4);
    h.set_size(egui::vec2(1440.0, 1900.0));
    for _ in 0..4 {
        h.step();
    }
    capture(&mut h, "phase-compare");
}

#[test]
fn sweep_results_and_a_one_parameter_sweep() {
    use udc_studio::app::WorkspaceId;
    use udc_studio::core::sweep::one_axis::{OneAxisPoint, SweepParameter};
    let dir = tempfile::tempdir().unwrap();
    let out = common::tiny_sweep(dir.path());
    let mut h = harness(dir.path());
    h.state_mut().set_workspace(WorkspaceId::Sweep);
    let ctx = h.ctx.clone();
    h.state_mut()
        .sweep_mut()
        .open_folder(&out, move || ctx.request_repaint());
    common::step_until(&mut h, "the sweep table", |app| {
        app.sweep().is_idle() && app.sweep().shown_rows().is_some()
    });
    for _ in 0..4 {
        h.step();
    }
    assert_eq!(h.state().sweep().shown_rows().unwrap().len(), 8);
    capture(&mut h, "sweep-results");
    // The T-OLED's pitch swept from its context menu's window, at preview quality.
    h.state_mut().set_workspace(WorkspaceId::Display);
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    h.state_mut()
        .display_mut()
        .show_left_tab(udc_studio::app::LeftTab::Tiling);
    h.state_mut()
        .act(DisplayAction::SweepParameter(SweepParameter::PitchUm));
    for _ in 0..4 {
        h.step();
    }
    let ctx = h.ctx.clone();
    h.state_mut().display_mut().field_sweep_mut().run(&ctx);
    common::step_until(&mut h, "the 1-D sweep", |app| {
        let w = app.display().one_axis_sweep();
        !w.is_running() && w.points().iter().all(|(_, p)| p.is_some())
    });
    settle(&mut h);
    let points = h.state().display().one_axis_sweep().points();
    assert_eq!(points.len(), 9);
    assert!(
        points
            .iter()
            .all(|(_, p)| matches!(p, Some(OneAxisPoint::Value(y)) if y.is_finite()))
    );
    capture(&mut h, "sweep-this-parameter");
}

/// Help ▸ Reproduce thesis results after a quick run of Table 5.1: the list, the result's facts
/// and its report beside the thesis's numbers.
#[test]
fn reproduce_window_with_a_report() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    settle(&mut h);
    common::open_reproduce_window(&mut h);
    h.get_by_label("table5.1").click();
    h.step();
    h.get_by_label_contains("Run quick").click();
    common::step_until(&mut h, "the quick run", |app| !app.reproduce().is_running());
    for _ in 0..4 {
        h.step();
    }
    assert!(h.state().reproduce().report().is_some());
    capture(&mut h, "reproduce");
}
