//! The design-rule check on the thesis's layouts: the widths it reports are the layouts' own,
//! and the random L2-inverse tiling's corner contacts are found.

use udc_studio::core::mask::drc::{Rules, ViolationKind, check};
use udc_studio::io::design::presets::load_preset;

#[test]
fn the_toled_slit_is_40_um_wide_with_128_um_of_chrome_between() {
    let d = load_preset("toled-150dpi").unwrap();
    let r = check(&d, &Rules::default());
    // 5 open cells of 8 µm, 16 closed (two runs of 8 joined across the tile edge).
    assert_eq!(r.min_feature_um, Some(40.0));
    assert_eq!(r.min_gap_um, Some(128.0));
    assert_eq!(r.corner_contacts, 0);
    assert!(r.is_clean());
}

#[test]
fn the_random_l2inv_layout_has_corner_contacts_and_one_cell_features() {
    let d = load_preset("l2inv-random").unwrap();
    let r = check(&d, &Rules::default());
    assert!(r.corner_contacts > 0, "{r:?}");
    assert!(r.counts[ViolationKind::CornerContact as usize] > 0);
    // Its smallest features and gaps are single 8-µm cells: fine for a 2-µm process...
    assert_eq!(r.min_feature_um, Some(8.0));
    assert_eq!(r.min_gap_um, Some(8.0));
    // ...and flagged by a 10-µm one, with places in the tile frame.
    let coarse = Rules {
        min_feature_um: 10.0,
        min_gap_um: 10.0,
        ..Rules::default()
    };
    let r = check(&d, &coarse);
    let v = r
        .violations
        .iter()
        .find(|v| v.kind == ViolationKind::MinFeature)
        .unwrap();
    assert_eq!(v.value, 8.0);
    assert!((0.0..=2.0 * 168.0).contains(&v.at_um[0]) && (0.0..=2.0 * 168.0).contains(&v.at_um[1]));
    // The contacts are inside the optimized opening itself: an 8-µm wiring gap between the
    // tiles does not remove them (it only removes contacts across tile edges).
    let mut wired = d.clone();
    wired.tiling.wiring_gap_um = 8.0;
    let with_gap = check(&wired, &Rules::default()).corner_contacts;
    assert!(with_gap > 0 && with_gap <= check(&d, &Rules::default()).corner_contacts);
}

#[test]
fn the_drc_command_reports_json_and_fails_strictly() {
    use crate::common::run_cli;
    let (ok, stdout, stderr) = run_cli(&["drc", "--preset", "l2inv-random", "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(v["clean"], false);
    assert_eq!(v["report"]["min_feature_um"], 8.0);
    assert_eq!(v["report"]["corner_contacts"], 8);
    // --strict turns violations into an error, a clean design passes.
    let (ok, _, stderr) = run_cli(&["drc", "--preset", "l2inv-random", "--strict"]);
    assert!(!ok && stderr.contains("design-rule violations"), "{stderr}");
    let (ok, _, stderr) = run_cli(&["drc", "--preset", "toled-150dpi", "--strict"]);
    assert!(ok, "{stderr}");
    // A rules file; flags override it; bad values are one line naming the rule.
    let dir = tempfile::tempdir().unwrap();
    let rules = dir.path().join("fab.json");
    std::fs::write(&rules, r#"{"min_feature_um": 50, "min_gap_um": 1, "no_corner_contact": true, "min_angle_deg": 90}"#).unwrap();
    let r = rules.to_str().unwrap();
    let (ok, _, _) = run_cli(&["drc", "--preset", "toled-150dpi", "--rules", r, "--strict"]);
    assert!(!ok, "a 40-µm slit under a 50-µm rule");
    let (ok, _, stderr) = run_cli(&[
        "drc",
        "--preset",
        "toled-150dpi",
        "--rules",
        r,
        "--min-feature-um",
        "10",
        "--strict",
    ]);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = run_cli(&["drc", "--preset", "toled-150dpi", "--min-gap-um", "nan"]);
    assert!(
        !ok && stderr.contains("min_gap_um") && stderr.trim().lines().count() == 1,
        "{stderr}"
    );
}

#[test]
fn the_phase_plate_reports_its_narrowest_ring() {
    use crate::common::run_cli;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plate.gds");
    let (ok, stdout, stderr) = run_cli(&[
        "phase",
        "export",
        "--format",
        "gds",
        "--height-step-um",
        "0.2",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    let narrowest = v["narrowest_feature_um"].as_f64().unwrap();
    // The rings thin out towards each lenslet's edge: the thesis plate's narrowest full step is
    // about 210 nm, under the default half-micron rule. Its part-level slivers, narrower still,
    // are joined to the next fold under that rule, and the summary says how many.
    assert!(narrowest > 0.15 && narrowest < 0.5, "{narrowest}");
    assert!(v["ring_merge"]["merged_rings"].as_u64().unwrap() > 0, "{v}");
    // The same feature the design-rule check measures.
    let drc_min = v["drc"]["report"]["min_feature_um"].as_f64().unwrap();
    assert!(
        (narrowest - drc_min).abs() <= 1e-5 * drc_min,
        "{narrowest} vs {drc_min}"
    );
    // In core: the narrowest of the plate's features (pieces joined where the height runs on
    // across a lenslet edge), positive, and where the rings are thinnest, near a lenslet's edge
    // (away from its centre by more than a third of the pitch).
    let mut d = udc_studio::core::phase::PhaseDesign::thesis(168.0, 1.0);
    d.height_step_um = Some(0.2);
    let lenslets = udc_studio::core::phase::geometry::Lenslets::new(&d).unwrap();
    let pieces = udc_studio::core::phase::plate::pieces(&d, &lenslets, 0.0).unwrap();
    let features = udc_studio::core::phase::plate::features(&d, &pieces);
    assert!(
        features.len() < pieces.len(),
        "some pieces run on across an edge"
    );
    let min = features
        .iter()
        .map(|f| f.width_um())
        .fold(f64::INFINITY, f64::min);
    let n = udc_studio::core::phase::plate::narrowest_feature(&d, &lenslets, 0.0)
        .unwrap()
        .unwrap();
    assert_eq!(n.width_um(), min);
    let (l, _) = lenslets.locate(n.x0_um + 0.5 * n.width_um()).unwrap();
    let from_centre = (n.x0_um - lenslets.centre_um(l)).abs();
    assert!(
        from_centre > d.pitch_um / 3.0,
        "{from_centre} µm from its lenslet's centre"
    );
}

/// The 600-DPI plate folded at `fold` waves of λ0 = 600 nm, floored to `step_um`.
fn plate_600(fold: f64, step_um: f64) -> udc_studio::core::phase::PhaseDesign {
    let mut d = udc_studio::core::phase::PhaseDesign::thesis(42.0, fold);
    d.lambda0 = udc_studio::core::phase::Lambda0::Fixed { nm: 600.0 };
    d.height_step_um = Some(step_um);
    d
}

#[test]
fn quantised_plates_leave_no_part_level_ring_under_the_rule_and_say_what_joining_them_costs() {
    use udc_studio::core::phase::drc::check_plate;
    use udc_studio::core::phase::geometry::Lenslets;
    use udc_studio::core::phase::plate::{narrowest_feature, ring_merge};
    let rule = Rules {
        phase_min_feature_um: 0.1,
        ..Rules::default()
    };
    for fold in [1.0, 2.0, 5.0, 10.0] {
        let d = plate_600(fold, 0.2);
        let lenslets = Lenslets::new(&d).unwrap();
        let report = check_plate(&d, &rule).unwrap();
        assert!(
            report.is_clean(),
            "T = {fold}: {:?}",
            report.violations.first()
        );
        let merge = ring_merge(&d, &lenslets, 0.1).unwrap();
        // Joining slivers costs next to nothing against the step's own quantisation error.
        let cost = merge.fabricated_rms_phase_error_rad - merge.model_rms_phase_error_rad;
        assert!(
            cost.abs() < 0.01 * merge.model_rms_phase_error_rad,
            "T = {fold}: {merge:?}"
        );
        let model = narrowest_feature(&d, &lenslets, 0.0).unwrap().unwrap();
        if merge.merged_rings > 0 {
            // Without joining, a part-level sliver breaks the rule.
            assert!(model.width_um() < 0.1, "T = {fold}: {model:?}");
        } else {
            assert!(model.width_um() >= 0.1, "T = {fold}: {model:?}");
        }
    }
    // T = 5 at 0.2 µm: one sliver (34 nm at r ≈ 15.84 µm) each side of every lenslet's centre.
    let d = plate_600(5.0, 0.2);
    let lenslets = Lenslets::new(&d).unwrap();
    let merge = ring_merge(&d, &lenslets, 0.1).unwrap();
    assert_eq!(merge.merged_rings, 2 * lenslets.count());
    // A floored step's error is uniform over a step: RMS 2π·(waves per step)/√3 at most.
    let waves_per_step = 5.0 * 0.2 / lenslets.fold_height_um[0];
    let bound = std::f64::consts::TAU * waves_per_step / 3f64.sqrt();
    assert!(
        merge.model_rms_phase_error_rad <= bound * 1.02,
        "{merge:?} vs {bound}"
    );
    assert!(
        merge.model_rms_phase_error_rad >= bound * 0.5,
        "{merge:?} vs {bound}"
    );
    // Full-step rings are the lens's slope: never joined, so a rule above them is refused.
    let fine = plate_600(1.0, 0.1);
    let steep = Rules {
        phase_min_feature_um: 0.12,
        ..Rules::default()
    };
    let report = check_plate(&fine, &steep).unwrap();
    assert!(!report.is_clean());
    // The same rule through the export: its summary names the joined rings and their cost.
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_udc-studio"))
        .args(["phase", "export", "--format", "gds", "--fold", "5"])
        .args([
            "--height-step-um",
            "0.2",
            "--lambda0",
            "fixed:600",
            "--strict",
        ])
        .args(["--phase-min-feature-um", "0.1", "--json", "--out"])
        .arg(dir.path().join("plate.gds"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        v["ring_merge"]["merged_rings"].as_u64(),
        Some(merge.merged_rings as u64)
    );
    assert!(v["narrowest_feature_um"].as_f64().unwrap() >= 0.1, "{v}");
}
