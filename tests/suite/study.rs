//! New study… driven like a designer: a study of the T-OLED over three DPIs × periodic/random
//! × 3 seeds built in the dialog (its points and estimate shown before it runs), run, rows
//! seen before it ends, cancelled, resumed to the end, and one point opened as the current
//! design with its parameters. The spec it saves, run by `udc-studio sweep`, gives the same
//! results table.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use egui_kittest::kittest::Queryable;

use crate::common::{self, Reach, run_cli, step_until};
use udc_studio::app::{DisplayAction, WorkspaceId};
use udc_studio::core::design::TilingMode;

/// The lines of a results table, sorted by point (rows land in the order points finish).
fn sorted_rows(csv: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let header = lines.remove(0);
    lines.sort_by_key(|l| l.split(',').next().unwrap().parse::<u64>().unwrap());
    lines.insert(0, header);
    lines
}

#[test]
fn a_study_of_the_toled_fills_live_cancels_resumes_and_opens_a_point() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio_small(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(&mut h, "the T-OLED result", common::display_up_to_date);
    h.state_mut().act(DisplayAction::NewStudy(None));
    h.run_steps(3);
    assert_eq!(h.state().workspace(), WorkspaceId::Sweep);
    {
        let d = &mut h.state_mut().sweep_mut().study_dialog;
        assert!(d.is_open());
        // DPI × tiling (repeat, random-d4) × 3 seeds: the dialog's start, three DPIs typed.
        d.axes[0].text = "100, 150, 200".into();
        let e = d
            .estimate()
            .unwrap()
            .expect("the design's time scales the estimate");
        assert_eq!(e.points, 18);
        assert!(e.seconds > 0.0 && e.bytes_per_point > 0);
    }
    h.run_steps(3);
    assert!(h.query_by_label_contains("18 points, about").is_some());
    // A bad value is refused in the dialog with its reason, and Run waits.
    h.state_mut().sweep_mut().study_dialog.axes[0].text = "100, -5".into();
    h.run_steps(2);
    assert!(h.query_by_label_contains("dots per inch").is_some());
    h.state_mut().sweep_mut().study_dialog.axes[0].text = "100, 150, 200".into();
    h.run_steps(2);
    crate::screenshots::capture(&mut h, "study-dialog-1024x700");
    // The run holds after 5 points until cancelled: certain to be stopped midway.
    h.state_mut().sweep_mut().hold_after_points = Some(5);
    h.run_steps(2);
    h.get_by_label("Run").click();
    step_until(&mut h, "rows before the end", |app| {
        app.sweep().is_studying() && app.sweep().table().is_some_and(|t| !t.rows.is_empty())
    });
    assert!(
        h.state().sweep().is_studying(),
        "rows arrived while it runs"
    );
    // Held after 5 new points (and the ones in flight then): the table and plots show them
    // while the study still runs.
    step_until(&mut h, "the held rows, shown", |app| {
        app.sweep().is_idle() && app.sweep().table().is_some_and(|t| t.rows.len() >= 5)
    });
    assert!(h.state().sweep().is_studying());
    crate::screenshots::capture(&mut h, "study-running-1024x700");
    h.get_by_label("Cancel study").click();
    step_until(&mut h, "the cancelled study, read", |app| {
        !app.sweep().is_studying() && app.sweep().is_idle()
    });
    let t = h.state().sweep().table().unwrap().clone();
    assert!(t.rows.len() < 18, "cancelled midway: {} rows", t.rows.len());
    assert!(!t.manifest.complete);
    let folder = t.dir.clone();

    h.state_mut().sweep_mut().hold_after_points = None;
    h.run_steps(2);
    h.get_by_label("Resume study").click();
    step_until(&mut h, "the resumed study, complete", |app| {
        !app.sweep().is_studying()
            && app.sweep().is_idle()
            && app.sweep().table().is_some_and(|t| t.manifest.complete)
    });
    let t = h.state().sweep().table().unwrap().clone();
    assert_eq!(t.rows.len(), 18);
    assert_eq!(t.manifest.failed, 0);
    assert!(
        h.state()
            .sweep()
            .message()
            .unwrap()
            .text
            .contains("complete: 18 points"),
        "{:?}",
        h.state().sweep().message()
    );
    crate::screenshots::capture(&mut h, "study-complete-1024x700");

    // Open the point at 200 DPI, random-d4, the second seed.
    h.state_mut().sweep_mut().filter = "dpi=200 tiling=random-d4".into();
    step_until(&mut h, "the filtered rows", |app| app.sweep().is_idle());
    let seed = {
        let s = h.state().sweep();
        let rows = s.shown_rows().unwrap();
        assert_eq!(rows.len(), 3, "three seeds");
        let col = t.column("seed").unwrap();
        t.number(&t.rows[rows[1]], col)
    };
    h.get_all_by_label("Open").nth(1).unwrap().click();
    step_until(&mut h, "the display workspace", |app| {
        app.workspace() == WorkspaceId::Display
    });
    let design = h.state().display().design().clone();
    assert!((design.opening.pitch_um - 25_400.0 / 200.0).abs() < 1e-9);
    assert_eq!(design.tiling.mode, TilingMode::RandomD4);
    assert_eq!(design.tiling.seed as f64, seed);
    crate::screenshots::capture(&mut h, "study-point-opened-1024x700");

    // The saved spec, run by the command line, gives the same table.
    let again = dir.path().join("cli");
    let spec = folder.join("spec.toml");
    let (ok, _, stderr) = run_cli(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(
        sorted_rows(&again.join("results.csv")),
        sorted_rows(&folder.join("results.csv"))
    );
}

/// The empty Sweep workspace teaches: a study from the current design, the shipped example.
#[test]
fn the_empty_sweep_workspace_offers_a_study_and_the_examples() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio_small(dir.path());
    step_until(&mut h, "the first result", common::display_up_to_date);
    h.state_mut().set_workspace(WorkspaceId::Sweep);
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("Run the example: T-OLED: DPI × tiling × seed")
            .is_some()
    );
    h.get_by_label("New study from the current design…").click();
    h.run_steps(4);
    let d = &h.state().sweep().study_dialog;
    assert!(d.is_open(), "the Display workspace's design came over");
    assert_eq!(d.design(), h.state().display().design());
    // Run on a cluster…: the study's folder with the Slurm scripts for the same spec.
    h.get_by_label("Run on a cluster…").click();
    h.run_steps(2);
    let m = h.state().sweep().message().unwrap().text.clone();
    let submit = m
        .split("bash ")
        .nth(1)
        .and_then(|rest| rest.split(" (").next())
        .unwrap_or_else(|| panic!("{m}"));
    let slurm = std::path::Path::new(submit).parent().unwrap();
    assert!(slurm.join("array.sbatch").exists() && slurm.join("merge.sbatch").exists());
    let spec = slurm.parent().unwrap().join("spec.toml");
    let spec = udc_studio::io::sweep::load_spec(&spec).unwrap();
    assert_eq!(spec.axes.len(), 3, "DPI × tiling × seeds");
    assert!(!h.state().sweep().is_studying(), "nothing runs here");
}
