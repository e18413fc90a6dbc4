//! A measured PSF's import against the truth: the core's PSF of a known design (its axis
//! placed off a pixel's centre, so the light sits at a sub-pixel position), recorded as a lab
//! records it (a bracket of three exposures with photon and read noise, a 12-bit full scale the
//! longer exposures clip, a dark offset, hot pixels, in a larger frame), merged back, has the
//! MTF of the PSF it was made from.

use ndarray::Array2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};

use udc_core::Progress;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_core::analysis::mtf::mtf_of;
use udc_core::measured::import::{Bracket, Exposure, ImportSteps, merge};
use udc_io::design::presets::load_preset;

/// `truth` at rows and columns `top … top + N` of a `frame × frame` field of no light.
pub fn placed(truth: &Array2<f64>, frame: usize, top: usize) -> Array2<f64> {
    let n = truth.nrows();
    Array2::from_shape_fn((frame, frame), |(y, x)| {
        let inside = (top..top + n).contains(&y) && (top..top + n).contains(&x);
        if inside {
            truth[[y - top, x - top]]
        } else {
            0.0
        }
    })
}

/// `light` (a PSF in a frame of no light) recorded as a lab records it: a bracket of 1, 4 and
/// 16 s with photon and read noise, a 12-bit full scale the longer exposures clip at the peak,
/// a dark offset, three hot pixels, and four dark frames.
pub fn recorded(light: &Array2<f64>, seed: u64) -> Bracket {
    let frame = light.nrows();
    let peak = light.iter().copied().fold(0.0, f64::max);
    let full_scale = 4095.0;
    // Electrons per second for the whole PSF; the peak then fills a 12-bit well in 1/4 of the
    // longest exposure, so the two longer frames clip it.
    let flux_e_per_s = 4.0 * full_scale / (peak * 16.0);
    let (dark_e, read_noise_e) = (64.0, 3.0);
    let hot: [(usize, usize, f64); 3] = [
        (5, 9, 900.0),
        (frame - 7, 40, 1500.0),
        (30, frame - 11, 2500.0),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let read = Normal::new(0.0, read_noise_e).expect("normal");
    let mut expose = |t: f64, lit: bool| {
        Array2::from_shape_fn((frame, frame), |(y, x)| {
            let mean = if lit {
                flux_e_per_s * t * light[[y, x]]
            } else {
                0.0
            };
            let photons = if mean > 0.0 {
                Poisson::new(mean).map_or(mean, |p| p.sample(&mut rng))
            } else {
                0.0
            };
            let hot_e = hot
                .iter()
                .find(|h| h.0 == y && h.1 == x)
                .map_or(0.0, |h| h.2);
            (photons + dark_e + hot_e + read.sample(&mut rng))
                .round()
                .clamp(0.0, full_scale)
        })
    };
    let times_s = [1.0, 4.0, 16.0];
    Bracket {
        exposures: times_s
            .iter()
            .map(|t| Exposure {
                frame: expose(*t, true),
                exposure_s: *t,
            })
            .collect(),
        darks: (0..4).map(|_| expose(1.0, false)).collect(),
        full_scale: Some(full_scale),
    }
}

#[test]
fn a_degraded_bracket_imports_to_the_psf_it_was_made_from() {
    let mut design = load_preset("toled-150dpi").expect("preset");
    // The axis 0.3 and 1.55 µm into its 2-µm pixel: the light's centre is not a pixel's.
    design.optics.axis_in_pixel_um = [0.3, 1.55];
    let options = AnalyzeOptions {
        quality: Quality::Preview,
        expected_psf: false,
    };
    let analysis = analyze_with(&design, &options, &Progress::new()).expect("analysis");
    let truth = analysis.channels[1].psf.clone();
    let n = truth.nrows();
    let (frame, top) = (n + 48, 24);
    let light = placed(&truth, frame, top);
    let bracket = recorded(&light, 7);
    let steps = ImportSteps {
        crop_px: Some(n),
        ..ImportSteps::default()
    };
    let (psf, report) = merge(&bracket, &steps, &Progress::new()).expect("merged");

    assert!(
        report.saturated_samples > 0,
        "the long exposures clip the peak"
    );
    assert_eq!(report.clipped_pixels, 0, "the short one holds it");
    assert_eq!(report.hot_pixels, 3, "{report:?}");
    // Where the bright core is: the noise, the dark level, the hot pixels and the clipped
    // samples move the centre found on the noise-free light by less than 0.05 px.
    let clean = Bracket {
        exposures: vec![Exposure {
            frame: light.clone(),
            exposure_s: 1.0,
        }],
        ..Bracket::default()
    };
    let (_, clean_report) = merge(&clean, &steps, &Progress::new()).expect("clean");
    for k in 0..2 {
        let (got, want) = (report.centre_px[k], clean_report.centre_px[k]);
        assert!((got - want).abs() < 0.05, "centre {got} against {want}");
        assert!(
            (want - (top + n / 2) as f64).abs() < 1.0,
            "on the axis pixel: {want}"
        );
    }
    // The MTF of the import against the truth's, up to Nyquist: ring by ring (radial mean)
    // within 0.02, and along the row and the column through DC (the T-OLED's slits make it
    // anisotropic; one line of samples averages less noise) within 0.03.
    let (got, want) = (mtf_of(&psf), mtf_of(&truth));
    let worst = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    for (name, a, b, bound) in [
        ("radial mean", &got.radial_mean, &want.radial_mean, 0.02),
        ("horizontal", &got.horizontal, &want.horizontal, 0.03),
        ("vertical", &got.vertical, &want.vertical, 0.03),
    ] {
        let w = worst(a, b);
        assert!(w < bound, "{name} MTF differs by up to {w:.4}");
    }
}

#[test]
fn a_set_serves_a_capture_one_kernel_for_all_colours_or_one_per_channel() {
    use udc_core::measured::{PsfChannel, PsfSet, PsfSource};
    let channel = |name: &str, psf: Array2<f64>| PsfChannel {
        name: name.into(),
        wavelength_nm: None,
        psf,
    };
    // Unit light with 1 % below zero (noise) in one sample.
    let mut noisy = Array2::<f64>::zeros((5, 5));
    noisy[[2, 2]] = 1.01;
    noisy[[0, 0]] = -0.01;
    let one = PsfSet {
        channels: vec![channel("G", noisy.clone())],
        pixel_um: 2.0,
        source: PsfSource::Measured,
    };
    let (kernels, negative) = one.restoration_kernels(3).unwrap();
    assert_eq!(kernels.len(), 3, "one channel serves every colour");
    assert!(kernels.iter().all(|k| k.iter().all(|v| *v >= 0.0)));
    assert!((negative - 0.01).abs() < 1e-12, "{negative}");
    let two = PsfSet {
        channels: vec![channel("R", noisy.clone()), channel("G", noisy)],
        ..one
    };
    assert_eq!(two.restoration_kernels(2).unwrap().0.len(), 2);
    let refused = two.restoration_kernels(3).unwrap_err().to_string();
    assert!(
        refused.contains("2 channels but the capture has 3"),
        "{refused}"
    );
}
