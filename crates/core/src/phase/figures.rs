//! The phase-mask views' plots as figure panels (`crate::figure`): each channel's PSF beside the
//! bare T-OLED's (Fig. 4.6), the MTFs of all channels, and the folded plate's height profile
//! around a lenslet beside the unfolded lens (Fig. 4.3). Pure functions of the results; the
//! studio draws them.

use super::geometry::{Lenslets, profile_um};
use super::imaging::{CompareRow, Setup};
use super::psf::{ChannelPsf, PhasePsfs};
use super::{PhaseDesign, Surface};
use crate::SimError;
use crate::figure::{Annotation, Axis, Mark, Panel, Rgb, Series, palette};

/// The smallest share a log-scale PSF plot shows: 10⁻⁹ of the light.
pub const LOG_FLOOR: f64 = 1e-9;

/// Sensor pixels either side of the image point a PSF figure shows by default (the studio's
/// and `phase psf --out`'s).
pub const PSF_HALF_WIDTH_PX: usize = 24;

/// What the masks are called in a figure's legend.
pub fn optics_label(optics: super::PhaseOptics) -> &'static str {
    match optics {
        super::PhaseOptics::SingleMask => "single mask",
        super::PhaseOptics::DoubleMla => "double MLA",
        super::PhaseOptics::Toled => "T-OLED",
    }
}

/// Samples across the height profile's three lenslets.
const PROFILE_SAMPLES: usize = 900;

/// The colour of channel `i` (R, G, B, then the series colours).
fn channel_colour(i: usize) -> Rgb {
    palette::CHANNELS
        .get(i)
        .copied()
        .unwrap_or_else(|| palette::series(i))
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
            Series::new(ours, channel_colour(index), Mark::Line, points(&c.psf)),
            Series::new(
                "T-OLED",
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
                Series::new(
                    format!("{} {ours}", c.name),
                    channel_colour(i),
                    Mark::Line,
                    points(&c.mtf),
                ),
                Series::new(
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
            Series::new(
                "folded plate",
                palette::series(0),
                Mark::Line,
                profile(Surface::Folded)?,
            ),
            Series::new(
                "unfolded lens",
                palette::REFERENCE,
                Mark::DashedLine,
                profile(Surface::Unfolded)?,
            ),
        ],
        annotations: edges.collect(),
        ..Panel::default()
    })
}

/// The V matrix (§4.4) as an image: columns λ, rows λ0 with the longest at the top, each cell
/// one grid step; linear from 0 to its largest entry.
pub fn v_panel(v: &super::VMatrix) -> Panel {
    use crate::figure::{ColorScale, Colormap, Image};
    let rows = v.v.len();
    let cols = v.v.first().map_or(0, Vec::len);
    // Row 0 of an image is its top: the last λ0 first.
    let values = ndarray::Array2::from_shape_fn((rows, cols), |(r, c)| {
        v.v.get(rows - 1 - r)
            .and_then(|row| row.get(c))
            .copied()
            .unwrap_or(0.0)
    });
    let max = crate::figure::peak(&values).max(1e-300);
    let span = |nm: &[f64]| -> [f64; 2] {
        let lo = nm.first().copied().unwrap_or(super::GRID_FIRST_NM);
        let hi = nm.last().copied().unwrap_or(lo);
        [
            lo - super::GRID_STEP_NM / 2.0,
            hi + super::GRID_STEP_NM / 2.0,
        ]
    };
    let (x, y) = (span(&v.lambda_nm), span(&v.lambda0_nm));
    Panel {
        title: "V: invertibility with every lenslet folded at λ0, seen at λ".into(),
        x: Axis::new("λ, columns", Some("nm")),
        y: Axis::new("λ0, rows", Some("nm")),
        images: vec![Image {
            name: "V".into(),
            unit: None,
            values: std::sync::Arc::new(values),
            centre: [(x[0] + x[1]) / 2.0, (y[0] + y[1]) / 2.0],
            size: [x[1] - x[0], y[1] - y[0]],
            scale: ColorScale::Linear { max },
            colormap: Colormap::Viridis,
            paint: crate::figure::Paint::Mapped,
        }],
        equal_aspect: true,
        ..Panel::default()
    }
}

/// The optimizer's allocation (Algorithm 1): lenslets per grid wavelength, one bar each in
/// the wavelength's colour.
pub fn allocation_panel(counts: &[usize]) -> Panel {
    let series = super::wavelength_grid_nm()
        .iter()
        .zip(counts)
        .map(|(nm, c)| {
            Series::new(
                "lenslets per λ0",
                palette::wavelength(*nm),
                Mark::Bars,
                vec![[*nm, *c as f64]],
            )
        })
        .collect();
    Panel {
        title: "Lenslets per folding wavelength".into(),
        x: Axis::new("λ0", Some("nm")),
        y: Axis::new("lenslets", None),
        series,
        ..Panel::default()
    }
}

/// Decades below its largest entry a blur matrix is drawn over.
pub const KERNEL_DECADES: f64 = 6.0;

/// A channel's blur matrix K (eq. 4.12) as an image: row `i` at the top is sensor pixel `i`,
/// column `j` the direction a plain lens images on pixel `j`; log scale over
/// [`KERNEL_DECADES`] below its largest entry.
pub fn kernel_panel(k: std::sync::Arc<ndarray::Array2<f64>>, channel_name: &str) -> Panel {
    use crate::figure::{ColorScale, Colormap, Image};
    let (rows, cols) = k.dim();
    let max = crate::figure::peak(&k);
    Panel {
        title: format!("Blur matrix K, {channel_name} channel"),
        x: Axis::new(
            "direction j, the pixel a plain lens images it on",
            Some("px"),
        ),
        y: Axis::downward("sensor pixel i", Some("px")),
        images: vec![Image {
            name: "K".into(),
            unit: None,
            values: k,
            // Cell (i, j) centred on x = j, y = −i: row 0 at the top.
            centre: [(cols as f64 - 1.0) / 2.0, -(rows as f64 - 1.0) / 2.0],
            size: [cols as f64, rows as f64],
            scale: ColorScale::Log {
                reference: max,
                floor_decades: KERNEL_DECADES,
            },
            colormap: Colormap::Viridis,
            paint: crate::figure::Paint::Mapped,
        }],
        equal_aspect: true,
        ..Panel::default()
    }
}

/// The score the table and the plot show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompareMetric {
    /// PSNR of the restoration on the field of view, in dB.
    PsnrDb,
    /// Mean SSIM of the restoration over the channels on the field of view.
    Ssim,
}

impl CompareMetric {
    /// This score of a comparison row.
    pub fn of(self, row: &CompareRow) -> f64 {
        match self {
            CompareMetric::PsnrDb => row.psnr_db,
            CompareMetric::Ssim => row.ssim,
        }
    }

    /// Name on the metric picker, the table header and the plot's axis.
    pub fn label(self) -> &'static str {
        match self {
            CompareMetric::PsnrDb => "PSNR (dB)",
            CompareMetric::Ssim => "SSIM",
        }
    }

    /// The value as the table prints it.
    pub fn format(self, v: f64) -> String {
        match self {
            CompareMetric::PsnrDb => format!("{v:.2}"),
            CompareMetric::Ssim => format!("{v:.3}"),
        }
    }
}

/// Fig. 4.6: each setup's `metric` against the light, on a log axis ticked at the `levels`
/// run (photons per pixel), one line per setup in `setups`' order.
pub fn compare_panel(
    rows: &[CompareRow],
    setups: &[Setup],
    levels: &[f64],
    metric: CompareMetric,
) -> Panel {
    let series = setups
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let pts: Vec<[f64; 2]> = rows
                .iter()
                .filter(|r| &r.setup == s)
                .map(|r| [r.photons.log10(), metric.of(r)])
                .collect();
            Series::new(s.label(), palette::series(i), Mark::LineAndPoints, pts)
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    let mut x = Axis::log10("light, photons per pixel", None);
    x.ticks = Some(levels.iter().map(|n| n.log10()).collect());
    Panel {
        title: format!("{} against light (Fig. 4.6)", metric.label()),
        x,
        y: Axis::new(metric.label(), None),
        series,
        ..Panel::default()
    }
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

    #[test]
    fn the_v_image_reads_v_at_its_wavelengths() {
        let grid = crate::phase::wavelength_grid_nm();
        let v = crate::phase::VMatrix {
            lambda_nm: grid.clone(),
            lambda0_nm: grid.clone(),
            v: (0..grid.len())
                .map(|j| (0..grid.len()).map(|k| (100 * j + k) as f64).collect())
                .collect(),
        };
        let panel = v_panel(&v);
        let img = &panel.images[0];
        // λ0 = 411 nm is row 1 of V, λ = 431 nm its column 3.
        assert_eq!(img.value_at(431.0, 411.0), Some(103.0));
        assert_eq!(img.value_at(grid[29], grid[29]), Some(2929.0));
        assert_eq!(img.value_at(380.0, 411.0), None);
    }

    #[test]
    fn a_blur_matrix_puts_row_zero_at_the_top_of_a_downward_axis() {
        let k = ndarray::Array2::from_shape_fn((3, 4), |(i, j)| (10 * i + j) as f64 + 1.0);
        let panel = kernel_panel(std::sync::Arc::new(k), "G");
        let img = &panel.images[0];
        assert!(panel.y.downward);
        // Sensor pixel i is drawn at y = −i and shown as i; direction j at x = j.
        assert_eq!(img.value_at(2.0, -1.0), Some(13.0));
        assert_eq!(img.value_at(0.0, 0.0), Some(1.0));
        assert_eq!(panel.y.shown(-2.0), 2.0);
    }

    #[test]
    fn the_allocation_is_one_bar_per_wavelength_in_its_colour() {
        let mut counts = vec![0; crate::phase::GRID_LEN];
        counts[3] = 7;
        let panel = allocation_panel(&counts);
        assert_eq!(panel.series.len(), crate::phase::GRID_LEN);
        let bar = &panel.series[3];
        assert_eq!(bar.points, vec![[431.0, 7.0]]);
        assert_eq!(bar.colour, palette::wavelength(431.0));
        assert!((panel.bar_width() - 8.0).abs() < 1e-9);
    }
}
