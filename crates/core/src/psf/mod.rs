//! Sensor PSFs per colour channel (conventions.md §2): per-wavelength Fraunhofer intensities,
//! each normalised by its total energy, weighted by the channel's spectral weights, integrated
//! over sensor pixels and normalised to sum 1 over the window.
//!
//! The sub-modules are the route to it: [`sampling`] plans each wavelength's grid, [`route`]
//! chooses between the full FFT ([`fft`]) and the pruned transforms ([`pruned`]), and [`zoom`]
//! (the chirp-z transform) samples a spectrum finely over a narrow band; [`warning`] says when a
//! sampling plan is unsafe; [`spectra`] holds the optimizer's window transform and its adjoint
//! (the seam's `window_spectrum` steps).

pub mod chirp_z;
pub mod fft;
pub mod pruned;
mod pruned_grid;
mod pruned_rows;
pub mod route;
pub mod sampling;
pub mod spectra;
pub mod warning;
pub mod zoom;

use ndarray::Array2;

use crate::SimError;
use crate::display::aperture::Field;
use crate::progress::Progress;
use crate::psf::route::{Fraunhofer, PsfRoute};
use crate::psf::sampling::WavelengthSampling;

/// The sensor PSF of one channel.
#[derive(Debug, Clone)]
pub struct ChannelPsf {
    /// `[row, col]`, axis pixel at `[W/2, W/2]`, sums to 1.
    pub sensor: Array2<f64>,
    /// Fraction of the channel's light that landed inside the window (before normalising).
    pub energy_in_window: f64,
    /// Fraction of the light in the outer 5 % band of the fine grid, where it wraps around
    /// (aliasing) — weighted like the PSF.
    pub edge_energy: f64,
}

/// Computes one channel's sensor PSF; `step` is called after each wavelength.
///
/// # Errors
/// [`SimError::Sampling`] when the field does not fit a grid, or no light reaches the grid;
/// [`SimError::Cancelled`].
pub fn channel_psf(
    field: &Field,
    samplings: &[WavelengthSampling],
    progress: &Progress,
    step: impl FnMut(),
) -> Result<ChannelPsf, SimError> {
    channel_psf_by(&PsfRoute::Auto, field, samplings, progress, step)
}

/// [`channel_psf`] with the Fraunhofer step computed by `route` (the CPU routes agree to
/// rounding; tests compare them).
///
/// # Errors
/// As [`channel_psf`], and `route`'s own.
pub fn channel_psf_by(
    route: &dyn Fraunhofer,
    field: &Field,
    samplings: &[WavelengthSampling],
    progress: &Progress,
    mut step: impl FnMut(),
) -> Result<ChannelPsf, SimError> {
    let Some(first) = samplings.first() else {
        return Err(SimError::Sampling("a channel without wavelengths".into()));
    };
    let w = first.binning.window_px;
    let mut acc = Array2::<f64>::zeros((w, w));
    let mut in_window = 0.0;
    let mut edge = 0.0;
    for ws in samplings {
        let b = route.binned(field, ws.fft_size, &ws.binning, progress)?;
        if !(b.total > 0.0) {
            return Err(SimError::Sampling("no light passes the aperture".into()));
        }
        acc.scaled_add(ws.weight / b.total, &b.sensor);
        in_window += ws.weight * b.sensor.sum() / b.total;
        edge += ws.weight * b.edge / b.total;
        step();
    }
    let sum = acc.sum();
    if !(sum > 0.0) {
        return Err(SimError::Sampling(
            "no light reaches the sensor window".into(),
        ));
    }
    acc /= sum;
    Ok(ChannelPsf {
        sensor: acc,
        energy_in_window: in_window,
        edge_energy: edge,
    })
}
