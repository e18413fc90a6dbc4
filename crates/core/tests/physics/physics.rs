//! Analytic references: Airy pattern, diffraction-limited MTF, Parseval, grating orders, symmetry.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common::{aperture_of, open_design};
use ndarray::Array2;
use udc_core::Progress;
use udc_core::analysis::analyze::analyze;
use udc_core::analysis::mtf::dft2;
use udc_core::design::{Channel, Opening, Optics};
use udc_core::psf::fft::full_intensity;
use udc_core::psf::sampling::fft_size;

fn optics(f_number: f64, fine_um: f64) -> Optics {
    Optics {
        recipe: udc_core::design::OpticsRecipe::Custom,
        focal_length_mm: 10.0,
        f_number,
        pupil_sample_um: 8.0,
        fine_sample_um: fine_um,
        sensor_pixel_um: 2.0,
        window_px: 64,
        axis_in_pixel_um: [0.0, 0.0],
    }
}

/// Fine PSF of a design at one wavelength, centred, with its fine spacing in µm.
fn fine_psf(design: &udc_core::Design, wavelength_nm: f64) -> (Array2<f64>, f64) {
    let o = &design.optics;
    let m = fft_size(
        wavelength_nm,
        o.focal_length_mm,
        o.pupil_sample_um,
        o.fine_sample_um,
    );
    let field = aperture_of(design);
    let psf = full_intensity(&field, m, &Progress::new()).expect("field fits");
    let spacing = wavelength_nm * o.focal_length_mm / (m as f64 * o.pupil_sample_um);
    (psf, spacing)
}

#[test]
fn circular_pupil_gives_the_airy_pattern() {
    // f/10 at 550 nm: first dark ring at 1.22 λ F# = 6.71 µm, sampled every 0.25 µm.
    let design = open_design(optics(10.0, 0.25), vec![Channel::peak("G", 550.0)]);
    let (psf, dx) = fine_psf(&design, 550.0);
    let m = psf.nrows();
    let c = m / 2;
    let peak = psf[[c, c]];
    let d_um = design.optics.pupil_diameter_um();
    let lf = 0.55 * 10_000.0;
    // Compare the central cut with (2 J1(v)/v)², v = π D x / (λ f), out to the third ring.
    let mut worst: f64 = 0.0;
    for k in 1..120 {
        let x = k as f64 * dx;
        let v = std::f64::consts::PI * d_um * x / lf;
        let airy = (2.0 * libm::j1(v) / v).powi(2);
        worst = worst.max((psf[[c, c + k]] / peak - airy).abs());
    }
    assert!(worst < 0.01, "Airy profile deviates by {worst} of the peak");
    // First minimum at 1.22 λ F#, to within one fine sample.
    let first_min = (1..60)
        .find(|&k| psf[[c, c + k]] < psf[[c, c + k - 1]] && psf[[c, c + k]] < psf[[c, c + k + 1]])
        .expect("a first dark ring");
    let want = 1.22 * 0.55 * 10.0;
    assert!(
        (first_min as f64 * dx - want).abs() <= dx,
        "first dark ring at {} µm, expected {want}",
        first_min as f64 * dx
    );
}

#[test]
fn optical_mtf_matches_the_diffraction_limited_formula() {
    // The DFT of the fine PSF is the pupil autocorrelation (eq. 3.5): for a disc it is
    // (2/π)(acos ν̂ − ν̂ √(1 − ν̂²)), ν̂ = ν λ F#.
    let design = open_design(optics(10.0, 1.0), vec![Channel::peak("G", 550.0)]);
    let (psf, dx) = fine_psf(&design, 550.0);
    let m = psf.nrows();
    let otf = dft2(&psf);
    let dc = otf[[0, 0]].norm();
    let cutoff = 1.0 / (0.55 * 10.0); // cycles/µm
    let mut worst: f64 = 0.0;
    for k in 0..m / 2 {
        let nu = k as f64 / (m as f64 * dx);
        let t = (nu / cutoff).min(1.0);
        let want = 2.0 / std::f64::consts::PI * (t.acos() - t * (1.0 - t * t).sqrt());
        worst = worst.max((otf[[0, k]].norm() / dc - want).abs());
        worst = worst.max((otf[[k, 0]].norm() / dc - want).abs());
    }
    assert!(worst < 0.01, "optical MTF deviates by {worst}");
}

#[test]
fn energy_is_conserved_from_pupil_to_sensor() {
    let design = open_design(optics(10.0, 1.0), vec![Channel::peak("G", 550.0)]);
    let (psf, _) = fine_psf(&design, 550.0);
    let m = psf.nrows() as f64;
    let field = aperture_of(&design);
    // Parseval for the unnormalised DFT: Σ|A|² = M² Σ|a|².
    let rel = (psf.sum() - m * m * field.energy()).abs() / psf.sum();
    assert!(rel < 1e-10, "Parseval off by {rel}");
    // The sensor PSF sums to 1 and reports the light that missed the window.
    let a = analyze(&design, &Progress::new()).expect("analysis");
    let ch = &a.channels[0];
    assert!((ch.psf.sum() - 1.0).abs() < 1e-12);
    assert!(ch.energy_in_window > 0.9 && ch.energy_in_window <= 1.0 + 1e-12);
    // A smaller window catches less light.
    let mut small = design.clone();
    small.optics.window_px = 8;
    let b = analyze(&small, &Progress::new()).expect("analysis");
    assert!(b.channels[0].energy_in_window < ch.energy_in_window - 0.01);
}

#[test]
fn slit_grating_puts_its_orders_at_lambda_f_over_t() {
    // Narrow vertical slits (1 cell of 8 µm) every T = 168 µm: orders along x at n·λf/T.
    let mut design = open_design(optics(2.5, 0.5), vec![Channel::peak("R", 610.0)]);
    design.opening = Opening::slit(21, 1, 168.0);
    let (psf, dx) = fine_psf(&design, 610.0);
    let c = psf.nrows() / 2;
    let order_um = 0.61 * 10_000.0 / 168.0;
    for n in 1..=4i64 {
        let want = n as f64 * order_um / dx;
        let lo = (want - 4.0) as usize;
        let best = (lo..lo + 9)
            .max_by(|a, b| psf[[c, c + a]].total_cmp(&psf[[c, c + b]]))
            .expect("non-empty range");
        assert!(
            (best as f64 - want).abs() <= 1.0,
            "order {n} at sample {best}, expected {want:.1}"
        );
        // A real order: far brighter than the midpoint between orders.
        let between = psf[[c, c + ((n as f64 - 0.5) * order_um / dx).round() as usize]];
        assert!(
            psf[[c, c + best]] > 100.0 * between,
            "order {n} is not a peak"
        );
    }
    // Along y the slit is fully open: no orders, the Airy core dominates.
    let y_order = (order_um / dx).round() as usize;
    assert!(psf[[c + y_order, c]] < 1e-3 * psf[[c, c]]);
}

#[test]
fn symmetric_openings_give_symmetric_psfs() {
    // A centred plus-shaped opening, tiled with the axis on the centre cell, 3 fine samples per
    // pixel with the axis in the middle one: the sensor PSF has the opening's D4 symmetry.
    let n = 21;
    let mut cells = vec![vec![0.0; n]; n];
    for (r, row) in cells.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            if (8..13).contains(&r) || (8..13).contains(&c) {
                *v = 1.0;
            }
        }
    }
    let mut design = open_design(optics(5.0, 0.5), vec![Channel::peak("G", 530.0)]);
    design.opening = Opening {
        pitch_um: 168.0,
        cells,
        polygons: vec![],
    };
    design.tiling.origin_offset_cells = [10.0, 10.0];
    design.optics.sensor_pixel_um = 1.5;
    design.optics.axis_in_pixel_um = [0.75, 0.75];
    design.optics.window_px = 65;
    let a = analyze(&design, &Progress::new()).expect("analysis");
    let p = &a.channels[0].psf;
    let w = p.nrows();
    let peak = p.iter().copied().fold(0.0, f64::max);
    for y in 0..w {
        for x in 0..w {
            let v = p[[y, x]];
            for other in [p[[y, w - 1 - x]], p[[w - 1 - y, x]], p[[x, y]]] {
                assert!((v - other).abs() < 1e-9 * peak, "asymmetry at ({y},{x})");
            }
        }
    }
    // …and a deliberately asymmetric opening does not.
    design.opening.cells[0][0] = 1.0;
    design.opening.cells[0][1] = 1.0;
    let b = analyze(&design, &Progress::new()).expect("analysis");
    let q = &b.channels[0].psf;
    let asym: f64 = (0..w)
        .map(|x| (q[[w / 2 + 3, x]] - q[[w / 2 + 3, w - 1 - x]]).abs())
        .sum();
    assert!(asym > 1e-9, "an asymmetric opening must break the symmetry");
}

#[test]
fn polychromatic_psf_is_the_energy_weighted_mix_of_its_wavelengths() {
    let one = |l: f64| {
        let d = open_design(optics(5.0, 1.0), vec![Channel::peak("G", l)]);
        let a = analyze(&d, &Progress::new()).unwrap();
        let c = &a.channels[0];
        (c.psf.clone(), c.energy_in_window)
    };
    let (p1, e1) = one(500.0);
    let (p2, e2) = one(600.0);
    let mixed = open_design(
        optics(5.0, 1.0),
        vec![Channel {
            name: "G".into(),
            wavelengths_nm: vec![500.0, 600.0],
            weights: vec![1.0, 3.0],
        }],
    );
    let a = analyze(&mixed, &Progress::new()).unwrap();
    let c = &a.channels[0];
    // Each wavelength weighs by its spectral weight times the light it put in the window.
    let (w1, w2) = (0.25 * e1, 0.75 * e2);
    let want = (&p1 * w1 + &p2 * w2) / (w1 + w2);
    let err = (&c.psf - &want).iter().map(|v| v.abs()).fold(0.0, f64::max);
    assert!(err < 1e-12, "max deviation {err}");
    assert!((c.energy_in_window - (w1 + w2)).abs() < 1e-12);
    assert_eq!(c.fft_sizes.len(), 2);
    assert!(
        (c.wavelength_nm - 575.0).abs() < 1e-9,
        "weighted mean wavelength"
    );
}
