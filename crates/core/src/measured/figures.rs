//! A measured PSF against the design's, as figure panels (`crate::figure`): the profiles
//! through the axis, the MTFs (radial minimum and mean) of both, both PSFs side by side and the
//! residual map.

use std::sync::Arc;

use super::compare::ChannelComparison;
use crate::figure::{Axis, ColorScale, Colormap, Mark, Panel, Series, palette};

/// The measured and simulated rows through the axis on a log scale, in µm from the axis.
pub fn profile_panel(c: &ChannelComparison, pixel_um: f64, channel: &str) -> Panel {
    let n = c.measured.nrows();
    let mid = n / 2;
    let row = |a: &ndarray::Array2<f64>| -> Vec<[f64; 2]> {
        (0..n)
            .filter(|x| a[[mid, *x]] > 0.0)
            .map(|x| [(x as f64 - mid as f64) * pixel_um, a[[mid, x]].log10()])
            .collect()
    };
    Panel {
        title: format!("Profile through the axis, {channel}"),
        x: Axis::new("x", Some("µm")),
        y: Axis::log10("PSF (share of the light per pixel)", None),
        series: vec![
            Series::new("measured", palette::series(0), Mark::Line, row(&c.measured)),
            Series::new(
                "design (simulated)",
                palette::REFERENCE,
                Mark::DashedLine,
                row(&c.simulated),
            ),
        ],
        ..Panel::default()
    }
}

/// The radially-minimum and mean MTFs of both, against the frequency in cycles/pixel, with the
/// AUCs in the legend.
pub fn mtf_panel(c: &ChannelComparison, channel: &str) -> Panel {
    let curve = |v: &[f64], f: &[f64]| -> Vec<[f64; 2]> {
        f.iter().zip(v).map(|(f, m)| [*f, *m]).collect()
    };
    let (m, s) = (&c.mtf_measured, &c.mtf_simulated);
    let (fm, fs) = (m.freqs_cyc_per_px(), s.freqs_cyc_per_px());
    Panel {
        title: format!("MTF, {channel}"),
        x: Axis::new("frequency", Some("cycles/pixel")),
        y: Axis::new("MTF", None),
        series: vec![
            Series::new(
                format!("measured, radial min (AUC {:.4})", m.auc_radial_min),
                palette::series(0),
                Mark::Line,
                curve(&m.radial_min, &fm),
            ),
            Series::new(
                "measured, radial mean",
                palette::series(0),
                Mark::FaintLine,
                curve(&m.radial_mean, &fm),
            ),
            Series::new(
                format!("design, radial min (AUC {:.4})", s.auc_radial_min),
                palette::REFERENCE,
                Mark::DashedLine,
                curve(&s.radial_min, &fs),
            ),
            Series::new(
                "design, radial mean",
                palette::REFERENCE,
                Mark::DottedLine,
                curve(&s.radial_mean, &fs),
            ),
        ],
        ..Panel::default()
    }
}

/// How far below the measured peak the PSF pictures reach: a bracket of three exposures
/// leaves its background noise about five decades down, and a deeper scale would only draw it.
pub const FLOOR_DECADES: f64 = 5.0;

/// Which of a comparison's two PSFs a picture shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// The measured PSF.
    Measured,
    /// The design's, simulated on the measurement's grid and aligned to it.
    Design,
}

/// One of the two PSFs as a picture in µm about the axis, on a log scale from the measured
/// peak down to `floor_decades` below it: both sides share the scale, so the brighter orders
/// and halo read as brighter.
pub fn psf_panel(
    c: &ChannelComparison,
    side: Side,
    pixel_um: f64,
    channel: &str,
    floor_decades: f64,
) -> Panel {
    let (values, what) = match side {
        Side::Measured => (&c.measured, "measured"),
        Side::Design => (&c.simulated, "design"),
    };
    let peak = c.measured.iter().fold(0.0f64, |m, v| m.max(*v));
    let image = crate::views::centred_image(
        &format!("{what} PSF"),
        Arc::new(values.clone()),
        pixel_um,
        ColorScale::Log {
            reference: peak,
            floor_decades,
        },
        Colormap::Inferno,
    );
    Panel {
        title: format!("{channel}, {what}"),
        x: Axis::new("x", Some("µm")),
        y: Axis::new("y", Some("µm")),
        images: vec![image],
        equal_aspect: true,
        ..Panel::default()
    }
}

/// The residual `measured − simulated` as a picture in µm about the axis, on a linear scale
/// of its largest magnitude.
pub fn residual_panel(c: &ChannelComparison, pixel_um: f64, channel: &str) -> Panel {
    let top = c.residual.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // |residual|: where the two differ, whatever the sign.
    let magnitude = Arc::new(c.residual.mapv(f64::abs));
    let image = crate::views::centred_image(
        "|measured − design|",
        magnitude,
        pixel_um,
        ColorScale::Linear { max: top },
        Colormap::Inferno,
    );
    Panel {
        title: format!(
            "Residual, {channel}: {:.1} % of the measured PSF's energy",
            100.0 * c.residual_energy_share
        ),
        x: Axis::new("x", Some("µm")),
        y: Axis::new("y", Some("µm")),
        images: vec![image],
        equal_aspect: true,
        ..Panel::default()
    }
}
