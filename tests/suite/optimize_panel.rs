//! The Optimize panel, driven like a user: run from the current design, watch the epochs arrive,
//! apply the result as one undoable edit.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use crate::common::step_until;
use egui_kittest::kittest::Queryable;
use udc_studio::app::{DisplayAction, LeftTab, ShellCommand};
use udc_studio::core::analysis::analyze::Quality;

#[test]
fn a_run_streams_epochs_and_applies_as_one_undoable_edit() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(
        &mut h,
        "the T-OLED result",
        crate::common::display_up_to_date,
    );
    let before = h.state().display().design().clone();
    let loss_before = h
        .state()
        .display()
        .shown()
        .unwrap()
        .analysis
        .invertibility_loss;
    h.state_mut().display_mut().show_left_tab(LeftTab::Optimize);
    {
        let s = h.state_mut().display_mut().optimizer_settings();
        s.epochs = 12;
        s.target_open_fraction = 0.3;
        s.area_every_epochs = 1;
        s.area_step = 0.1;
        s.quality = Quality::Preview;
    }
    h.step();
    h.get_by_label("Run optimizer").click();
    h.step();
    step_until(&mut h, "the run to finish", |app| {
        app.display().optimizer().finished().is_some()
    });
    // Every epoch reached the panel, in order, and the plot and opening are on screen.
    let epochs: Vec<usize> = h
        .state()
        .display()
        .optimizer()
        .history()
        .iter()
        .map(|r| r.epoch)
        .collect();
    assert_eq!(epochs, (0..12).collect::<Vec<_>>());
    // The data loss on the built-in training photo is on by default, as in the thesis.
    let data: Vec<Option<f64>> = h
        .state()
        .display()
        .optimizer()
        .history()
        .iter()
        .map(|r| r.loss_data)
        .collect();
    assert!(data.iter().all(Option::is_some), "{data:?}");
    assert!(h.query_by_label("Apply as new design").is_some());
    assert_eq!(
        h.state().display().design(),
        &before,
        "nothing changes before Apply"
    );
    // The summary's full-quality start is what the numbers showed before the run.
    let scores = h
        .state()
        .display()
        .optimizer()
        .finished()
        .unwrap()
        .result
        .at_full_quality;
    let start = scores.start.unwrap().loss_inv;
    assert!(
        (start - loss_before).abs() < 1e-9,
        "{start} vs {loss_before}"
    );
    let result = format!("{:.4}", scores.result.loss_inv);
    assert!(
        h.query_all_by_label(&result).next().is_some(),
        "the summary shows the result's L_inv {result}"
    );
    h.get_by_label("Apply as new design").click();
    h.step();
    h.step();
    let after = h.state().display().design().clone();
    // Applied, the numbers show the very L_inv the summary promised.
    step_until(
        &mut h,
        "the applied result",
        crate::common::display_up_to_date,
    );
    let shown = h
        .state()
        .display()
        .shown()
        .unwrap()
        .analysis
        .invertibility_loss;
    assert!(
        (shown - scores.result.loss_inv).abs() < 1e-9,
        "summary {} vs numbers {shown}",
        scores.result.loss_inv
    );
    assert!(h.query_all_by_label(&result).next().is_some());
    let open = after
        .opening
        .cells
        .iter()
        .flatten()
        .filter(|v| **v == 1.0)
        .count();
    assert_eq!(open, (0.3f64 * 441.0).round() as usize);
    assert_eq!(after.tiling, before.tiling, "geometry kept");
    assert_eq!(after.optics, before.optics);
    h.state_mut().command(ShellCommand::Undo);
    h.step();
    assert_eq!(
        h.state().display().design(),
        &before,
        "one undo restores the start"
    );
    h.state_mut().command(ShellCommand::Redo);
    h.step();
    assert_eq!(h.state().display().design(), &after);
}

#[test]
fn stop_keeps_the_run_so_far() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    h.state_mut().display_mut().show_left_tab(LeftTab::Optimize);
    h.state_mut().display_mut().optimizer_settings().epochs = 2000;
    h.step();
    h.get_by_label("Run optimizer").click();
    step_until(&mut h, "a few epochs", |app| {
        app.display().optimizer().history().len() >= 2
    });
    h.get_by_label("Stop").click();
    step_until(&mut h, "the stopped run", |app| {
        app.display().optimizer().finished().is_some()
    });
    let f = h.state().display().optimizer().finished().unwrap();
    assert!(f.result.stopped_early);
    assert!(f.result.history.len() < 2000);
    assert!(h.query_by_label_contains("(stopped)").is_some());
}
