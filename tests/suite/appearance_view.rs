//! The Appearance view, driven like a user: it opens, renders periodic and random side by side
//! and shows the display-quality numbers beside the camera's AUC.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::step_until;
use egui_kittest::kittest::Queryable;
use udc_studio::app::panels::views::ViewTab;
use udc_studio::app::{Command, StudioApp};

#[test]
fn the_appearance_view_shows_quality_beside_the_camera_auc() {
    let dir = tempfile::tempdir().unwrap();
    // With UDC_SCREENSHOTS_DIR (screenshots/make.sh) the harness renders, for the README.
    let shots = std::env::var_os("UDC_SCREENSHOTS_DIR").map(std::path::PathBuf::from);
    let mut h = common::studio(dir.path(), shots.is_some(), Duration::from_secs(600));
    h.state_mut()
        .command(Command::LoadPreset("l2inv-repeat".into()));
    step_until(&mut h, "the result", StudioApp::is_up_to_date);
    h.state_mut().views().set_tab(ViewTab::Appearance);
    step_until(&mut h, "both renderings", |app| {
        let v = app.appearance_view();
        !v.is_running() && v.qualities().len() == 2
    });
    let q = h.state().appearance_view().qualities();
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
