//! What the display workspace's views show, as figures: the results of [`crate::analysis`]
//! with the landmarks of [`crate::theory`] (a module above both, so neither depends on the
//! other through it). A channel's PSF (linear or log) with the
//! lens's Airy ring and the display's diffraction orders, the RGB composite, the 2-D MTF, and
//! one random tiling's PSF beside the expectation over all tilings. Centred grids (sample
//! `n / 2` at 0, conventions.md §1): a PSF in µm on the sensor, an MTF in cycles per pixel.

pub mod saved;

use std::sync::Arc;

use ndarray::Array2;

use crate::analysis::analyze::{Analysis, ChannelAnalysis};
use crate::design::Design;
use crate::figure::palette::rgb_role;
use crate::figure::{Annotation, Axis, ColorScale, Colormap, Image, Paint, Panel, peak};
use crate::theory::landmarks::{airy_radius_um, order_lattice, order_spacing_um};

/// The most diffraction orders marked each way from the zero order: a tiny spacing must not
/// flood the picture.
const MAX_ORDERS_PER_SIDE: usize = 64;

/// Which reference marks a PSF figure draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Landmarks {
    /// The Airy ring of the lens alone.
    pub airy: bool,
    /// The display's diffraction orders (off by default: on a periodic display they sit on the
    /// peaks they explain and would hide them).
    pub orders: bool,
}

impl Default for Landmarks {
    fn default() -> Self {
        Landmarks {
            airy: true,
            orders: false,
        }
    }
}

/// How a PSF's values map to colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PsfScale {
    /// 0 … the peak.
    Linear,
    /// The peak down to `floor_decades` decades below it.
    Log {
        /// Decades below the peak.
        floor_decades: f64,
    },
}

impl PsfScale {
    fn with_reference(self, reference: f64) -> ColorScale {
        match self {
            PsfScale::Linear => ColorScale::Linear { max: reference },
            PsfScale::Log { floor_decades } => ColorScale::Log {
                reference,
                floor_decades,
            },
        }
    }
}

/// `values` on a centred square grid of `step` a sample (sample `n / 2` at 0, rows downward).
pub fn centred_image(
    name: &str,
    values: Arc<Array2<f64>>,
    step: f64,
    scale: ColorScale,
    colormap: Colormap,
) -> Image {
    let (rows, cols) = values.dim();
    // Sample k sits at step·(k − n/2): the image's middle is half a step off 0 for even n.
    let centre_of = |n: usize| step * ((n as f64 - 1.0) / 2.0 - (n / 2) as f64);
    Image {
        name: name.into(),
        unit: None,
        centre: [centre_of(cols), -centre_of(rows)],
        size: [cols as f64 * step, rows as f64 * step],
        values,
        scale,
        colormap,
        paint: Paint::Mapped,
    }
}

/// The Airy ring and the diffraction orders of light at `wavelength_nm` through `design`,
/// within `half_extent_um` of the axis, as `which` asks.
pub fn psf_landmarks(
    design: &Design,
    wavelength_nm: f64,
    half_extent_um: f64,
    which: Landmarks,
) -> Vec<Annotation> {
    let mut out = Vec::new();
    if which.orders {
        let period_um = design.opening.pitch_um + design.tiling.wiring_gap_um;
        let spacing = order_spacing_um(wavelength_nm, design.optics.focal_length_mm, period_um);
        out.push(Annotation::Lattice {
            points: order_lattice(spacing, half_extent_um, MAX_ORDERS_PER_SIDE),
            label: "diffraction orders".into(),
        });
    }
    if which.airy {
        out.push(Annotation::Ring {
            centre: [0.0, 0.0],
            radius: airy_radius_um(wavelength_nm, design.optics.f_number),
            label: "Airy radius".into(),
        });
    }
    out
}

fn sensor_axes() -> (Axis, Axis) {
    (Axis::new("x", Some("µm")), Axis::new("y", Some("µm")))
}

/// A PSF on the sensor grid of `analysis`, in the PSF colour map.
fn psf_image(name: &str, analysis: &Analysis, values: &Array2<f64>, scale: ColorScale) -> Image {
    let values = Arc::new(values.clone());
    centred_image(
        name,
        values,
        analysis.sensor_pixel_um,
        scale,
        Colormap::Inferno,
    )
}

/// `image` (light at `wavelength_nm` through `design`) with the landmarks `which` asks for.
fn psf_image_panel(
    title: String,
    image: Image,
    design: &Design,
    wavelength_nm: f64,
    which: Landmarks,
) -> Panel {
    let half = image.size[0] / 2.0;
    let (x, y) = sensor_axes();
    Panel {
        title,
        x,
        y,
        annotations: psf_landmarks(design, wavelength_nm, half, which),
        images: vec![image],
        equal_aspect: true,
        ..Panel::default()
    }
}

/// Channel `ch`'s PSF on the sensor, linear or log, with its landmarks.
pub fn psf_panel(
    design: &Design,
    analysis: &Analysis,
    ch: &ChannelAnalysis,
    scale: PsfScale,
    which: Landmarks,
) -> Panel {
    let what = match scale {
        PsfScale::Linear => "PSF",
        PsfScale::Log { .. } => "log-PSF",
    };
    let scale = scale.with_reference(peak(&ch.psf));
    psf_image_panel(
        format!("{} {what} ({:.0} nm)", ch.name, ch.wavelength_nm),
        psf_image("PSF", analysis, &ch.psf, scale),
        design,
        ch.wavelength_nm,
        which,
    )
}

/// Which channel index feeds the red, green and blue planes of the composite: by name when any
/// channel is called R/G/B, otherwise the first three in order.
pub fn rgb_slots(names: &[&str]) -> [Option<usize>; 3] {
    let mut slots = [None; 3];
    for (i, name) in names.iter().enumerate() {
        if let Some(k) = rgb_role(name) {
            slots[k].get_or_insert(i);
        }
    }
    if slots.iter().all(Option::is_none) {
        for (k, slot) in slots.iter_mut().enumerate() {
            *slot = (k < names.len()).then_some(k);
        }
    }
    slots
}

/// The channels' PSFs as one RGB picture, each on a log scale from its own peak down to
/// `floor_decades` below it; `None` when there is no channel.
pub fn rgb_panel(analysis: &Analysis, floor_decades: f64) -> Option<Panel> {
    let channels = &analysis.channels;
    let names: Vec<&str> = channels.iter().map(|c| c.name.as_str()).collect();
    let slots = rgb_slots(&names);
    let first = slots.iter().flatten().find_map(|i| channels.get(*i))?;
    let planes = slots.map(|s| {
        s.and_then(|i| channels.get(i))
            .map(|c| Arc::new(c.psf.clone()))
    });
    let mut image = centred_image(
        &format!("{} PSF", first.name),
        Arc::new(first.psf.clone()),
        analysis.sensor_pixel_um,
        ColorScale::Log {
            reference: peak(&first.psf),
            floor_decades,
        },
        // Each plane runs from black (its floor) to full (its own peak).
        Colormap::Gray,
    );
    image.paint = Paint::Composite(planes);
    let (x, y) = sensor_axes();
    Some(Panel {
        title: "RGB composite of the PSFs".into(),
        x,
        y,
        images: vec![image],
        equal_aspect: true,
        ..Panel::default()
    })
}

/// Channel `ch`'s 2-D MTF in cycles per pixel, log scale from 1 down to `floor_decades`.
pub fn mtf2d_panel(ch: &ChannelAnalysis, floor_decades: f64) -> Panel {
    let mtf = &ch.mtf.centred;
    // MTF(0) = 1 by construction; the peak guards against a degenerate PSF.
    let reference = peak(mtf).max(f64::MIN_POSITIVE);
    let n = mtf.nrows().max(1);
    let image = centred_image(
        "MTF",
        Arc::new(mtf.clone()),
        1.0 / n as f64,
        ColorScale::Log {
            reference,
            floor_decades,
        },
        Colormap::Viridis,
    );
    Panel {
        title: format!("{} MTF ({:.0} nm)", ch.name, ch.wavelength_nm),
        x: Axis::new("νx", Some("cyc/px")),
        y: Axis::new("νy", Some("cyc/px")),
        images: vec![image],
        equal_aspect: true,
        ..Panel::default()
    }
}

/// This random tiling's PSF beside the expectation over all tilings, on one log scale (the
/// larger peak); `None` without an expected PSF (a periodic tiling, a preview).
pub fn expected_panels(
    design: &Design,
    analysis: &Analysis,
    ch: &ChannelAnalysis,
    floor_decades: f64,
    which: Landmarks,
) -> Option<[Panel; 2]> {
    let expected = ch.expected_psf.as_ref()?;
    let scale = ColorScale::Log {
        reference: peak(&ch.psf).max(peak(expected)),
        floor_decades,
    };
    let seed = design.tiling.seed;
    let mode = design.tiling.mode.as_str();
    Some([
        psf_image_panel(
            format!("this realisation ({mode}, seed {seed})"),
            psf_image("PSF", analysis, &ch.psf, scale),
            design,
            ch.wavelength_nm,
            which,
        ),
        psf_image_panel(
            "expected over all random tilings".into(),
            psf_image("expected PSF", analysis, expected, scale),
            design,
            ch.wavelength_nm,
            which,
        ),
    ])
}

/// Which curve families the MTF figure draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MtfFamilies {
    /// The horizontal slice.
    pub horizontal: bool,
    /// The vertical slice.
    pub vertical: bool,
    /// The radially-minimum MTF (the thesis's eq. 3.8).
    pub radial_min: bool,
    /// The radially-averaged MTF.
    pub radial_mean: bool,
}

impl Default for MtfFamilies {
    fn default() -> Self {
        MtfFamilies {
            horizontal: false,
            vertical: false,
            radial_min: true,
            radial_mean: true,
        }
    }
}

impl MtfFamilies {
    /// Only the radial minimum (the A/B comparison).
    pub const RADIAL_MIN: MtfFamilies = MtfFamilies {
        horizontal: false,
        vertical: false,
        radial_min: true,
        radial_mean: false,
    };
}

/// The AUC as a legend shows it: a preview's is marked as an estimate.
fn auc_label(analysis: &Analysis, auc: f64) -> String {
    match analysis.quality {
        crate::analysis::analyze::Quality::Full => format!("AUC {auc:.3}"),
        crate::analysis::analyze::Quality::Preview => format!("AUC ≈ {auc:.3}, preview"),
    }
}

/// The colour of a channel in figures: R, G, B by name, the reference grey otherwise.
fn channel_colour(name: &str) -> crate::figure::Rgb {
    crate::figure::palette::channel(name).unwrap_or(crate::figure::palette::REFERENCE)
}

/// MTF curves of `b` over 0 … 0.5 cycles/pixel (the `families` asked for, one legend row a
/// channel) and the radial minima of a pinned design `a` (dashed, "A:"); with `repeats`, the
/// frequencies where each channel's MTF repeats (`ν = T p / (λ f)` of `design`'s period) as
/// faint rules.
pub fn mtf_curves_panel(
    b: &Analysis,
    a: Option<&Analysis>,
    families: MtfFamilies,
    repeats: Option<&Design>,
) -> Panel {
    use crate::figure::{Mark, Series};
    use crate::theory::landmarks::{mtf_repeat_cyc_per_px, multiples_up_to};
    let curve = |name: String, ch: &ChannelAnalysis, values: &[f64], mark: Mark| Series {
        name,
        colour: channel_colour(&ch.name),
        mark,
        points: ch
            .mtf
            .freqs_cyc_per_px()
            .into_iter()
            .zip(values)
            .map(|(f, v)| [f, *v])
            .collect(),
        band: None,
    };
    let mut rows: Vec<Vec<Series>> = Vec::new();
    for ch in &b.channels {
        let (m, name) = (&ch.mtf, &ch.name);
        let mut row = Vec::new();
        if families.radial_min {
            let label = format!("{name} radial min ({})", auc_label(b, m.auc_radial_min));
            row.push(curve(label, ch, &m.radial_min, Mark::Line));
        }
        if families.radial_mean {
            row.push(curve(
                format!("{name} radial mean"),
                ch,
                &m.radial_mean,
                Mark::FaintLine,
            ));
        }
        if families.horizontal {
            row.push(curve(
                format!("{name} horizontal"),
                ch,
                &m.horizontal,
                Mark::DottedLine,
            ));
        }
        if families.vertical {
            row.push(curve(
                format!("{name} vertical"),
                ch,
                &m.vertical,
                Mark::DashedLine,
            ));
        }
        rows.push(row);
    }
    // A's curve of a channel sits in that channel's row; channels only A has, in a last row.
    let mut a_only = Vec::new();
    if let Some(a) = a {
        for ch in &a.channels {
            let label = format!(
                "A: {} radial min ({})",
                ch.name,
                auc_label(a, ch.mtf.auc_radial_min)
            );
            let s = curve(label, ch, &ch.mtf.radial_min, Mark::DashedLine);
            match b.channels.iter().position(|c| c.name == ch.name) {
                Some(row) => rows[row].push(s),
                None => a_only.push(s),
            }
        }
    }
    rows.push(a_only);
    let mut rules = Vec::new();
    if let Some(d) = repeats {
        let period_um = d.opening.pitch_um + d.tiling.wiring_gap_um;
        for c in &b.channels {
            let nu = mtf_repeat_cyc_per_px(
                period_um,
                b.sensor_pixel_um,
                c.wavelength_nm,
                d.optics.focal_length_mm,
            );
            rules.push(Series {
                name: format!("{} repeats every {nu:.3} cyc/px", c.name),
                colour: channel_colour(&c.name),
                mark: Mark::Rules,
                points: multiples_up_to(nu, 0.5, 200)
                    .into_iter()
                    .map(|f| [f, 0.0])
                    .collect(),
                band: None,
            });
        }
    }
    let legend_rows = rows
        .iter()
        .chain(std::iter::once(&rules))
        .map(|r| r.iter().map(|s| s.name.clone()).collect())
        .filter(|r: &Vec<String>| !r.is_empty())
        .collect();
    // The rules first, under the curves.
    let series = rules
        .into_iter()
        .chain(rows.into_iter().flatten())
        .collect();
    Panel {
        title: "MTF".into(),
        x: Axis::new("spatial frequency", Some("cycles/pixel")).with_view(0.0, 0.5),
        y: Axis::new("MTF (fraction of DC)", None).with_view(0.0, 1.0),
        series,
        legend_rows,
        ..Panel::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_centred_image_puts_sample_half_n_at_the_origin() {
        for n in [4usize, 5] {
            let img = centred_image(
                "v",
                Arc::new(Array2::zeros((n, n))),
                2.0,
                ColorScale::Linear { max: 1.0 },
                Colormap::Gray,
            );
            assert_eq!(img.position(n / 2, n / 2), [0.0, 0.0], "n = {n}");
            assert_eq!(img.index_at(0.0, 0.0), Some([n / 2, n / 2]));
            // Row 0 is the top: y falls with the row.
            assert!(img.position(0, 0)[1] > 0.0 && img.position(n - 1, 0)[1] < 0.0);
        }
    }

    #[test]
    fn rgb_slots_follow_names_then_order() {
        assert_eq!(rgb_slots(&["B", "G", "R"]), [Some(2), Some(1), Some(0)]);
        assert_eq!(rgb_slots(&["550nm", "650nm"]), [Some(0), Some(1), None]);
        assert_eq!(rgb_slots(&["green"]), [None, Some(0), None]);
    }
}
