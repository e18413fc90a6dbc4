//! Phase-mask speed (issue 5): one on-axis PSF at one wavelength with the thesis sampling
//! (15 nm over the 58-lenslet, 2.6 mm display aperture: 175 k display samples and a 14 336-sample
//! chirp-z window), the studio's three-channel update at thesis and preview sampling, and the
//! whole 30 × 30 V matrix (900 propagations) timed once — too long for criterion's ten samples.
//! V's wall time and values go to `<target>/udc-bench/phase.json` for benches/report.sh, which
//! compares them with benches/phase_numpy.py (goals: ≤ 100 ms per PSF, V ≤ 30 s on 2 cores and
//! ≥ 3× faster than numpy; issue 12: V ≤ 3 s). Also one capture + restore and the blur matrix
//! of all 1024 directions ([`imaging`]). Run with `cargo bench --bench phase -- --noplot`.

mod common;

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use udc_studio::core::Progress;
use udc_studio::core::design::Channel;
use udc_studio::core::phase::{
    Chain, Incidence, PhaseDesign, PhaseOptics, PhaseSampling, phase_psfs, v_matrix,
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
    let start = Instant::now();
    let v = v_matrix(&design, &PhaseSampling::thesis(), &Progress::new());
    let seconds = start.elapsed().as_secs_f64();
    let Ok(v) = v else {
        eprintln!("V failed: {v:?}");
        return;
    };
    println!(
        "V, 900 propagations, pitch 42 µm, T = 1: {seconds:.1} s on {} threads",
        rayon::current_num_threads()
    );
    let text = format!(
        "{{\"seconds\": {seconds:.3}, \"threads\": {}, \"v\": {:?}}}\n",
        rayon::current_num_threads(),
        v.v
    );
    common::write_figures("phase.json", &text);
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
    for (name, sampling) in [
        ("rgb-vs-toled/thesis", PhaseSampling::thesis()),
        ("rgb-vs-toled/preview", PhaseSampling::preview()),
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
    group.finish();
    full_v();
    imaging();
}

criterion_group!(benches, bench_phase);
criterion_main!(benches);
