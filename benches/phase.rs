//! Phase-mask speed (issue 5): one on-axis PSF at one wavelength with the thesis sampling
//! (15 nm over the 58-lenslet, 2.6 mm display aperture: 175 k display samples and a 14 336-sample
//! chirp-z window), the studio's three-channel update at thesis and preview sampling, and the
//! whole 30 × 30 V matrix (900 propagations) timed once — too long for criterion's ten samples.
//! V's wall time and values go to `<target>/udc-bench/phase.json` for benches/report.sh, which
//! compares them with benches/phase_numpy.py (goals: ≤ 100 ms per PSF, V ≤ 30 s on 2 cores and
//! ≥ 3× faster than numpy; issue 12: V ≤ 3 s; issue 30: V ≤ 1 s through the lenslet period).
//! Also one capture + restore, the blur matrix of all 1024 directions ([`imaging`]) and the
//! spectral operator of a 256- and a 512-pixel photo ([`spectral_operator`]). Run with
//! `cargo bench --bench phase -- --noplot`.

mod common;

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use udc_studio::core::Progress;
use udc_studio::core::design::Channel;
use udc_studio::core::phase::{
    Chain, Incidence, PhaseDesign, PhaseOptics, PhaseSampling, Relay, phase_psfs, v_matrix,
};

/// The capture + restoration of a 512×512 photo at one light level through a prepared operator
/// (goal ≤ 2 s), and the operator itself over all 1024 sensor directions, R, G and B at their
/// peak wavelengths and the thesis sampling (goal ≤ 20 s): both timed once, written to
/// `phase-imaging.json`.
fn imaging() {
    use udc_studio::core::phase::imaging::{capture_and_restore, phase_blur};
    let design = PhaseDesign::thesis(42.0, 5.0);
    let channels = Channel::rgb_peaks();
    let start = Instant::now();
    let all = phase_blur(
        &design,
        &PhaseSampling::thesis(),
        &channels,
        PhaseOptics::DoubleMla,
        1024,
        &Progress::new(),
    );
    let blur_seconds = start.elapsed().as_secs_f64();
    if let Err(e) = all {
        eprintln!("blur matrix failed: {e}");
        return;
    }
    let Ok(photo) = udc_studio::io::photo::built_in_photo() else {
        eprintln!("no built-in photo");
        return;
    };
    // The 256-px photo tiled 2×2: a 512×512 scene.
    let scene: Vec<ndarray::Array2<f64>> = photo
        .iter()
        .map(|p| ndarray::Array2::from_shape_fn((512, 512), |(y, x)| p[[y % 256, x % 256]]))
        .collect();
    let Ok(blur) = phase_blur(
        &design,
        &PhaseSampling::preview(),
        &channels,
        PhaseOptics::DoubleMla,
        512,
        &Progress::new(),
    ) else {
        eprintln!("operator failed");
        return;
    };
    let start = Instant::now();
    let run = capture_and_restore(
        &blur,
        &scene,
        1600.0,
        1,
        udc_studio::core::phase::imaging::thesis_denoise(),
        &Progress::new(),
    );
    let restore_seconds = start.elapsed().as_secs_f64();
    let psnr = run.map(|r| r.psnr_db).unwrap_or(f64::NAN);
    println!(
        "blur matrix of 1024 directions × 3 channels: {blur_seconds:.1} s; capture + BM3D + \
         restore 512×512 at 1600 photons: {restore_seconds:.2} s ({psnr:.2} dB)"
    );
    common::write_figures(
        "phase-imaging.json",
        &format!(
            "{{\"blur_seconds\": {blur_seconds:.3}, \"restore_seconds\": {restore_seconds:.3}, \
             \"psnr_db\": {psnr:.3}}}\n"
        ),
    );
}

fn full_v() {
    let design = PhaseDesign::thesis(42.0, 1.0);
    let timed = |relay: Relay| {
        let start = Instant::now();
        let v = v_matrix(
            &design,
            &PhaseSampling::thesis().with_relay(relay),
            &Progress::new(),
        );
        (start.elapsed().as_secs_f64(), v)
    };
    let (seconds, v) = timed(Relay::WholeDisplay);
    let Ok(v) = v else {
        eprintln!("V failed: {v:?}");
        return;
    };
    let (period_seconds, vp) = timed(Relay::LensletPeriod);
    let worst = vp.map_or(f64::NAN, |vp| {
        v.v.iter()
            .flatten()
            .zip(vp.v.iter().flatten())
            .map(|(a, b)| ((a - b) / a).abs())
            .fold(0.0, f64::max)
    });
    let threads = rayon::current_num_threads();
    println!(
        "V, 900 propagations, pitch 42 µm, T = 1, on {threads} threads: {seconds:.2} s through the \
         whole display, {period_seconds:.2} s through the lenslet period (entries within \
         {worst:.1e})"
    );
    let text = format!(
        "{{\"seconds\": {seconds:.3}, \"lenslet_period_seconds\": {period_seconds:.3}, \
         \"lenslet_period_worst\": {worst:e}, \"threads\": {threads}, \"v\": {:?}}}\n",
        v.v
    );
    common::write_figures("phase.json", &text);
}

/// The spectral capture operator (30 wavelengths of the thesis response, every direction of
/// the scene) of the fixed-530-nm plate at T = 5 for a 256- and a 512-pixel photo, thesis
/// sampling, through the lenslet period (goals ≤ 3 s and ≤ 10 s), and the 256-pixel one
/// through the whole display for comparison; then the thesis's optimized plan at T = 5 (26 λ0s
/// over 58 lenslets, no lenslet period) for a 256-pixel photo through the wrapped and the whole
/// display; and the bare T-OLED's 256-pixel operator through the whole display, which is the
/// opening's chirp-z transform alone: the floor of any relay that transforms the whole opening
/// per direction and wavelength. Timed once each, written to `phase-operator.json`.
/// The thesis's "Ours" at T = 5 from `base`: Algorithm 1's allocation for the thesis response
/// (26 λ0s over 58 lenslets), a plate with no lenslet period.
fn optimized_plan(base: &PhaseDesign) -> Result<PhaseDesign, String> {
    use udc_studio::core::phase::imaging::{Lambda0Plan, Setup};
    use udc_studio::core::phase::wavelength_grid_nm;
    use udc_studio::io::design::spectral::{channels_from_response, thesis_response};
    let channels = channels_from_response(&thesis_response(), &wavelength_grid_nm())
        .map_err(|e| e.to_string())?;
    let sampling = PhaseSampling::thesis().with_relay(Relay::LensletPeriod);
    Setup::mla(42.0, 5.0, Lambda0Plan::Optimized)
        .resolve(base, &sampling, &channels, None, &Progress::new())
        .map(|(design, _)| design)
        .map_err(|e| e.to_string())
}

fn spectral_operator() {
    use udc_studio::core::phase::imaging::phase_blur;
    use udc_studio::core::phase::wavelength_grid_nm;
    use udc_studio::io::design::spectral::{channels_from_response, thesis_response};
    let design = PhaseDesign::thesis(42.0, 5.0);
    let Ok(channels) = channels_from_response(&thesis_response(), &wavelength_grid_nm()) else {
        eprintln!("no thesis response");
        return;
    };
    let timed_through = |design: &PhaseDesign, optics, width: usize, relay: Relay| {
        let start = Instant::now();
        let blur = phase_blur(
            design,
            &PhaseSampling::thesis().with_relay(relay),
            &channels,
            optics,
            width,
            &Progress::new(),
        );
        blur.map(|_| start.elapsed().as_secs_f64())
            .unwrap_or(f64::NAN)
    };
    let timed = |design: &PhaseDesign, width: usize, relay: Relay| {
        timed_through(design, PhaseOptics::DoubleMla, width, relay)
    };
    let p256 = timed(&design, 256, Relay::LensletPeriod);
    let p512 = timed(&design, 512, Relay::LensletPeriod);
    let w256 = timed(&design, 256, Relay::WholeDisplay);
    let toled = timed_through(&design, PhaseOptics::Toled, 256, Relay::WholeDisplay);
    let (plan_wrapped, plan_whole) = match optimized_plan(&design) {
        Ok(plan) => (
            timed(&plan, 256, Relay::LensletPeriod),
            timed(&plan, 256, Relay::WholeDisplay),
        ),
        Err(e) => {
            eprintln!("no optimized plan: {e}");
            (f64::NAN, f64::NAN)
        }
    };
    println!(
        "spectral operator, 30 wavelengths: 256 px {p256:.2} s and 512 px {p512:.2} s through \
         the lenslet period; 256 px {w256:.1} s through the whole display; the optimized plan, \
         256 px: {plan_wrapped:.1} s through the wrapped display, {plan_whole:.1} s through the \
         whole display; the bare T-OLED's opening transforms alone, 256 px: {toled:.1} s"
    );
    common::write_figures(
        "phase-operator.json",
        &format!(
            "{{\"period_256_seconds\": {p256:.3}, \"period_512_seconds\": {p512:.3}, \
             \"whole_256_seconds\": {w256:.3}, \"plan_wrapped_256_seconds\": {plan_wrapped:.3}, \
             \"plan_whole_256_seconds\": {plan_whole:.3}, \"toled_whole_256_seconds\": {toled:.3}, \
             \"threads\": {}}}\n",
            rayon::current_num_threads()
        ),
    );
}

fn bench_phase(c: &mut Criterion) {
    let design = PhaseDesign::thesis(42.0, 1.0);
    let Ok(chain) = Chain::new(&design, &PhaseSampling::thesis()) else {
        eprintln!("cannot sample the thesis design");
        return;
    };
    let mut group = c.benchmark_group("phase");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    group.bench_function("psf-530nm/thesis", |b| {
        b.iter(|| {
            black_box(chain.mono(
                PhaseOptics::DoubleMla,
                chain.heights_um(),
                black_box(530.0),
                Incidence::Pixel(0),
            ))
        })
    });
    let channels = Channel::rgb_peaks();
    // The thesis code's relay, and the lenslet period the studio's update goes through.
    for (name, sampling) in [
        ("rgb-vs-toled/thesis", PhaseSampling::thesis()),
        ("rgb-vs-toled/preview", PhaseSampling::preview()),
        (
            "rgb-vs-toled/thesis-lenslet-period",
            PhaseSampling::thesis().with_relay(Relay::LensletPeriod),
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                black_box(phase_psfs(
                    &design,
                    &sampling,
                    &channels,
                    PhaseOptics::DoubleMla,
                    Incidence::Pixel(0),
                    &Progress::new(),
                ))
            })
        });
    }
    // A λ0 plan has no lenslet period: the thesis code's relay against the wrapped display
    // that the studio's update takes for it.
    match optimized_plan(&PhaseDesign::thesis(42.0, 5.0)) {
        Ok(plan) => {
            for (name, relay) in [
                ("rgb-vs-toled/optimized-plan", Relay::WholeDisplay),
                ("rgb-vs-toled/optimized-plan-wrapped", Relay::LensletPeriod),
            ] {
                let sampling = PhaseSampling::thesis().with_relay(relay);
                group.bench_function(name, |b| {
                    b.iter(|| {
                        black_box(phase_psfs(
                            &plan,
                            &sampling,
                            &channels,
                            PhaseOptics::DoubleMla,
                            Incidence::Pixel(0),
                            &Progress::new(),
                        ))
                    })
                });
            }
        }
        Err(e) => eprintln!("no optimized plan: {e}"),
    }
    group.finish();
    full_v();
    spectral_operator();
    imaging();
}

criterion_group!(benches, bench_phase);
criterion_main!(benches);
