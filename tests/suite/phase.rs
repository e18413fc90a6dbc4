//! Phase masks (thesis chapter 4, PHYSICS.md §7): geometry, the folded plate, energy, FoV,
//! invertibility, Lemma 1 and the λ0 allocation.

use proptest::prelude::*;
use rustfft::num_complex::Complex64;
use udc_studio::core::Progress;
use udc_studio::core::design::Channel;
use udc_studio::core::phase::allocate::{barrier_gradient, channel_invertibility};
use udc_studio::core::phase::geometry::lenslet_count;
use udc_studio::core::phase::{
    AllocationSettings, Chain, GRID_LEN, Incidence, Lambda0, Optics, PhaseDesign, PhaseSampling,
    Surface, optical_mtf, optimize_lambda0, phase_psfs, v_matrix_on, wavelength_grid_nm,
};
use udc_studio::io::spectral::{channels_from_response, thesis_response};

fn thesis(pitch_um: f64, fold: f64) -> PhaseDesign {
    PhaseDesign::thesis(pitch_um, fold)
}

#[test]
fn lenslet_counts_follow_the_display_aperture() {
    let counts: Vec<usize> = [42.0, 56.0, 84.0, 168.0]
        .iter()
        .map(|&p| lenslet_count(&thesis(p, 1.0)))
        .collect();
    assert_eq!(counts, vec![58, 45, 31, 17]);
}

#[test]
fn at_lambda0_the_folded_plate_equals_the_thick_lens() {
    let sampling = PhaseSampling::thesis();
    for (fold, l0) in [(1.0, 530.0), (5.0, 611.0)] {
        let mut folded = thesis(42.0, fold);
        folded.lambda0 = Lambda0::Fixed { nm: l0 };
        let chain = Chain::new(&folded, &sampling).unwrap();
        let mut thick = folded.clone();
        thick.surface = Surface::Unfolded;
        let thick_h = chain.heights_for(&thick).unwrap();
        // The plate really is folded: its heights differ from the lens's by whole fold heights.
        let max_diff = chain
            .heights_um()
            .iter()
            .zip(&thick_h)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            max_diff > 5.0,
            "fold T={fold}: the plate is not folded ({max_diff} µm)"
        );
        let a = chain.mono(
            Optics::DoubleMla,
            chain.heights_um(),
            l0,
            Incidence::Pixel(0),
        );
        let b = chain.mono(Optics::DoubleMla, &thick_h, l0, Incidence::Pixel(0));
        let peak = b.sensor.iter().copied().fold(0.0, f64::max);
        for (x, y) in a.sensor.iter().zip(&b.sensor) {
            assert!((x - y).abs() <= 1e-9 * peak, "T={fold}: {x} vs {y}");
        }
        // Away from λ0 the fold matters.
        let c = chain.mono(
            Optics::DoubleMla,
            chain.heights_um(),
            l0 - 90.0,
            Incidence::Pixel(0),
        );
        let d = chain.mono(Optics::DoubleMla, &thick_h, l0 - 90.0, Incidence::Pixel(0));
        let diff: f64 = c
            .sensor
            .iter()
            .zip(&d.sensor)
            .map(|(x, y)| (x - y).abs())
            .sum();
        assert!(
            diff > 1e-3 * d.window_energy,
            "T={fold}: folding changed nothing off λ0"
        );
    }
}

#[test]
fn double_mla_passes_about_one_over_the_open_ratio_more_light_than_the_toled() {
    let design = thesis(42.0, 1.0);
    let psfs = phase_psfs(
        &design,
        &PhaseSampling::thesis(),
        &[Channel::peak("G", 530.0)],
        Optics::DoubleMla,
        Incidence::Pixel(0),
        &Progress::new(),
    )
    .unwrap();
    let g = &psfs.channels[0];
    eprintln!(
        "ratio {} window {} toled {} trans {} toled trans {}",
        g.energy_vs_toled_before_polariser,
        g.window_energy,
        g.toled_window_energy,
        g.transmission,
        g.toled_transmission
    );
    let expected = 1.0 / 0.238;
    assert!(
        (g.energy_vs_toled_before_polariser / expected - 1.0).abs() < 0.05,
        "{} vs {expected}",
        g.energy_vs_toled_before_polariser
    );
    assert!((g.energy_vs_toled - 0.5 * g.energy_vs_toled_before_polariser).abs() < 1e-12);
    // The bare T-OLED passes its open ratio.
    assert!(
        (g.toled_transmission - 0.238).abs() < 0.005,
        "{}",
        g.toled_transmission
    );
    // The lenslets also sharpen: a higher peak and invertibility than the T-OLED.
    assert!(
        g.peak > 2.0 * g.toled_peak,
        "{} vs {}",
        g.peak,
        g.toled_peak
    );
    assert!(g.invertibility > g.toled_invertibility);
}

#[test]
fn v_diagonal_does_not_depend_on_the_fold() {
    let lambdas = [471.0, 531.0, 611.0];
    let v = |fold: f64| {
        v_matrix_on(
            &thesis(42.0, fold),
            &PhaseSampling::thesis(),
            &lambdas,
            &lambdas,
            &Progress::new(),
        )
        .unwrap()
        .v
    };
    let (thin, thick) = (v(1.0), v(5.0));
    for j in 0..3 {
        assert!(
            (thin[j][j] - thick[j][j]).abs() <= 1e-9 * thick[j][j],
            "λ0 = λ = {}: {} vs {}",
            lambdas[j],
            thin[j][j],
            thick[j][j]
        );
        for k in 0..3 {
            if k != j {
                // Off the diagonal the thin plate's wraps cost invertibility; the fold matters.
                assert!(
                    thin[j][k] < thick[j][k],
                    "λ0 {} λ {}",
                    lambdas[j],
                    lambdas[k]
                );
                assert!(thin[j][k] < thin[j][j] && thin[j][k] < thin[k][k]);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Lemma 1: a phase mask pressed against the display never raises the MTF anywhere.
    #[test]
    fn lemma1_a_single_mask_never_raises_the_mtf(
        open in prop::collection::vec(0.0f64..=1.0, 8..96),
        heights in prop::collection::vec(0.0f64..4.0, 96),
        wavelength_nm in 400.0f64..700.0,
    ) {
        let k = 2.0 * std::f64::consts::PI / (wavelength_nm * 1e-3);
        let bare: Vec<Complex64> = open.iter().map(|&a| Complex64::new(a, 0.0)).collect();
        let masked: Vec<Complex64> = open
            .iter()
            .zip(&heights)
            .map(|(&a, &h)| Complex64::from_polar(a, k * 0.515 * h))
            .collect();
        let (a, b) = (optical_mtf(&bare), optical_mtf(&masked));
        for (tau, (x, y)) in a.iter().zip(&b).enumerate() {
            prop_assert!(*y <= *x + 1e-9, "τ = {}: masked {} > bare {}", tau, y, x);
        }
    }
}

#[test]
fn lemma1_holds_for_the_studio_single_mask_mode() {
    let psfs = phase_psfs(
        &thesis(42.0, 1.0),
        &PhaseSampling::preview(),
        &Channel::rgb_peaks(),
        Optics::SingleMask,
        Incidence::Pixel(0),
        &Progress::new(),
    )
    .unwrap();
    for c in &psfs.channels {
        eprintln!(
            "{} single {} toled {}",
            c.name, c.invertibility, c.toled_invertibility
        );
        assert!(
            c.invertibility <= c.toled_invertibility * (1.0 + 1e-6),
            "{}",
            c.name
        );
        // A phase mask moves light around but passes all of it.
        assert!((c.transmission - c.toled_transmission).abs() < 1e-9);
    }
}

#[test]
fn the_optimised_allocation_is_a_barrier_optimum_and_beats_fixed_530() {
    let design = thesis(42.0, 1.0);
    let channels = channels_from_response(&thesis_response(), &wavelength_grid_nm()).unwrap();
    let settings = AllocationSettings::default();
    let (_, alloc) = optimize_lambda0(
        &design,
        &PhaseSampling::preview(),
        &channels,
        &settings,
        &Progress::new(),
    )
    .unwrap();
    assert_eq!(alloc.counts.len(), GRID_LEN);
    assert_eq!(alloc.counts.iter().sum::<usize>(), 58);
    assert_eq!(alloc.lambda0_nm.len(), 58);
    assert!(alloc.lambda0_nm.windows(2).all(|w| w[0] <= w[1]));
    // Optimality of the last barrier stage: the gradient vanishes and x stays inside.
    let g = barrier_gradient(&alloc.a, &alloc.x, alloc.final_t, settings.q);
    let scale = alloc.x.iter().map(|x| 1.0 / x).fold(0.0, f64::max);
    let gmax = g.iter().map(|v| v.abs()).fold(0.0, f64::max);
    eprintln!(
        "x {:?}\ncounts {:?}\ninv {:?} t {} g {gmax} scale {scale}",
        alloc.x, alloc.counts, alloc.channel_invertibility, alloc.final_t
    );
    assert!(alloc.x.iter().all(|&x| x > 0.0));
    assert!(gmax < 1e-3 * scale, "gradient {gmax} vs 1/x up to {scale}");
    // Fixed 530 nm on the grid is 531 nm (index 13).
    let mut fixed = vec![0; GRID_LEN];
    fixed[13] = 58;
    let fixed_inv = channel_invertibility(&alloc.a, &fixed);
    let worst = |v: [f64; 3]| v.iter().copied().fold(f64::INFINITY, f64::min);
    eprintln!("fixed {fixed_inv:?}");
    assert!(
        worst(alloc.channel_invertibility) > worst(fixed_inv),
        "optimised {:?} vs fixed {:?}",
        alloc.channel_invertibility,
        fixed_inv
    );
    // Achromatic: the channels end closer together than with one fold wavelength.
    let spread = |v: [f64; 3]| v.iter().copied().fold(0.0, f64::max) - worst(v);
    assert!(spread(alloc.channel_invertibility) < spread(fixed_inv));
}

#[test]
fn field_of_view_follows_kappa() {
    let design = thesis(42.0, 5.0);
    assert!((design.kappa() - 4.2).abs() < 1e-12);
    let fov = design.fov_deg();
    assert!((fov - 14.0).abs() < 0.6, "FoV {fov}°");
    assert!((design.ltr_min() - (1.0 - 1.0 / 4.2)).abs() < 1e-12);
    // The simulation agrees: light inside half the FoV passes, light well outside it is blocked
    // by the display.
    let at = |deg: f64| {
        phase_psfs(
            &design,
            &PhaseSampling::preview(),
            &[Channel::peak("G", 530.0)],
            Optics::DoubleMla,
            Incidence::AngleDeg(deg),
            &Progress::new(),
        )
        .unwrap()
        .channels[0]
            .transmission
    };
    let (inside, edge, outside) = (at(2.0), at(fov / 2.0), at(fov));
    eprintln!("inside {inside} edge {edge} outside {outside}");
    assert!(inside > 0.85, "{inside}");
    assert!(outside < 0.5, "{outside}");
    assert!(edge < inside && edge > outside);
}

#[test]
fn the_kernel_matrix_holds_each_direction_and_the_telescope_inverts_it() {
    let mut design = thesis(42.0, 5.0);
    design.camera.pixels = 256;
    let sampling = PhaseSampling::preview();
    let channel = Channel::peak("G", 530.0);
    let kernels = |optics| {
        udc_studio::core::phase::kernel_matrix(
            &design,
            &sampling,
            &channel,
            optics,
            &Progress::new(),
        )
        .unwrap()
    };
    let (ours, toled) = (kernels(Optics::DoubleMla), kernels(Optics::Toled));
    assert_eq!(ours.dim(), (256, 256));
    let chain = Chain::new(&design, &sampling).unwrap();
    let centroid = |col: Vec<f64>| -> f64 {
        let sum: f64 = col.iter().sum();
        col.iter()
            .enumerate()
            .map(|(i, v)| (i as f64 - 128.0) * v)
            .sum::<f64>()
            / sum
    };
    for j_rel in [-20i64, 0, 20] {
        let j = (128 + j_rel) as usize;
        // Each column is that direction's PSF over the whole sensor.
        let psf = chain.mono(
            Optics::DoubleMla,
            chain.heights_um(),
            530.0,
            Incidence::Pixel(j_rel),
        );
        for i in 0..256 {
            assert!((ours[[i, j]] - psf.sensor[i]).abs() <= 1e-12, "K[{i}, {j}]");
        }
        // The bare T-OLED images direction j on pixel j; each lenslet pair is a 1:1 Keplerian
        // telescope that inverts the angle, so the double MLA's light lands near −j.
        let t = toled.column(j).to_vec();
        let argmax = (0..256).max_by(|&a, &b| t[a].total_cmp(&t[b])).unwrap();
        assert_eq!(argmax, j);
        let c = centroid(ours.column(j).to_vec());
        eprintln!("j {j_rel}: centroid {c}");
        assert!(
            (c + j_rel as f64).abs() < 6.0,
            "direction {j_rel}: centroid at {c}"
        );
    }
}
