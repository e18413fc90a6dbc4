//! The Theory view's figures: the simulated PSF profile (or diffraction orders) over the closed
//! form, and the horizontal MTF slice over the theory's, each opening on the part of the
//! pattern worth reading (a few lobes, the aperture's cutoff).

use super::{ProfileKind, TheoryComparison};
use crate::design::Theory;
use crate::figure::{Axis, Mark, Panel, Rgb, Series, palette};

/// Values below this fraction of the peak sit on the floor of the log profile.
pub const LOG_FLOOR: f64 = 1e-6;

/// How far from the axis the profile opens, µm: a few lobes of the pattern at `λ f`
/// (`lf_um2`, µm²); `None` for a grating (its orders span the window).
pub fn profile_extent_um(theory: Theory, lf_um2: f64) -> Option<f64> {
    match theory {
        Theory::Slit { width_um } | Theory::Rectangle { width_um, .. } => {
            Some(6.0 * lf_um2 / width_um)
        }
        Theory::DoubleSlit { width_um, .. } => Some(3.0 * lf_um2 / width_um),
        Theory::Circle { diameter_um } => Some(5.0 * 1.22 * lf_um2 / diameter_um),
        Theory::Grating => None,
    }
}

/// Channel `name`'s simulated profile (in `colour`) over the closed form (dashed, or hollow
/// markers at the orders), against the position on the sensor; the profile in decades
/// (floored at [`LOG_FLOOR`]) when `log`. `lf_um2`: the channel's `λ f` in µm².
pub fn profile_panel(
    c: &TheoryComparison,
    name: &str,
    colour: Rgb,
    lf_um2: f64,
    log: bool,
) -> Panel {
    let log = log && c.kind != ProfileKind::Orders;
    let value = |v: f64| if log { v.max(LOG_FLOOR).log10() } else { v };
    let pts = |v: &[f64]| -> Vec<[f64; 2]> {
        c.x_um.iter().zip(v).map(|(x, y)| [*x, value(*y)]).collect()
    };
    let (ours, theirs) = match c.kind {
        ProfileKind::Orders => (Mark::Points, Mark::Hollow),
        ProfileKind::ColumnSums | ProfileKind::AxisRow => (Mark::Line, Mark::DashedLine),
    };
    let mut x = Axis::new("position on the sensor, x", Some("µm"));
    if let Some(e) = profile_extent_um(c.theory, lf_um2) {
        x = x.with_view(-e, e);
    }
    let y = if log {
        Axis::log10(c.kind.label(), None).with_view(LOG_FLOOR.log10(), 0.1)
    } else {
        Axis::new(c.kind.label(), None)
    };
    Panel {
        title: format!("{name}: simulation over {}", c.theory.name()),
        x,
        y,
        series: vec![
            Series::new(format!("{name} simulated"), colour, ours, pts(&c.simulated)),
            Series::new("theory", palette::REFERENCE, theirs, pts(&c.predicted)),
        ],
        ..Panel::default()
    }
}

/// The horizontal MTF slice of the simulation over the theory's, opening a little past the
/// frequency where the theory falls below 10⁻³ (a slit's MTF ends at 0.07 cycles/pixel);
/// `None` when the comparison has no MTF.
pub fn mtf_panel(c: &TheoryComparison, name: &str, colour: Rgb) -> Option<Panel> {
    let m = c.mtf.as_ref()?;
    let last = m
        .predicted
        .iter()
        .rposition(|v| *v > 1e-3)
        .and_then(|i| m.freqs_cyc_per_px.get(i + 1))
        .map_or(0.5, |f| (1.3 * f).min(0.5));
    let pts = |v: &[f64]| -> Vec<[f64; 2]> {
        m.freqs_cyc_per_px
            .iter()
            .zip(v)
            .map(|(f, y)| [*f, *y])
            .collect()
    };
    Some(Panel {
        title: format!("{name}: MTF over {}", c.theory.name()),
        x: Axis::new("spatial frequency along x", Some("cycles/pixel")).with_view(0.0, last),
        y: Axis::new("MTF", None).with_view(0.0, 1.05),
        series: vec![
            Series::new(
                format!("{name} simulated"),
                colour,
                Mark::Line,
                pts(&m.simulated),
            ),
            Series::new(
                "theory",
                palette::REFERENCE,
                Mark::DashedLine,
                pts(&m.predicted),
            ),
        ],
        ..Panel::default()
    })
}
