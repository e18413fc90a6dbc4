//! The phase model's Bloch relay on the device against the CPU's: single PSFs through the
//! double MLA on the wrapped grid, a restoration's whole spectral operator and V.

use std::sync::Arc;

use udc_core::Progress;
use udc_core::design::Channel;
use udc_core::phase::chain::BlochRelay;
use udc_core::phase::imaging::phase_blur_on;
use udc_core::phase::{
    Chain, Incidence, Lambda0, PhaseDesign, PhaseOptics, PhaseSampling, Relay, SamplingConvention,
};
use udc_core::phase::{
    kernel_matrix, kernel_matrix_on, phase_psfs, phase_psfs_on, v_matrix_on, v_matrix_through,
};
use udc_gpu::Route;

use crate::device;

/// The thesis's 42 µm design with a λ0 plan (every lenslet its own λ0): the Bloch relay's case,
/// where the lenslet period does not apply.
fn plan() -> PhaseDesign {
    let mut d = PhaseDesign::thesis(42.0, 5.0);
    d.lambda0 = Lambda0::Uniform;
    d
}

fn sampling() -> PhaseSampling {
    PhaseSampling::preview().with_relay(Relay::WrappedDisplay)
}

fn worst_of_peak(a: &[f64], b: &[f64]) -> f64 {
    let peak = a.iter().copied().fold(0.0, f64::max);
    let d = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    d / peak
}

/// Directions on both sides of the axis and across the sensor, two wavelengths: each PSF within
/// 1e-4 of its peak, the light leaving the opening and on the window within 1e-5.
#[test]
fn the_device_relay_gives_the_cpus_psfs() {
    let Some(gpu) = device("the_device_relay_gives_the_cpus_psfs") else {
        return;
    };
    let design = plan();
    assert_eq!(design.sampling, SamplingConvention::Thesis);
    let cpu = Chain::new(&design, &sampling()).unwrap();
    let dev = Chain::new(&design, &sampling()).unwrap().with_relay(gpu);
    let at: Vec<Incidence> = [-61, -7, 0, 13, 40]
        .into_iter()
        .map(Incidence::Pixel)
        .collect();
    let p = Progress::new();
    for nm in [451.0, 633.0] {
        let mla = PhaseOptics::DoubleMla;
        let want = cpu
            .mono_directions(mla, cpu.heights_um(), nm, &at, &p)
            .unwrap();
        let got = dev
            .mono_directions(mla, dev.heights_um(), nm, &at, &p)
            .unwrap();
        for ((w, g), i) in want.iter().zip(&got).zip(&at) {
            let worst = worst_of_peak(&w.sensor, &g.sensor);
            eprintln!("{nm} nm, {i:?}: worst {worst:.2e} of the peak");
            assert!(worst < 1e-4, "{nm} nm {i:?}: {worst:e} of the peak");
            let rel = |a: f64, b: f64| (a - b).abs() / a.abs();
            assert!(
                rel(w.total_energy, g.total_energy) < 1e-5,
                "{nm} nm {i:?} total"
            );
            assert!(
                rel(w.window_energy, g.window_energy) < 1e-5,
                "{nm} nm {i:?} window"
            );
            assert_eq!(w.image_pixel, g.image_pixel);
        }
    }
}

/// A restoration's operator (three channels, four wavelengths, 16 scene columns and 4 more on
/// each side) computed with the device's relay: every entry within 1e-4 of the largest, the
/// LTR within 1e-5.
#[test]
fn the_device_operator_is_the_cpus() {
    let Some(gpu) = device("the_device_operator_is_the_cpus") else {
        return;
    };
    let design = plan();
    let channel = |name: &str, nm: &[f64], weights: &[f64]| Channel {
        name: name.into(),
        wavelengths_nm: nm.to_vec(),
        weights: weights.to_vec(),
    };
    let channels = [
        channel("B", &[455.0], &[1.0]),
        channel("G", &[515.0, 545.0], &[0.4, 0.6]),
        channel("R", &[625.0], &[1.0]),
    ];
    let blur = |chain: &Chain| {
        phase_blur_on(
            chain,
            &channels,
            PhaseOptics::DoubleMla,
            16,
            4,
            &Progress::new(),
        )
        .unwrap()
    };
    let cpu = blur(&Chain::new(&design, &sampling()).unwrap());
    let relay: Arc<dyn BlochRelay> = gpu;
    let dev = blur(&Chain::new(&design, &sampling()).unwrap().with_relay(relay));
    for (c, (a, b)) in cpu.channels.iter().zip(&dev.channels).enumerate() {
        let (a, b) = (a.as_slice().unwrap(), b.as_slice().unwrap());
        let worst = worst_of_peak(a, b);
        eprintln!("channel {c}: worst {worst:.2e} of the largest entry");
        assert!(worst < 1e-4, "channel {c}: {worst:e}");
    }
    assert!(
        (cpu.ltr - dev.ltr).abs() < 1e-5 * cpu.ltr,
        "{} vs {}",
        cpu.ltr,
        dev.ltr
    );
}

/// A cancelled job stops on the device too.
#[test]
fn the_device_relay_stops_when_cancelled() {
    let Some(gpu) = device("the_device_relay_stops_when_cancelled") else {
        return;
    };
    let dev = Chain::new(&plan(), &sampling()).unwrap().with_relay(gpu);
    let p = Progress::new();
    p.cancel();
    let at = [Incidence::Pixel(3)];
    let got = dev.mono_directions(PhaseOptics::DoubleMla, dev.heights_um(), 531.0, &at, &p);
    assert!(matches!(got, Err(udc_core::SimError::Cancelled)), "{got:?}");
}

/// `phase psf` and its `--all-angles` matrix (eq. 4.12) with the device's relay, on a 32-pixel
/// sensor: each channel's PSF within 1e-4 of its peak, its transmission within 1e-5, and the
/// matrix of all 32 directions within 1e-4 of its largest entry.
#[test]
fn the_device_psfs_and_kernel_matrix_are_the_cpus() {
    let Some(gpu) = device("the_device_psfs_and_kernel_matrix_are_the_cpus") else {
        return;
    };
    let mut design = plan();
    design.camera.pixels = 32;
    let relay: Arc<dyn BlochRelay> = gpu;
    let dev = Chain::new(&design, &sampling()).unwrap().with_relay(relay);
    let p = Progress::new();
    let channels = [Channel {
        name: "G".into(),
        wavelengths_nm: vec![515.0, 545.0],
        weights: vec![0.4, 0.6],
    }];
    let mla = PhaseOptics::DoubleMla;
    let at = Incidence::AngleDeg(1.5);
    let want = phase_psfs(&design, &sampling(), &channels, mla, at, &p).unwrap();
    let got = phase_psfs_on(&dev, &channels, mla, at, &p).unwrap();
    for (w, g) in want.channels.iter().zip(&got.channels) {
        let worst = worst_of_peak(&w.psf, &g.psf);
        eprintln!("PSF: worst {worst:.2e} of the peak");
        assert!(worst < 1e-4, "{worst:e}");
        assert!((w.transmission - g.transmission).abs() < 1e-5 * w.transmission);
        // The bare T-OLED has no Fresnel step: the CPU's, bit for bit.
        assert_eq!(w.toled_psf, g.toled_psf);
    }
    let want = kernel_matrix(&design, &sampling(), &channels[0], mla, &p).unwrap();
    let got = kernel_matrix_on(&dev, &channels[0], mla, &p).unwrap();
    assert_eq!(want.dim(), (32, 32));
    let worst = worst_of_peak(want.as_slice().unwrap(), got.as_slice().unwrap());
    eprintln!("kernel matrix: worst {worst:.2e} of the largest entry");
    assert!(worst < 1e-4, "{worst:e}");
}

/// V (§4.3.5) through the wrapped display with the device's relay: two λ0 rows at two
/// wavelengths, each entry within 1e-5 of the CPU's, every propagation counted on the device;
/// under the lenslet period (one lenslet's samples) the device runs none and V is the CPU's.
#[test]
fn the_device_v_matrix_is_the_cpus() {
    let Some(gpu) = device("the_device_v_matrix_is_the_cpus") else {
        return;
    };
    let design = PhaseDesign::thesis(42.0, 1.0);
    let (rows, cols) = ([461.0, 611.0], [471.0, 631.0]);
    let p = Progress::new();
    let want = v_matrix_on(&design, &sampling(), &rows, &cols, &p).unwrap();
    let route = Arc::new(Route::device(gpu));
    let relay: Arc<dyn BlochRelay> = route.clone();
    let chain = Chain::new(&design, &sampling())
        .unwrap()
        .with_relay(relay.clone());
    let got = v_matrix_through(&chain, &rows, &cols, &p).unwrap();
    for (w, g) in want.v.iter().flatten().zip(got.v.iter().flatten()) {
        eprintln!("V {w:.4} vs {g:.4}");
        assert!(*w > 1.0 && (w - g).abs() <= 1e-5 * w, "{w} vs {g}");
    }
    assert_eq!(route.device_transforms(), rows.len() * cols.len());
    let period = PhaseSampling::preview().with_relay(Relay::LensletPeriod);
    let want = v_matrix_on(&design, &period, &rows, &cols, &p).unwrap();
    let chain = Chain::new(&design, &period).unwrap().with_relay(relay);
    assert_eq!(v_matrix_through(&chain, &rows, &cols, &p).unwrap(), want);
    assert_eq!(route.device_transforms(), rows.len() * cols.len());
}
