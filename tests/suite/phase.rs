//! Phase masks (thesis chapter 4, PHYSICS.md §7): geometry, the folded plate, energy, FoV,
//! invertibility, Lemma 1 and the λ0 allocation.

use udc_studio::core::Progress;
use udc_studio::core::design::Channel;
use udc_studio::core::phase::geometry::lenslet_count;
use udc_studio::core::phase::{
    Chain, Incidence, Lambda0, Optics, PhaseDesign, PhaseSampling, Surface, phase_psfs,
};

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
