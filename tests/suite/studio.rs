//! The studio, driven like a user would: egui_kittest runs the real app headless.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::step_until;

use crate::common::Reach;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use udc_studio::app::panels::views::ViewTab;
use udc_studio::app::{DisplayAction, ShellCommand, StudioApp};
use udc_studio::core::design::TilingMode;

fn harness(dir: &std::path::Path) -> Harness<'static, StudioApp> {
    common::studio(dir, false, Duration::from_millis(200))
}

fn auc_r(app: &StudioApp) -> f64 {
    app.display().shown().expect("a result").analysis.channels[0]
        .mtf
        .auc_radial_min
}

#[test]
fn random_tiling_raises_the_auc_shown() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(
        &mut h,
        "the T-OLED result",
        crate::common::display_up_to_date,
    );
    let before = auc_r(h.state());
    h.get_by_label("Tiling").click();
    h.step();
    h.get_by_label("Random D4").click();
    h.step();
    assert_eq!(
        h.state().display().design().tiling.mode,
        TilingMode::RandomD4
    );
    step_until(
        &mut h,
        "the random-tiling result",
        crate::common::display_up_to_date,
    );
    let after = auc_r(h.state());
    assert!(after > 3.0 * before, "AUC {before} → {after}");
    // The numbers panel shows it (4 decimals).
    let shown = format!("{after:.4}");
    assert!(
        h.query_all_by_label(&shown).next().is_some(),
        "the AUC {shown} is on screen"
    );
}

fn cell_centre(h: &Harness<'_, StudioApp>, row: usize, col: usize) -> egui::Pos2 {
    let rect = h
        .state()
        .display()
        .editor()
        .grid_rect()
        .expect("the editor was drawn");
    let n = h.state().display().design().opening.n() as f32;
    egui::pos2(
        rect.left() + (col as f32 + 0.5) * rect.width() / n,
        rect.top() + (row as f32 + 0.5) * rect.height() / n,
    )
}

#[test]
fn drawing_changes_the_design_and_undo_restores_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    let before = h.state().display().design().clone();
    assert_eq!(before.opening.cells[2][1], 0.0);
    // One drag with the paint tool across row 2, columns 1…4.
    let (a, b) = (cell_centre(&h, 2, 1), cell_centre(&h, 2, 4));
    common::press_and_move(&mut h, a, b, 6);
    h.event(egui::Event::PointerButton {
        pos: b,
        button: egui::PointerButton::Primary,
        pressed: false,
        modifiers: Default::default(),
    });
    h.step();
    h.step();
    let after = h.state().display().design().clone();
    for c in 1..=4 {
        assert_eq!(after.opening.cells[2][c], 1.0, "cell (2, {c}) painted");
    }
    assert!(h.state().display().document().can_undo());
    // The drag was one undo step.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.step();
    assert_eq!(h.state().display().design(), &before);
    h.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    h.step();
    assert_eq!(h.state().display().design(), &after);
}

/// A flick (the press and the first move in one frame) paints its first cell, and no frame
/// shows the opening without the stroke once the button is up.
#[test]
fn a_quick_stroke_keeps_its_first_cell_and_does_not_blink() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    let before = h.state().display().design().opening.cells.clone();
    assert!((1..=6).all(|c| before[3][c] == 0.0));
    let (a, b, c) = (
        cell_centre(&h, 3, 1),
        cell_centre(&h, 3, 4),
        cell_centre(&h, 3, 6),
    );
    h.hover_at(a);
    h.step();
    let button = |pos, pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: Default::default(),
    };
    // The press and the first move in one frame (`Harness::event` would run a frame each).
    h.input_mut()
        .events
        .extend([button(a, true), egui::Event::PointerMoved(b)]);
    h.step();
    h.event(egui::Event::PointerMoved(c));
    h.step();
    h.event(button(c, false));
    h.step();
    let after = h.state().display().design().opening.cells.clone();
    assert_eq!(after[3][1..=6], [1.0; 6], "cells (3, 1)…(3, 6) painted");
    let opened = |cells: &[Vec<f64>]| cells.iter().flatten().filter(|v| **v == 1.0).count();
    assert_eq!(opened(&after), opened(&before) + 6);
    // The frame of the release drew what the document now holds.
    assert_eq!(
        h.state().display().editor().shown_cells(),
        Some(after.as_slice()),
        "the stroke stays on screen"
    );
    h.step();
    assert_eq!(
        h.state().display().editor().shown_cells(),
        Some(after.as_slice())
    );
}

/// Pinned and edited, A and B carry one design name; the Compare tab names them apart.
#[test]
fn compare_names_the_pinned_and_the_edited_design_apart() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    h.state_mut().act(DisplayAction::PinCompare);
    step_until(&mut h, "the pin", |app| app.display().pinned().is_some());
    let name = h.state().display().design().name.clone();
    let pinned_at = h.state().display().pinned().unwrap().pinned_at.clone();
    assert_eq!(pinned_at.len(), 5, "HH:MM, got {pinned_at}");
    h.state_mut().act(DisplayAction::Invert);
    step_until(
        &mut h,
        "the edited result",
        crate::common::display_up_to_date,
    );
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::Compare);
    h.step();
    h.step();
    let a = format!("A: {name} (pinned {pinned_at})");
    let b = format!("B: {name} (current, edited: opening)");
    assert!(h.query_by_label(&a).is_some(), "{a}");
    assert!(h.query_by_label(&b).is_some(), "{b}");
}

#[test]
fn a_corrupt_design_file_shows_an_error_and_keeps_the_design() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.json");
    std::fs::write(
        &bad,
        "{ \"format\": \"udc-studio-design\", \"version\": 1, \"opening\": ",
    )
    .unwrap();
    let mut h = harness(dir.path());
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    let before = h.state().display().design().clone();
    h.state_mut().act(DisplayAction::OpenPath(bad.clone()));
    step_until(&mut h, "the error", |a| {
        a.status().is_some_and(|n| n.is_error())
    });
    let notice = h.state().status().unwrap().clone();
    let (msg, _) = (notice.text.clone(), notice.is_error());
    assert!(msg.contains("broken.json"), "{msg}");
    assert_eq!(
        h.state().display().design(),
        &before,
        "the design is unchanged"
    );
    assert!(
        h.query_by_label_contains("broken.json").is_some(),
        "the error is on screen"
    );
}

#[test]
fn the_design_is_autosaved_and_restored() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    let mut d = h.state().display().design().clone();
    d.tiling.mode = TilingMode::Random4;
    d.tiling.seed = 99;
    h.state_mut().act(DisplayAction::Edit(Box::new(d.clone())));
    step_until(&mut h, "the autosave", |_| {
        udc_studio::io::design::file::load_design(&dir.path().join("autosave.json"))
            .is_ok_and(|s| s.tiling.seed == 99)
    });
    drop(h);
    let mut h2 = harness(dir.path());
    h2.step();
    assert_eq!(
        h2.state().display().design(),
        &d,
        "the next session opens the last design"
    );
}

#[test]
fn unsaved_changes_are_confirmed_before_loading_another_design() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    // A preset replaces an unedited design without asking.
    h.state_mut()
        .act(DisplayAction::LoadPreset("poled-336um".into()));
    h.step();
    assert!(h.query_by_label("Unsaved changes").is_none());
    assert_eq!(h.state().display().design().opening.n(), 42);
    // After an edit, it asks first; Cancel keeps the edit, Discard loads.
    let mut d = h.state().display().design().clone();
    d.tiling.seed = 1234;
    h.state_mut().act(DisplayAction::Edit(Box::new(d.clone())));
    h.state_mut()
        .act(DisplayAction::LoadPreset("open-aperture".into()));
    h.step();
    h.step();
    assert!(
        h.query_by_label("Unsaved changes").is_some(),
        "the prompt is shown"
    );
    h.get_by_label("Cancel").click();
    h.step();
    h.step();
    assert_eq!(h.state().display().design(), &d);
    h.state_mut()
        .act(DisplayAction::LoadPreset("open-aperture".into()));
    h.step();
    h.step();
    h.get_by_label("Don't save").click();
    h.step();
    h.step();
    assert_eq!(
        h.state().display().design().opening.cells,
        vec![vec![1.0; 21]; 21]
    );
    // …and the discarded edit is still one undo away.
    h.state_mut().command(ShellCommand::Undo);
    assert_eq!(h.state().display().design(), &d);
}

#[test]
fn a_mask_imports_back_as_the_opening() {
    use udc_studio::core::mask::{MaskRegion, MaskSpec};
    use udc_studio::io::mask::{ExportOptions, MaskFormat, export_mask};
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("l2inv-random".into()));
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    let exported = h.state().display().design().clone();
    let gds = dir.path().join("pixel.gds");
    let options = ExportOptions {
        format: MaskFormat::Gds,
        spec: MaskSpec {
            region: MaskRegion::PIXEL,
            ..MaskSpec::default()
        },
        ..ExportOptions::default()
    };
    export_mask(
        &exported,
        &options,
        &gds,
        &udc_studio::core::Progress::new(),
    )
    .unwrap();
    // Clear the opening, then bring it back from the mask file.
    h.state_mut().act(DisplayAction::Clear);
    assert!(
        h.state()
            .display()
            .design()
            .opening
            .cells
            .iter()
            .flatten()
            .all(|v| *v == 0.0)
    );
    h.state_mut().act(DisplayAction::ImportOpening(gds));
    step_until(&mut h, "the import", |a| {
        a.status().is_some_and(|n| n.text == "opening imported")
    });
    assert_eq!(
        h.state().display().design().opening.cells,
        exported.opening.cells
    );
    // One undo step back to the cleared opening.
    h.state_mut().command(ShellCommand::Undo);
    assert!(
        h.state()
            .display()
            .design()
            .opening
            .cells
            .iter()
            .flatten()
            .all(|v| *v == 0.0)
    );
}

#[test]
fn unreadable_autosaves_are_kept_aside_numbered_and_said_so() {
    let dir = tempfile::tempdir().unwrap();
    let autosave = dir.path().join("autosave.json");
    let phase = dir.path().join(udc_studio::app::phase::DESIGN_FILE);
    let names = || {
        let mut n: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains("unreadable"))
            .collect();
        n.sort();
        n
    };
    for (round, garbage) in ["{ first", "{ second"].into_iter().enumerate() {
        std::fs::write(&autosave, garbage).unwrap();
        std::fs::write(&phase, garbage).unwrap();
        let mut h = harness(dir.path());
        step_until(
            &mut h,
            "the first result",
            crate::common::display_up_to_date,
        );
        // The notice outlives the first good result: it is not the simulation's error.
        let notice = h.state().status().cloned().expect("a notice");
        let (msg, is_error) = (notice.text.clone(), notice.is_error());
        assert!(is_error && msg.contains("kept it as"), "{msg}");
        let pmsg = h
            .state_mut()
            .phase_mut()
            .message()
            .map(|n| n.text.clone())
            .expect("a phase notice");
        assert!(pmsg.contains("kept it as"), "{pmsg}");
        drop(h);
        // Every copy is still there, none overwritten.
        let kept = names();
        assert_eq!(kept.len(), 2 * (round + 1), "{kept:?}");
        for name in &kept {
            let text = std::fs::read_to_string(dir.path().join(name)).unwrap();
            assert!(text == "{ first" || text == "{ second", "{name}: {text}");
        }
    }
    assert_eq!(
        names(),
        [
            "autosave.unreadable-2.json",
            "autosave.unreadable.json",
            "phase-design.unreadable-2.json",
            "phase-design.unreadable.json"
        ]
    );
}

/// Typing a number is one edit: nothing reaches the design (or the simulation) until Enter,
/// then one undo step takes the whole number back.
#[test]
fn a_typed_number_commits_once_on_enter() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    h.state_mut()
        .display_mut()
        .show_left_tab(udc_studio::app::LeftTab::Tiling);
    h.run_steps(3);
    let before = h.state().display().design().clone();
    let undo_steps_before = undo_depth(&mut h);
    h.get_by_role_and_label(egui::Role::SpinButton, "Wiring gap")
        .focus();
    h.run_steps(2);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    for ch in ["1", "2"] {
        h.get_by_role_and_label(egui::Role::SpinButton, "Wiring gap")
            .type_text(ch);
        h.run_steps(2);
        assert_eq!(
            h.state().display().design().tiling.wiring_gap_um,
            before.tiling.wiring_gap_um,
            "a keystroke must not reach the design"
        );
    }
    h.key_press(egui::Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().display().design().tiling.wiring_gap_um, 12.0);
    assert_eq!(undo_depth(&mut h), undo_steps_before + 1, "one undo step");
    h.state_mut().command(ShellCommand::Undo);
    h.run_steps(2);
    assert_eq!(h.state().display().design(), &before);
    // Text that is not a number never reaches the design, and the status bar says why, in red.
    h.get_by_role_and_label(egui::Role::SpinButton, "Wiring gap")
        .focus();
    h.run_steps(2);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    h.get_by_role_and_label(egui::Role::SpinButton, "Wiring gap")
        .type_text("abc");
    h.key_press(egui::Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().display().design(), &before);
    let status = h.state().status().unwrap();
    assert!(status.is_error(), "{}", status.text);
    assert!(
        status.text.contains("\"abc\" is not a number"),
        "{}",
        status.text
    );
}

/// How many undo steps the display document holds.
fn undo_depth(h: &mut Harness<'static, StudioApp>) -> usize {
    let mut n = 0;
    let start = h.state().display().design().clone();
    while h.state().display().document().can_undo() {
        h.state_mut().command(ShellCommand::Undo);
        n += 1;
    }
    for _ in 0..n {
        h.state_mut().command(ShellCommand::Redo);
    }
    assert_eq!(h.state().display().design(), &start);
    n
}

/// The Help menu of every workspace opens with its tour and its shortcuts (and every glyph in
/// them exists in the studio's fonts: a missing one would panic here).
#[test]
fn the_help_menu_tours_every_workspace() {
    use udc_studio::app::WorkspaceId;
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(dir.path());
    for (ws, first_step) in [
        (WorkspaceId::Display, "1. Draw one display pixel's opening"),
        (
            WorkspaceId::Phase,
            "1. The left sets the two microlens arrays",
        ),
        (WorkspaceId::Sensor, "1. Open an HDR scene"),
        (
            WorkspaceId::Sweep,
            "1. Study > New study… in Display layouts",
        ),
    ] {
        h.state_mut().set_workspace(ws);
        h.run_steps(2);
        h.get_by_label("Help").click();
        h.run_steps(2);
        assert!(
            h.query_by_label_contains(first_step).is_some(),
            "{ws:?}: the tour is missing"
        );
        assert!(h.query_by_label_contains("undo / redo").is_some());
        h.key_press(egui::Key::Escape);
        h.run_steps(2);
    }
}

/// After an edit the worker sends the full-quality numbers first and the same result with the
/// advice for its warnings after (each advice is a further analysis); at f/2.5 it sends no
/// preview, which would repeat the full-quality computation.
#[test]
fn the_worker_sends_the_numbers_before_the_advice_and_no_repeated_preview() {
    use udc_studio::app::{Payload, Worker};
    use udc_studio::core::Quality;
    let compute = udc_studio::app::compute::Compute::new(None, Default::default());
    let mut worker = Worker::spawn(|| {}, compute.shared());
    // The thesis recipe: its grey notes get advice.
    let design = udc_studio::io::design::presets::load_preset("toled-150dpi").expect("preset");
    let generation = worker.submit(design);
    let mut seen = Vec::new();
    while let Some(r) = worker.wait(Duration::from_secs(60)) {
        if r.generation != generation {
            continue;
        }
        if let Payload::Analysis {
            quality,
            advised,
            result,
            route,
        } = r.payload
        {
            // The route the job ran on, which the studies of the shown design then use.
            assert!(std::sync::Arc::ptr_eq(&route, &compute.current()));
            let a = result.expect("analysis");
            let fixes = a.warnings.iter().filter(|w| w.fix.is_some()).count();
            seen.push((quality, advised, a.warnings.len(), fixes));
            if advised {
                break;
            }
        }
    }
    assert_eq!(seen.len(), 2, "{seen:?}");
    let (first, last) = (seen[0], seen[1]);
    assert_eq!(
        (first.0, first.1, first.3),
        (Quality::Full, false, 0),
        "{seen:?}"
    );
    assert_eq!((last.0, last.1), (Quality::Full, true), "{seen:?}");
    assert_eq!(first.2, last.2, "the same warnings");
    assert!(last.3 > 0, "advice arrives with the last: {seen:?}");
}
