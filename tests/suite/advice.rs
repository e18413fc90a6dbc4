//! Sampling warnings with advice that resolves them: every fix is applied and the fixed design
//! analysed again; no preset opens with a warning; the CLI prints the advice; the studio's
//! Apply button sets it as one undo step.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeSet;
use std::time::Duration;

use egui_kittest::kittest::Queryable;
use udc_studio::app::{DisplayAction, LeftTab, StudioApp};
use udc_studio::core::analysis::advice::advise;
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::design::{Optics, OpticsRecipe};
use udc_studio::core::psf::warning::{Severity, WarningKind};
use udc_studio::core::{Analysis, Design, Progress};
use udc_studio::io::design::presets::{self, load_preset};

use crate::common::Reach;
use crate::common::{self, run_cli, step_until};

fn analysis(design: &Design, quality: Quality) -> Analysis {
    let options = AnalyzeOptions {
        quality,
        expected_psf: false,
    };
    analyze_with(design, &options, &Progress::new()).expect("analysis")
}

fn kinds(a: &Analysis) -> BTreeSet<WarningKind> {
    a.warnings.iter().map(|w| w.kind).collect()
}

/// Custom designs that warn: a window past the grid, an odd δ2, a phone camera behind the
/// P-OLED, cells finer than δ1.
fn custom_designs() -> Vec<(String, Design)> {
    let toled = load_preset("toled-150dpi").unwrap();
    let custom = |name: &str, base: &Design, edit: &dyn Fn(&mut Optics)| {
        let mut d = base.clone();
        d.optics.recipe = OpticsRecipe::Custom;
        edit(&mut d.optics);
        (name.to_string(), d)
    };
    let poled = load_preset("poled-336um").unwrap();
    let toled300 = load_preset("toled-300dpi").unwrap();
    vec![
        custom("window 400 px", &toled, &|o| o.window_px = 400),
        custom("δ2 0.6 µm", &toled, &|o| o.fine_sample_um = 0.6),
        custom("phone optics", &poled, &|o| *o = Optics::phone()),
        custom("8-µm δ1 over 4-µm cells", &toled300, &|o| {
            o.pupil_sample_um = 8.0;
        }),
    ]
}

#[test]
fn every_fix_resolves_its_warning_and_raises_no_new_one() {
    let mut designs: Vec<(String, Design)> = ["toled-150dpi", "poled-336um", "l2inv-random"]
        .iter()
        .map(|n| (n.to_string(), load_preset(n).unwrap()))
        .collect();
    designs.extend(custom_designs());
    let mut fixed_kinds = BTreeSet::new();
    for (name, d) in &designs {
        let mut a = analysis(d, Quality::Preview);
        assert!(!a.warnings.is_empty(), "{name} warns");
        advise(d, &mut a.warnings, &Progress::new()).unwrap();
        let before = kinds(&a);
        for w in &a.warnings {
            let fix = w
                .fix
                .as_ref()
                .unwrap_or_else(|| panic!("{name}: no fix for {}", w.message));
            let fixed = Design {
                optics: fix.optics.clone(),
                ..d.clone()
            };
            let after = kinds(&analysis(&fixed, Quality::Preview));
            assert!(
                !after.contains(&w.kind),
                "{name}: {} does not resolve {:?}",
                fix.summary(),
                w.kind
            );
            assert!(
                after.is_subset(&before),
                "{name}: {} raises {:?} (before: {before:?})",
                fix.summary(),
                after.difference(&before).collect::<Vec<_>>()
            );
            fixed_kinds.insert(w.kind);
        }
    }
    // Every kind the designs raise was fixed at least once.
    assert_eq!(
        fixed_kinds,
        WarningKind::ALL.into_iter().collect::<BTreeSet<_>>()
    );
}

#[test]
fn the_default_presets_fix_leaves_a_full_quality_analysis_without_warnings() {
    let d = load_preset(presets::DEFAULT_PRESET).unwrap();
    let mut a = analysis(&d, Quality::Full);
    advise(&d, &mut a.warnings, &Progress::new()).unwrap();
    let [w] = a.warnings.as_slice() else {
        panic!("one note: {:?}", a.warnings)
    };
    assert_eq!(
        (w.kind, w.severity),
        (WarningKind::LightOutsideWindow, Severity::Note)
    );
    let fix = w.fix.as_ref().expect("a fix");
    assert_eq!(fix.summary(), "δ1 8 → 4 µm, window 294 → 588 px");
    let fixed = Design {
        optics: fix.optics.clone(),
        ..d
    };
    let after = analysis(&fixed, Quality::Full);
    assert!(after.warnings.is_empty(), "{:?}", after.warnings);
}

#[test]
fn no_preset_opens_with_a_warning() {
    for (name, _, _) in presets::list() {
        let d = load_preset(name).unwrap();
        // The studio shows the preview first, then the full result with its advice.
        let preview = analysis(&d, Quality::Preview);
        let mut full = analysis(&d, Quality::Full);
        advise(&d, &mut full.warnings, &Progress::new()).unwrap();
        assert_eq!(kinds(&preview), kinds(&full), "{name}");
        for w in preview.warnings.iter().chain(&full.warnings) {
            assert_eq!(w.severity, Severity::Note, "{name}: {}", w.message);
            // Notes belong to the thesis's crop only.
            assert!(
                w.message.starts_with("Thesis recipe: ")
                    || w.message.starts_with("Thesis window: "),
                "{name}: {}",
                w.message
            );
        }
        // Each says what resolves it, or why nothing within the limits does.
        for w in &full.warnings {
            assert!(
                w.fix.is_some() || w.message.contains("no change of"),
                "{name}: {}",
                w.message
            );
        }
    }
}

#[test]
fn the_cli_prints_each_warning_with_its_advice() {
    // Without --advice a note is printed without a checked fix (that check is a further
    // analysis); warnings always get theirs.
    let (ok, stdout, stderr) = run_cli(&["analyze", "--preset", "toled-150dpi", "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(v["advice"][0]["severity"], "note");
    assert!(v["advice"][0]["fix"].is_null(), "{stdout}");
    let (ok, stdout, stderr) = run_cli(&["analyze", "--preset", "toled-150dpi", "--advice"]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains(
            "note: Thesis recipe: 2.1 % of channel R's light falls outside the 294-pixel window"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains("  advice: set optics.pupil_sample_um = 4, optics.window_px = 588"),
        "{stdout}"
    );
    let (ok, stdout, stderr) =
        run_cli(&["analyze", "--preset", "toled-150dpi", "--advice", "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0].as_str().unwrap().starts_with("Thesis recipe: "));
    let advice = &v["advice"][0];
    assert_eq!(advice["kind"], "light-outside-window");
    assert_eq!(advice["severity"], "note");
    assert_eq!(advice["message"], warnings[0]);
    assert_eq!(
        advice["fix"]["set"],
        serde_json::json!({"optics.pupil_sample_um": 4.0, "optics.window_px": 588})
    );
}

#[test]
fn apply_sets_the_advised_optics_and_undo_restores_them() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_millis(200));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(&mut h, "the result and its advice", |a: &StudioApp| {
        a.display().is_up_to_date()
    });
    // On the Optics tab (the opening editor has an Apply button of its own).
    h.state_mut().display_mut().show_left_tab(LeftTab::Optics);
    h.step();
    assert!(h.query_by_value("294 px").is_some(), "the window field");
    assert!(h.query_by_value("8.00 µm").is_some(), "the δ1 field");
    let before = h.state().display().design().optics.clone();
    let fix = h.state().display().shown().unwrap().analysis.warnings[0]
        .fix
        .clone()
        .expect("the note's fix");
    // The note in the studio's words, its tooltip naming the controls and values.
    assert!(
        h.query_by_label_contains("falls outside the 294-pixel window, as in the thesis's numbers")
            .is_some()
    );
    h.get_by_label("Apply").hover();
    h.run();
    assert!(
        h.query_by_label_contains(
            "Sets Optics > Pupil sampling δ1: 8 to 4 µm, Optics > Window: 294 to 588 px"
        )
        .is_some(),
        "the tooltip says what changes"
    );
    h.get_by_label("Apply").click();
    h.step();
    assert_eq!(h.state().display().design().optics, fix.optics);
    assert_eq!(h.state().display().design().optics.window_px, 588);
    assert_eq!(
        h.state().display().design().optics.recipe,
        OpticsRecipe::Custom
    );
    // The Optics panel shows the new values.
    h.step();
    assert!(h.query_by_value("588 px").is_some(), "the window field");
    assert!(h.query_by_value("4.00 µm").is_some(), "the δ1 field");
    // The fixed design's result has nothing to say, so no Apply button is left.
    step_until(
        &mut h,
        "the fixed result",
        crate::common::display_up_to_date,
    );
    assert!(
        h.state()
            .display()
            .shown()
            .unwrap()
            .analysis
            .warnings
            .is_empty()
    );
    assert!(h.query_by_label("Apply").is_none());
    // One undo step restores the thesis recipe.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.step();
    assert_eq!(h.state().display().design().optics, before);
    h.step();
    assert!(h.query_by_value("294 px").is_some());
}
