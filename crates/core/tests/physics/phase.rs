//! Phase masks (thesis chapter 4, conventions.md §7): geometry, the folded plate, energy, FoV,
//! invertibility, Lemma 1 and the λ0 allocation.

use proptest::prelude::*;
use rustfft::num_complex::Complex64;
use udc_core::design::Channel;
use udc_core::phase::allocate::{barrier_gradient, channel_invertibility};
use udc_core::phase::geometry::lenslet_count;
use udc_core::phase::{
    AllocationSettings, Chain, GRID_LEN, Incidence, Lambda0, PhaseDesign, PhaseOptics,
    PhaseSampling, SamplingConvention, Surface, invertibility_score, optical_mtf, optimize_lambda0,
    phase_psfs, v_matrix_on, wavelength_grid_nm,
};
use udc_core::{Progress, SimError};
use udc_io::design::spectral::{channels_from_response, thesis_response};

fn thesis(pitch_um: f64, fold: f64) -> PhaseDesign {
    // The default sampling convention is the thesis's.
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
            PhaseOptics::DoubleMla,
            chain.heights_um(),
            l0,
            Incidence::Pixel(0),
        );
        let b = chain.mono(PhaseOptics::DoubleMla, &thick_h, l0, Incidence::Pixel(0));
        let peak = b.sensor.iter().copied().fold(0.0, f64::max);
        for (x, y) in a.sensor.iter().zip(&b.sensor) {
            assert!((x - y).abs() <= 1e-9 * peak, "T={fold}: {x} vs {y}");
        }
        // Away from λ0 the fold matters.
        let c = chain.mono(
            PhaseOptics::DoubleMla,
            chain.heights_um(),
            l0 - 90.0,
            Incidence::Pixel(0),
        );
        let d = chain.mono(
            PhaseOptics::DoubleMla,
            &thick_h,
            l0 - 90.0,
            Incidence::Pixel(0),
        );
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
        PhaseOptics::DoubleMla,
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

/// Lemma 1 speaks of the continuous, unbinned OTF (conventions.md §7): the studio's single-mask
/// plate, as sampled by the chain, never raises the autocorrelation of the bare T-OLED's
/// aperture at any shift. (The pixel-binned sensor MTF may: aliasing is not covered.)
#[test]
fn lemma1_holds_for_the_studio_single_mask_on_the_unbinned_otf() {
    for (sampling, fold) in [
        (SamplingConvention::Thesis, 1.0),
        (SamplingConvention::Centred, 5.0),
    ] {
        let mut design = thesis(84.0, fold);
        design.sampling = sampling;
        let chain = Chain::new(&design, &PhaseSampling::preview()).unwrap();
        for nm in [470.0, 530.0, 610.0] {
            let bare = optical_mtf(&chain.aperture(PhaseOptics::Toled, &[], nm).unwrap());
            let masked = optical_mtf(
                &chain
                    .aperture(PhaseOptics::SingleMask, chain.heights_um(), nm)
                    .unwrap(),
            );
            assert_eq!(bare.len(), masked.len());
            // A phase mask passes all the light: equal at τ = 0 ...
            assert!((bare[0] - masked[0]).abs() < 1e-12);
            // ... and never more correlation at any shift; somewhere strictly less.
            let mut lower = 0;
            for (tau, (x, y)) in bare.iter().zip(&masked).enumerate() {
                assert!(*y <= *x + 1e-9, "{nm} nm, τ = {tau}: masked {y} > bare {x}");
                if *y < *x - 1e-3 {
                    lower += 1;
                }
            }
            assert!(
                lower > bare.len() / 10,
                "{nm} nm: the mask changed too little"
            );
        }
        assert!(chain.aperture(PhaseOptics::DoubleMla, &[], 530.0).is_err());
    }
}

/// Sum, value and 0-based index of the largest entry of a PSF normalised by `norm`.
fn summary(psf: &[f64], norm: f64) -> (f64, f64, usize) {
    let (at, peak) = psf
        .iter()
        .enumerate()
        .fold((0, f64::MIN), |a, (i, &v)| if v > a.1 { (i, v) } else { a });
    (psf.iter().sum::<f64>() / norm, peak / norm, at)
}

/// The thesis code's own numbers (issue 12): normal incidence at 530 nm, PSFs normalised by the
/// bare T-OLED's energy at the same λ over the 1024-pixel window, the invertibility score of
/// conventions.md §7 (DC + 511 positive frequencies). They depend on every detail of the sampling
/// convention: the axis on the left edge of pixel 512, 2.03 µm pixels, lenslets from the first
/// display sample, the slit at sample 1066 of 2800, the grating padded with ones.
#[test]
fn the_thesis_sampling_reproduces_the_thesis_codes_psfs() {
    let sampling = PhaseSampling::thesis();
    let check = |what: &str, got: f64, want: f64, tol: f64| {
        assert!(
            (got - want).abs() <= tol,
            "{what}: {got} vs the thesis's {want}"
        );
    };
    for (pitch, peak, at, score) in [(42.0, 0.1329, 512, 79.74), (168.0, 0.1725, 519, 112.64)] {
        let design = thesis(pitch, 1.0);
        assert_eq!(design.sampling, SamplingConvention::Thesis);
        let chain = Chain::new(&design, &sampling).unwrap();
        let t = chain.mono(PhaseOptics::Toled, &[], 530.0, Incidence::Pixel(0));
        let (sum, p, i) = summary(&t.sensor, t.window_energy);
        check("T-OLED Σ", sum, 1.0, 1e-12);
        check(&format!("T-OLED {pitch} µm peak"), p, peak, 5e-5);
        assert_eq!(i, at, "T-OLED {pitch} µm peak pixel");
        check(
            &format!("T-OLED {pitch} µm score"),
            invertibility_score(&t.sensor),
            score,
            5e-3,
        );
    }
    let mut design = thesis(42.0, 5.0);
    design.lambda0 = Lambda0::Fixed { nm: 530.0 };
    let chain = Chain::new(&design, &sampling).unwrap();
    let t = chain.mono(PhaseOptics::Toled, &[], 530.0, Incidence::Pixel(0));
    let ours = chain.mono(
        PhaseOptics::DoubleMla,
        chain.heights_um(),
        530.0,
        Incidence::Pixel(0),
    );
    let (sum, p, i) = summary(&ours.sensor, t.window_energy);
    check("double MLA Σ", sum, 4.1135, 5e-5);
    check("double MLA peak", p, 2.1647, 5e-5);
    assert_eq!(i, 512, "double MLA peak pixel");
    check(
        "double MLA score",
        invertibility_score(&ours.sensor),
        307.22,
        5e-3,
    );
}

/// The centred convention is a different model, not a rounding of the thesis's: its PSFs and V
/// differ by far more than the thesis's published precision.
#[test]
fn the_centred_sampling_differs_from_the_thesis() {
    let sampling = PhaseSampling::thesis();
    let psf = |convention, optics| {
        let mut d = thesis(168.0, 5.0);
        d.sampling = convention;
        let chain = Chain::new(&d, &sampling).unwrap();
        let p = chain.mono(optics, chain.heights_um(), 530.0, Incidence::Pixel(0));
        (
            invertibility_score(&p.sensor),
            summary(&p.sensor, p.window_energy),
        )
    };
    let (thesis_score, (_, thesis_peak, thesis_at)) =
        psf(SamplingConvention::Thesis, PhaseOptics::Toled);
    let (centred_score, (_, centred_peak, centred_at)) =
        psf(SamplingConvention::Centred, PhaseOptics::Toled);
    assert_eq!(thesis_at, 519);
    assert_ne!(centred_at, thesis_at, "the axis moved half a pixel");
    assert!(
        (thesis_peak - centred_peak).abs() > 0.01 && (thesis_score - centred_score).abs() > 1.0,
        "T-OLED 168 µm: thesis {thesis_peak}/{thesis_score}, centred {centred_peak}/{centred_score}"
    );
    let v = |convention| {
        let mut d = thesis(42.0, 1.0);
        d.sampling = convention;
        v_matrix_on(
            &d,
            &PhaseSampling::preview(),
            &[451.0, 651.0],
            &[451.0, 651.0],
            &Progress::new(),
        )
        .unwrap()
        .v
    };
    let (a, b) = (
        v(SamplingConvention::Thesis),
        v(SamplingConvention::Centred),
    );
    let off = (a[0][1] - b[0][1]).abs() / a[0][1];
    assert!(
        off > 0.02,
        "V off the diagonal: thesis {} centred {}",
        a[0][1],
        b[0][1]
    );
}
#[test]
fn the_optimized_allocation_is_a_barrier_optimum_and_beats_fixed_530() {
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
        "optimized {:?} vs fixed {:?}",
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
            PhaseOptics::DoubleMla,
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
        udc_core::phase::kernel_matrix(&design, &sampling, &channel, optics, &Progress::new())
            .unwrap()
    };
    let (ours, toled) = (kernels(PhaseOptics::DoubleMla), kernels(PhaseOptics::Toled));
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
            PhaseOptics::DoubleMla,
            chain.heights_um(),
            530.0,
            Incidence::Pixel(j_rel),
        );
        for i in 0..256 {
            assert!((ours[[i, j]] - psf.sensor[i]).abs() <= 1e-12, "K[{i}, {j}]");
        }
        // The bare T-OLED images direction j where a plain lens does (pixel ⌊j·2/2.03⌋ under
        // the thesis sampling); each lenslet pair is a 1:1 Keplerian telescope that inverts
        // the angle, so the double MLA's light lands near −j.
        let t = toled.column(j).to_vec();
        let argmax = (0..256).max_by(|&a, &b| t[a].total_cmp(&t[b])).unwrap();
        let image = Incidence::Pixel(j_rel).image_pixel(&design);
        assert_eq!(image, (j_rel as f64 * 2.0 / 2.03).floor() as i64);
        assert_eq!(argmax as i64, 128 + image);
        let c = centroid(ours.column(j).to_vec());
        eprintln!("j {j_rel}: centroid {c}");
        assert!(
            (c + j_rel as f64).abs() < 6.0,
            "direction {j_rel}: centroid at {c}"
        );
    }
}

/// The identities the allocation's comparisons rest on: a plan with every lenslet at grid
/// wavelength j scores A's column j (so "fixed 530 nm" scores the 531 nm column, index 13);
/// scores are linear in the counts; rounding keeps the lenslet count.
#[test]
fn allocation_identities_hold() {
    use udc_core::phase::geometry::round_to_total;
    use udc_core::phase::geometry::uniform_counts;
    let a: Vec<Vec<f64>> = (0..3)
        .map(|c| {
            (0..GRID_LEN)
                .map(|j| 0.2 + 0.8 * ((j as f64 * 0.37 + c as f64).sin().abs()))
                .collect()
        })
        .collect();
    let grid = wavelength_grid_nm();
    let at531 = grid.iter().position(|&l| l == 531.0).unwrap();
    assert_eq!(at531, 13);
    let mut fixed = vec![0; GRID_LEN];
    fixed[at531] = 58;
    let got = channel_invertibility(&a, &fixed);
    let studio = udc_core::phase::allocate::plan_invertibility(&a, &[530.0; 58]);
    for c in 0..3 {
        assert!((got[c] - a[c][at531]).abs() < 1e-15);
        // The studio's per-lenslet scoring of a fixed 530 nm plate uses the same 531 nm row.
        assert!((studio[c] - a[c][at531]).abs() < 1e-12);
    }
    // Linear in the counts: half the lenslets at j, half at k is the mean of the two columns.
    let mut split = vec![0; GRID_LEN];
    split[3] = 29;
    split[20] = 29;
    let got = channel_invertibility(&a, &split);
    for c in 0..3 {
        assert!((got[c] - 0.5 * (a[c][3] + a[c][20])).abs() < 1e-15);
    }
    for lenslets in [17, 31, 45, 58, 61] {
        let u = uniform_counts(lenslets);
        assert_eq!(u.iter().sum::<usize>(), lenslets);
        assert!(u.iter().max().unwrap() - u.iter().min().unwrap() <= 1);
        let shares: Vec<f64> = (0..GRID_LEN)
            .map(|j| (j as f64 * 0.7).cos().abs() * 3.0)
            .collect();
        let total = shares.iter().sum::<f64>().round() as usize + 2;
        assert_eq!(round_to_total(&shares, total).iter().sum::<usize>(), total);
    }
}

/// With floored 0.2 µm steps the plate's tallest point is the top level below the 1.029 µm fold.
#[test]
fn a_floored_plate_is_no_taller_than_its_top_level() {
    let mut d = thesis(42.0, 1.0);
    d.height_step_um = Some(0.2);
    let lenslets = udc_core::phase::Lenslets::new(&d).unwrap();
    assert!((lenslets.max_height_um(&d) - 1.0).abs() < 1e-12);
    d.height_step_um = None;
    let fold = 0.53 / 0.515;
    assert!((lenslets.max_height_um(&d) - fold).abs() < 1e-12);
}

/// Many directions at one wavelength through one plate (what the imaging operator sends) give
/// each direction's PSF exactly as one call per direction does: the plate's transmission formed
/// once is the one each call would form. A cancelled run stops.
#[test]
fn directions_through_one_plate_equal_one_call_per_direction() {
    let mut design = thesis(42.0, 5.0);
    // λ0 spread over 400–700 nm: the plate's transmission differs from lenslet to lenslet.
    design.lambda0 = Lambda0::Uniform;
    let sampling = PhaseSampling::preview();
    let chain = Chain::new(&design, &sampling).unwrap();
    let incidences: Vec<Incidence> = [-300, -40, 0, 7, 511]
        .into_iter()
        .map(Incidence::Pixel)
        .collect();
    for optics in [PhaseOptics::DoubleMla, PhaseOptics::Toled] {
        for wavelength in [471.0, 611.0] {
            let many = chain
                .mono_directions(
                    optics,
                    chain.heights_um(),
                    wavelength,
                    &incidences,
                    &Progress::new(),
                )
                .unwrap();
            assert_eq!(many.len(), incidences.len());
            for (psf, &incidence) in many.iter().zip(&incidences) {
                let one = chain.mono(optics, chain.heights_um(), wavelength, incidence);
                assert_eq!(psf, &one, "{optics:?} {wavelength} nm {incidence:?}");
                assert!(one.window_energy > 0.0);
            }
            // Directions differ: a PSF repeated for every direction would pass the loop above
            // only if `mono` ignored the direction too.
            assert_ne!(many[1].sensor, many[3].sensor);
        }
    }
    let cancelled = Progress::new();
    cancelled.cancel();
    let err = chain
        .mono_directions(
            PhaseOptics::DoubleMla,
            chain.heights_um(),
            530.0,
            &incidences,
            &cancelled,
        )
        .unwrap_err();
    assert!(matches!(err, SimError::Cancelled), "{err}");
}
