//! A photo at a finite depth (thesis §3.7, Fig. 3.31's top and bottom rows): captured through
//! the PSF focused on the object and through the PSF focused at infinity (defocused), each
//! restored with the infinity PSF's Wiener filter, as the thesis restores every depth with the
//! kernel it calibrated at infinity; beside the photo captured and restored with the infinity
//! PSF itself (the best this filter can do).

use crate::Setting;
use ndarray::Array2;

use crate::SimError;
use crate::camera::depth::DepthResult;
use crate::restore::capture::{CaptureSettings, blur, expose};
use crate::restore::quality::{PlanesQuality, planes_quality};
use crate::restore::spectrum::{PadGrid, Padding};
use crate::restore::wiener::wiener;

/// One capture restored with the infinity PSF, and its scores against the photo.
#[derive(Debug, Clone)]
pub struct DepthRestored {
    /// The restoration, one plane per channel.
    pub restored: Vec<Array2<f64>>,
    /// PSNR against the photo, dB.
    pub psnr_db: f64,
    /// Mean SSIM over channels.
    pub ssim: f64,
}

/// The three captures of [`depth_capture`].
#[derive(Debug, Clone)]
pub struct DepthCapture {
    /// Through the infinity PSF (the filter's own kernel: the reference).
    pub infinity: DepthRestored,
    /// Through the PSF focused on the object (the camera refocused).
    pub focused: DepthRestored,
    /// Through the PSF focused at infinity (the object out of focus).
    pub defocused: DepthRestored,
}

/// Captures `photo` (linear, `[0, 1]`, one plane per channel) through each PSF of `depth` with
/// `capture`'s noise and restores it with the infinity PSF at `nsr`.
///
/// # Errors
/// [`SimError::InvalidSetting`] for a photo that does not match the channels, bad capture
/// settings or `nsr`.
pub fn depth_capture(
    photo: &[Array2<f64>],
    depth: &DepthResult,
    capture: &CaptureSettings,
    nsr: f64,
) -> Result<DepthCapture, SimError> {
    let Some(first) = photo.first() else {
        return Err(SimError::invalid(Setting::Photo, "has no planes"));
    };
    let dim = first.dim();
    let n = depth.infinity.len();
    if photo.len() != n
        || photo.iter().any(|p| p.dim() != dim)
        || depth.focused.len() != n
        || depth.defocused.len() != n
    {
        return Err(SimError::invalid(
            Setting::Photo,
            format!("needs {n} planes of one size (got {})", photo.len()),
        ));
    }
    if !(nsr.is_finite() && nsr > 0.0) {
        return Err(SimError::invalid(
            Setting::Nsr,
            format!("must be positive (got {nsr})"),
        ));
    }
    let grid = PadGrid::new(dim, depth.infinity[0].dim(), Padding::Double);
    let kernels: Vec<_> = depth
        .infinity
        .iter()
        .map(|k| grid.forward_kernel(k))
        .collect();
    let run = |psfs: &[Array2<f64>]| -> Result<DepthRestored, SimError> {
        let mut restored = Vec::with_capacity(n);
        for (c, plane) in photo.iter().enumerate() {
            let blurred = blur(&grid, plane.view(), &grid.forward_kernel(&psfs[c]));
            let captured = expose(blurred.view(), capture, c)?.image;
            restored.push(wiener(&grid, captured.view(), &kernels[c], nsr)?);
        }
        let PlanesQuality { psnr_db, ssim } = planes_quality(&restored, photo)?;
        Ok(DepthRestored {
            restored,
            psnr_db,
            ssim,
        })
    };
    Ok(DepthCapture {
        infinity: run(&depth.infinity)?,
        focused: run(&depth.focused)?,
        defocused: run(&depth.defocused)?,
    })
}
