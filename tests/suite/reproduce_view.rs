//! Help ▸ Reproduce thesis results, driven like a user: the window lists every result with what
//! it checks and costs, a quick run goes in the background and its report opens in the window,
//! Cancel stops a long run, and a run that fails says why in one line.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use egui_kittest::kittest::Queryable;
use udc_studio::core::reproduce::ResultId;

use crate::common::{open_reproduce_window, step_until, studio};

#[test]
fn the_help_menu_lists_the_results_and_a_quick_run_opens_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = studio(dir.path(), false, Duration::from_secs(3600));
    open_reproduce_window(&mut h);
    assert!(h.state_mut().reproduce_mut().open);
    for id in ResultId::ALL {
        assert!(h.query_by_label(id.as_str()).is_some(), "{}", id.as_str());
    }
    h.get_by_label("table5.1").click();
    h.step();
    assert!(h.query_by_label(ResultId::Table5_1.title()).is_some());
    assert!(
        h.query_by_label("udc-studio reproduce table5.1 --out DIR")
            .is_some()
    );
    h.get_by_label_contains("Run quick").click();
    h.step();
    assert!(h.state_mut().reproduce_mut().is_running());
    step_until(&mut h, "the quick run", |app| !app.reproduce().is_running());
    let w = h.state_mut().reproduce_mut();
    let m = w.message().unwrap().clone();
    assert!(
        !m.is_error() && m.text.contains("table5.1 reproduced"),
        "{m:?}"
    );
    let (path, text) = w.report().unwrap();
    // The run wrote under the studio's data folder, and the report is the command's own.
    assert_eq!(path, dir.path().join("reproduce/table5.1/report.md"));
    assert_eq!(text, std::fs::read_to_string(path).unwrap());
    assert!(
        text.contains("Table 5.1") && text.contains("thesis"),
        "{text}"
    );
    // Shown in the window.
    h.step();
    assert!(h.query_all_by_label_contains("additive").next().is_some());
}

#[test]
fn cancel_stops_a_run_and_a_failing_run_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = studio(dir.path(), false, Duration::from_secs(3600));
    open_reproduce_window(&mut h);
    h.get_by_label("fig3.8").click();
    h.step();
    h.get_by_label_contains("Run quick").click();
    h.step();
    assert!(h.state_mut().reproduce_mut().is_running());
    h.step();
    h.get_by_label("Cancel").click();
    step_until(&mut h, "the cancelled run", |app| {
        !app.reproduce().is_running()
    });
    let m = h.state_mut().reproduce_mut().message().unwrap().clone();
    assert!(!m.is_error() && m.text.contains("cancelled"), "{m:?}");
    // A results folder that cannot be made fails the run: one line, no report.
    let out = dir.path().join("reproduce/fig3.8");
    std::fs::remove_dir_all(&out).unwrap();
    std::fs::write(&out, "not a folder").unwrap();
    h.get_by_label_contains("Run quick").click();
    step_until(&mut h, "the failed run", |app| {
        !app.reproduce().is_running()
    });
    let w = h.state_mut().reproduce_mut();
    let m = w.message().unwrap().clone();
    assert!(
        m.is_error() && m.text.contains("reproduce fig3.8 failed"),
        "{m:?}"
    );
    assert_eq!(m.text.lines().count(), 1);
    assert!(w.report().is_none());
}
