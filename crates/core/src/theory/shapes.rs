//! The closed-form Fraunhofer patterns, each normalised to unit total light, and their
//! integration over sensor pixels on the simulation's own fine samples.

use super::{Theory, sinc};
use crate::psf::sampling::WavelengthSampling;

/// The light per unit length along x (integrated over y, unit total) of a slit, double slit or
/// rectangle at `x_um` from the axis; `lf_um2` is `λ f` in µm². Other shapes give 0.
pub(super) fn marginal_x(theory: Theory, x_um: f64, lf_um2: f64) -> f64 {
    match theory {
        Theory::Slit { width_um: a } | Theory::Rectangle { width_um: a, .. } => {
            // ∫ sinc²(a x / λf) dx = λf / a.
            a / lf_um2 * sinc(a * x_um / lf_um2).powi(2)
        }
        Theory::DoubleSlit {
            width_um: a,
            separation_um: d,
        } => {
            // cos² = (1 + cos 2πdu/a)/2 and sinc²'s transform is a triangle: for d ≥ a the
            // cosine term integrates to 0, so the total is λf / (2a).
            let fringe = (std::f64::consts::PI * d * x_um / lf_um2).cos().powi(2);
            2.0 * a / lf_um2 * sinc(a * x_um / lf_um2).powi(2) * fringe
        }
        Theory::Circle { .. } | Theory::Grating => 0.0,
    }
}

/// The Airy pattern of a circular opening of diameter `diameter_um` at radius `r_um`, per unit
/// area with unit total light: `(π D² / 4) / (λf)² · [2 J1(v) / v]²`, `v = π D r / (λf)`.
pub(super) fn airy(diameter_um: f64, r_um: f64, lf_um2: f64) -> f64 {
    let v = std::f64::consts::PI * diameter_um * r_um / lf_um2;
    let shape = if v.abs() < 1e-9 {
        1.0
    } else {
        (2.0 * libm::j1(v) / v).powi(2)
    };
    std::f64::consts::PI * diameter_um * diameter_um / 4.0 / (lf_um2 * lf_um2) * shape
}

/// The triangle `max(0, 1 − |t|)`: the autocorrelation of a unit box.
fn triangle(t: f64) -> f64 {
    (1.0 - t.abs()).max(0.0)
}

/// The optical MTF along x (`ν_y = 0`) of the shape at `nu_cyc_per_um`: the aperture's
/// autocorrelation at shift `λf ν`, normalised to 1 at 0. `None` for the grating.
pub(super) fn mtf_x(theory: Theory, nu_cyc_per_um: f64, lf_um2: f64) -> Option<f64> {
    let shift_um = lf_um2 * nu_cyc_per_um;
    match theory {
        Theory::Slit { width_um: a } | Theory::Rectangle { width_um: a, .. } => {
            Some(triangle(shift_um / a))
        }
        Theory::DoubleSlit {
            width_um: a,
            separation_um: d,
        } => Some(
            triangle(shift_um / a)
                + 0.5 * triangle((shift_um - d) / a)
                + 0.5 * triangle((shift_um + d) / a),
        ),
        Theory::Circle { diameter_um } => {
            // The overlap of two discs, the textbook diffraction-limited MTF.
            let s = (shift_um / diameter_um).abs();
            Some(if s >= 1.0 {
                0.0
            } else {
                2.0 / std::f64::consts::PI * (s.acos() - s * (1.0 - s * s).sqrt())
            })
        }
        Theory::Grating => None,
    }
}

/// The MTF of integrating `samples` fine samples `fine_um` apart into one pixel, at
/// `nu_cyc_per_um`: `|sin(π ν n δ) / (n sin(π ν δ))|`.
pub(super) fn pixel_mtf(nu_cyc_per_um: f64, samples: usize, fine_um: f64) -> f64 {
    let x = std::f64::consts::PI * nu_cyc_per_um * fine_um;
    if x.sin().abs() < 1e-12 {
        return 1.0;
    }
    ((samples as f64 * x).sin() / (samples as f64 * x.sin())).abs()
}

/// The fine-sample offsets (from the axis sample) that sensor pixel `j` integrates along
/// `axis` (0 = x, 1 = y), as the simulation bins them (`Binning::pixel_of`).
fn samples_of_pixel(ws: &WavelengthSampling, j: usize, axis: usize) -> std::ops::Range<i64> {
    let b = &ws.binning;
    let spp = b.samples_per_px as i64;
    let start = (j as i64 - (b.window_px / 2) as i64) * spp - b.phase[axis] as i64;
    start..start + spp
}

/// `f(x)` integrated over each sensor pixel of the window along x, on the fine samples.
pub(super) fn binned_line(ws: &WavelengthSampling, f: impl Fn(f64) -> f64) -> Vec<f64> {
    (0..ws.binning.window_px)
        .map(|j| {
            samples_of_pixel(ws, j, 0)
                .map(|s| f(s as f64 * ws.fine_um) * ws.fine_um)
                .sum()
        })
        .collect()
}

/// `f(r)` integrated over each sensor pixel of the axis row, on the fine samples.
pub(super) fn binned_axis_row(ws: &WavelengthSampling, f: impl Fn(f64) -> f64) -> Vec<f64> {
    let rows = samples_of_pixel(ws, ws.binning.window_px / 2, 1);
    let area = ws.fine_um * ws.fine_um;
    (0..ws.binning.window_px)
        .map(|j| {
            let mut sum = 0.0;
            for sy in rows.clone() {
                for sx in samples_of_pixel(ws, j, 0) {
                    let r = (sx as f64 * ws.fine_um).hypot(sy as f64 * ws.fine_um);
                    sum += f(r) * area;
                }
            }
            sum
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each pattern holds unit light: the normalisations the spectral weighting relies on.
    #[test]
    fn every_pattern_integrates_to_one() {
        let lf = 5300.0;
        let dx = 0.05;
        for t in [
            Theory::Slit { width_um: 200.0 },
            Theory::DoubleSlit {
                width_um: 100.0,
                separation_um: 400.0,
            },
            Theory::Rectangle {
                width_um: 420.0,
                height_um: 100.0,
            },
        ] {
            // sinc² tails fall as 1/x²: ±20 mm leaves < 0.1 % outside.
            let total: f64 = (-400_000..400_000)
                .map(|k| marginal_x(t, k as f64 * dx, lf) * dx)
                .sum();
            assert!((total - 1.0).abs() < 2e-3, "{t:?}: {total}");
        }
        let dr = 0.02;
        let total: f64 = (0..200_000)
            .map(|k| {
                let r = (k as f64 + 0.5) * dr;
                airy(600.0, r, lf) * 2.0 * std::f64::consts::PI * r * dr
            })
            .sum();
        assert!((total - 1.0).abs() < 2e-3, "Airy: {total}");
    }

    /// The MTF closed forms at their landmarks: 1 at 0, cut off at a/λf (slit) and D/λf
    /// (circle), the double slit's side peaks at d/λf half as high as its centre.
    #[test]
    fn mtf_closed_forms_have_their_cutoffs() {
        let lf = 5300.0;
        let slit = Theory::Slit { width_um: 200.0 };
        assert_eq!(mtf_x(slit, 0.0, lf), Some(1.0));
        assert_eq!(mtf_x(slit, 200.0 / lf, lf), Some(0.0));
        let circle = Theory::Circle { diameter_um: 600.0 };
        assert!((mtf_x(circle, 0.0, lf).unwrap_or(0.0) - 1.0).abs() < 1e-12);
        assert_eq!(mtf_x(circle, 600.0 / lf, lf), Some(0.0));
        let ds = Theory::DoubleSlit {
            width_um: 100.0,
            separation_um: 400.0,
        };
        assert_eq!(mtf_x(ds, 400.0 / lf, lf), Some(0.5));
        assert_eq!(mtf_x(ds, 250.0 / lf, lf), Some(0.0));
        assert_eq!(mtf_x(Theory::Grating, 0.0, lf), None);
        // A 2-µm pixel of four 0.5-µm samples: zero at 1 cycle/pixel, 1/(4 sin π/8) at 0.5.
        assert!(pixel_mtf(0.5, 4, 0.5) < 1e-12);
        let nyquist = 1.0 / (4.0 * (std::f64::consts::PI / 8.0).sin());
        assert!((pixel_mtf(0.25, 4, 0.5) - nyquist).abs() < 1e-12);
    }

    /// The textbook landmarks: slit zeros at λf/a, the Airy ring at 1.22 λf/D.
    #[test]
    fn zeros_sit_where_the_textbook_puts_them() {
        let lf = 5300.0;
        let slit = Theory::Slit { width_um: 200.0 };
        assert!(marginal_x(slit, lf / 200.0, lf) < 1e-12 * marginal_x(slit, 0.0, lf) + 1e-20);
        let ring = 1.2197 * lf / 600.0;
        assert!(airy(600.0, ring, lf) < 1e-6 * airy(600.0, 0.0, lf));
        assert!(airy(600.0, 0.8 * ring, lf) > 1e-3 * airy(600.0, 0.0, lf));
        // A double slit's first fringe minimum at λf/(2d).
        let ds = Theory::DoubleSlit {
            width_um: 100.0,
            separation_um: 400.0,
        };
        assert!(marginal_x(ds, lf / 800.0, lf) < 1e-12);
    }
}
