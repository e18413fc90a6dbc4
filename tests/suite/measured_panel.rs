//! The Measured PSF panel, driven like a user: a prototype's PSF set dropped on the window
//! opens beside the design on screen, compared, the display fitted to it (with Cancel), and the
//! fit applied as one undoable edit; a real capture restored with the set.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use egui_kittest::kittest::Queryable;

use crate::common::{self, Reach, step_until};
use udc_studio::app::{DisplayAction, LeftTab, ShellCommand};

#[test]
fn a_measured_set_compares_fits_and_applies_as_one_undoable_edit() {
    let dir = tempfile::tempdir().unwrap();
    // The 150-DPI T-OLED built 10 % coarser than drawn (184.8 µm), green, on 96 pixels.
    let set = dir.path().join("prototype.npy");
    common::toled_green_set(&set, 184.8, 96);
    // Rendered (lavapipe) so that the screenshot script can take the panel's picture.
    let mut h = common::studio(dir.path(), true, Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(&mut h, "the T-OLED result", common::display_up_to_date);
    let before = h.state().display().design().clone();
    h.state_mut().display_mut().show_left_tab(LeftTab::Measured);
    h.step();
    // Without native dialogs the button says so instead of hanging.
    h.get_by_label("Open PSF set…").click();
    h.step();
    h.step();
    assert!(
        h.state().display().measured().message().unwrap().is_error(),
        "the disabled dialog is reported"
    );
    // Dropped on the window, as the dialog's message says.
    crate::drop::drop_file(&mut h, set.clone());
    step_until(&mut h, "the set", |app| {
        app.display().measured().loaded().is_some()
    });
    assert!(
        h.query_by_label_contains("96 px at 2 µm, measured")
            .is_some(),
        "the set's line names its size, pitch and source"
    );

    h.get_by_label("Compare with the design").click();
    step_until(&mut h, "the comparison", |app| {
        app.display().measured().compared().is_some()
    });
    let compared = h.state().display().measured().compared().unwrap()[0].clone();
    assert_eq!(compared.design_channel, "G");
    // A display 10 % off is not the design: most of the PSF's energy is in the residual.
    assert!(compared.comparison.residual_energy_share > 0.1);
    assert!(h.query_by_label("Measured against the design").is_some());
    for picture in ["G, measured", "G, design"] {
        assert!(
            h.query_all_by_label(picture).next().is_some(),
            "the two PSFs side by side: {picture}"
        );
    }
    assert!(
        h.query_all_by_label_contains("Residual, G")
            .next()
            .is_some(),
        "and the residual map"
    );

    // A fit cancelled midway leaves nothing fitted and says so.
    h.get_by_label("Fit the display").click();
    h.step();
    assert!(h.state().display().measured().is_busy());
    h.get_by_label("Cancel").click();
    step_until(&mut h, "the cancel", |app| {
        !app.display().measured().is_busy()
    });
    assert!(h.state().display().measured().fitted().is_none());
    assert_eq!(
        h.state().display().measured().message().unwrap().text,
        "cancelled"
    );

    h.get_by_label("Fit the display").click();
    step_until(&mut h, "the fit", |app| {
        app.display().measured().fitted().is_some()
    });
    let fitted = h.state().display().measured().fitted().unwrap();
    let pitch = fitted.pitch_um.value;
    assert!((pitch / 184.8 - 1.0).abs() < 0.01, "{pitch}");
    assert!(h.query_by_label("Fitted display").is_some());
    assert!(
        h.query_by_label_contains(&format!("{pitch:.2} ±"))
            .is_some(),
        "the table shows the fitted pitch with its uncertainty"
    );
    assert_eq!(
        h.state().display().design(),
        &before,
        "nothing changes before Apply"
    );
    crate::screenshots::capture(&mut h, "measured-psf-fit");

    h.get_by_label("Apply the fitted pitch and opening").click();
    h.step();
    h.step();
    let after = h.state().display().design().clone();
    assert!((after.opening.pitch_um - pitch).abs() < 1e-9);
    assert_eq!(after.optics, before.optics, "the optics stay");
    h.state_mut().command(ShellCommand::Undo);
    h.step();
    assert_eq!(
        h.state().display().design(),
        &before,
        "one undo restores the design"
    );
}

#[test]
fn a_real_capture_restores_with_the_loaded_set_as_restore_psf_does() {
    use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
    use udc_studio::core::measured::PsfSet;
    use udc_studio::core::restore::quality::psnr_db_planes;
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    let s = |p: &std::path::Path| p.to_str().unwrap().to_owned();
    // A 128² crop of a test photo captured through the thesis's best layout (photon noise at
    // 10 000 electrons at white: a capture Wiener restores without a denoiser), as the CLI
    // simulates it.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    image::open(root.join("assets/testset/astronaut.png"))
        .unwrap()
        .crop_imm(160, 80, 128, 128)
        .to_rgb8()
        .save(p("scene.png"))
        .unwrap();
    let (ok, _, stderr) = common::run_cli(&[
        "restore",
        "--preset",
        "l2inv-random",
        "--image",
        &s(&p("scene.png")),
        "--light",
        "10000",
        "--out",
        &s(dir.path()),
    ]);
    assert!(ok, "{stderr}");
    let capture = p("light-10000e_captured.exr");
    // The design's PSFs as the prototype's set.
    let design = udc_studio::io::design::presets::load_preset("l2inv-random").unwrap();
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let analysis = analyze_with(&design, &options, &udc_studio::core::Progress::new()).unwrap();
    let set_path = p("prototype.npy");
    udc_studio::io::measured::write_psf_set(&set_path, &PsfSet::from_analysis(&analysis), None)
        .unwrap();

    let mut h = common::studio(dir.path(), true, Duration::from_secs(600));
    h.state_mut().display_mut().show_left_tab(LeftTab::Measured);
    crate::drop::drop_file(&mut h, set_path.clone());
    step_until(&mut h, "the set", |app| {
        app.display().measured().loaded().is_some()
    });
    // Without native dialogs the button says so instead of hanging.
    h.get_by_label("Restore a capture…").click();
    h.step();
    h.step();
    assert!(
        h.state()
            .display()
            .measured()
            .restore
            .message()
            .unwrap()
            .is_error(),
        "the disabled dialog is reported"
    );
    let set = h.state().display().measured().loaded().unwrap().set.clone();
    let ctx = h.ctx.clone();
    h.state_mut()
        .display_mut()
        .measured_mut()
        .restore
        .restore(&capture, set, &ctx);
    step_until(&mut h, "the restoration", |app| {
        app.display().measured().restore.restored().is_some()
    });
    let restored = h.state().display().measured().restore.restored().unwrap();
    assert!(
        h.query_by_label("restored capture").is_some(),
        "both pictures show"
    );
    let truth = udc_studio::io::photo::load_photo::<f64>(&p("scene.png"), None).unwrap();
    let panel_db = psnr_db_planes(&restored.restored, &truth, 1.0).unwrap();
    let captured_db = psnr_db_planes(&restored.captured, &truth, 1.0).unwrap();
    assert!(
        panel_db > captured_db + 3.0,
        "the restoration sharpens: {panel_db:.2} dB against the capture's {captured_db:.2} dB"
    );
    // The command line's `restore --psf` (Wiener, no denoiser) scores the same.
    let (ok, stdout, stderr) = common::run_cli(&[
        "restore",
        "--psf",
        &s(&set_path),
        "--image",
        &s(&capture),
        "--truth",
        &s(&p("scene.png")),
        "--denoise",
        "none",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let cli: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    let cli_db = cli["psnr_db"].as_f64().unwrap();
    assert!(
        (cli_db - panel_db).abs() < 1e-6,
        "the studio {panel_db} dB, the CLI {cli_db} dB"
    );
    crate::screenshots::capture(&mut h, "measured-psf-restore");
}
