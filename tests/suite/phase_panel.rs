//! The phase-mask workspace, driven like a user: the thesis design on screen, PSFs from the
//! worker that match the core, live edits, a bad value that keeps the last result, the λ0
//! optimizer with Apply, undo and Cancel, persistence and the exports.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::Duration;

use crate::common::Reach;
use crate::common::step_until;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use udc_studio::app::phase::{ChannelSet, HeightFormat, PhaseView, Quality};
use udc_studio::app::{StudioApp, WorkspaceId};
use udc_studio::core::Progress;
use udc_studio::core::design::Channel;
use udc_studio::core::phase::geometry::lenslet_count;
use udc_studio::core::phase::{
    Incidence, Lambda0, PhaseDesign, PhaseOptics, PhaseSampling, phase_psfs,
};

fn phase_studio(dir: &std::path::Path, quality: Quality) -> Harness<'static, StudioApp> {
    let mut h = common::studio(dir, false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Phase);
    h.state_mut().phase_mut().quality = quality;
    h.step();
    h
}

/// Whether a widget with exactly this label is on screen (any number of them).
fn on_screen(h: &Harness<'_, StudioApp>, label: &str) -> bool {
    h.query_all_by_label(label).next().is_some()
}

fn wait_psfs(h: &mut Harness<'_, StudioApp>, what: &str) {
    step_until(h, what, |app| app.phase().is_up_to_date());
}

#[test]
fn the_thesis_design_shows_and_its_psfs_match_the_core() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Full);
    let d = h.state().phase().design().clone();
    assert_eq!(d, PhaseDesign::thesis(42.0, 1.0));
    assert_eq!(lenslet_count(&d), 58);
    assert!((d.fov_deg() - 13.6).abs() < 0.05, "{}", d.fov_deg());
    // The numbers panel shows them with units.
    assert!(on_screen(&h, "58"), "58 lenslets on screen");
    assert!(on_screen(&h, "13.6° (±6.8°)"), "the FoV on screen");
    assert!(on_screen(&h, "42.00 µm (605 DPI)"));
    assert!(on_screen(&h, "4.20"), "κ");
    wait_psfs(&mut h, "the full-quality PSFs");
    let shown = h.state().phase().shown().unwrap();
    assert_eq!(shown.quality, Quality::Full);
    let psfs = shown.psfs.clone();
    let direct = phase_psfs(
        &d,
        &PhaseSampling::for_quality(Quality::Full),
        &Channel::rgb_peaks(),
        PhaseOptics::DoubleMla,
        Incidence::AngleDeg(0.0),
        &Progress::new(),
    )
    .unwrap();
    assert_eq!(psfs.lenslets, 58);
    assert_eq!(psfs.channels.len(), 3);
    for (a, b) in psfs.channels.iter().zip(&direct.channels) {
        assert_eq!(a.name, b.name);
        let rel = (a.energy_vs_toled - b.energy_vs_toled).abs() / b.energy_vs_toled;
        assert!(
            rel < 1e-12,
            "{}: {} vs {}",
            a.name,
            a.energy_vs_toled,
            b.energy_vs_toled
        );
        // The double MLA gains light over the T-OLED even after the polariser's 1/2.
        assert!(b.energy_vs_toled > 1.5, "{}: {}", b.name, b.energy_vs_toled);
        let label = format!("{:.3}×", b.energy_vs_toled);
        assert!(on_screen(&h, &label), "{label} on screen");
    }
    assert!((psfs.ltr_with_polariser - direct.ltr_with_polariser).abs() < 1e-12);
    let ltr = format!("{:.3}", direct.ltr_with_polariser);
    assert!(on_screen(&h, &ltr), "LTR {ltr} on screen");
    // Every view draws.
    for (view, label) in [
        (PhaseView::Geometry, "Height profile around lenslet"),
        (PhaseView::Optimizer, "Run optimizer"),
        (PhaseView::Psf, "incidence angle"),
    ] {
        h.state_mut().phase_mut().show(view);
        h.step();
        h.step();
        assert!(
            h.query_all_by_label_contains(label).next().is_some(),
            "{label}"
        );
    }
}

#[test]
fn edits_recompute_and_a_bad_value_keeps_the_last_result() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Preview);
    wait_psfs(&mut h, "the preview PSFs");
    let first = h.state().phase().shown().unwrap().psfs.clone();
    // A thicker fold: the same geometry, other PSFs.
    h.state_mut().phase_mut().design_mut().fold = 5.0;
    step_until(&mut h, "the T = 5 PSFs", |app| {
        app.phase().is_up_to_date() && app.phase().shown().is_some_and(|s| s.design.fold == 5.0)
    });
    let thick = h.state().phase().shown().unwrap().psfs.clone();
    assert_ne!(thick.channels[0].psf, first.channels[0].psf);
    // A coarser display: fewer lenslets.
    {
        let d = h.state_mut().phase_mut().design_mut();
        d.pitch_um = 84.0;
        d.f_mla_um = 84.0;
    }
    step_until(&mut h, "the 84-µm PSFs", |app| {
        app.phase().is_up_to_date() && app.phase().shown().is_some_and(|s| s.psfs.lenslets == 31)
    });
    assert!(on_screen(&h, "31"), "31 lenslets on screen");
    let double = h.state().phase().shown().unwrap().psfs.clone();
    // Lemma 1's single mask, off axis, with the spectral channels: each reaches the worker.
    h.state_mut().phase_mut().single_mask = true;
    step_until(&mut h, "the single-mask PSFs", |app| {
        app.phase().is_up_to_date()
            && app
                .phase()
                .shown()
                .is_some_and(|s| s.optics == PhaseOptics::SingleMask)
    });
    let single = h.state().phase().shown().unwrap().psfs.clone();
    assert_ne!(single.channels[1].psf, double.channels[1].psf);
    h.state_mut().phase_mut().single_mask = false;
    h.state_mut().phase_mut().angle_deg = 5.0;
    h.state_mut().phase_mut().channels = ChannelSet::Spectral;
    step_until(&mut h, "the off-axis spectral PSFs", |app| {
        app.phase().is_up_to_date()
            && app
                .phase()
                .shown()
                .is_some_and(|s| s.channels == ChannelSet::Spectral && s.psfs.angle_deg > 4.9)
    });
    let off = h.state().phase().shown().unwrap().psfs.clone();
    // sin 5° · 4.67 mm = 407.0 µm: pixel ⌊407.0 / 2.03⌋ = 200 under the thesis sampling.
    assert_eq!(off.image_pixel, 200);
    assert_eq!(off.channels.len(), 3);
    assert!(
        off.channels
            .iter()
            .all(|c| (450.0..650.0).contains(&c.wavelength_nm)),
        "response-weighted mean wavelengths"
    );
    let generation = h.state().phase().shown().unwrap().generation;
    // NaN: the validate() message, and the last result stays.
    h.state_mut().phase_mut().design_mut().pitch_um = f64::NAN;
    for _ in 0..5 {
        h.step();
    }
    let notice = h.state().phase().message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(is_error && msg.contains("pitch_um"), "{msg}");
    assert!(
        h.query_by_label_contains("pitch_um").is_some(),
        "{msg} on screen"
    );
    let kept = h.state().phase().shown().unwrap();
    assert_eq!(kept.generation, generation);
    assert_eq!(kept.design.pitch_um, 84.0);
    assert!(!h.state().phase().is_up_to_date());
    // Out of range is refused the same way.
    h.state_mut().phase_mut().design_mut().pitch_um = 84.0;
    h.state_mut().phase_mut().design_mut().fold = 0.0;
    for _ in 0..3 {
        h.step();
    }
    let notice = h.state().phase().message().unwrap().clone();
    let (msg, _) = (notice.text.clone(), notice.is_error());
    assert!(msg.contains("fold"), "{msg}");
    assert_eq!(h.state().phase().shown().unwrap().generation, generation);
    // Ctrl+Z steps back over the bad values (each an undo step) to T = 5 at 84 µm.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.step();
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    step_until(&mut h, "the undone design", |app| {
        app.phase().is_up_to_date()
    });
    let d = h.state().phase().design().clone();
    assert_eq!((d.pitch_um, d.fold), (84.0, 5.0));
    assert!(h.state().phase().message().is_none_or(|m| !m.is_error()));
    // The display document was not touched by the phase workspace's undo.
    assert!(!h.state().display().document().can_undo());
}

#[test]
fn the_optimizer_allocates_every_lenslet_and_apply_is_undoable() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Preview);
    h.state_mut().phase_mut().show(PhaseView::Optimizer);
    wait_psfs(&mut h, "the preview PSFs");
    // V runs under the lenslet period, on the CPU whatever the menu's backend: the view says so.
    h.get_by_label("at preview sampling, peak channels, on the CPU");
    h.get_by_label("Run optimizer").click();
    h.step();
    assert!(h.state().phase().is_optimizing());
    step_until(&mut h, "the optimizer", |app| {
        app.phase().optimized().is_some()
    });
    let o = h.state().phase().optimized().unwrap();
    let counts = o.allocation.counts.clone();
    assert_eq!(counts.len(), 30);
    assert_eq!(counts.iter().sum::<usize>(), 58);
    assert_eq!(o.allocation.lambda0_nm.len(), 58);
    // The optimized plan's worst channel beats the fixed 530 nm.
    let worst = |v: [f64; 3]| v.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(worst(o.allocation.channel_invertibility) >= worst(o.fixed_530) - 1e-9);
    let v = h.state().phase().v().unwrap();
    assert_eq!((v.v.v.len(), v.v.v[0].len()), (30, 30));
    assert!(on_screen(&h, "fixed 530 nm (V row 531 nm)"));
    // Apply: the plan becomes the counts, and the PSFs follow.
    h.get_by_label("Apply").click();
    h.step();
    assert_eq!(
        h.state().phase().design().lambda0,
        Lambda0::Counts {
            counts: counts.clone()
        }
    );
    wait_psfs(&mut h, "the optimized PSFs");
    assert!(matches!(
        h.state().phase().shown().unwrap().design.lambda0,
        Lambda0::Counts { .. }
    ));
    // Undo and redo.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.step();
    assert_eq!(
        h.state().phase().design().lambda0,
        Lambda0::Fixed { nm: 530.0 }
    );
    h.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    h.step();
    assert_eq!(
        h.state().phase().design().lambda0,
        Lambda0::Counts { counts }
    );
}

#[test]
fn cancel_stops_an_optimizer_run() {
    let dir = tempfile::tempdir().unwrap();
    // Thesis sampling: a run takes long enough to cancel.
    let mut h = phase_studio(dir.path(), Quality::Full);
    h.state_mut().phase_mut().show(PhaseView::Optimizer);
    h.step();
    h.get_by_label("Run optimizer").click();
    h.step();
    h.step();
    assert!(h.state().phase().is_optimizing());
    assert!(
        h.query_by_label_contains("optimizer (V, then Algorithm 1)")
            .is_some()
    );
    h.get_by_label("Cancel").click();
    h.step();
    assert!(!h.state().phase().is_optimizing());
    assert!(h.state().phase().optimized().is_none());
    let notice = h.state().phase().optimizer_message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(!is_error && msg.contains("cancelled"), "{msg}");
    // The buttons are back.
    h.step();
    assert!(
        !h.get_by_label("Run optimizer")
            .accesskit_node()
            .is_disabled()
    );
}

#[test]
fn the_phase_design_is_kept_between_runs_and_exports() {
    let dir = tempfile::tempdir().unwrap();
    {
        let mut h = common::studio(dir.path(), false, Duration::from_millis(20));
        h.state_mut().set_workspace(WorkspaceId::Phase);
        h.state_mut().phase_mut().quality = Quality::Preview;
        let mut d = PhaseDesign::thesis(56.0, 5.0);
        d.height_step_um = Some(0.2);
        h.state_mut().phase_mut().set_design(d);
        let file = dir.path().join("phase-design.json");
        step_until(&mut h, "the phase autosave", |_| {
            std::fs::read_to_string(&file).is_ok_and(|t| t.contains("56"))
        });
        // Exports write off the UI thread.
        let ctx = h.ctx.clone();
        for (format, name) in [
            (HeightFormat::Csv, "plate.csv"),
            (HeightFormat::Gds, "plate.gds"),
        ] {
            let path = dir.path().join(name);
            h.state_mut()
                .phase_mut()
                .export_to(format, path.clone(), &ctx);
            step_until(&mut h, "the export", |app| !app.phase().is_exporting());
            let notice = h.state().phase().export_message().unwrap().clone();
            let (msg, is_error) = (notice.text.clone(), notice.is_error());
            assert!(!is_error && msg.contains(name), "{msg}");
            assert!(std::fs::metadata(&path).unwrap().len() > 100, "{name}");
        }
        // Without native dialogs the buttons say so instead of blocking.
        h.get_by_label("Heights (CSV)…").click_accesskit();
        h.step();
        let notice = h.state().phase().export_message().unwrap().clone();
        let (msg, _) = (notice.text.clone(), notice.is_error());
        assert!(msg.contains("dialogs are disabled"), "{msg}");
    }
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Phase);
    h.step();
    let d = h.state().phase().design();
    assert_eq!(
        (d.pitch_um, d.fold, d.height_step_um),
        (56.0, 5.0, Some(0.2))
    );
    assert_eq!(lenslet_count(d), 45);
}

#[test]
fn a_response_csv_replaces_the_channels_and_a_bad_one_keeps_them() {
    use udc_studio::core::phase::wavelength_grid_nm;
    use udc_studio::io::design::spectral;
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Preview);
    h.state_mut().phase_mut().channels = ChannelSet::Spectral;
    step_until(&mut h, "the thesis-response PSFs", |app| {
        app.phase().is_up_to_date()
            && app
                .phase()
                .shown()
                .is_some_and(|s| s.channels == ChannelSet::Spectral)
    });
    let thesis_nm: Vec<f64> = h
        .state()
        .phase()
        .shown()
        .unwrap()
        .psfs
        .channels
        .iter()
        .map(|c| c.wavelength_nm)
        .collect();
    let generation = h.state().phase().shown().unwrap().generation;
    // The Canon table: the channels switch and the PSFs run again.
    let canon = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/spectral/canon_eos_5d_mark_ii_rawtoaces.csv");
    let ctx = h.ctx.clone();
    h.state_mut()
        .phase_mut()
        .load_response_from(canon.clone(), &ctx);
    step_until(&mut h, "the Canon PSFs", |app| {
        app.phase().is_up_to_date()
            && app
                .phase()
                .shown()
                .is_some_and(|s| matches!(s.channels, ChannelSet::Custom(_)))
    });
    let phase = h.state().phase();
    let notice = phase.response_message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(
        !is_error && msg.contains("canon_eos_5d_mark_ii_rawtoaces.csv"),
        "{msg}"
    );
    let custom = phase.channels;
    assert!(matches!(custom, ChannelSet::Custom(_)));
    let shown = phase.shown().unwrap();
    assert!(shown.generation > generation);
    let expected = spectral::channels_from_response(
        &spectral::load_response_csv(&canon).unwrap(),
        &wavelength_grid_nm(),
    )
    .unwrap();
    assert_eq!(shown.psfs.channels.len(), 3);
    for ((c, e), t) in shown.psfs.channels.iter().zip(&expected).zip(&thesis_nm) {
        assert!(
            (c.wavelength_nm - e.mean_wavelength_nm()).abs() < 1e-9,
            "{}: {} vs {}",
            c.name,
            c.wavelength_nm,
            e.mean_wavelength_nm()
        );
        assert!((c.wavelength_nm - t).abs() > 1e-3, "{}: {t}", c.name);
    }
    // The file's name is the channel choice's label.
    assert!(on_screen(
        &h,
        "canon_eos_5d_mark_ii_rawtoaces.csv (custom response)"
    ));
    // A malformed table: the error names the line and column, and the channels stay.
    let bad = dir.path().join("bad.csv");
    std::fs::write(
        &bad,
        "wavelength,R,G,B\n400,0.1,0.2,0.3\n410,0.1,oops,0.3\n",
    )
    .unwrap();
    h.state_mut().phase_mut().load_response_from(bad, &ctx);
    step_until(&mut h, "the bad table", |app| {
        !app.phase().is_loading_response()
    });
    let phase = h.state().phase();
    let notice = phase.response_message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(is_error, "{msg}");
    assert!(msg.contains("line 3, column 3"), "{msg}");
    assert_eq!(phase.channels, custom);
    assert!(phase.is_up_to_date());
    assert!(on_screen(&h, &msg), "the error on screen");
    // Without native dialogs the button says so instead of blocking.
    h.get_by_label("Open response CSV…").click_accesskit();
    h.step();
    let notice = h.state().phase().response_message().unwrap().clone();
    let (msg, _) = (notice.text.clone(), notice.is_error());
    assert!(msg.contains("dialogs are disabled"), "{msg}");
}

#[test]
fn the_blur_matrix_of_all_directions_matches_the_core_and_saves_as_csv() {
    use udc_studio::core::phase::kernel_matrix;
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Preview);
    let mut d = PhaseDesign::thesis(42.0, 1.0);
    d.camera.pixels = 64;
    h.state_mut().phase_mut().set_design(d.clone());
    wait_psfs(&mut h, "the 64-pixel PSFs");
    h.state_mut().phase_mut().set_kernel_channel(1);
    h.get_by_label("Blur matrix (all 64 directions)…")
        .click_accesskit();
    h.step();
    step_until(&mut h, "the blur matrix", |app| {
        app.phase().kernels().is_some()
    });
    let k = h.state().phase().kernels().unwrap();
    assert_eq!(k.k.dim(), (64, 64));
    assert_eq!(k.channel_name, "G");
    assert!(!h.state().phase().kernels_are_stale());
    assert!(
        h.query_by_label("Blur matrix K, G channel").is_some(),
        "the figure is drawn"
    );
    let direct = kernel_matrix(
        &d,
        &PhaseSampling::for_quality(Quality::Preview),
        &Channel::rgb_peaks()[1],
        PhaseOptics::DoubleMla,
        &Progress::new(),
    )
    .unwrap();
    // The CSV: one line per sensor pixel, its column j the core's direction j.
    let path = dir.path().join("k.csv");
    let ctx = h.ctx.clone();
    h.state_mut()
        .phase_mut()
        .save_kernels_to(path.clone(), &ctx);
    step_until(&mut h, "the CSV", |app| !app.phase().is_saving_kernels());
    let notice = h.state().phase().kernels_message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(!is_error && msg.contains("k.csv"), "{msg}");
    let text = std::fs::read_to_string(&path).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 64);
    let max = direct.iter().copied().fold(0.0, f64::max);
    assert!(max > 0.0);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 64, "row {i}");
        for (j, v) in row.iter().enumerate() {
            let e = direct[[i, j]];
            assert!(
                (v - e).abs() <= 1e-12 * e.abs().max(max * 1e-300),
                "K[{i}, {j}] {v} vs {e}"
            );
        }
    }
    // A change makes it stale.
    h.state_mut().phase_mut().design_mut().fold = 5.0;
    h.step();
    assert!(h.state().phase().kernels_are_stale());
    assert!(h.query_by_label_contains("Stale:").is_some());
}

#[test]
fn cancel_stops_a_blur_matrix_run() {
    let dir = tempfile::tempdir().unwrap();
    // Thesis sampling, 1024 directions and a λ0 plan (no lenslet period: the whole display is
    // relayed for each of the red channel's 30 000 direction–wavelength pairs, about a minute on
    // 2 cores): the run cannot finish in the two frames before the Cancel, however fast the
    // machine.
    let mut h = phase_studio(dir.path(), Quality::Full);
    h.state_mut().phase_mut().design_mut().lambda0 = udc_studio::core::phase::Lambda0::Uniform;
    h.step();
    h.get_by_label("Blur matrix (all 1024 directions)…")
        .click_accesskit();
    h.step();
    h.step();
    assert!(h.state().phase().is_computing_kernels());
    assert!(
        h.query_by_label_contains("blur matrix of R over 1024")
            .is_some()
    );
    h.get_by_label("Cancel").click_accesskit();
    h.step();
    assert!(!h.state().phase().is_computing_kernels());
    assert!(h.state().phase().kernels().is_none());
    let notice = h.state().phase().kernels_message().unwrap().clone();
    let (msg, is_error) = (notice.text.clone(), notice.is_error());
    assert!(!is_error && msg.contains("cancelled"), "{msg}");
}

/// The Sampling selector switches the convention as one undoable edit, and the PSFs follow.
#[test]
fn the_sampling_selector_switches_the_convention_and_undoes() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Preview);
    wait_psfs(&mut h, "the preview PSFs");
    assert_eq!(
        h.state().phase().design().sampling,
        udc_studio::core::phase::SamplingConvention::Thesis
    );
    let thesis = h.state().phase().shown().unwrap().psfs.clone();
    h.get_by_label("centred").click();
    step_until(&mut h, "the centred PSFs", |app| {
        app.phase().is_up_to_date()
            && app.phase().shown().is_some_and(|s| {
                s.design.sampling == udc_studio::core::phase::SamplingConvention::Centred
            })
    });
    let centred = h.state().phase().shown().unwrap().psfs.clone();
    assert_ne!(centred.channels[1].psf, thesis.channels[1].psf);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    step_until(&mut h, "undo back to the thesis sampling", |app| {
        app.phase().design().sampling == udc_studio::core::phase::SamplingConvention::Thesis
    });
}

#[test]
fn the_export_panel_checks_the_plate_against_the_design_rules() {
    use udc_studio::core::mask::drc::Rules;
    use udc_studio::core::phase::drc::check_plate;
    // What the panel must say: the same check as `udc-studio drc`, run off the UI thread.
    let line = |d: &PhaseDesign| {
        let r = check_plate(d, &Rules::default()).unwrap();
        if r.is_clean() {
            "Design rules: clean".to_string()
        } else {
            format!("Design rules: {} features narrower than", r.total())
        }
    };
    let wait_for = |h: &mut Harness<'_, StudioApp>, text: &str| {
        for _ in 0..600 {
            if h.query_by_label_contains(text).is_some() {
                return;
            }
            h.step();
            std::thread::sleep(Duration::from_millis(20));
        }
        panic!("`{text}` never appeared on the export panel");
    };
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Preview);
    let mut stepped = PhaseDesign::thesis(168.0, 1.0);
    stepped.height_step_um = Some(0.2);
    let want = line(&stepped);
    assert!(
        want.contains("narrower"),
        "the thesis plate has sub-0.5-µm rings: {want}"
    );
    h.state_mut().phase_mut().set_design(stepped);
    wait_for(&mut h, &want);
    let mut coarse = PhaseDesign::thesis(168.0, 1.0);
    coarse.height_step_um = Some(2.0);
    let other = line(&coarse);
    assert_ne!(other, want);
    h.state_mut().phase_mut().set_design(coarse);
    wait_for(&mut h, &other);
}

/// The panel's buttons change the design only through the workspace's queue: Thesis design is
/// one undo step, the panel's Undo and Redo walk it back and forth, and a queued live edit
/// waits for the frame's end.
#[test]
fn the_panels_change_the_design_through_the_queue_and_the_history() {
    use udc_studio::app::phase::PhaseAction;
    let dir = tempfile::tempdir().unwrap();
    let mut h = phase_studio(dir.path(), Quality::Preview);
    let mut wide = PhaseDesign::thesis(84.0, 1.0);
    wide.fold = 5.0;
    h.state_mut().phase_mut().set_design(wide.clone());
    h.step();
    h.get_by_label("Thesis design").click();
    h.step();
    assert_eq!(h.state().phase().design(), &PhaseDesign::thesis(42.0, 1.0));
    h.get_by_label("Undo").click();
    h.step();
    assert_eq!(h.state().phase().design(), &wide);
    h.get_by_label("Redo").click();
    h.step();
    assert_eq!(h.state().phase().design().pitch_um, 42.0);
    // Two live edits in a row (a drag) are one undo step once committed.
    let mut a = h.state().phase().design().clone();
    a.fold = 2.0;
    h.state_mut()
        .phase_mut()
        .act(PhaseAction::Live(Box::new(a.clone())));
    a.fold = 3.0;
    h.state_mut()
        .phase_mut()
        .act(PhaseAction::Live(Box::new(a)));
    h.step();
    assert_eq!(h.state().phase().design().fold, 3.0);
    h.state_mut().phase_mut().act(PhaseAction::Undo);
    assert_eq!(h.state().phase().design().fold, 1.0);
}
