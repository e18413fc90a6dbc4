//! The Fourier-optics presets against their closed-form patterns: theory and simulation agree
//! on every teaching preset, and stop agreeing once the symmetry is broken.

use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_core::theory::{ProfileKind, Theory, compare};
use udc_core::{Design, Progress};
use udc_io::design::file::to_json;
use udc_io::design::presets::{PRESETS, PresetGroup, load_preset};

fn full(d: &Design) -> udc_core::Analysis {
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    analyze_with(d, &options, &Progress::new()).expect("teaching presets analyse")
}

/// Largest deviation over the channels, relative to the predicted peak.
fn deviation(d: &Design) -> f64 {
    let a = full(d);
    let theory = d.theory.expect("a teaching preset has a theory");
    (0..a.channels.len())
        .map(|c| compare(d, theory, &a, c).expect("comparable").deviation)
        .fold(0.0, f64::max)
}

#[test]
fn every_teaching_preset_agrees_with_its_formula() {
    // Shapes agree to 0.1 % (the circle's 96-gon on 24-µm cells is the worst); an order keeps
    // ~1 % less than theory in its cell because the lens's own Airy pattern spills it into the
    // neighbours. A zero or an order in the wrong place costs tens of percent.
    let tolerance = [
        ("fourier-slit", 0.005),
        ("fourier-double-slit", 0.005),
        ("fourier-square", 0.005),
        ("fourier-circle", 0.005),
        ("fourier-grating", 0.02),
        ("fourier-periodic", 0.02),
    ];
    let teaching: Vec<&str> = PRESETS
        .iter()
        .filter(|p| p.group == PresetGroup::FourierOptics)
        .map(|p| p.name)
        .collect();
    assert_eq!(
        teaching.len(),
        tolerance.len() + 1,
        "fourier-random is checked below"
    );
    for (name, tol) in tolerance {
        let d = load_preset(name).unwrap();
        let dev = deviation(&d);
        assert!(
            dev < tol,
            "{name}: theory and simulation differ by {dev:.4}"
        );
    }
}

#[test]
fn the_apertures_mtf_matches_its_autocorrelation() {
    // The MTF is the aperture's autocorrelation: a triangle for a slit, three for a double
    // slit, the disc overlap for a circle, times the pixel's box. Left over: the window crop
    // of the PSF's tails and the disc's staircase (a few 0.1 %).
    for name in [
        "fourier-slit",
        "fourier-double-slit",
        "fourier-square",
        "fourier-circle",
    ] {
        let d = load_preset(name).unwrap();
        let a = full(&d);
        for c in 0..a.channels.len() {
            let m = compare(&d, d.theory.unwrap(), &a, c).unwrap().mtf.unwrap();
            assert!(
                m.deviation < 0.01,
                "{name} channel {c}: MTF off by {}",
                m.deviation
            );
        }
    }
}

#[test]
fn teaching_presets_are_design_files_with_a_theory() {
    for p in PRESETS
        .iter()
        .filter(|p| p.group == PresetGroup::FourierOptics)
    {
        let d = load_preset(p.name).unwrap();
        assert!(d.theory.is_some(), "{}", p.name);
        assert_eq!(
            p.text,
            to_json(&d),
            "{} is in the design_file format",
            p.name
        );
    }
}

#[test]
fn breaking_the_slit_breaks_the_agreement() {
    let mut d = load_preset("fourier-slit").unwrap();
    let n = d.opening.n();
    // Open a second, narrower slit beside the first: the sinc² no longer describes it.
    for row in d.opening.cells.iter_mut().take(n / 2 + 40).skip(n / 2 - 40) {
        row[n / 2 + 12] = 1.0;
    }
    let dev = deviation(&d);
    assert!(dev > 0.1, "an asymmetric opening still matches: {dev}");
}

#[test]
fn a_slit_grating_misses_the_orders_its_duty_cycle_predicts() {
    let d = load_preset("fourier-grating").unwrap();
    let a = full(&d);
    let c = compare(&d, Theory::Grating, &a, 1).unwrap();
    assert_eq!(c.kind, ProfileKind::Orders);
    let zero = c.x_um.iter().position(|x| x.abs() < 1e-9).unwrap();
    // Duty 1/5: order 5 is dark in theory and nearly so in the simulation.
    assert!(c.predicted[zero + 5] < 1e-12);
    assert!(c.simulated[zero + 5] < 0.02 * c.simulated[zero + 4]);
    assert!(c.simulated[zero + 4] > 0.005, "order 4 carries light");
}

#[test]
fn a_random_tiling_keeps_only_the_mean_tile_in_its_orders() {
    let periodic = load_preset("fourier-periodic").unwrap();
    let random = load_preset("fourier-random").unwrap();
    let (ap, ar) = (full(&periodic), full(&random));
    let cp = compare(&periodic, Theory::Grating, &ap, 1).unwrap();
    let cr = compare(&random, Theory::Grating, &ar, 1).unwrap();
    assert!(cp.note.is_none() && cr.note.is_some());
    // Same opening, same mean: theory gives both the same zero order and the random tiling
    // weaker first orders (the mean of its orientations diffracts less).
    let zero = cp.x_um.iter().position(|x| x.abs() < 1e-9).unwrap();
    assert!((cp.predicted[zero] - cr.predicted[zero]).abs() < 1e-12);
    assert!(cr.predicted[zero + 1] < 0.7 * cp.predicted[zero + 1]);
    // The simulation agrees: the first order's sharp peak (its brightest pixel) drops...
    let peak = |a: &udc_core::Analysis, x_um: f64| {
        let psf = &a.channels[1].psf;
        let w = psf.nrows();
        let j = (w / 2) as f64 + ((x_um + 0.25) / 2.0).floor();
        let j = j as usize;
        (w / 2 - 1..=w / 2 + 1)
            .flat_map(|i| (j - 1..=j + 1).map(move |j| (i, j)))
            .map(|(i, j)| psf[[i, j]])
            .fold(0.0, f64::max)
    };
    let x1 = cp.x_um[zero + 1];
    assert!(
        peak(&ar, x1) < 0.7 * peak(&ap, x1),
        "{} vs {}",
        peak(&ar, x1),
        peak(&ap, x1)
    );
    // ...while the light around it never falls below the coherent part: the halo only adds.
    for (s, p) in cr.simulated.iter().zip(&cr.predicted) {
        assert!(*s > 0.95 * p, "{s} < {p}");
    }
}

#[test]
fn every_formula_names_its_numbers() {
    let f = Theory::Slit { width_um: 216.0 }.formula(530.0, 10.0, 4200.0);
    assert!(f.contains("a = 216 µm") && f.contains("24.5 µm"), "{f}");
    let f = Theory::Circle { diameter_um: 600.0 }.formula(530.0, 10.0, 4200.0);
    assert!(f.contains("10.8 µm"), "{f}");
    let f = Theory::Grating.formula(530.0, 10.0, 160.0);
    assert!(f.contains("33.1 µm"), "{f}");
}

#[test]
fn the_psf_figure_marks_the_orders_where_the_light_is_and_the_airy_ring_at_1_22_lambda_f() {
    use udc_core::figure::Annotation;
    use udc_core::views::{Landmarks, PsfScale, psf_panel};
    let d = load_preset("fourier-periodic").unwrap();
    let a = full(&d);
    let ch = &a.channels[0];
    let which = Landmarks {
        airy: true,
        orders: true,
    };
    let panel = psf_panel(&d, &a, ch, PsfScale::Log { floor_decades: 6.0 }, which);
    let image = &panel.images[0];
    assert_eq!(
        image.value_at(0.0, 0.0),
        Some(udc_core::figure::peak(&ch.psf))
    );
    let mut checked = 0;
    for note in &panel.annotations {
        match note {
            Annotation::Ring { radius, .. } => {
                let want = 1.22 * ch.wavelength_nm * 1e-3 * d.optics.f_number;
                assert!(
                    (radius - want).abs() < 1e-12,
                    "Airy radius {radius} µm, want {want}"
                );
            }
            Annotation::Lattice { points, .. } => {
                // The first orders along x and y: each is brighter than the dark band halfway
                // to it, by an order of magnitude.
                let spacing = points
                    .iter()
                    .filter(|p| p[1] == 0.0 && p[0] > 0.0)
                    .map(|p| p[0])
                    .fold(f64::INFINITY, f64::min);
                for [x, y] in [[spacing, 0.0], [0.0, spacing], [-spacing, 0.0]] {
                    let on = image.value_at(x, y).unwrap();
                    let between = image.value_at(x / 2.0, y / 2.0).unwrap();
                    assert!(
                        on > 10.0 * between,
                        "order at ({x}, {y}): {on} vs {between}"
                    );
                }
                checked += 1;
            }
            _ => {}
        }
    }
    assert_eq!(checked, 1, "the orders were asked for");
}

#[test]
fn the_mtf_figure_rows_a_channel_each_and_rules_where_the_mtf_repeats() {
    use udc_core::figure::Mark;
    use udc_core::theory::landmarks::mtf_repeat_cyc_per_px;
    use udc_core::views::{MtfFamilies, mtf_curves_panel};
    let d = load_preset("fourier-periodic").unwrap();
    let b = full(&d);
    let panel = mtf_curves_panel(&b, Some(&b), MtfFamilies::default(), Some(&d));
    // A row per channel (min, mean, A's min), then the rules' row.
    assert_eq!(panel.legend_rows.len(), b.channels.len() + 1);
    for (row, ch) in panel.legend_rows.iter().zip(&b.channels) {
        assert_eq!(row.len(), 3, "{row:?}");
        assert!(row.iter().all(|n| n.contains(&ch.name)));
    }
    let ch = &b.channels[0];
    let nu = mtf_repeat_cyc_per_px(
        d.opening.pitch_um + d.tiling.wiring_gap_um,
        b.sensor_pixel_um,
        ch.wavelength_nm,
        d.optics.focal_length_mm,
    );
    let rules = panel
        .series
        .iter()
        .find(|s| s.mark == Mark::Rules && s.name.starts_with(&ch.name))
        .expect("the channel's rules");
    assert!((rules.points[0][0] - nu).abs() < 1e-12);
    assert!(rules.points.iter().all(|p| p[0] <= 0.5 + 1e-12));
    // The minimum curve is the analysis's, point for point.
    let min = panel
        .series
        .iter()
        .find(|s| s.name.starts_with(&format!("{} radial min", ch.name)))
        .expect("the minimum");
    assert_eq!(min.points.len(), ch.mtf.radial_min.len());
    assert_eq!(min.points[3][1], ch.mtf.radial_min[3]);
}
