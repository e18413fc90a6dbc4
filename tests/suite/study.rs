//! New study… driven like a designer: a study of the T-OLED over three DPIs × periodic/random
//! × 3 seeds built in the dialog (its points and estimate shown before it runs), run, rows
//! seen before it ends, cancelled, resumed to the end, and one point opened as the current
//! design with its parameters. The spec it saves, run by `udc-studio sweep`, gives the same
//! results table.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use egui_kittest::kittest::Queryable;

use crate::common::{self, Reach, run_cli, step_until};
use udc_studio::app::sweep::study_dialog::{AxisKind, AxisRow};
use udc_studio::app::{DisplayAction, WorkspaceId};
use udc_studio::core::design::TilingMode;
use udc_studio::core::phase::Lambda0;
use udc_studio::core::sweep::study::{RestoreSetup, StudyMetric};

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
    // Through accesskit: a pointer click lands where the button was in the last frame, and
    // rows landing meanwhile can move it (the progress bar's text changes width).
    h.get_by_label("Cancel study").click_accesskit();
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
    step_until(
        &mut h,
        "the opened point's result",
        common::display_up_to_date,
    );
    crate::screenshots::capture(&mut h, "study-point-opened-1024x700");

    // Pin another point as A for Compare: analysed at full quality, the current design kept.
    h.state_mut().set_workspace(WorkspaceId::Sweep);
    h.state_mut().sweep_mut().filter = "dpi=100 tiling=repeat".into();
    step_until(&mut h, "the 100-DPI rows", |app| app.sweep().is_idle());
    h.get_all_by_label("Pin A").next().unwrap().click();
    step_until(&mut h, "the point pinned as A", |app| {
        app.display().pinned().is_some()
    });
    let pinned = h.state().display().pinned().unwrap().design.clone();
    assert!((pinned.opening.pitch_um - 254.0).abs() < 1e-9);
    assert_eq!(pinned.tiling.mode, TilingMode::Repeat);
    assert_eq!(
        h.state().display().design(),
        &design,
        "B is still the opened point"
    );

    // The saved spec, run by the command line, gives the same table.
    cli_reruns_the_same_table(&folder, dir.path());
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
    assert_eq!(
        *d.subject(),
        udc_studio::core::sweep::study::StudySubject::Display(Box::new(
            h.state().display().design().clone()
        ))
    );
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

type Studio = egui_kittest::Harness<'static, udc_studio::app::StudioApp>;

/// The studio on the default design, its result on screen, with New study… open for it.
fn studio_with_the_dialog(dir: &std::path::Path) -> Studio {
    let mut h = common::studio_small(dir);
    step_until(&mut h, "the first result", common::display_up_to_date);
    h.state_mut().act(DisplayAction::NewStudy(None));
    h.run_steps(3);
    h
}

/// Presses Run and waits for the study's complete table.
fn run_to_the_end(h: &mut Studio, what: &str) -> udc_studio::app::sweep::table::SweepTable {
    h.get_by_label("Run").click();
    step_until(h, what, |app| {
        !app.sweep().is_studying()
            && app.sweep().is_idle()
            && app.sweep().table().is_some_and(|t| t.manifest.complete)
    });
    h.state().sweep().table().unwrap().as_ref().clone()
}

/// The number in `column` of the row whose parameters read `values` (name, text).
fn cell(
    t: &udc_studio::app::sweep::table::SweepTable,
    values: &[(&str, &str)],
    column: &str,
) -> f64 {
    let row = t
        .rows
        .iter()
        .find(|r| {
            values
                .iter()
                .all(|(name, text)| t.text(r, t.column(name).unwrap()) == *text)
        })
        .unwrap();
    t.number(row, t.column(column).unwrap())
}

/// Runs the study's saved spec with `udc-studio sweep` and compares the tables.
fn cli_reruns_the_same_table(folder: &std::path::Path, scratch: &std::path::Path) {
    let again = scratch.join("cli");
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

/// A study from the Phase workspace: fold × λ0 plan of the thesis's 42 µm masks, run on the
/// sweep runner (`phase psf` points), and a point opened back in the Phase workspace as one
/// undo step.
#[test]
fn a_phase_mask_study_runs_its_fold_and_plans_and_opens_a_point_in_the_phase_workspace() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio_small(dir.path());
    h.state_mut().set_workspace(WorkspaceId::Phase);
    step_until(&mut h, "the phase PSFs", |app| app.phase().is_up_to_date());
    let before = h.state().phase().design().clone();
    h.get_by_label("Study").click();
    h.run_steps(2);
    h.get_by_label("New study…").click();
    h.run_steps(4);
    assert_eq!(h.state().workspace(), WorkspaceId::Sweep);
    {
        let d = &mut h.state_mut().sweep_mut().study_dialog;
        assert!(d.is_open());
        assert_eq!(
            d.axes.iter().map(|a| a.kind).collect::<Vec<_>>(),
            [AxisKind::Fold, AxisKind::Lambda0]
        );
        d.axes[0].text = "1, 5".into();
        d.axes[1].text = "fixed:530, uniform".into();
        let e = d.estimate().unwrap().expect("the PSFs' time scales it");
        assert_eq!(e.points, 4);
        assert!(e.at_least, "the uniform plan's relay is not modelled");
    }
    h.run_steps(2);
    assert!(h.query_by_label_contains("4 points, at least").is_some());
    let t = run_to_the_end(&mut h, "the phase study, complete");
    assert_eq!((t.rows.len(), t.manifest.failed), (4, 0));
    // Folding for 530 nm gives green the invertibility the uniform plan spreads out.
    let inv = |fold: &str, plan: &str| {
        cell(
            &t,
            &[("fold", fold), ("lambda0", plan)],
            "channels.G.invertibility",
        )
    };
    assert!(inv("1", "fixed:530") > inv("1", "uniform"));
    let plot = &h.state().sweep().plots().unwrap()[0].0;
    assert_eq!(
        (plot.x.as_str(), plot.group.as_deref()),
        ("fold", Some("lambda0"))
    );
    h.state_mut().sweep_mut().filter = "fold=5 lambda0=uniform".into();
    step_until(&mut h, "the one row", |app| {
        app.sweep().is_idle() && app.sweep().shown_rows().is_some_and(|r| r.len() == 1)
    });
    assert!(
        h.query_by_label("Pin A").is_none(),
        "phase masks have no Compare A"
    );
    h.get_by_label("Open").click();
    step_until(&mut h, "the Phase workspace", |app| {
        app.workspace() == WorkspaceId::Phase
    });
    let opened = h.state().phase().design().clone();
    assert_eq!((opened.fold, &opened.lambda0), (5.0, &Lambda0::Uniform));
    h.state_mut().phase_mut().undo();
    assert_eq!(h.state().phase().design(), &before, "one undo step");
    cli_reruns_the_same_table(&t.dir, dir.path());
}

/// Light level × method restores the Restore view's photo at every point: a `restore` study
/// whose PSNR rises with the light, whose folder keeps the photo, and which the CLI reruns.
#[test]
fn a_light_and_method_study_restores_the_photo_at_every_point() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = studio_with_the_dialog(dir.path());
    {
        let d = &mut h.state_mut().sweep_mut().study_dialog;
        let subject = d.subject().clone();
        let setup = RestoreSetup::default();
        d.axes = vec![
            AxisRow::new(AxisKind::SnrDb, &subject, &setup),
            AxisRow::new(AxisKind::Method, &subject, &setup),
        ];
        d.axes[0].text = "24, 40".into();
        for (m, on) in &mut d.metrics {
            *on = matches!(m, StudyMetric::PsnrDb | StudyMetric::Ssim);
        }
        let s = d.study().unwrap();
        assert!(s.needs_photo());
        assert_eq!(s.points(), 4);
    }
    h.run_steps(2);
    assert!(h.query_by_label_contains("4 points").is_some());
    let t = run_to_the_end(&mut h, "the restore study, complete");
    assert_eq!((t.rows.len(), t.manifest.failed), (4, 0));
    assert!(t.dir.join("photo.png").exists());
    let at = |snr: &str, method: &str, metric: &str| {
        cell(&t, &[("snr-db", snr), ("method", method)], metric)
    };
    // More light restores better by either method (Wiener's fixed NSR keeps its PSNR nearly
    // flat; its SSIM still rises); conjugate gradients gain in PSNR too.
    for method in ["wiener", "cg"] {
        let (dim, bright) = (
            at("24", method, "runs.0.ssim"),
            at("40", method, "runs.0.ssim"),
        );
        assert!(bright > dim + 0.05, "{method}: SSIM {dim} → {bright}");
    }
    assert!(at("40", "cg", "runs.0.psnr_db") > at("24", "cg", "runs.0.psnr_db") + 0.5);
    let plot = &h.state().sweep().plots().unwrap()[0].0;
    assert_eq!(
        (plot.x.as_str(), plot.y.as_str(), plot.group.as_deref()),
        ("snr-db", "runs.0.psnr_db", Some("method"))
    );
    cli_reruns_the_same_table(&t.dir, dir.path());
}

/// An opening axis grows and shrinks the drawn slit by whole cells: each point is a design file
/// named by its open fraction, its LTR follows the fraction, and a point opens with its opening.
#[test]
fn an_opening_axis_studies_the_slit_grown_and_shrunk_and_opens_a_variant() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = studio_with_the_dialog(dir.path());
    {
        let d = &mut h.state_mut().sweep_mut().study_dialog;
        let subject = d.subject().clone();
        d.axes = vec![AxisRow::new(
            AxisKind::Opening,
            &subject,
            &RestoreSetup::default(),
        )];
        assert_eq!(d.study().unwrap().points(), 3);
        d.axes[0].text = "0, -9".into();
        assert!(d.study().unwrap_err().contains("nothing"));
        d.axes[0].text = "-1, 0, 1".into();
    }
    h.run_steps(2);
    let t = run_to_the_end(&mut h, "the opening study, complete");
    assert_eq!((t.rows.len(), t.manifest.failed), (3, 0));
    let (f, l) = (t.column("open-fraction").unwrap(), t.column("ltr").unwrap());
    let mut pairs: Vec<(f64, f64)> = t
        .rows
        .iter()
        .map(|r| (t.number(r, f), t.number(r, l)))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(
        pairs.iter().map(|p| p.0).collect::<Vec<_>>(),
        [0.1429, 0.2381, 0.3333]
    );
    // The slit in the round pupil: LTR within 2 % of the open fraction, rising with it.
    for (fraction, ltr) in &pairs {
        assert!((ltr / fraction - 1.0).abs() < 0.02, "{fraction}: LTR {ltr}");
    }
    h.state_mut().sweep_mut().filter = "open-fraction>0.3".into();
    step_until(&mut h, "the widest slit's row", |app| {
        app.sweep().is_idle() && app.sweep().shown_rows().is_some_and(|r| r.len() == 1)
    });
    h.get_by_label("Open").click();
    step_until(&mut h, "the display workspace", |app| {
        app.workspace() == WorkspaceId::Display
    });
    let cells = &h.state().display().design().opening.cells;
    assert!(
        (udc_studio::core::display::opening_ops::open_fraction(cells) - 7.0 / 21.0).abs() < 1e-12
    );
    cli_reruns_the_same_table(&t.dir, dir.path());
}
