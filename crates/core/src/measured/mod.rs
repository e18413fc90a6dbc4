//! Point-spread functions as sets of channels, simulated or measured, and the import of a
//! measured one: a bracket of exposures with dark frames merged into one linear PSF
//! ([`import::merge`]), each step switchable and reported.
//!
//! A set's PSFs follow the core's conventions: `[row, col]`, the optical axis at `[N/2, N/2]`,
//! each summing to 1; `pixel_um` is the camera's pixel pitch they are sampled at.

pub mod compare;
pub mod figures;
pub mod fit;
pub mod import;
pub mod shift;

use ndarray::Array2;
use serde::{Deserialize, Serialize};

use crate::SimError;
use crate::analysis::analyze::Analysis;

/// The offset (−½ … ½) of the top of the parabola through three equally spaced samples from
/// the middle one; 0 when the middle is not a maximum (a sub-pixel peak, along one axis).
pub(crate) fn parabola_peak(lo: f64, mid: f64, hi: f64) -> f64 {
    let d = lo - 2.0 * mid + hi;
    if d < 0.0 {
        (0.5 * (lo - hi) / d).clamp(-0.5, 0.5)
    } else {
        0.0
    }
}

/// The camera pixel pitches a set may have, µm: from a microscope's sampling to a coarse
/// detector. Outside, the number is a typo or a unit slip (metres, nanometres).
pub const PIXEL_UM_RANGE: std::ops::RangeInclusive<f64> = 0.01..=1000.0;

/// The wavelengths a channel may name, nm: deep UV to thermal infrared.
pub const WAVELENGTH_NM_RANGE: std::ops::RangeInclusive<f64> = 100.0..=20_000.0;

/// `value` against `range`, or the rule as `"{what} must be {lo} … {hi} {unit}, got {value}"`.
fn in_range(
    what: &str,
    unit: &str,
    range: &std::ops::RangeInclusive<f64>,
    value: f64,
) -> Result<(), String> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(format!(
            "{what} must be {} … {} {unit}, got {value}",
            range.start(),
            range.end()
        ))
    }
}

/// Checks a camera pixel pitch against [`PIXEL_UM_RANGE`].
///
/// # Errors
/// The rule, with the value given.
pub fn check_pixel_um(pixel_um: f64) -> Result<(), String> {
    in_range("the camera's pixel pitch", "µm", &PIXEL_UM_RANGE, pixel_um)
}

/// Checks a wavelength against [`WAVELENGTH_NM_RANGE`].
///
/// # Errors
/// The rule, with the value given.
pub fn check_wavelength_nm(wavelength_nm: f64) -> Result<(), String> {
    in_range("the wavelength", "nm", &WAVELENGTH_NM_RANGE, wavelength_nm)
}

/// `design` simulated on a measurement's grid: the set's pixel pitch (the fine grid a whole
/// number of samples a pixel, as near the design's own as may be), its window and the optical
/// axis in a pixel's middle, where an import centres a measured PSF.
pub fn design_on_grid(design: &crate::design::Design, set: &PsfSet) -> crate::design::Design {
    let mut design = design.clone();
    let op = &mut design.optics;
    let per_pixel = (set.pixel_um / op.fine_sample_um).round().max(1.0);
    op.sensor_pixel_um = set.pixel_um;
    op.fine_sample_um = set.pixel_um / per_pixel;
    op.window_px = set.side_px();
    op.axis_in_pixel_um = [set.pixel_um / 2.0, set.pixel_um / 2.0];
    op.recipe = crate::design::OpticsRecipe::Custom;
    design
}

/// Where a PSF set came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PsfSource {
    /// Computed by the core from a design.
    Simulated,
    /// Measured on a prototype and imported.
    Measured,
}

/// One channel of a PSF set.
#[derive(Debug, Clone, PartialEq)]
pub struct PsfChannel {
    /// The channel's name (`R`, `G`, `B`, `green`, `530 nm`).
    pub name: String,
    /// The wavelength it was measured or simulated at (a channel's centre), when known.
    pub wavelength_nm: Option<f64>,
    /// `[row, col]`, the axis at `[N/2, N/2]`, summing to 1.
    pub psf: Array2<f64>,
}

/// PSFs per channel at one camera pixel pitch.
#[derive(Debug, Clone, PartialEq)]
pub struct PsfSet {
    /// The channels, in order.
    pub channels: Vec<PsfChannel>,
    /// The camera's pixel pitch the PSFs are sampled at, µm.
    pub pixel_um: f64,
    /// Simulated or measured.
    pub source: PsfSource,
}

impl PsfSet {
    /// The simulated PSFs of an analysis.
    pub fn from_analysis(analysis: &Analysis) -> PsfSet {
        PsfSet {
            channels: analysis
                .channels
                .iter()
                .map(|c| PsfChannel {
                    name: c.name.clone(),
                    wavelength_nm: Some(c.wavelength_nm),
                    psf: c.psf.clone(),
                })
                .collect(),
            pixel_um: analysis.sensor_pixel_um,
            source: PsfSource::Simulated,
        }
    }

    /// Checks what every user of a set relies on: a positive pixel pitch, at least one
    /// channel, every PSF square, of one size, finite and with light.
    ///
    /// # Errors
    /// The first broken rule, naming the channel.
    pub fn check(&self) -> Result<(), SimError> {
        check_pixel_um(self.pixel_um).map_err(|e| SimError::invalid("pixel_um", e))?;
        let Some(first) = self.channels.first() else {
            return Err(SimError::invalid("channels", "the PSF set has no channel"));
        };
        let dim = first.psf.dim();
        for c in &self.channels {
            let at = format!("channel {}", c.name);
            let (rows, cols) = c.psf.dim();
            if rows != cols || rows == 0 {
                return Err(SimError::invalid(
                    at,
                    format!("the PSF must be square and not empty, got {rows}×{cols}"),
                ));
            }
            if c.psf.dim() != dim {
                return Err(SimError::invalid(
                    at,
                    format!(
                        "{rows}×{cols}, but the first channel is {}×{}",
                        dim.0, dim.1
                    ),
                ));
            }
            if let Some(v) = c.psf.iter().find(|v| !v.is_finite()) {
                return Err(SimError::invalid(at, format!("holds {v}")));
            }
            if !(c.psf.sum() > 0.0) {
                return Err(SimError::invalid(
                    at,
                    "holds no light (its sum is not positive)",
                ));
            }
            if let Some(w) = c.wavelength_nm {
                check_wavelength_nm(w).map_err(|e| SimError::invalid(at, e))?;
            }
        }
        Ok(())
    }

    /// Side of the PSFs, pixels.
    pub fn side_px(&self) -> usize {
        self.channels.first().map_or(0, |c| c.psf.nrows())
    }

    /// The kernels that restore a capture of `planes` colour planes: one channel serves every
    /// plane, else there must be one per plane. A measured PSF dips below zero where the
    /// background's noise and the sub-pixel move left it; light is not negative, so those
    /// samples become 0, and the largest share of a channel's light they held comes back.
    ///
    /// # Errors
    /// A set that fails [`PsfSet::check`], or as many channels as neither 1 nor `planes`.
    pub fn restoration_kernels(&self, planes: usize) -> Result<(Vec<Array2<f64>>, f64), SimError> {
        self.check()?;
        let k = self.channels.len();
        if k != 1 && k != planes {
            return Err(SimError::invalid(
                "channels",
                format!(
                    "the PSF set has {k} channels but the capture has {planes}: give one PSF \
                     for every colour or one per channel"
                ),
            ));
        }
        let mut negative = 0.0f64;
        let cleaned: Vec<Array2<f64>> = self
            .channels
            .iter()
            .map(|c| {
                let below: f64 = c.psf.iter().filter(|v| **v < 0.0).map(|v| -v).sum();
                negative = negative.max(below / c.psf.sum());
                c.psf.mapv(|v| v.max(0.0))
            })
            .collect();
        let kernels = if k == 1 {
            vec![cleaned[0].clone(); planes]
        } else {
            cleaned
        };
        Ok((kernels, negative))
    }
}
