//! The closed-form aperture a teaching design names (the Theory view compares with it): kept
//! with the design, which stores it, so the design does not depend on the theory's code.

use serde::{Deserialize, Serialize};

/// The analytic aperture a teaching design is compared with (stored in the design file as
/// `"theory"`). Positions are relative to the optical axis; `x` runs along the tile's columns.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Theory {
    /// One slit of width `a` along x, long along y: `I(x) ∝ sinc²(a x / λf)`.
    Slit {
        /// Slit width `a`, µm.
        width_um: f64,
    },
    /// Two slits of width `a` whose centres are `d` apart:
    /// `I(x) ∝ sinc²(a x / λf) · cos²(π d x / λf)`.
    DoubleSlit {
        /// Width `a` of each slit, µm.
        width_um: f64,
        /// Centre-to-centre separation `d`, µm.
        separation_um: f64,
    },
    /// A rectangle `a × b`: `I(x, y) ∝ sinc²(a x / λf) · sinc²(b y / λf)`.
    Rectangle {
        /// Width `a` along x, µm.
        width_um: f64,
        /// Height `b` along y, µm.
        height_um: f64,
    },
    /// A circular opening of diameter `D`: the Airy pattern `I(r) ∝ [2 J1(v) / v]²`,
    /// `v = π D r / (λf)`.
    Circle {
        /// Diameter `D`, µm.
        diameter_um: f64,
    },
    /// The display's own diffraction orders: the tile's Fourier coefficients `c(m, n)` put
    /// `|c(m, n)|²` of the light at `(m, n) · λf / P`; a random tiling keeps only the mean
    /// over its orientations coherent, the rest goes to a halo.
    Grating,
}

impl Theory {
    /// Every shape, in the order the UI lists them (parameters are placeholders).
    pub fn name(self) -> &'static str {
        match self {
            Theory::Slit { .. } => "single slit",
            Theory::DoubleSlit { .. } => "double slit",
            Theory::Rectangle { .. } => "rectangle",
            Theory::Circle { .. } => "circle (Airy)",
            Theory::Grating => "grating orders",
        }
    }

    /// The formula with this design's numbers, for a tooltip; `wavelength_nm` and
    /// `focal_length_mm` give the scale `λf`.
    pub fn formula(self, wavelength_nm: f64, focal_length_mm: f64, period_um: f64) -> String {
        let lf_um2 = wavelength_nm * focal_length_mm; // λ[µm]·f[µm] = λ[nm]·f[mm]
        let scale = format!("λ = {wavelength_nm:.0} nm, f = {focal_length_mm} mm");
        match self {
            Theory::Slit { width_um: a } => format!(
                "Single slit: I(x) = I(0)·sinc²(a·x / λf), a = {a} µm, {scale}.\n\
                 Dark fringes every λf/a = {:.1} µm; the central lobe is twice as wide.",
                lf_um2 / a
            ),
            Theory::DoubleSlit {
                width_um: a,
                separation_um: d,
            } => format!(
                "Double slit: I(x) = I(0)·sinc²(a·x / λf)·cos²(π·d·x / λf), a = {a} µm, d = {d} µm, \
                 {scale}.\nFringes every λf/d = {:.1} µm under a sinc² envelope whose zeros are \
                 λf/a = {:.1} µm apart.",
                lf_um2 / d,
                lf_um2 / a
            ),
            Theory::Rectangle {
                width_um: a,
                height_um: b,
            } => format!(
                "Rectangle: I(x, y) = I(0)·sinc²(a·x / λf)·sinc²(b·y / λf), a = {a} µm, b = {b} µm, \
                 {scale}.\nThe profile along x (summed over y) is sinc²(a·x / λf): zeros every \
                 λf/a = {:.1} µm.",
                lf_um2 / a
            ),
            Theory::Circle { diameter_um: dd } => format!(
                "Circular opening: I(r) = I(0)·[2·J1(v) / v]², v = π·D·r / (λf), D = {dd} µm, {scale}.\n\
                 First dark ring at r = 1.22·λf/D = {:.1} µm (the Airy disc).",
                1.22 * lf_um2 / dd
            ),
            Theory::Grating => format!(
                "Grating: orders at (m, n)·λf/P, P = {period_um:.1} µm, {scale}: {:.1} µm apart.\n\
                 Order (m, n) carries |c(m, n)|² of the light, c the tile's Fourier coefficients; \
                 for a slit of duty a/P, |c(m)|² = (a/P)²·sinc²(m·a/P), so orders at multiples \
                 of P/a are missing. A random tiling keeps only |mean c|² in the orders.",
                lf_um2 / period_um
            ),
        }
    }
}
