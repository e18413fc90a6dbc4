//! Field and depth dependence of the display blur (thesis §3.7, Figs. 3.29 and 3.31): physical
//! checks of the core and the JSON contract of `udc-studio field` and `udc-studio depth`.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use rustfft::num_complex::Complex64;
use udc_studio::core::Progress;
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::camera::depth::{
    DepthSettings, defocused_psfs, depth_psfs, image_distance_mm,
};
use udc_studio::core::camera::field::{FieldSettings, field_psfs};
use udc_studio::core::psf::route::{Fraunhofer, PsfRoute};
use udc_studio::io::design::presets::load_preset;

use crate::common::run_cli as run;

fn max_residual(preset: &str, z_mm: f64) -> f64 {
    let design = load_preset(preset).expect("preset");
    let settings = FieldSettings {
        display_distance_mm: z_mm,
        ..FieldSettings::default()
    };
    field_psfs(&design, &settings, &PsfRoute::Auto, &Progress::new())
        .expect("field")
        .max_residual_rel
}

#[test]
fn a_periodic_display_blurs_alike_over_the_field_and_a_random_one_does_not() {
    // Periodic: a shift is only a phase of every diffraction order; what is left comes from the
    // tiles the pupil's rim cuts.
    let periodic = max_residual("l2inv-repeat", 1.0);
    let random = max_residual("l2inv-random", 1.0);
    assert!(periodic < 1e-4, "periodic residual {periodic}");
    assert!(
        random > 3.0 * periodic,
        "random {random} vs periodic {periodic}"
    );
    // Display on the pupil: no shift, identical PSFs.
    assert_eq!(max_residual("l2inv-random", 0.0), 0.0);
    // The random residual grows with the shift z·tanθ: 29 µm (under one 168-µm tile) at 50 µm,
    // 3.4 tiles at 1 mm.
    let near = max_residual("l2inv-random", 0.05);
    assert!(near > 0.0 && near < random, "{near} vs {random}");
}

#[test]
fn the_lens_law_scales_the_focused_psf_by_less_than_ten_percent_down_to_10_cm() {
    // Thesis §3.7: f = 5.56 mm focuses 10 cm to infinity.
    let z2 = image_distance_mm(5.56, 100.0).expect("valid");
    assert!((z2 - 5.887).abs() < 1e-3, "{z2}"); // the thesis rounds to 5.86
    assert!(z2 / 5.56 - 1.0 < 0.10);
    assert!((image_distance_mm(5.56, 1000.0).expect("valid") - 5.591).abs() < 1e-3);
    let mut design = load_preset("l2inv-random").expect("preset");
    design.optics = udc_studio::core::design::Optics::phone();
    let near = depth_psfs(
        &design,
        &DepthSettings {
            object_distance_mm: 100.0,
            ..DepthSettings::default()
        },
        &PsfRoute::Auto,
        &Progress::new(),
    )
    .expect("depth");
    let far = depth_psfs(
        &design,
        &DepthSettings {
            object_distance_mm: 1000.0,
            ..DepthSettings::default()
        },
        &PsfRoute::Auto,
        &Progress::new(),
    )
    .expect("depth");
    assert!((near.psf_scale - z2 / 5.56).abs() < 1e-12);
    // Focused on the object the infinity PSF still deblurs it (Fig. 3.31 top rows); the
    // residual falls as the object recedes, and defocus is far worse than either.
    assert!(
        far.residual_rel_focused < near.residual_rel_focused,
        "{} {}",
        far.residual_rel_focused,
        near.residual_rel_focused
    );
    assert!(
        near.residual_rel_focused < 0.1,
        "{}",
        near.residual_rel_focused
    );
    assert!(near.residual_rel_defocused > 5.0 * near.residual_rel_focused);
    // Defocus in waves at the pupil rim: R²/(2 λ z1).
    let r_um = 0.5 * design.optics.pupil_diameter_um();
    let g = r_um * r_um / (2.0 * 0.530 * 100_000.0);
    assert!((near.defocus_waves[1] - g).abs() < 1e-9);
}

#[test]
fn an_object_far_away_defocuses_to_the_infinity_psf() {
    // The complex-pupil path must agree with the analysis when the defocus vanishes.
    let design = load_preset("l2inv-random").expect("preset");
    let options = AnalyzeOptions {
        quality: Quality::Preview,
        expected_psf: false,
    };
    let a = analyze_with(&design, &options, &Progress::new()).expect("analysis");
    let (psfs, _) = defocused_psfs(
        &design,
        Quality::Preview,
        1e7,
        &PsfRoute::Auto,
        &Progress::new(),
    )
    .expect("defocus");
    for (c, p) in a.channels.iter().zip(&psfs) {
        let diff = c
            .psf
            .iter()
            .zip(p.iter())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        // 3e-4 waves of defocus are left at 10 km: a change of order (2π·3e-4)² of the peak.
        assert!(diff < 1e-5, "{}: {diff}", c.name);
    }
    // Too close for the pupil sampling: an error, not aliased nonsense.
    assert!(
        defocused_psfs(
            &design,
            Quality::Preview,
            20.0,
            &PsfRoute::Auto,
            &Progress::new()
        )
        .is_err()
    );
}

#[test]
fn field_json_has_a_point_per_grid_node() {
    let (ok, stdout, stderr) = run(&[
        "field",
        "--preset",
        "l2inv-random",
        "--display-distance-mm",
        "1",
        "--grid",
        "3",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    let points = v["points"].as_array().expect("points");
    assert_eq!(points.len(), 9);
    let mut max: f64 = 0.0;
    for p in points {
        assert_eq!(p["field_deg"].as_array().expect("[x, y]").len(), 2);
        let r = p["residual_rel"].as_f64().expect("number");
        assert!(r >= 0.0);
        max = max.max(r);
    }
    assert_eq!(v["max_residual_rel"].as_f64(), Some(max));
    assert_eq!(points[4]["residual_rel"].as_f64(), Some(0.0), "the centre");
}

#[test]
fn depth_json_reports_the_lens_law_scale() {
    let (ok, stdout, stderr) = run(&[
        "depth",
        "--preset",
        "l2inv-random",
        "--object-distance-mm",
        "100",
        "--focal-mm",
        "5.56",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    let scale = v["psf_scale"].as_f64().expect("psf_scale");
    assert!((scale - 5.887 / 5.56).abs() < 1e-3, "{scale}");
    assert_eq!(v["focus"], "object");
    assert_eq!(v["residual_rel"], v["residual_rel_focused_at_object"]);
    assert!(v["image_distance_mm"].as_f64().is_some());
}

#[test]
fn bad_field_and_depth_values_fail_with_one_line() {
    for args in [
        &["field", "--display-distance-mm", "NaN"][..],
        &["field", "--display-distance-mm", "-1"],
        &["field", "--display-distance-mm", "1", "--grid", "1000000"],
        &[
            "field",
            "--display-distance-mm",
            "1",
            "--max-field-deg",
            "95",
        ],
        &["depth", "--object-distance-mm", "-3"],
        &["depth", "--object-distance-mm", "inf"],
        &["depth", "--object-distance-mm", "100", "--focal-mm", "0"],
        &["depth", "--object-distance-mm", "100", "--nsr", "-1"],
    ] {
        let (ok, _, stderr) = run(args);
        assert!(!ok, "{args:?} should fail");
        assert!(stderr.starts_with("error: --"), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

#[test]
fn bracketing_restores_linearity_around_specular_highlights() {
    use udc_studio::core::camera::saturation::{SaturationSettings, saturation_study};
    let design = load_preset("l2inv-random").expect("preset");
    let options = AnalyzeOptions {
        quality: Quality::Preview,
        expected_psf: false,
    };
    let a = analyze_with(&design, &options, &Progress::new()).expect("analysis");
    let psfs: Vec<_> = a.channels.iter().map(|c| &c.psf).collect();
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/hdr/");
    // Oil lamps over glasses, and a stained-glass window over a desk.
    for (file, margin_db) in [("StillLife_620x423.exr", 1.0), ("Desk_322x437.exr", 2.0)] {
        let scene =
            udc_studio::io::photo::hdr::load_hdr(std::path::Path::new(&format!("{dir}{file}")))
                .expect("scene");
        let r =
            saturation_study(&scene.planes, &psfs, &SaturationSettings::default()).expect("study");
        assert!(
            (r.clipped.clipped_fraction - 0.02).abs() < 0.005,
            "{file}: {}",
            r.clipped.clipped_fraction
        );
        assert!(r.bracketed.clipped_fraction < 0.25 * r.clipped.clipped_fraction);
        assert!(
            r.bracketed.psnr_db > r.clipped.psnr_db + margin_db,
            "{file}: bracketed {} dB vs clipped {} dB",
            r.bracketed.psnr_db,
            r.clipped.psnr_db
        );
        assert!(r.bracketed.ssim > r.clipped.ssim, "{file}");
    }
}

#[test]
fn saturation_json_compares_both_captures() {
    let (ok, stdout, stderr) = run(&[
        "saturation",
        "--preset",
        "l2inv-random",
        "--max-side-px",
        "200",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    for run in ["clipped", "bracketed"] {
        assert!(v[run]["psnr_db"].as_f64().is_some(), "{run}");
        assert!(v[run]["ssim"].as_f64().is_some(), "{run}");
    }
    assert_eq!(v["exposure_factors"].as_array().map(Vec::len), Some(3));
    let (ok, _, stderr) = run(&["saturation", "--clip-percent", "NaN"]);
    assert!(
        !ok && stderr.starts_with("error: --clip-percent"),
        "{stderr}"
    );
}

#[test]
fn a_field_capture_blends_the_field_psfs_and_reports_both_restorations() {
    let photo = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/photos/astronaut_256.png"
    );
    let psnr = |z: &str| {
        let (ok, stdout, stderr) = run(&[
            "field",
            "--preset",
            "l2inv-random",
            "--display-distance-mm",
            z,
            "--image",
            photo,
            "--max-side-px",
            "96",
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
        let c = &v["capture"];
        (
            c["psnr_db_field"].as_f64().expect("number"),
            c["psnr_db_invariant"].as_f64().expect("number"),
        )
    };
    // Display on the pupil: every field PSF is the centre PSF, the blend is the plain blur.
    let (field, invariant) = psnr("0");
    assert!((field - invariant).abs() < 0.01, "{field} vs {invariant}");
    let (field, invariant) = psnr("2");
    assert!(field.is_finite() && invariant.is_finite());
}

#[test]
fn a_near_object_restored_with_the_infinity_psf_keeps_its_quality_when_refocused() {
    // Fig. 3.31: the thesis restores every depth with the kernel calibrated at infinity. With the
    // camera refocused on an object at 10 cm the PSF is the infinity PSF scaled by z2/f (+11 %
    // here), so the photo restores almost as well as one at infinity; left focused at infinity
    // the object is defocused and the same filter cannot restore it.
    use udc_studio::core::camera::depth_capture::depth_capture;
    use udc_studio::core::restore::{CaptureSettings, Light};
    let design = load_preset("l2inv-random").unwrap();
    let settings = DepthSettings {
        object_distance_mm: 100.0,
        ..DepthSettings::default()
    };
    let depth = depth_psfs(&design, &settings, &PsfRoute::Auto, &Progress::new()).unwrap();
    let photo =
        udc_studio::io::photo::fit_max_side(udc_studio::io::photo::built_in_photo().unwrap(), 128);
    let capture = CaptureSettings {
        light: Light::SnrDb(28.0),
        ..CaptureSettings::default()
    };
    let c = depth_capture(&photo, &depth, &capture, settings.nsr).unwrap();
    let (inf, foc, def) = (c.infinity.psnr_db, c.focused.psnr_db, c.defocused.psnr_db);
    assert!(foc > def + 3.0, "refocused {foc} dB vs defocused {def} dB");
    assert!(
        (inf - foc).abs() < 3.0,
        "infinity {inf} dB vs refocused {foc} dB"
    );
    assert!(c.focused.ssim > c.defocused.ssim);
    // The photo has to match the channels.
    assert!(depth_capture(&photo[..1], &depth, &capture, settings.nsr).is_err());
}

/// A Fraunhofer step that counts its calls and gives the CPU's own numbers.
#[derive(Default)]
struct Counting(std::sync::atomic::AtomicUsize);

impl Fraunhofer for Counting {
    fn binned(
        &self,
        field: &udc_studio::core::display::aperture::Field,
        m: usize,
        binning: &udc_studio::core::psf::sampling::Binning,
        progress: &Progress,
    ) -> Result<udc_studio::core::psf::fft::Binned, udc_studio::core::SimError> {
        self.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        PsfRoute::Auto.binned(field, m, binning, progress)
    }

    fn binned_complex(
        &self,
        field: &udc_studio::core::display::aperture::Field<Complex64>,
        m: usize,
        binning: &udc_studio::core::psf::sampling::Binning,
        progress: &Progress,
    ) -> Result<udc_studio::core::psf::fft::Binned, udc_studio::core::SimError> {
        self.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        PsfRoute::Auto.binned_complex(field, m, binning, progress)
    }
}

impl Counting {
    fn calls(&self) -> usize {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// Every PSF of the field and depth studies comes through the route handed in (the GPU's, in
/// the CLI and the studio): a field grid of 2 × 2 is five analyses, a depth study three (at
/// infinity, focused on the object, and defocused: a complex pupil), each as many steps as one
/// analysis.
#[test]
fn field_and_depth_compute_their_psfs_through_the_route_handed_in() {
    let design = load_preset("fourier-square").unwrap();
    let options = AnalyzeOptions {
        quality: Quality::Preview,
        expected_psf: false,
    };
    let one = Counting::default();
    udc_studio::core::analysis::analyze::analyze_with_route(
        &design,
        &options,
        &one,
        &Progress::new(),
    )
    .unwrap();
    assert!(one.calls() >= design.channels.len());
    let field = Counting::default();
    let settings = FieldSettings {
        display_distance_mm: 1.0,
        grid: 2,
        quality: Quality::Preview,
        ..FieldSettings::default()
    };
    let counted = field_psfs(&design, &settings, &field, &Progress::new()).unwrap();
    assert_eq!(field.calls(), 5 * one.calls());
    let reference = field_psfs(&design, &settings, &PsfRoute::Auto, &Progress::new()).unwrap();
    assert_eq!(counted.max_residual_rel, reference.max_residual_rel);
    let depth = Counting::default();
    let settings = DepthSettings {
        object_distance_mm: 1000.0,
        quality: Quality::Preview,
        ..DepthSettings::default()
    };
    depth_psfs(&design, &settings, &depth, &Progress::new()).unwrap();
    assert_eq!(depth.calls(), 3 * one.calls());
}
