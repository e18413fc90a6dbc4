//! Drag and drop works wherever a file can be opened: the active workspace takes what it can
//! open, else the first that can, which is then shown.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::common::Reach;
use crate::common::{self, step_until};
use udc_studio::app::WorkspaceId;
use udc_studio::app::phase::PhaseView;

fn asset(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets").join(p)
}

/// A file as the window system hands it over.
#[derive(Debug)]
struct Dropped(PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

pub fn drop_file(h: &mut egui_kittest::Harness<'_, udc_studio::app::StudioApp>, path: PathBuf) {
    h.input_mut()
        .dropped_files
        .push(std::sync::Arc::new(Dropped(path)));
    h.step();
}

#[test]
fn each_dropped_file_reaches_the_workspace_that_opens_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.step();
    // An HDR scene dropped on the display opens the sensor previewer with it.
    drop_file(&mut h, asset("hdr/StillLife_620x423.exr"));
    assert_eq!(h.state().workspace(), WorkspaceId::Sensor);
    step_until(&mut h, "the dropped scene", |app| {
        app.sensor().scene_name() == Some("StillLife_620x423.exr")
    });
    // A photo dropped on the phase workspace becomes its capture photo, not a display opening.
    h.state_mut().set_workspace(WorkspaceId::Phase);
    h.step();
    drop_file(&mut h, asset("photos/coffee_256.png"));
    assert_eq!(h.state().workspace(), WorkspaceId::Phase);
    assert_eq!(h.state().phase().view(), PhaseView::Capture);
    step_until(&mut h, "the dropped photo", |app| {
        app.phase().capture_photo_name() == Some("coffee_256.png")
    });
    // A response CSV dropped there becomes the sensor response.
    drop_file(&mut h, asset("spectral/thesis_sensor_response.csv"));
    step_until(&mut h, "the dropped response", |app| {
        app.phase().custom_response().is_some()
    });
    // A design file goes to the display, wherever it is dropped.
    let design = dir.path().join("d.json");
    std::fs::write(&design, udc_studio::io::design::presets::PRESETS[0].text).unwrap();
    drop_file(&mut h, design);
    assert_eq!(h.state().workspace(), WorkspaceId::Display);
}

/// The shell decides a dropped file's kind once: by extension (any case), and a sweep's results
/// by the `sweep.json` beside them, whatever their extension.
#[test]
fn a_dropped_file_has_one_kind() {
    use udc_studio::app::DroppedKind as K;
    let dir = tempfile::tempdir().unwrap();
    let sweep = dir.path().join("sweep");
    std::fs::create_dir_all(&sweep).unwrap();
    std::fs::write(sweep.join("sweep.json"), "{}").unwrap();
    for (name, kind) in [
        ("scene.EXR", K::HdrScene),
        ("scene.hdr", K::HdrScene),
        ("design.json", K::Design),
        ("design.udc.json", K::Design),
        ("photo.JPG", K::Image),
        ("photo.tiff", K::Image),
        ("response.csv", K::Table),
        ("mask.gds", K::Mask),
        ("mask.OAS", K::Mask),
        ("mask.dxf", K::Mask),
        ("notes.txt", K::Unknown),
        ("no-extension", K::Unknown),
    ] {
        assert_eq!(K::of(&dir.path().join(name)), kind, "{name}");
    }
    // A sweep's folder and its files belong to the Sweep workspace, not to a CSV or JSON reader.
    assert_eq!(K::of(&sweep), K::SweepResults);
    assert_eq!(K::of(&sweep.join("sweep.json")), K::SweepResults);
    assert_eq!(K::of(&sweep.join("results.csv")), K::SweepResults);
}

/// A file no workspace opens changes nothing and says so.
#[test]
fn a_file_no_workspace_opens_is_refused_in_the_status_line() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.step();
    let before = h.state().workspace();
    let notes = dir.path().join("notes.txt");
    std::fs::write(&notes, "not a design").unwrap();
    drop_file(&mut h, notes);
    assert_eq!(h.state().workspace(), before);
    let notice = h.state().status().cloned().expect("a status message");
    assert!(notice.is_error(), "{notice:?}");
    assert!(
        notice.text.contains("no workspace opens") && notice.text.contains("notes.txt"),
        "{notice:?}"
    );
}
