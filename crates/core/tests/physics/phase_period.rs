//! The lenslet-period relay ([`Relay::LensletPeriod`]) and the wrapped display
//! ([`Relay::WrappedDisplay`]) against the whole display (conventions.md §7): the same PSFs
//! where the array's edges do not reach, the same V to 1e-3, the same λ0 allocation, and the
//! wrapped display wherever the lenslets differ.

use udc_core::Progress;
use udc_core::phase::{
    AllocationSettings, Chain, Incidence, Lambda0, MonoPsf, PhaseDesign, PhaseOptics,
    PhaseSampling, Relay, optimize_lambda0, v_matrix,
};
use udc_io::design::spectral::{channels_from_response, thesis_response};

fn with_relay(mut s: PhaseSampling, relay: Relay) -> PhaseSampling {
    s.relay = relay;
    s
}

/// The largest difference of two PSFs over the sensor, as a fraction of the first one's peak.
fn worst_difference(a: &MonoPsf, b: &MonoPsf) -> f64 {
    let peak = a.sensor.iter().copied().fold(0.0, f64::max);
    let worst = a
        .sensor
        .iter()
        .zip(&b.sensor)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    worst / peak
}

/// The bare T-OLED's field on the opening is periodic exactly, so the period's two chirp-z
/// transforms and their geometric series give its PSF to the single-precision transform's
/// rounding; the double MLA differs by the light the array's two ends diffract: a few 1e-5 of
/// the peak where most light passes, 1e-3 at a direction where 97 % is lost. Energies follow.
#[test]
fn the_lenslet_period_gives_the_whole_displays_psfs() {
    let design = PhaseDesign::thesis(42.0, 5.0);
    let base = PhaseSampling::thesis();
    let whole = Chain::new(&design, &with_relay(base.clone(), Relay::WholeDisplay)).unwrap();
    let period = Chain::new(&design, &with_relay(base, Relay::LensletPeriod)).unwrap();
    for l in [401.0, 531.0, 691.0] {
        for j in [0i64, 37, -128, 400] {
            let at = Incidence::Pixel(j);
            let a = whole.mono(PhaseOptics::Toled, &[], l, at);
            let b = period.mono(PhaseOptics::Toled, &[], l, at);
            assert!(worst_difference(&a, &b) < 1e-6, "T-OLED {l} nm, {j}");
            assert!((a.total_energy - b.total_energy).abs() < 1e-9);
            let a = whole.mono(PhaseOptics::DoubleMla, whole.heights_um(), l, at);
            let b = period.mono(PhaseOptics::DoubleMla, period.heights_um(), l, at);
            let d = worst_difference(&a, &b);
            let bound = if j == 400 { 1e-3 } else { 5e-5 };
            assert!(d < bound, "double MLA {l} nm, {j}: {d:e}");
            let e = (a.window_energy - b.window_energy).abs() / a.window_energy;
            assert!(e < 10.0 * bound, "window energy {l} nm, {j}: {e:e}");
            // Not the same computation: the period's field is not the whole display's.
            assert_ne!(a.sensor, b.sensor);
        }
    }
}

/// Lenslets with different plates (λ0 spread over 400–700 nm) have no period: the route falls
/// back to the wrapped display, bit for bit.
#[test]
fn a_plate_without_a_period_takes_the_wrapped_display() {
    let mut design = PhaseDesign::thesis(42.0, 5.0);
    design.lambda0 = Lambda0::Uniform;
    let base = PhaseSampling::preview();
    let wrapped = Chain::new(&design, &with_relay(base.clone(), Relay::WrappedDisplay)).unwrap();
    let period = Chain::new(&design, &with_relay(base, Relay::LensletPeriod)).unwrap();
    let incidences = [Incidence::Pixel(0), Incidence::Pixel(-90)];
    let psfs = |chain: &Chain| {
        chain
            .mono_directions(
                PhaseOptics::DoubleMla,
                chain.heights_um(),
                531.0,
                &incidences,
                &Progress::new(),
            )
            .unwrap()
    };
    assert_eq!(psfs(&wrapped), psfs(&period));
}

/// The thesis's "Ours" at 600 DPI: Algorithm 1's allocation at T = 5 for the thesis response
/// (`phase optimize --fold 5`), 26 λ0s over 58 lenslets in runs of 1 to 7: no lenslet period.
fn optimized_plan() -> PhaseDesign {
    let mut design = PhaseDesign::thesis(42.0, 5.0);
    let counts = vec![
        0, 1, 1, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 2, 2, 3, 3, 4, 7, 7, 3, 2, 2, 2, 7,
    ];
    design.lambda0 = Lambda0::Counts { counts };
    design
}

/// The optimized plan on a grid of the display's own width: the light the array's ends send
/// beyond it wraps around instead of leaving, which moves the PSF by < 2e-5 of its peak where
/// most light passes (4.4e-6 measured) and by < 5e-4 at a direction where 97 % is lost
/// (1.3e-4). The other optics have no Fresnel step, so nothing wraps: bit for bit.
#[test]
fn the_wrapped_display_gives_the_whole_displays_psfs() {
    let design = optimized_plan();
    let base = PhaseSampling::thesis();
    let whole = Chain::new(&design, &with_relay(base.clone(), Relay::WholeDisplay)).unwrap();
    let wrapped = Chain::new(&design, &with_relay(base, Relay::WrappedDisplay)).unwrap();
    let mut worst = [0.0f64; 2];
    for l in [401.0, 531.0, 691.0] {
        for j in [0i64, 37, -128, 400] {
            let at = Incidence::Pixel(j);
            let a = whole.mono(PhaseOptics::DoubleMla, whole.heights_um(), l, at);
            let b = wrapped.mono(PhaseOptics::DoubleMla, wrapped.heights_um(), l, at);
            let d = worst_difference(&a, &b);
            let bound = if j == 400 { 5e-4 } else { 2e-5 };
            assert!(d < bound, "{l} nm, {j}: {d:e}");
            worst[usize::from(j == 400)] = worst[usize::from(j == 400)].max(d);
            let e = (a.window_energy - b.window_energy).abs() / a.window_energy;
            assert!(e < 10.0 * bound, "window energy {l} nm, {j}: {e:e}");
            assert_ne!(a.sensor, b.sensor);
            for optics in [PhaseOptics::Toled, PhaseOptics::SingleMask] {
                let a = whole.mono(optics, whole.heights_um(), l, at);
                let b = wrapped.mono(optics, wrapped.heights_um(), l, at);
                assert_eq!(a, b, "{optics:?} {l} nm, {j}");
            }
        }
    }
    eprintln!(
        "worst: {:e} of the peak, {:e} at direction +400",
        worst[0], worst[1]
    );
}

/// V over the 30 × 30 grid at the thesis sampling (T = 1) agrees entry by entry to 1e-3 (the
/// worst entries are λ0 = 401 nm at the longest wavelengths, whose light the plate spreads
/// widest and the array's ends diffract most), and the λ0 allocation made from it is the same:
/// the faster V changes no design.
#[test]
fn the_lenslet_period_keeps_v_and_the_allocation() {
    let design = PhaseDesign::thesis(42.0, 1.0);
    let base = PhaseSampling::thesis();
    let whole_sampling = with_relay(base.clone(), Relay::WholeDisplay);
    let period_sampling = with_relay(base, Relay::LensletPeriod);
    let a = v_matrix(&design, &whole_sampling, &Progress::new()).unwrap();
    let b = v_matrix(&design, &period_sampling, &Progress::new()).unwrap();
    let mut worst = 0.0f64;
    for (ra, rb) in a.v.iter().zip(&b.v) {
        for (x, y) in ra.iter().zip(rb) {
            worst = worst.max((x - y).abs() / x.abs());
        }
    }
    eprintln!("V: worst relative difference {worst:e}");
    assert!(worst < 1.5e-3, "{worst:e}");
    assert!(worst > 0.0);
    let channels =
        channels_from_response(&thesis_response(), &udc_core::phase::wavelength_grid_nm()).unwrap();
    let settings = AllocationSettings::default();
    let (_, wa) = optimize_lambda0(
        &design,
        &whole_sampling,
        &channels,
        &settings,
        &Progress::new(),
    )
    .unwrap();
    let (_, pa) = optimize_lambda0(
        &design,
        &period_sampling,
        &channels,
        &settings,
        &Progress::new(),
    )
    .unwrap();
    eprintln!("counts {:?}", wa.counts);
    assert_eq!(wa.counts, pa.counts);
}

/// An operator's window of sensor pixels: through the lenslet period the transform evaluates
/// only those pixels' samples, to the single-precision rounding of the whole sensor's; through
/// either display the PSF is the whole sensor's, cut. Pixels outside read zero; a window
/// beyond the sensor is an error.
#[test]
fn a_window_of_pixels_is_the_whole_sensors_psf_there() {
    let design = PhaseDesign::thesis(42.0, 5.0);
    let incidences = [
        Incidence::Pixel(0),
        Incidence::Pixel(-60),
        Incidence::Pixel(90),
    ];
    let window = 384..640;
    for relay in [
        Relay::LensletPeriod,
        Relay::WrappedDisplay,
        Relay::WholeDisplay,
    ] {
        let chain = Chain::new(&design, &PhaseSampling::preview().with_relay(relay)).unwrap();
        let p = Progress::new();
        let heights = chain.heights_um();
        let all = chain
            .mono_directions(PhaseOptics::DoubleMla, heights, 531.0, &incidences, &p)
            .unwrap();
        let cut = chain
            .mono_directions_on(
                PhaseOptics::DoubleMla,
                heights,
                531.0,
                &incidences,
                window.clone(),
                &p,
            )
            .unwrap();
        for (a, b) in all.iter().zip(&cut) {
            let peak = a.sensor.iter().copied().fold(0.0, f64::max);
            for (k, (x, y)) in a.sensor.iter().zip(&b.sensor).enumerate() {
                if window.contains(&k) {
                    assert!(
                        (x - y).abs() < 1e-6 * peak,
                        "{relay:?} pixel {k}: {x} vs {y}"
                    );
                } else {
                    assert_eq!(*y, 0.0);
                }
            }
            let inside: f64 = a.sensor[window.clone()].iter().sum();
            assert!((b.window_energy - inside).abs() < 1e-6 * inside);
            assert!(b.window_energy < a.window_energy);
            assert_eq!(a.total_energy, b.total_energy);
        }
        let err = chain
            .mono_directions_on(
                PhaseOptics::DoubleMla,
                heights,
                531.0,
                &incidences,
                1000..1100,
                &p,
            )
            .unwrap_err();
        assert!(err.to_string().contains("1000..1100"), "{err}");
    }
}

/// The relay a design goes through, as the CLI's JSON and the studio's quick look name it,
/// is the one the chain takes: the lenslet period for the bare T-OLED and any plate with one
/// λ0 under the thesis convention, the wrapped display for a λ0 plan there, the whole display
/// under the centred convention.
#[test]
fn the_relay_named_is_the_relay_taken() {
    let fast = PhaseSampling::preview().with_relay(Relay::LensletPeriod);
    let slow = PhaseSampling::preview();
    let mut one = PhaseDesign::thesis(42.0, 5.0);
    let mut counts = vec![0; udc_core::phase::GRID_LEN];
    counts[13] = 58;
    one.lambda0 = Lambda0::Counts { counts };
    let mut plan = PhaseDesign::thesis(42.0, 5.0);
    plan.lambda0 = Lambda0::Uniform;
    let mut centred = PhaseDesign::thesis(42.0, 5.0);
    centred.sampling = udc_core::phase::SamplingConvention::Centred;
    let mla = PhaseOptics::DoubleMla;
    let wrapped = PhaseSampling::preview().with_relay(Relay::WrappedDisplay);
    for (design, optics, named) in [
        (&one, mla, Relay::LensletPeriod),
        (&one, PhaseOptics::Toled, Relay::LensletPeriod),
        (&plan, mla, Relay::WrappedDisplay),
        (&plan, PhaseOptics::Toled, Relay::LensletPeriod),
        (&centred, mla, Relay::WholeDisplay),
    ] {
        assert_eq!(
            fast.relay_for(design, optics),
            named,
            "{:?}",
            design.lambda0
        );
        assert_eq!(slow.relay_for(design, optics), Relay::WholeDisplay);
        // Asked for, the wrapped display is taken wherever there is a Fresnel step to wrap.
        let wraps = optics == mla && design.sampling == udc_core::phase::SamplingConvention::Thesis;
        assert_eq!(
            wrapped.relay_for(design, optics),
            if wraps {
                Relay::WrappedDisplay
            } else {
                Relay::WholeDisplay
            }
        );
        // The route taken: through the lenslet period the PSF is not the whole display's.
        let heights = |s: &PhaseSampling| Chain::new(design, s).unwrap();
        let (a, b) = (heights(&fast), heights(&slow));
        let at = Incidence::Pixel(20);
        let pa = a.mono(optics, a.heights_um(), 531.0, at);
        let pb = b.mono(optics, b.heights_um(), 531.0, at);
        assert_eq!(
            pa == pb,
            named == Relay::WholeDisplay,
            "{:?} {optics:?}",
            design.lambda0
        );
    }
}

/// What a restoration consumes: the spectral operator of the thesis's optimized plan (here at
/// preview sampling, 48 columns) through the wrapped display is the whole display's to a small
/// fraction of its largest entry, channel by channel, and its LTR agrees.
#[test]
fn the_wrapped_display_gives_the_whole_displays_operator() {
    use udc_core::phase::imaging::phase_blur;
    let design = optimized_plan();
    let channels =
        channels_from_response(&thesis_response(), &udc_core::phase::wavelength_grid_nm()).unwrap();
    let blur = |relay: Relay| {
        phase_blur(
            &design,
            &PhaseSampling::preview().with_relay(relay),
            &channels,
            PhaseOptics::DoubleMla,
            48,
            &Progress::new(),
        )
        .unwrap()
    };
    let (whole, wrapped) = (blur(Relay::WholeDisplay), blur(Relay::LensletPeriod));
    let mut worst = 0.0f64;
    for (a, b) in whole.channels.iter().zip(&wrapped.channels) {
        let peak = a.iter().copied().fold(0.0, f64::max);
        let d = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        worst = worst.max(d / peak);
    }
    eprintln!(
        "operator: worst {worst:e} of the largest entry; LTR {} against {}",
        wrapped.ltr, whole.ltr
    );
    assert!(worst < 2e-5, "{worst:e}");
    assert!(worst > 0.0);
    assert!((whole.ltr - wrapped.ltr).abs() < 5e-4 * whole.ltr);
}
