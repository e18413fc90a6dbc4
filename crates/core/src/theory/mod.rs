//! Fourier-optics theory beside the simulation: the closed-form Fraunhofer patterns of a slit,
//! a double slit, a rectangle and a circle, and the diffraction orders of a periodic (or
//! randomly oriented) tiling from the tile's Fourier series.
//!
//! Each comparison is sampled exactly as the simulation samples its PSF: the same fine samples
//! per wavelength (`λ f / (M δ1)`), the same sensor-pixel integration and axis phase, the same
//! spectral weights. What is left between theory and simulation is physics the formula leaves
//! out (the lens pupil's rim, cell staircases, the window crop), which is what a lecturer wants
//! to point at once the symmetry is broken.

pub mod figures;
pub mod landmarks;
mod orders;
mod shapes;

use crate::SimError;
use crate::analysis::analyze::Analysis;
use crate::analysis::mtf::Mtf;
use crate::design::Design;
use crate::psf::sampling::WavelengthSampling;

pub use crate::design::Theory;
pub use orders::{OrderEnergy, order_energies};

/// What a comparison plots against position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProfileKind {
    /// The PSF summed over rows (the light per column), against x.
    ColumnSums,
    /// The PSF's row through the axis, against x.
    AxisRow,
    /// The light in each diffraction order along the x axis (n = 0), against its position.
    Orders,
}

impl ProfileKind {
    /// How the plot's y axis is labelled.
    pub fn label(self) -> &'static str {
        match self {
            ProfileKind::ColumnSums => "PSF per column (peak = 1)",
            ProfileKind::AxisRow => "PSF on the axis row (peak = 1)",
            ProfileKind::Orders => "light in the order (fraction)",
        }
    }
}

/// The horizontal MTF slice of the simulation beside the theory's.
#[derive(Debug, Clone, PartialEq)]
pub struct MtfComparison {
    /// Frequencies, cycles/pixel (`0 … 0.5`).
    pub freqs_cyc_per_px: Vec<f64>,
    /// The simulated MTF along x.
    pub simulated: Vec<f64>,
    /// The aperture's MTF times the sensor pixel's, weighted over the channel's wavelengths.
    pub predicted: Vec<f64>,
    /// Largest `|simulated − predicted|` (MTF(0) = 1).
    pub deviation: f64,
}

/// Theory and simulation side by side for one channel.
#[derive(Debug, Clone, PartialEq)]
pub struct TheoryComparison {
    /// The reference compared with.
    pub theory: Theory,
    /// What the values are.
    pub kind: ProfileKind,
    /// Positions, µm from the axis (pixel centres, or order positions).
    pub x_um: Vec<f64>,
    /// The simulated values at `x_um`.
    pub simulated: Vec<f64>,
    /// The predicted values at `x_um`.
    pub predicted: Vec<f64>,
    /// Largest `|simulated − predicted|`, relative to the largest predicted value.
    pub deviation: f64,
    /// What a reader should know to read the comparison (e.g. a random tiling's halo).
    pub note: Option<String>,
    /// The MTF along x, for the shapes with a closed-form MTF.
    pub mtf: Option<MtfComparison>,
}

/// Compares channel `channel` of `analysis` (an analysis of `design`) with `theory`.
///
/// # Errors
/// [`SimError::Sampling`] when the sampling plan fails, the channel does not exist, or the
/// orders are closer than the comparison can separate (see [`order_energies`]).
pub fn compare(
    design: &Design,
    theory: Theory,
    analysis: &Analysis,
    channel: usize,
) -> Result<TheoryComparison, SimError> {
    let quality = analysis.quality;
    let ch = analysis
        .channels
        .get(channel)
        .ok_or_else(|| SimError::Sampling(format!("no channel {channel}")))?;
    let (psf, energy_in_window) = (&ch.psf, ch.energy_in_window);
    let samplings = quality.plan(design, &mut Vec::new())?;
    let samp = samplings
        .get(channel)
        .ok_or_else(|| SimError::Sampling(format!("no channel {channel}")))?;
    let (w, w2) = psf.dim();
    if w != w2 || samp.is_empty() || samp[0].binning.window_px != w {
        return Err(SimError::Sampling(
            "the PSF does not match the design's sampling".into(),
        ));
    }
    let pixel_um = design.optics.sensor_pixel_um;
    let axis_um = design.optics.axis_in_pixel_um;
    let pixel_centre = |j: usize| (j as f64 - (w / 2) as f64 + 0.5) * pixel_um - axis_um[0];
    let lf = |ws: &WavelengthSampling| ws.wavelength_nm * design.optics.focal_length_mm;
    let (kind, x_um, simulated, predicted, note) = match theory {
        Theory::Slit { .. } | Theory::DoubleSlit { .. } | Theory::Rectangle { .. } => {
            let sim: Vec<f64> = psf.sum_axis(ndarray::Axis(0)).to_vec();
            let mut pred = vec![0.0; w];
            for ws in samp {
                let line = shapes::binned_line(ws, |x| shapes::marginal_x(theory, x, lf(ws)));
                for (p, v) in pred.iter_mut().zip(line) {
                    *p += ws.weight * v;
                }
            }
            let x: Vec<f64> = (0..w).map(pixel_centre).collect();
            (ProfileKind::ColumnSums, x, sim, pred, None)
        }
        Theory::Circle { diameter_um } => {
            let sim: Vec<f64> = psf.row(w / 2).to_vec();
            let mut pred = vec![0.0; w];
            for ws in samp {
                let row = shapes::binned_axis_row(ws, |r| shapes::airy(diameter_um, r, lf(ws)));
                for (p, v) in pred.iter_mut().zip(row) {
                    *p += ws.weight * v;
                }
            }
            let x: Vec<f64> = (0..w).map(pixel_centre).collect();
            (ProfileKind::AxisRow, x, sim, pred, None)
        }
        Theory::Grating => {
            let o = order_energies(design, samp, psf, energy_in_window)?;
            let note = design.tiling.mode.is_random().then(|| {
                format!(
                    "Random tiling: theory counts only the coherent light (the mean tile's \
                     orders, {:.1} % of the light); the simulated orders also hold the halo \
                     that the random orientations spread everywhere ({:.1} % in all).",
                    100.0 * o.coherent_fraction,
                    100.0 * (1.0 - o.coherent_fraction)
                )
            });
            (ProfileKind::Orders, o.x_um, o.simulated, o.predicted, note)
        }
    };
    let (simulated, predicted) = match kind {
        ProfileKind::Orders => (simulated, predicted),
        _ => (to_peak(simulated), to_peak(predicted)),
    };
    let top = predicted.iter().cloned().fold(0.0_f64, f64::max);
    let deviation = simulated
        .iter()
        .zip(&predicted)
        .map(|(s, p)| (s - p).abs())
        .fold(0.0_f64, f64::max)
        / top.max(f64::MIN_POSITIVE);
    let mtf = mtf_comparison(theory, samp, &ch.mtf, design.optics.focal_length_mm);
    Ok(TheoryComparison {
        theory,
        kind,
        x_um,
        simulated,
        predicted,
        deviation,
        note,
        mtf,
    })
}

/// The simulated horizontal MTF slice beside the closed form (aperture × pixel integration,
/// weighted like the channel's PSF); `None` for the grating.
fn mtf_comparison(
    theory: Theory,
    samp: &[WavelengthSampling],
    mtf: &Mtf,
    focal_length_mm: f64,
) -> Option<MtfComparison> {
    let pixel_um = samp.first()?.binning.samples_per_px as f64 * samp.first()?.fine_um;
    let freqs = mtf.freqs_cyc_per_px();
    let mut predicted = vec![0.0; freqs.len()];
    for ws in samp {
        let lf = ws.wavelength_nm * focal_length_mm;
        for (p, nu_px) in predicted.iter_mut().zip(&freqs) {
            // Pixels of this wavelength's own binning (`spp·δ2`, within 2 % of the sensor's).
            let nu_um = nu_px / pixel_um;
            let aperture = shapes::mtf_x(theory, nu_um, lf)?;
            let pixel = shapes::pixel_mtf(nu_um, ws.binning.samples_per_px, ws.fine_um);
            *p += ws.weight * aperture * pixel;
        }
    }
    let simulated = mtf.horizontal.clone();
    let deviation = simulated
        .iter()
        .zip(&predicted)
        .map(|(s, p)| (s - p).abs())
        .fold(0.0_f64, f64::max);
    Some(MtfComparison {
        freqs_cyc_per_px: freqs,
        simulated,
        predicted,
        deviation,
    })
}

/// `sin(π t) / (π t)`, 1 at 0.
fn sinc(t: f64) -> f64 {
    if t.abs() < 1e-12 {
        1.0
    } else {
        let pt = std::f64::consts::PI * t;
        pt.sin() / pt
    }
}

/// `v` divided by its largest value (left alone when that is not positive).
fn to_peak(mut v: Vec<f64>) -> Vec<f64> {
    let top = v.iter().cloned().fold(0.0_f64, f64::max);
    if top > 0.0 {
        v.iter_mut().for_each(|x| *x /= top);
    }
    v
}
