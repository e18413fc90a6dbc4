//! The phase workspace's Capture & restore view, driven like a user: the built-in photo through
//! this design and the bare T-OLED with the core's numbers, a light change that reuses the
//! operators, a bad photo that keeps the current one, Cancel, and the setup comparison with its
//! CSV. A 64-pixel sensor at preview sampling keeps each run well under a second.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use crate::common::step_until;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ndarray::Array2;
use udc_studio::app::phase::{ChannelSet, PhaseView, Quality};
use udc_studio::app::{StudioApp, WorkspaceId};
use udc_studio::core::Progress;
use udc_studio::core::design::Channel;
use udc_studio::core::phase::imaging::{
    Setup, capture_and_restore, compare_setups, phase_blur, thesis_denoise, unpassed_mse,
};
use udc_studio::core::phase::{PhaseDesign, PhaseOptics, PhaseSampling};
use udc_studio::core::restore::Denoise;
use udc_studio::io::photo::{built_in_photo, fit_max_side};

const PIXELS: usize = 64;

/// The studio on the phase workspace's Capture & restore view, a 64-pixel sensor, peaks.
fn capture_studio(dir: &std::path::Path) -> (Harness<'static, StudioApp>, PhaseDesign) {
    let mut h = common::studio(dir, false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Phase);
    h.state_mut().phase_mut().quality = Quality::Preview;
    let mut d = PhaseDesign::thesis(42.0, 1.0);
    d.camera.pixels = PIXELS;
    h.state_mut().phase_mut().set_design(d.clone());
    common::choose_capture(h.state_mut().phase_mut(), |c| {
        c.channels = ChannelSet::Peaks
    });
    h.step();
    h.get_by_label("Capture & restore").click_accesskit();
    h.step();
    assert_eq!(h.state().phase().view(), PhaseView::Capture);
    (h, d)
}

fn wait_capture(h: &mut Harness<'_, StudioApp>, what: &str) {
    step_until(h, what, |app| app.phase().capture_is_current());
}

fn photo() -> Vec<Array2<f64>> {
    fit_max_side(built_in_photo().unwrap(), PIXELS)
}

#[test]
fn the_built_in_photo_restores_as_the_core_does_and_the_light_reuses_the_operators() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, d) = capture_studio(dir.path());
    wait_capture(&mut h, "the first capture");
    let truth = photo();
    assert_eq!(
        truth[0].ncols(),
        PIXELS,
        "the built-in photo fits the sensor"
    );
    let sampling = PhaseSampling::for_quality(Quality::Preview);
    let peaks = Channel::rgb_peaks();
    let p = Progress::new();
    let bare = Setup::Bare { pitch_um: 42.0 }
        .resolve(&d, &sampling, &[], None, &p)
        .unwrap();
    let expected = |photons: f64| {
        [(d.clone(), PhaseOptics::DoubleMla), bare.clone()].map(|(design, optics)| {
            let blur = phase_blur(&design, &sampling, &peaks, optics, PIXELS, &p).unwrap();
            (
                blur.ltr,
                unpassed_mse(&blur, &truth).unwrap(),
                capture_and_restore(&blur, &truth, photons, 0, thesis_denoise(), &p).unwrap(),
            )
        })
    };
    let check = |h: &Harness<'_, StudioApp>, photons: f64| {
        let rows = h.state().phase().capture_rows();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].optics, PhaseOptics::DoubleMla);
        assert_eq!(rows[1].optics, PhaseOptics::Toled);
        for (row, (ltr, unpassed, run)) in rows.iter().zip(expected(photons)) {
            assert_eq!(row.run.photons, photons);
            assert!(
                (row.unpassed_mse - unpassed).abs() < 1e-15,
                "{}: unpassed {} vs the core's {unpassed}",
                row.label,
                row.unpassed_mse
            );
            assert!(
                (row.ltr - ltr).abs() < 1e-12,
                "{}: LTR {} vs {ltr}",
                row.label,
                row.ltr
            );
            assert!(
                (row.run.psnr_db - run.psnr_db).abs() < 1e-9
                    && (row.run.ssim - run.ssim).abs() < 1e-9,
                "{}: {} dB {} vs the core's {} dB {}",
                row.label,
                row.run.psnr_db,
                row.run.ssim,
                run.psnr_db,
                run.ssim
            );
        }
        // The double MLA passes about twice the bare T-OLED's light (§4.3).
        assert!(
            rows[0].ltr > 1.5 * rows[1].ltr,
            "{} vs {}",
            rows[0].ltr,
            rows[1].ltr
        );
        rows.iter().map(|r| r.run.psnr_db).collect::<Vec<f64>>()
    };
    let bright = check(&h, 1600.0);
    assert_eq!(h.query_all_by_label_contains("restored PSNR").count(), 2);
    // A row names unpassed frequencies exactly when its setup has some (on this 64-pixel
    // sensor the T-OLED's diffraction orders fall off the sensor, so neither has: the
    // 1024-pixel screenshot test sees the T-OLED's).
    let rows = h.state().phase().capture_rows();
    assert_eq!(
        h.query_all_by_label_contains("passes < 1 % of").count(),
        rows.iter().filter(|r| r.unpassed_mse > 0.0).count()
    );
    // Each setup's row shows the capture, the BM3D-denoised capture and the restoration.
    for kind in ["captured", "denoised (BM3D)", "restored"] {
        assert_eq!(
            h.query_all_by_label_contains(&format!(") {kind}")).count(),
            2,
            "a {kind} picture per setup"
        );
    }
    assert_eq!(h.state().phase().capture_operators_built(), 2);
    // A lower light: the same operators, a noisier restoration.
    common::choose_capture(h.state_mut().phase_mut(), |c| c.photons = 250.0);
    wait_capture(&mut h, "the capture at 250 photons");
    let dim = check(&h, 250.0);
    assert_eq!(
        h.state().phase().capture_operators_built(),
        2,
        "the light level reuses the operators"
    );
    for (b, d) in bright.iter().zip(&dim) {
        assert!(
            d < b,
            "PSNR at 250 photons {d} dB must be below 1600's {b} dB"
        );
    }
    // A fold change builds this design's operator again; the bare T-OLED (no plate) is kept.
    h.state_mut().phase_mut().design_mut().fold = 5.0;
    wait_capture(&mut h, "the capture at T = 5");
    assert_eq!(h.state().phase().capture_operators_built(), 3);
}

#[test]
fn a_bad_photo_keeps_the_current_one_and_cancel_stops_a_run() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, _) = capture_studio(dir.path());
    wait_capture(&mut h, "the first capture");
    let name = h.state().phase().capture_photo_name().unwrap().to_string();
    assert!(name.contains("astronaut"), "{name}");
    let bad = dir.path().join("not-a-photo.png");
    std::fs::write(&bad, b"this is text, not a PNG").unwrap();
    let ctx = h.ctx.clone();
    h.state_mut().phase_mut().load_capture_photo(bad, &ctx);
    step_until(&mut h, "the photo reader", |app| {
        app.phase()
            .capture_message()
            .is_some_and(|m| m.text.contains("cannot open the photo"))
    });
    let notice = h.state().phase().capture_message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(is_error && msg.contains("not-a-photo.png"), "{msg}");
    assert_eq!(h.state().phase().capture_photo_name(), Some(name.as_str()));
    assert_eq!(
        h.state().phase().capture_rows().len(),
        2,
        "the pictures stay"
    );
    // A full-quality run over 64 directions × the spectral grid of a λ0 plan (no lenslet
    // period: the whole display) takes long enough to cancel.
    let mut plan = h.state().phase().design().clone();
    plan.lambda0 = udc_studio::core::phase::Lambda0::Uniform;
    h.state_mut().phase_mut().set_design(plan);
    h.state_mut().phase_mut().quality = Quality::Full;
    common::choose_capture(h.state_mut().phase_mut(), |c| {
        c.channels = ChannelSet::Spectral
    });
    h.step();
    h.step();
    assert!(h.state().phase().is_capturing());
    // A quick look through the peak wavelengths first, then the spectral operators: 8 steps.
    let start = std::time::Instant::now();
    while h.query_by_label_contains(" of 8: ").is_none() {
        assert!(
            start.elapsed().as_secs() < 30,
            "no 8-step progress on screen"
        );
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    assert!(h.state().phase().is_capturing());
    h.get_by_label("Cancel").click_accesskit();
    h.step();
    assert!(!h.state().phase().is_capturing());
    let notice = h.state().phase().capture_message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(!is_error && msg.contains("cancelled"), "{msg}");
    for _ in 0..5 {
        h.step();
    }
    assert!(
        !h.state().phase().is_capturing(),
        "a cancelled run does not start again by itself"
    );
    assert_eq!(
        h.state().phase().capture_rows().len(),
        2,
        "the last pictures stay"
    );
}

#[test]
fn the_setup_comparison_matches_the_core_and_saves_as_csv() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, d) = capture_studio(dir.path());
    let setups = h.state().phase().compare_setups().to_vec();
    assert_eq!(setups[0], Setup::Bare { pitch_um: 42.0 });
    assert!(setups.len() >= 16, "the thesis's setups are on offer");
    h.state_mut().phase_mut().select_compare_setups(&[0, 1]);
    h.state_mut()
        .phase_mut()
        .select_compare_levels(&[250.0, 10_000.0]);
    h.get_by_label("Run comparison").click_accesskit();
    h.step();
    step_until(&mut h, "the comparison", |app| {
        !app.phase().compare().is_running()
    });
    let rows = h.state().phase().compare().rows().to_vec();
    assert_eq!(rows.len(), 4, "2 setups × 2 light levels");
    let mut expected = Vec::new();
    compare_setups(
        &d,
        &PhaseSampling::for_quality(Quality::Preview),
        &setups[..2],
        &[],
        &Channel::rgb_peaks(),
        &[photo()],
        &[250.0, 10_000.0],
        0,
        thesis_denoise(),
        None,
        &Progress::new(),
        |r| expected.push(r),
    )
    .unwrap();
    assert_eq!(rows, expected, "the studio's rows are the core's");
    // Each row carries its setup's unpassed content of the photo, as the core measures it.
    for setup in &setups[..2] {
        let p = Progress::new();
        let (design, optics) = setup
            .resolve(
                &d,
                &PhaseSampling::for_quality(Quality::Preview),
                &[],
                None,
                &p,
            )
            .unwrap();
        let blur = phase_blur(
            &design,
            &PhaseSampling::for_quality(Quality::Preview),
            &Channel::rgb_peaks(),
            optics,
            PIXELS,
            &p,
        )
        .unwrap();
        let want = unpassed_mse(&blur, &photo()).unwrap();
        for row in rows.iter().filter(|r| &r.setup == setup) {
            assert_eq!(row.unpassed_mse, want, "{}", row.label);
        }
    }
    let notice = h.state().phase().compare().message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(!is_error && msg.contains("4 runs"), "{msg}");
    // The table names the setups; the mean column fills once every level is in.
    assert!(
        h.query_all_by_label(&setups[1].label()).count() >= 2,
        "a table row"
    );
    // Its last column is the PSNR of the photo without what each setup passes < 1 % of, or
    // "-" for a setup that passes every frequency.
    assert!(h.query_by_label("unpassed (dB)").is_some(), "the column");
    for row in &rows {
        if row.unpassed_mse > 0.0 {
            let cell = format!("{:.2}", -10.0 * row.unpassed_mse.log10());
            assert!(h.query_by_label(&cell).is_some(), "{}: {cell}", row.label);
        }
    }
    let path = dir.path().join("compare.csv");
    let ctx = h.ctx.clone();
    h.state_mut()
        .phase_mut()
        .save_compare_csv_to(path.clone(), &ctx);
    step_until(&mut h, "the CSV", |app| !app.phase().compare().is_saving());
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "setup,ltr,photo,photons,psnr_db,ssim,unpassed_mse"
    );
    assert_eq!(lines.len(), 5);
    for (line, row) in lines[1..].iter().zip(&rows) {
        assert!(line.starts_with(&format!("\"{}\",", row.label)), "{line}");
        let fields: Vec<f64> = line
            .rsplitn(5, ',')
            .take(4)
            .map(|f| f.parse().unwrap())
            .collect();
        assert_eq!(
            fields,
            [row.unpassed_mse, row.ssim, row.psnr_db, row.photons],
            "{line}"
        );
    }
}

/// The Denoise control: BM3D told each capture's own noise by default, "none" drops the
/// denoised picture and restores with the solver alone, "override" hands BM3D another σ².
#[test]
fn the_denoise_control_switches_bm3d_off_and_overrides_sigma2() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, _) = capture_studio(dir.path());
    wait_capture(&mut h, "the first capture");
    assert_eq!(h.state().phase().capture_denoise(), thesis_denoise());
    let row = &h.state().phase().capture_rows()[1];
    let (with, ltr) = (row.run.clone(), row.ltr);
    // The bare T-OLED's capture at 1600 photons: Poisson, read noise and the 12-bit ADC at white.
    let e = 1600.0 * ltr;
    let want = 1.0 / e + 4.87 * 4.87 / (e * e) + 1.0 / (12.0 * 4095.0 * 4095.0);
    let got = with.denoise.sigma2.unwrap();
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    // The authors' σ² at the light level is on the control.
    assert!(h.query_by_label("σ² 5.00e-4 (authors' table)").is_some());
    h.get_by_label("none").click_accesskit();
    h.step();
    assert_eq!(h.state().phase().capture_denoise(), Denoise::None);
    wait_capture(&mut h, "the capture without a denoiser");
    let without = h.state().phase().capture_rows()[1].run.clone();
    assert!(without.denoised.is_empty() && without.denoise.sigma2.is_none());
    assert_eq!(
        h.query_all_by_label_contains(" denoised (BM3D)").count(),
        0,
        "no denoised picture without a denoiser"
    );
    assert_eq!(h.query_all_by_label_contains(") restored").count(), 2);
    assert_ne!(with.psnr_db, without.psnr_db);
    h.get_by_label("BM3D").click_accesskit();
    h.step();
    h.get_by_label("override").click_accesskit();
    h.step();
    let Denoise::Bm3d {
        sigma2: udc_studio::core::restore::Sigma2::Fixed(s),
    } = h.state().phase().capture_denoise()
    else {
        panic!("override keeps BM3D with a fixed σ²");
    };
    assert_eq!(s, 0.0005, "the override starts at the authors' value");
}
