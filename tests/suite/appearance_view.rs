//! The Appearance view, driven like a user: it opens, renders periodic and random side by side
//! and shows the display-quality numbers beside the camera's AUC.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use crate::common::step_until;
use egui_kittest::kittest::Queryable;
use udc_studio::app::DisplayAction;
use udc_studio::app::panels::views::ViewTab;

#[test]
fn the_appearance_view_shows_quality_beside_the_camera_auc() {
    let dir = tempfile::tempdir().unwrap();
    // With UDC_SCREENSHOTS_DIR (screenshots/make.sh) the harness renders, for the README.
    let shots = std::env::var_os("UDC_SCREENSHOTS_DIR").map(std::path::PathBuf::from);
    let mut h = common::studio(dir.path(), shots.is_some(), Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-repeat".into()));
    step_until(&mut h, "the result", crate::common::display_up_to_date);
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::Appearance);
    step_until(&mut h, "both renderings", |app| {
        let v = app.display().appearance_view();
        !v.is_running() && v.qualities().len() == 2
    });
    let q = h.state().display().appearance_view().qualities();
    assert_eq!(q[0].0, "periodic");
    assert!(q[1].0.starts_with("random"));
    assert!(
        q.iter()
            .all(|(_, q)| q.nonuniformity.is_finite() && q.nonuniformity > 0.0)
    );
    assert_eq!(
        h.query_all_by_label_contains("nonuniformity").count(),
        2,
        "numbers under each rendering"
    );
    assert!(h.query_by_label_contains("camera AUC").is_some());
    if let Some(dir) = shots {
        h.step();
        match h.render() {
            Ok(img) => img.save(dir.join("views-appearance.png")).unwrap(),
            Err(e) => eprintln!("no renderer here ({e})"),
        }
    }
}

#[test]
fn the_preset_scatter_places_the_thesis_layouts_on_auc_and_nonuniformity() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    step_until(&mut h, "the result", crate::common::display_up_to_date);
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::Appearance);
    step_until(&mut h, "the renderings", |app| {
        !app.display().appearance_view().is_running()
    });
    h.get_by_label("Scatter presets").click();
    h.step();
    step_until(&mut h, "the scatter", |app| {
        let v = app.display().appearance_view();
        !v.is_running() && !v.scatter().is_empty()
    });
    let points = h.state().display().appearance_view().scatter().to_vec();
    let at = |name: &str| {
        points
            .iter()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("{name} missing from {points:?}"))
            .clone()
    };
    assert!(
        points
            .iter()
            .all(|p| p.camera_auc > 0.0 && p.nonuniformity >= 0.0)
    );
    // The thesis's trade-off: the optimized random layout sees better (AUC) than the T-OLED and
    // its own periodic tiling, and pays for it in display uniformity.
    let (toled, repeat, random) = (at("toled-150dpi"), at("l2inv-repeat"), at("l2inv-random"));
    assert!(
        random.camera_auc > toled.camera_auc,
        "{random:?} vs {toled:?}"
    );
    assert!(
        random.camera_auc > repeat.camera_auc,
        "{random:?} vs {repeat:?}"
    );
    assert!(
        random.nonuniformity > repeat.nonuniformity,
        "{random:?} vs {repeat:?}"
    );
    h.step();
    assert!(
        h.query_by_label_contains("Presets: camera AUC against display nonuniformity")
            .is_some()
    );
}
