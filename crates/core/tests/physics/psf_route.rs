//! The pruned PSF route (zooms onto the sensor window, `core::pruned`) gives the full-FFT
//! route's numbers to rounding on every kind of design, and the cost model picks every zoom
//! kind somewhere (conventions.md §2, "PSF route"); a Fraunhofer step handed in from outside the
//! core computes every PSF of an analysis, and one that reads back in `f32` keeps its numbers.

use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::display::aperture::Field;
use udc_core::display::aperture::{Display, Extent, effective_cells, rasterise};
use udc_core::psf::fft::Binned;
use udc_core::psf::pruned::zoom_kinds;
use udc_core::psf::route::{Fraunhofer, PsfRoute};
use udc_core::psf::sampling::Binning;
use udc_core::psf::zoom::ZoomKind;
use udc_core::{Analysis, Design, Progress, SimError};
use udc_io::design::presets::load_preset;

fn preset(name: &str) -> Design {
    load_preset(name).unwrap_or_else(|e| panic!("preset {name}: {e}"))
}

/// `H = |K|²/(|K|² + ε)` of a zero of the OTF is rounding noise, ~1e-31: compare absolutely there.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()) + 1e-15
}

fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

/// The largest relative AUC difference; every other number is checked inside.
fn compare(label: &str, full: &Analysis, pruned: &Analysis) -> f64 {
    let mut worst_auc = 0.0f64;
    for (f, p) in full.channels.iter().zip(&pruned.channels) {
        let auc = rel(f.mtf.auc_radial_min, p.mtf.auc_radial_min);
        assert!(auc <= 1e-9, "{label} {}: AUC {auc:e}", f.name);
        worst_auc = worst_auc.max(auc);
        assert!(rel(f.mtf.auc_radial_mean, p.mtf.auc_radial_mean) <= 1e-9);
        let peak = f.psf.iter().copied().fold(0.0, f64::max);
        for (a, b) in f.psf.iter().zip(p.psf.iter()) {
            assert!(
                (a - b).abs() <= 1e-12 * peak,
                "{label} {}: PSF {a} vs {b}",
                f.name
            );
        }
        // The MTF is 1 at DC: below 1e-15 a difference is the FFTs' rounding.
        for (a, b) in f.mtf.radial_min.iter().zip(&p.mtf.radial_min) {
            assert!(
                (a - b).abs() <= 1e-10 * a.abs() + 1e-15,
                "{label}: MTF {a} vs {b}"
            );
        }
        assert!((f.energy_in_window - p.energy_in_window).abs() <= 1e-12);
        assert!(
            close(f.invertibility, p.invertibility),
            "{label} {}: invertibility {:e} vs {:e}",
            f.name,
            f.invertibility,
            p.invertibility
        );
    }
    assert!(close(full.invertibility_loss, pruned.invertibility_loss));
    assert_eq!(full.ltr, pruned.ltr);
    let words = |a: &Analysis| a.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>();
    assert_eq!(
        words(full),
        words(pruned),
        "{label}: warnings (aliasing measure included)"
    );
    worst_auc
}

/// Every (route, window zoom, band zoom) the cost model picks for the design's wavelengths.
fn choices(design: &Design, quality: Quality) -> Vec<(PsfRoute, ZoomKind, ZoomKind)> {
    let op = &design.optics;
    let mut warnings = Vec::new();
    let samplings = quality
        .plan(design, &mut warnings)
        .unwrap_or_else(|e| panic!("plan: {e}"));
    let cells = effective_cells(&design.opening);
    let display = Display::from_design(design, &cells);
    let field = rasterise(
        &display,
        Extent::Pupil {
            diameter_um: op.pupil_diameter_um(),
        },
        op.pupil_sample_um,
    );
    samplings
        .iter()
        .flatten()
        .map(|s| {
            let route = udc_core::psf::route::choose(&field, s.fft_size, &s.binning);
            let (w, b) = zoom_kinds(&field, s.fft_size, &s.binning);
            (route, w, b)
        })
        .collect()
}

fn check(label: &str, design: &Design, quality: Quality) -> Vec<(PsfRoute, ZoomKind, ZoomKind)> {
    let options = AnalyzeOptions {
        quality,
        expected_psf: false,
    };
    let run = |route: PsfRoute| {
        analyze_with_route(design, &options, &route, &Progress::new())
            .unwrap_or_else(|e| panic!("{label}: {e}"))
    };
    let worst = compare(label, &run(PsfRoute::Full), &run(PsfRoute::Pruned));
    let auto = run(PsfRoute::Auto);
    compare(label, &run(PsfRoute::Full), &auto);
    let picked = choices(design, quality);
    println!("{label}: max relative AUC difference {worst:.1e}; picked {picked:?}");
    picked
}

#[test]
fn pruned_route_matches_the_full_route_at_150_and_300_dpi() {
    let mut picked = Vec::new();
    for name in [
        "toled-150dpi",
        "l2inv-random",
        "toled-300dpi",
        "open-aperture",
    ] {
        picked.extend(check(name, &preset(name), Quality::Full));
    }
    assert!(
        picked
            .iter()
            .any(|c| c.0 == PsfRoute::Pruned && c.1 == ZoomKind::Chirp)
    );
}

#[test]
fn pruned_route_matches_the_full_route_at_600_dpi() {
    let picked = check("toled-600dpi", &preset("toled-600dpi"), Quality::Full);
    assert!(picked.iter().all(|c| c.0 == PsfRoute::Pruned));
}

#[test]
fn pruned_route_matches_on_spectral_preview_and_tiny_window_designs() {
    // A spectral design: three wavelengths per channel, unequal weights, three FFT sizes each.
    let mut spectral = preset("l2inv-random");
    for (ch, centre) in spectral.channels.iter_mut().zip([610.0, 530.0, 470.0]) {
        ch.wavelengths_nm = vec![centre - 20.0, centre, centre + 20.0];
        ch.weights = vec![0.25, 0.5, 0.3];
    }
    check("spectral", &spectral, Quality::Full);
    // A focal length that makes the green FFT 7-smooth (M = 1344 = 2⁶·3·7): a slice of the
    // full FFT is cheapest there.
    let mut smooth = preset("toled-150dpi");
    smooth.optics.focal_length_mm = 10.144;
    let sliced = check("smooth size", &smooth, Quality::Full);
    assert!(sliced.iter().any(|c| c.1 == ZoomKind::Slice), "{sliced:?}");
    // A preview that doubles the spacing (f/10: the intensity is oversampled enough).
    let mut slow = preset("toled-150dpi");
    slow.optics.f_number = 10.0;
    assert!(Quality::Preview.doubles_spacing(&slow));
    check("preview", &slow, Quality::Preview);
    // A 2-pixel window: eight outputs per column, a matrix DFT beats any FFT.
    let mut tiny = preset("l2inv-random");
    tiny.optics.window_px = 2;
    let tiny_picked = check("tiny window", &tiny, Quality::Full);
    assert!(
        tiny_picked.iter().any(|c| c.1 == ZoomKind::Matrix),
        "{tiny_picked:?}"
    );
}

/// A Fraunhofer step from outside the core that reads back in `f32`, as a device computing in
/// single precision would: the CPU route's numbers rounded to `f32`.
struct F32Readback;

impl Fraunhofer for F32Readback {
    fn binned(
        &self,
        field: &Field,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        let b = PsfRoute::Auto.binned(field, m, binning, progress)?;
        let single = |v: f64| f64::from(v as f32);
        Ok(Binned {
            sensor: b.sensor.mapv(single),
            total: single(b.total),
            edge: single(b.edge),
        })
    }
}

/// A Fraunhofer step that puts all the window's light on the axis pixel: a PSF that is a point.
struct Point;

impl Fraunhofer for Point {
    fn binned(
        &self,
        field: &Field,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        let mut b = PsfRoute::Full.binned(field, m, binning, progress)?;
        let (sum, c) = (b.sensor.sum(), binning.window_px / 2);
        b.sensor.fill(0.0);
        b.sensor[[c, c]] = sum;
        Ok(b)
    }
}

#[test]
fn a_fraunhofer_step_from_outside_the_core_computes_every_psf_of_the_analysis() {
    let design = preset("toled-150dpi");
    let options = AnalyzeOptions {
        quality: Quality::Preview,
        expected_psf: false,
    };
    let run = |route: &dyn Fraunhofer| {
        analyze_with_route(&design, &options, route, &Progress::new()).expect("analyses")
    };
    let (reference, single) = (run(&PsfRoute::Auto), run(&F32Readback));
    // The tolerances a single-precision device is held to: the PSF within 1e-5 of its peak,
    // the AUC within 0.3 %, the transmittance exact (it is not the transform's).
    for (r, s) in reference.channels.iter().zip(&single.channels) {
        let peak = r.psf.iter().copied().fold(0.0, f64::max);
        for (a, b) in r.psf.iter().zip(s.psf.iter()) {
            assert!((a - b).abs() <= 1e-5 * peak, "{}: PSF {a} vs {b}", r.name);
        }
        let auc = rel(r.mtf.auc_radial_min, s.mtf.auc_radial_min);
        assert!(auc <= 3e-3, "{}: AUC differs by {auc:e}", r.name);
    }
    assert_eq!(reference.ltr, single.ltr);
    // Every channel's PSF came through the step handed in: a point in each, so every MTF is 1.
    let point = run(&Point);
    assert_eq!(point.channels.len(), reference.channels.len());
    for c in &point.channels {
        assert!(
            c.mtf.radial_min.iter().all(|v| (v - 1.0).abs() < 1e-12),
            "{}: the MTF of a point is 1 everywhere",
            c.name
        );
    }
}
