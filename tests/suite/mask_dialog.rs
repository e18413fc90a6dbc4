//! The Export-mask dialog, driven like a user would: open it from the File menu, read its
//! statistics, change the region and tone, and export on the background task.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use egui_kittest::kittest::Queryable;
use udc_studio::app::{DisplayAction, ShellCommand};
use udc_studio::core::mask::Tone;
use udc_studio::core::mask::drc::ViolationKind;
use udc_studio::io::mask::{estimate, plan};

#[test]
fn the_dialog_shows_the_statistics_and_exports_in_the_background() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(3600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    h.step();
    h.get_by_label("File").click();
    h.step();
    h.step();
    h.get_by_label("Export mask…").click();
    // A new window is laid out invisibly on its first frame.
    for _ in 0..4 {
        h.step();
    }
    assert!(h.state().display().mask_export().is_open());
    // The preview is laid out off the UI thread.
    common::step_until(&mut h, "the dialog's preview", |app| {
        !app.display().mask_export().previewing()
    });
    // One T-OLED pixel: the slit is one rectangle of 40 × 168 µm.
    assert!(
        h.query_by_label("1 in 1 orientation").is_some(),
        "pixel count"
    );
    assert!(h.query_by_label("Open area").is_some());
    assert!(h.query_by_label("File size").is_some());
    assert!(h.query_by_label("0.2381").is_some(), "open fraction 5/21");
    assert!(
        h.query_by_label("6.7200e3 µm²").is_some(),
        "open area 40 × 168 µm²"
    );
    // Every pixel over the 4 mm pupil, chrome tone.
    h.get_by_label("Lens pupil").click();
    h.step();
    h.get_by_label("drawn = chrome (dark)").click();
    h.step();
    h.step();
    common::step_until(&mut h, "the pupil's preview", |app| {
        !app.display().mask_export().previewing()
    });
    assert_eq!(
        h.state().display().mask_export().options().spec.tone,
        Tone::Chrome
    );
    assert!(
        h.query_by_label("496 in 1 orientation").is_some(),
        "pupil pixels"
    );
    // The dialog shows what the writer's estimate says for these options.
    let options = h.state().display().mask_export().options().clone();
    let layout = plan(h.state().display().design(), &options).unwrap();
    let counts = estimate(&layout, &options);
    let arrays = if counts.arrays == 1 {
        "array"
    } else {
        "arrays"
    };
    let refs = format!("{} single, {} {arrays}", counts.references, counts.arrays);
    assert!(h.query_by_label(&refs).is_some(), "{refs}");
    // Without native dialogs the Export… button reports it; the command writes directly.
    h.get_by_label("Export…").click();
    h.step();
    let path = dir.path().join("pupil.gds");
    h.state_mut()
        .act(DisplayAction::WriteMask(Some(path.clone())));
    common::step_until(&mut h, "the mask export", |app| {
        !app.display().mask_export().is_running()
    });
    let notice = h.state().status().cloned().expect("a status message");
    let (status, is_error) = (notice.text.clone(), notice.is_error());
    assert!(!is_error, "{status}");
    assert!(status.contains("wrote"), "{status}");
    assert!(path.exists());
    assert!(dir.path().join("pupil.gds.design.json").exists());
}

#[test]
fn the_dialog_shows_the_design_rules_before_export() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(3600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-random".into()));
    h.step();
    h.get_by_label("File").click();
    h.step();
    h.step();
    h.get_by_label("Export mask…").click();
    for _ in 0..4 {
        h.step();
    }
    // The check runs off the UI thread; the dialog says "checking…" until it answers.
    common::step_until(&mut h, "the dialog's design-rule check", |app| {
        !app.display().mask_export().rules_checking()
    });
    // The thesis's random L2-inverse opening: single-cell features and 8 corner contacts,
    // the same numbers `udc-studio drc` reports.
    let r = udc_studio::core::mask::drc::check(h.state().display().design(), &Default::default());
    assert_eq!(r.corner_contacts, 8);
    // The pixel as tiled, then the file to be written (the one pixel on the optical axis, its
    // cut openings left out): the same widths, and the same 8 contacts inside the opening.
    let contacts = h.query_all_by_label("8 corner contacts").count();
    assert_eq!(contacts, 2);
    assert_eq!(h.query_all_by_label("smallest opening 8.00 µm").count(), 2);
    assert_eq!(
        h.query_all_by_label("smallest chrome gap 8.00 µm").count(),
        2
    );
    assert!(
        h.query_by_label_contains("Written file: design rules")
            .is_some(),
        "the written file's check"
    );
}

#[test]
fn the_editor_canvas_rings_the_cells_that_break_a_rule() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(3600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-random".into()));
    for _ in 0..3 {
        h.step();
    }
    // Off by default: no check runs and the canvas has no rings.
    assert!(h.state().display().editor().rule_marks().is_empty());
    assert!(!h.state().display().editor().rules_checking());
    // View > Design rules on the editor.
    h.get_by_label("View").click();
    h.step();
    h.step();
    h.get_by_label("Design rules on the editor").click();
    h.step();
    common::step_until(&mut h, "the canvas's design-rule check", |app| {
        !app.display().editor().rule_marks().is_empty()
    });
    // The random L2-inverse tiling's cells touching at a corner, one ring each, the rule named
    // on hover; the same places as the command line's check.
    let r = udc_studio::core::mask::drc::check(h.state().display().design(), &Default::default());
    let marks = h.state().display().editor().rule_marks().to_vec();
    assert_eq!(marks.len(), r.violations.len());
    assert!(marks.iter().all(|m| m.kind == ViolationKind::CornerContact));
    assert!(
        marks[0].text.starts_with("Corner contact") && marks[0].text.contains("not allowed"),
        "{}",
        marks[0].text
    );
    assert_eq!(marks[0].at_um, r.violations[0].at_um);
    assert!(
        h.query_by_label("design rules: 8 violations (8 corner contacts)")
            .is_some()
    );
    // Hovering a ring inside the tile names its rule.
    let pitch = h.state().display().design().opening.pitch_um;
    let grid = h.state().display().editor().grid_rect().unwrap();
    let inside = marks
        .iter()
        .find(|m| m.at_um.iter().all(|v| *v > 0.0 && *v < pitch))
        .expect("a contact inside the tile");
    let scale = grid.width() / pitch as f32;
    let at = grid.min + egui::vec2(inside.at_um[0] as f32, inside.at_um[1] as f32) * scale;
    h.hover_at(at);
    for _ in 0..4 {
        h.step();
    }
    assert!(
        h.query_by_label_contains("Corner contact: openings touch")
            .is_some(),
        "the hover names the rule"
    );
    // A clean design: no rings once its check is done.
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    common::step_until(&mut h, "the clean design's check", |app| {
        !app.display().editor().rules_checking()
    });
    assert!(h.state().display().editor().rule_marks().is_empty());
    assert!(h.query_by_label("design rules: clean").is_some());
    // Turned off again, the rings and the summary go.
    h.state_mut().command(ShellCommand::ToggleDesignRules);
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-random".into()));
    for _ in 0..3 {
        h.step();
    }
    assert!(h.state().display().editor().rule_marks().is_empty());
    assert!(h.query_by_label("design rules: clean").is_none());
}
