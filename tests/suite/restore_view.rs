//! The Restore view, driven like a user: the same photo and light through two designs, the
//! thesis's order (random tiling restores the T-OLED better), and a bad photo that changes nothing.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use crate::common::step_until;
use egui_kittest::kittest::Queryable;
use udc_studio::app::panels::views::ViewTab;
use udc_studio::app::{DisplayAction, StudioApp};
use udc_studio::core::design::TilingMode;

#[test]
fn random_tiling_restores_better_than_the_pinned_periodic_toled() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(
        &mut h,
        "the T-OLED result",
        crate::common::display_up_to_date,
    );
    h.state_mut().act(DisplayAction::PinCompare);
    step_until(&mut h, "the pinned design", |app| {
        app.display().pinned().is_some()
    });
    let mut d = h.state().display().design().clone();
    d.tiling.mode = TilingMode::RandomD4;
    h.state_mut().act(DisplayAction::Edit(Box::new(d)));
    step_until(
        &mut h,
        "the random-tiling result",
        crate::common::display_up_to_date,
    );
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::Restore);
    step_until(&mut h, "both restorations", |app| {
        let v = app.display().restore_view();
        !v.is_running() && v.current().is_some() && v.pinned().is_some()
    });
    let v = h.state().display().restore_view();
    let (random, periodic) = (v.current().unwrap(), v.pinned().unwrap());
    assert!(
        random.psnr_db > periodic.psnr_db + 1.0,
        "random {} dB vs periodic {} dB",
        random.psnr_db,
        periodic.psnr_db
    );
    assert!(random.ssim > periodic.ssim);
    // Both at the same light behind the reference display (28 dB = 654 e-), the same LTR here.
    assert!((random.light_e - periodic.light_e).abs() < 1e-9);
    assert!((random.light_e - 654.0).abs() < 1.0);
    assert_eq!(
        h.query_all_by_label_contains("restored PSNR").count(),
        2,
        "a row per design"
    );
    // Right-click the first difference picture: Save figure… opens the window with it as a
    // picture in pixels.
    h.run_steps(2);
    let at = h
        .query_all_by_label_contains("|restored - truth|")
        .map(|n| n.rect())
        .max_by(|a, b| a.area().total_cmp(&b.area()))
        .expect("the difference picture")
        .center();
    common::right_click(&mut h, at);
    h.get_by_label("Save figure…").click();
    h.run_steps(2);
    let figure = h
        .state()
        .save_figure()
        .figure()
        .expect("the window is open");
    let panel = &figure.panels[0];
    assert!(
        panel.title.contains("|restored - truth|"),
        "{}",
        panel.title
    );
    assert_eq!(panel.x.unit.as_deref(), Some("px"));
    assert_eq!(panel.images.len(), 1);
}

#[test]
fn a_bad_photo_shows_an_error_and_keeps_the_last_one() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.png");
    std::fs::write(&bad, b"not a png at all").unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::Restore);
    step_until(&mut h, "the built-in photo restored", |app| {
        let v = app.display().restore_view();
        !v.is_running() && v.current().is_some()
    });
    let psnr = h
        .state()
        .display()
        .restore_view()
        .current()
        .unwrap()
        .psnr_db;
    let ctx = h.ctx.clone();
    h.state_mut()
        .display_mut()
        .views()
        .restore
        .load_photo(bad.clone(), &ctx);
    step_until(&mut h, "the photo error", |app| {
        !app.display().restore_view().is_running()
    });
    assert!(h.query_by_label_contains("cannot open the photo").is_some());
    assert!(
        h.query_by_label_contains("astronaut").is_some(),
        "the old photo stays"
    );
    assert_eq!(
        h.state()
            .display()
            .restore_view()
            .current()
            .unwrap()
            .psnr_db,
        psnr
    );
}

/// The thesis's pipeline on screen: captured, denoised (BM3D) and restored side by side; the
/// Denoise control's "none" drops the denoised picture and reruns with the deblurring alone.
#[test]
fn the_view_shows_captured_denoised_and_restored_and_denoise_switches_off() {
    use udc_studio::core::restore::{Denoise, Recipe};
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    step_until(
        &mut h,
        "the first result",
        crate::common::display_up_to_date,
    );
    h.state_mut()
        .display_mut()
        .views()
        .set_tab(ViewTab::Restore);
    let done = |app: &StudioApp| {
        let v = app.display().restore_view();
        !v.is_running() && v.current().is_some()
    };
    step_until(&mut h, "the built-in photo restored", done);
    assert_eq!(
        h.state().display().restore_view().denoise(),
        Denoise::default()
    );
    let with = h
        .state()
        .display()
        .restore_view()
        .current()
        .unwrap()
        .clone();
    assert_eq!(with.denoised.len(), 3);
    for kind in ["captured", "denoised (BM3D)", "restored"] {
        assert_eq!(
            h.query_all_by_label_contains(&format!(" {kind}")).count(),
            1,
            "one {kind} picture"
        );
    }
    assert!(h.query_by_label_contains("(authors' table)").is_some());
    // The default, "matched", hands BM3D the capture's own variance at white, shown with its
    // value; the authors' table is one click away.
    let matched = Denoise::Bm3d {
        sigma2: udc_studio::core::restore::Sigma2::Matched,
    };
    assert_eq!(h.state().display().restore_view().denoise(), matched);
    assert_eq!(with.denoise.setting, matched);
    // Poisson, read noise and the rounding to whole electrons, at white.
    let e = with.electrons_per_unit;
    let want = 1.0 / e + 4.87 * 4.87 / (e * e) + 1.0 / (12.0 * e * e);
    let got = with.denoise.sigma2.unwrap();
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    h.get_by_label_contains("(authors' table)")
        .click_accesskit();
    h.step();
    let table = Denoise::authors_table(Recipe::Iccp21);
    assert_eq!(h.state().display().restore_view().denoise(), table);
    step_until(&mut h, "the run with the authors' σ²", |app| {
        done(app)
            && app
                .display()
                .restore_view()
                .current()
                .is_some_and(|r| r.denoise.setting == table)
    });
    let t = h
        .state()
        .display()
        .restore_view()
        .current()
        .unwrap()
        .clone();
    assert_ne!(t.denoise.sigma2, with.denoise.sigma2);
    assert_eq!(t.captured, with.captured);
    h.get_by_label("none").click_accesskit();
    h.step();
    assert_eq!(h.state().display().restore_view().denoise(), Denoise::None);
    step_until(&mut h, "the run without a denoiser", |app| {
        done(app)
            && app
                .display()
                .restore_view()
                .current()
                .is_some_and(|r| r.denoised.is_empty())
    });
    let without = h
        .state()
        .display()
        .restore_view()
        .current()
        .unwrap()
        .clone();
    assert_eq!(h.query_all_by_label_contains(" denoised (BM3D)").count(), 0);
    assert_eq!(h.query_all_by_label_contains(" restored").count(), 1);
    // The same capture, a worse restoration: the noise goes straight into Wiener.
    assert_eq!(with.captured, without.captured);
    assert!(
        with.psnr_db > without.psnr_db,
        "BM3D {} dB vs none {} dB",
        with.psnr_db,
        without.psnr_db
    );
}
