//! The phase-mask views' plots as figure panels (`crate::figure`): each channel's PSF beside the
//! bare T-OLED's (Fig. 4.6), the MTFs of all channels, and the folded plate's height profile
//! around a lenslet beside the unfolded lens (Fig. 4.3). Pure functions of the results; the
//! studio draws them.

use super::geometry::{Lenslets, profile_um};
use super::psf::{ChannelPsf, PhasePsfs};
use super::{PhaseDesign, Surface};
use crate::SimError;
use crate::figure::{Annotation, Axis, Mark, Panel, Rgb, Series, palette};

/// The smallest share a log-scale PSF plot shows: 10⁻⁹ of the light.
pub const LOG_FLOOR: f64 = 1e-9;

/// Samples across the height profile's three lenslets.
const PROFILE_SAMPLES: usize = 900;

/// The colour of channel `i` (R, G, B, then the series colours).
fn channel_colour(i: usize) -> Rgb {
    palette::CHANNELS
        .get(i)
        .copied()
        .unwrap_or_else(|| palette::series(i))
}

/// A series `name` through `ys`, against x.
fn series(name: String, colour: Rgb, mark: Mark, points: Vec<[f64; 2]>) -> Series {
    Series {
        name,
        colour,
        mark,
        points,
        band: None,
    }
}

/// Channel `index`'s PSF (`ours`: "double MLA" or "single mask") and the bare T-OLED's against
/// the sensor pixel from the axis, within `half_width_px` of it; as shares of the light, or
/// their log10 (floored at [`LOG_FLOOR`]) when `log`.
pub fn psf_panel(c: &ChannelPsf, index: usize, ours: &str, half_width_px: i64, log: bool) -> Panel {
    let points = |v: &[f64]| -> Vec<[f64; 2]> {
        let mid = (v.len() / 2) as i64;
        v.iter()
            .enumerate()
            .map(|(k, y)| (k as i64 - mid, *y))
            .filter(|(x, _)| x.abs() <= half_width_px)
            .map(|(x, y)| [x as f64, if log { y.max(LOG_FLOOR).log10() } else { y }])
            .collect()
    };
    Panel {
        title: format!("{} ({:.0} nm)", c.name, c.wavelength_nm),
        x: Axis::new("sensor pixel from the axis", None),
        y: Axis::new(if log { "log10 share" } else { "energy share" }, None),
        series: vec![
            series(
                ours.into(),
                channel_colour(index),
                Mark::Line,
                points(&c.psf),
            ),
            series(
                "T-OLED".into(),
                palette::REFERENCE,
                Mark::DashedLine,
                points(&c.toled_psf),
            ),
        ],
        annotations: Vec::new(),
        ..Panel::default()
    }
}

/// The one-sided MTFs of every channel (`ours` solid) and of the bare T-OLED (dashed), against
/// the frequency in cycles per pixel.
pub fn mtf_panel(psfs: &PhasePsfs, ours: &str) -> Panel {
    let points = |v: &[f64]| -> Vec<[f64; 2]> {
        let len = 2.0 * v.len() as f64;
        v.iter()
            .enumerate()
            .map(|(k, y)| [k as f64 / len, *y])
            .collect()
    };
    let series = psfs
        .channels
        .iter()
        .enumerate()
        .flat_map(|(i, c)| {
            [
                series(
                    format!("{} {ours}", c.name),
                    channel_colour(i),
                    Mark::Line,
                    points(&c.mtf),
                ),
                series(
                    format!("{} T-OLED", c.name),
                    channel_colour(i),
                    Mark::DashedLine,
                    points(&c.toled_mtf),
                ),
            ]
        })
        .collect();
    Panel {
        title: "MTF: ours solid, the bare T-OLED dashed (one-sided, window of 1024 pixels)".into(),
        x: Axis::new("frequency", Some("cycles/pixel")),
        y: Axis::new("MTF", None),
        series,
        annotations: Vec::new(),
        ..Panel::default()
    }
}

/// The folded plate's height across lenslet `selected` and its neighbours, beside the unfolded
/// lens, with the lenslets' edges marked.
///
/// # Errors
/// A design whose profile cannot be computed.
pub fn profile_panel(
    design: &PhaseDesign,
    lenslets: &Lenslets,
    selected: usize,
) -> Result<Panel, SimError> {
    let n = lenslets.count();
    let lo = selected.saturating_sub(1);
    let hi = (selected + 1).min(n.saturating_sub(1));
    let x0 = lenslets.centre_um(lo) - design.pitch_um / 2.0;
    let x1 = lenslets.centre_um(hi) + design.pitch_um / 2.0;
    let xs: Vec<f64> = (0..=PROFILE_SAMPLES)
        .map(|k| x0 + (x1 - x0) * k as f64 / PROFILE_SAMPLES as f64)
        .collect();
    let profile = |surface: Surface| -> Result<Vec<[f64; 2]>, SimError> {
        let mut d = design.clone();
        d.surface = surface;
        Ok(xs
            .iter()
            .zip(profile_um(&d, &xs)?)
            .map(|(x, h)| [*x, h])
            .collect())
    };
    let edges = (lo..=hi + 1).map(|l| Annotation::VLine {
        x: x0 + (l - lo) as f64 * design.pitch_um,
        label: "lenslet edges".into(),
    });
    Ok(Panel {
        title: format!("Height profile around lenslet {selected}"),
        x: Axis::new("x from the axis", Some("µm")),
        y: Axis::new("height", Some("µm")),
        series: vec![
            series(
                "folded plate".into(),
                palette::series(0),
                Mark::Line,
                profile(Surface::Folded)?,
            ),
            series(
                "unfolded lens".into(),
                palette::REFERENCE,
                Mark::DashedLine,
                profile(Surface::Unfolded)?,
            ),
        ],
        annotations: edges.collect(),
        ..Panel::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel() -> ChannelPsf {
        let mut psf = vec![0.0; 11];
        psf[5] = 0.6;
        psf[4] = 0.2;
        psf[6] = 0.2;
        ChannelPsf {
            name: "G".into(),
            wavelength_nm: 530.0,
            toled_psf: vec![1.0 / 11.0; 11],
            mtf: vec![1.0, 0.5],
            toled_mtf: vec![1.0, 0.2],
            psf,
            ..ChannelPsf::default()
        }
    }

    /// The PSF panel centres the array on the axis, keeps the window asked for, and the log
    /// scale floors empty pixels instead of dropping them.
    #[test]
    fn the_psf_panel_is_centred_windowed_and_floored() {
        let c = channel();
        let p = psf_panel(&c, 1, "double MLA", 2, false);
        assert_eq!(
            p.series[0].points,
            vec![[-2.0, 0.0], [-1.0, 0.2], [0.0, 0.6], [1.0, 0.2], [2.0, 0.0]]
        );
        assert_eq!(p.series[1].mark, Mark::DashedLine);
        assert_eq!(p.series[0].colour, palette::CHANNELS[1]);
        let log = psf_panel(&c, 1, "double MLA", 2, true);
        assert_eq!(log.series[0].points[0], [-2.0, LOG_FLOOR.log10()]);
        assert!((log.series[0].points[2][1] - 0.6f64.log10()).abs() < 1e-12);
    }

    /// The MTF's frequencies are `k / P` cycles per pixel, `P` twice the one-sided length.
    #[test]
    fn the_mtf_panel_puts_each_sample_at_its_frequency() {
        let psfs = PhasePsfs {
            channels: vec![channel()],
            ..PhasePsfs::default()
        };
        let p = mtf_panel(&psfs, "double MLA");
        assert_eq!(p.series.len(), 2);
        assert_eq!(p.series[0].points, vec![[0.0, 1.0], [0.25, 0.5]]);
        assert_eq!(p.series[1].points, vec![[0.0, 1.0], [0.25, 0.2]]);
        assert_eq!(p.x.unit.as_deref(), Some("cycles/pixel"));
    }

    /// The profile spans the selected lenslet and its neighbours, one pitch apart at the edges,
    /// and the folded plate is never thicker than the unfolded lens.
    #[test]
    fn the_profile_panel_spans_three_lenslets_and_folds_below_the_lens() {
        let d = PhaseDesign::thesis(42.0, 1.0);
        let lenslets = Lenslets::new(&d).expect("lenslets");
        let p = profile_panel(&d, &lenslets, 5).expect("profile");
        let edges: Vec<f64> = p
            .annotations
            .iter()
            .filter_map(|a| match a {
                Annotation::VLine { x, .. } => Some(*x),
                _ => None,
            })
            .collect();
        assert_eq!(edges.len(), 4);
        for w in edges.windows(2) {
            assert!((w[1] - w[0] - 42.0).abs() < 1e-9, "{edges:?}");
        }
        let (folded, unfolded) = (&p.series[0].points, &p.series[1].points);
        assert_eq!(folded.len(), unfolded.len());
        assert!(
            folded
                .iter()
                .zip(unfolded)
                .all(|(f, u)| f[1] <= u[1] + 1e-9)
        );
        assert!(folded.iter().any(|f| f[1] > 0.0));
    }
}
