//! The Sweep workspace and "Sweep this parameter…", driven like a user: a results folder made
//! by the real CLI opens as a table that sorts and filters, a row's design opens in Display
//! layouts with the hash the sweep recorded, and a 1-D sweep of the T-OLED's pitch grows a
//! finite curve with a gap where the values are invalid.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use egui_kittest::kittest::Queryable;
use udc_studio::app::sweep::table::{Column, Sort};
use udc_studio::app::{DisplayAction, StudioApp, WorkspaceId};
use udc_studio::core::design::TilingMode;
use udc_studio::core::sweep::one_axis::{OneAxisPoint, SweepMetric, SweepParameter, values};
use udc_studio::io::design::hash::design_hash;

use crate::common::Reach;
use common::tiny_sweep;

/// Opens a results folder in the Sweep workspace and waits for its table.
fn open_results(h: &mut egui_kittest::Harness<'_, StudioApp>, out: &std::path::Path) {
    let ctx = h.ctx.clone();
    h.state_mut()
        .sweep_mut()
        .open_folder(out, move || ctx.request_repaint());
    common::step_until(h, "the table", idle);
}

fn idle(app: &StudioApp) -> bool {
    app.sweep().is_idle() && app.sweep().shown_rows().is_some()
}

/// The shown rows' values of column `name`.
fn shown(app: &StudioApp, name: &str) -> Vec<String> {
    let s = app.sweep();
    let t = s.table().unwrap();
    let c = t.column(name).unwrap();
    s.shown_rows()
        .unwrap()
        .iter()
        .map(|i| t.text(&t.rows[*i], c))
        .collect()
}

#[test]
fn a_results_folder_shows_sorts_filters_and_opens_a_rows_design() {
    let dir = tempfile::tempdir().unwrap();
    let out = tiny_sweep(dir.path());
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sweep);
    h.step();
    open_results(&mut h, &out);
    assert_eq!(h.state().sweep().table().unwrap().rows.len(), 8);
    assert_eq!(h.state().sweep().shown_rows().unwrap().len(), 8);
    assert!(h.query_by_label("8 shown / 8 rows").is_some());
    // The spec's default plots: the metric against the tiling, and the Pareto front.
    let plots = h.state().sweep().plots().unwrap();
    assert!(plots.len() >= 2, "{} plots", plots.len());
    assert!(plots.iter().all(|(_, d)| d.is_ok()));

    // Sort by a metric by clicking its header: ascending, then descending.
    h.get_by_label("auc_radial_min_mean").click();
    common::step_until(&mut h, "the sorted view", idle);
    let sort = h.state().sweep().sort;
    assert!(!sort.descending && matches!(sort.column, Column::Metric(_)));
    let nums = |app: &StudioApp| -> Vec<f64> {
        shown(app, "auc_radial_min_mean")
            .iter()
            .map(|s| s.parse().unwrap())
            .collect()
    };
    let up = nums(h.state());
    assert!(up.windows(2).all(|w| w[0] <= w[1]), "{up:?}");
    h.get_by_label("auc_radial_min_mean").click();
    common::step_until(&mut h, "the reversed view", idle);
    let down = nums(h.state());
    assert!(down.windows(2).all(|w| w[0] >= w[1]), "{down:?}");
    assert!(h.state().sweep().sort.descending);

    // Filter: the random-4 rows, then a comparison.
    h.state_mut().sweep_mut().filter = "random-4".into();
    common::step_until(&mut h, "the filtered view", idle);
    assert_eq!(shown(h.state(), "tiling"), vec!["random-4"; 4]);
    assert!(h.query_by_label("4 shown / 8 rows").is_some());
    h.state_mut().sweep_mut().filter = "random-4 seed<2".into();
    common::step_until(&mut h, "the compared view", idle);
    assert_eq!(shown(h.state(), "seed").len(), 2);

    // Open the design of the row with seed 1 (random-4, sorted by point).
    h.state_mut().sweep_mut().filter = "tiling=random-4 seed=1".into();
    h.state_mut().sweep_mut().sort = Sort::default();
    common::step_until(&mut h, "one row", idle);
    let (index, row_hash) = {
        let s = h.state().sweep();
        let rows = s.shown_rows().unwrap();
        assert_eq!(rows.len(), 1);
        let t = s.table().unwrap();
        (rows[0], t.rows[rows[0]].design_hash.clone())
    };
    h.get_by_label("Open").click();
    common::step_until(&mut h, "the display workspace", |app| {
        app.workspace() == WorkspaceId::Display
    });
    let design = h.state().display().design().clone();
    assert_eq!(design.tiling.mode, TilingMode::Random4);
    assert_eq!(design.tiling.seed, 1);
    assert_eq!(design_hash(&design), row_hash, "row {index}'s design");
    assert!(
        h.state().display().document().can_undo(),
        "opening is one undo step"
    );
    let status = h.state().status().unwrap();
    assert!(!status.is_error(), "{}", status.text);
    assert!(status.text.contains("point"), "{}", status.text);
}

#[test]
fn a_folder_that_is_not_a_sweep_keeps_the_table_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let out = tiny_sweep(dir.path());
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sweep);
    open_results(&mut h, &out);
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let ctx = h.ctx.clone();
    h.state_mut()
        .sweep_mut()
        .open_folder(&empty, move || ctx.request_repaint());
    common::step_until(&mut h, "the error", |app| {
        app.sweep().message().is_some_and(|m| m.is_error())
    });
    assert_eq!(h.state().sweep().table().unwrap().rows.len(), 8);
    assert!(
        h.state()
            .sweep()
            .message()
            .unwrap()
            .text
            .contains("sweep.json")
    );
}

#[test]
fn sweep_values_are_linear_and_whole_for_the_seed() {
    assert_eq!(values(84.0, 252.0, 3, false), vec![84.0, 168.0, 252.0]);
    let (from, to, steps) = SweepParameter::PitchUm.default_range(168.0);
    assert_eq!((from, to, steps), (84.0, 252.0, 9));
    let v = values(from, to, steps, false);
    assert_eq!(v.len(), 9);
    assert!(
        (v[4] - 168.0).abs() < 1e-12,
        "the current value in the middle"
    );
    let (from, to, steps) = SweepParameter::Seed.default_range(5.0);
    assert_eq!(
        values(from, to, steps, true),
        (5..=13).map(f64::from).collect::<Vec<_>>()
    );
}

#[test]
fn sweep_this_parameter_grows_a_finite_curve_with_gaps_for_invalid_values() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    h.step();
    let pitch = h.state().display().design().opening.pitch_um;
    h.state_mut()
        .act(DisplayAction::SweepParameter(SweepParameter::PitchUm));
    h.step();
    {
        let w = h.state().display().one_axis_sweep();
        assert!(w.is_open());
        assert_eq!(w.field(), SweepParameter::PitchUm);
        assert_eq!(w.current(), pitch);
        assert_eq!(w.values().len(), 9);
    }
    // Five values at preview quality.
    let w = h.state_mut().display_mut().field_sweep_mut();
    w.from = 0.75 * pitch;
    w.to = 1.25 * pitch;
    w.steps = 5;
    w.metric = SweepMetric::AucMean;
    let ctx = h.ctx.clone();
    h.state_mut().display_mut().field_sweep_mut().run(&ctx);
    h.step();
    // A design change meanwhile does not disturb the run: it works on its copy.
    let mut d = h.state().display().design().clone();
    d.tiling.mode = TilingMode::RandomD4;
    h.state_mut().act(DisplayAction::Edit(Box::new(d)));
    common::step_until(&mut h, "the 1-D sweep", |app| {
        !app.display().one_axis_sweep().is_running()
    });
    let points = h.state().display().one_axis_sweep().points().to_vec();
    assert_eq!(points.len(), 5);
    for (x, p) in &points {
        match p {
            Some(OneAxisPoint::Value(y)) => assert!(y.is_finite() && *y > 0.0, "{x}: {y}"),
            other => panic!("{x}: {other:?}"),
        }
    }
    assert_eq!(points[2].0, pitch);

    // Negative and zero pitches are invalid: gaps, a note, no crash.
    let w = h.state_mut().display_mut().field_sweep_mut();
    w.from = -pitch;
    w.to = pitch;
    w.steps = 3;
    w.run(&ctx);
    common::step_until(&mut h, "the sweep with gaps", |app| {
        let w = app.display().one_axis_sweep();
        !w.is_running() && w.points().iter().all(|(_, p)| p.is_some())
    });
    let points = h.state().display().one_axis_sweep().points().to_vec();
    assert!(matches!(points[0].1, Some(OneAxisPoint::Invalid(_))));
    assert!(matches!(points[1].1, Some(OneAxisPoint::Invalid(_))));
    assert!(matches!(points[2].1, Some(OneAxisPoint::Value(y)) if y.is_finite()));
    let note = h
        .state()
        .display()
        .one_axis_sweep()
        .message()
        .unwrap()
        .text
        .clone();
    assert!(note.contains("2 invalid"), "{note}");

    // Escape closes the window.
    h.key_press(egui::Key::Escape);
    h.step();
    assert!(!h.state().display().one_axis_sweep().is_open());
}

#[test]
fn the_context_menu_of_a_number_field_opens_the_sweep_window() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut()
        .display_mut()
        .show_left_tab(udc_studio::app::LeftTab::Tiling);
    h.step();
    // Right-click the number field (labelled by its label) with the pointer.
    let at = h.get_by_label("Wiring gap").rect().center();
    common::right_click(&mut h, at);
    h.get_by_label("Sweep this parameter…").click();
    h.step();
    h.step();
    let w = h.state().display().one_axis_sweep();
    assert!(w.is_open());
    assert_eq!(w.field(), SweepParameter::WiringGapUm);
    for _ in 0..4 {
        h.step();
    }
    // The window draws its controls (a window is invisible in its first frame).
    assert!(h.query_by_label("Run").is_some());
    assert!(
        h.query_by_label("Full quality (slower; preview otherwise)")
            .is_some()
    );
}

/// A file as the window system hands it over.
#[derive(Debug)]
struct Dropped(std::path::PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &std::path::Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

#[test]
fn a_dropped_results_csv_opens_in_the_sweep_workspace_from_anywhere() {
    let dir = tempfile::tempdir().unwrap();
    let out = tiny_sweep(dir.path());
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.step();
    assert_eq!(h.state().workspace(), WorkspaceId::Display);
    // Not the display's opening nor the phase workspace's spectral response: the sweep's table.
    h.input_mut()
        .dropped_files
        .push(std::sync::Arc::new(Dropped(out.join("results.csv"))));
    h.step();
    assert_eq!(h.state().workspace(), WorkspaceId::Sweep);
    common::step_until(&mut h, "the dropped table", idle);
    assert_eq!(h.state().sweep().table().unwrap().rows.len(), 8);
}

#[test]
fn a_sensor_sweeps_row_says_open_design_is_for_display_and_phase_designs() {
    let dir = tempfile::tempdir().unwrap();
    let out = tiny_sweep(dir.path());
    // The same table under a sensor job's manifest: its rows have no design to open.
    let path = out.join("sweep.json");
    let mut m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    m["spec"]["job"] = "sensor".into();
    std::fs::write(&path, m.to_string()).unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sweep);
    open_results(&mut h, &out);
    h.get_all_by_label("Open").next().unwrap().click();
    common::step_until(&mut h, "the notice", |app| {
        app.sweep().message().is_some_and(|m| m.is_error())
    });
    let text = h.state().sweep().message().unwrap().text.clone();
    assert!(
        text.contains("`sensor` sweep") && text.contains("display and phase-mask designs"),
        "{text}"
    );
    assert_eq!(h.state().workspace(), WorkspaceId::Sweep);
}

/// Open rebuilds a row's design as its point computed it, linked values included: a label axis
/// (`dpi`) whose `with` list sets the pitch opens the row's pitch, not the preset's, and its
/// hash is the row's (a row's CSV carries the label, not the linked values).
#[test]
fn open_rebuilds_a_rows_design_with_the_values_a_label_axis_links() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("dpi.toml");
    std::fs::write(
        &spec,
        "job = \"analyze\"\n[base]\npreset = \"toled-150dpi\"\npreview = true\n\
         [[axis]]\nparam = \"dpi\"\nlabel = true\nvalues = [150, 300]\n\
         with = { pitch-um = [168, 84] }\n",
    )
    .unwrap();
    let out = dir.path().join("dpi-results");
    let (ok, _, stderr) = common::run_cli(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{stderr}");
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sweep);
    h.step();
    open_results(&mut h, &out);
    h.state_mut().sweep_mut().filter = "dpi=300".into();
    common::step_until(&mut h, "one row", idle);
    let row_hash = {
        let s = h.state().sweep();
        let rows = s.shown_rows().unwrap();
        assert_eq!(rows.len(), 1);
        s.table().unwrap().rows[rows[0]].design_hash.clone()
    };
    h.get_by_label("Open").click();
    common::step_until(&mut h, "the display workspace", |app| {
        app.workspace() == WorkspaceId::Display
    });
    let design = h.state().display().design().clone();
    assert_eq!(design.opening.pitch_um, 84.0);
    assert_eq!(design_hash(&design), row_hash);
    let status = h.state().status().unwrap();
    assert!(!status.text.contains("differs"), "{}", status.text);
}
