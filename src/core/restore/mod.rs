//! Capture and restore (thesis §3.5, conventions.md §5): what a photo looks like through the display
//! and how much of it deconvolution gets back. One entry point, [`simulate`], serves the CLI, the
//! studio, the tests and the benches.
//!
//! Per colour channel: the sharp plane is blurred by the channel's sensor PSF (linear FFT
//! convolution, [`spectrum`]), exposed at a light level with photon and read noise, full well and
//! ADC ([`capture`]), restored by Wiener deconvolution ([`wiener`]) or by gradient-regularised
//! least squares ([`cg`]), and scored against the sharp plane with PSNR and SSIM ([`quality`]).
//!
//! **Photos are linear intensities in `[0, 1]`**, `[row, col]`, one plane per channel, exactly as
//! the thesis feeds its 8-bit dataset to the simulation: no sRGB decoding. A pixel of value 1
//! collects `L · ltr_relative` electrons (see [`capture::CaptureSettings`]); captures and
//! restorations are divided by that number, so they share the ground truth's scale and PSNR uses
//! a peak of 1. PSFs follow the crate's convention (axis pixel at `[W/2, W/2]`) and are
//! normalised to sum 1 here, so the blur keeps the mean brightness.

pub mod capture;
pub mod cg;
pub mod quality;
pub mod spectrum;
pub mod wiener;

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;

pub use capture::{CaptureSettings, Light};
pub use cg::{CgReport, CgSettings, LinearBlur, cg_with};
pub use spectrum::{PadGrid, Padding};
pub use wiener::THESIS_NSR;

use crate::core::{Progress, SimError};

/// The restoration algorithm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Wiener deconvolution with a constant noise-to-signal ratio (the thesis: 0.00371).
    Wiener {
        /// Noise-to-signal ratio added to `|K|²` in the denominator.
        nsr: f64,
    },
    /// Gradient-regularised least squares by conjugate gradients.
    Cg(CgSettings),
}

impl Default for Method {
    fn default() -> Self {
        Method::Wiener { nsr: THESIS_NSR }
    }
}

/// Everything [`simulate`] needs besides the photo and the PSFs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RestoreSettings {
    /// Sensor, light level and noise of the capture.
    pub capture: CaptureSettings,
    /// The restoration algorithm.
    pub method: Method,
    /// Zero padding of the FFT grid: conventions.md §5's 2× by default ([`Padding::Double`]);
    /// [`Padding::Linear`] is the smallest grid on which the blur is exactly linear, faster, and
    /// changes Wiener's output only near the borders and conjugate gradients' not at all.
    pub padding: Padding,
}

/// Numbers of one channel.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelResult {
    /// PSNR of the restoration against the ground truth, peak 1 (`+∞` when identical).
    pub psnr_db: f64,
    /// SSIM of the restoration against the ground truth (Gaussian window σ = 1.5).
    pub ssim: f64,
    /// PSNR of the capture itself (blurred and noisy), for comparison.
    pub captured_psnr_db: f64,
    /// Fraction of pixels that reached the full well.
    pub saturated_fraction: f64,
    /// What conjugate gradients did (`None` for Wiener).
    pub cg: Option<CgReport>,
}

/// The result of [`simulate`].
#[derive(Debug, Clone)]
pub struct RestoreResult {
    /// Per channel, on the ground truth's scale.
    pub captured: Vec<Array2<f64>>,
    /// Restoration per channel, on the ground truth's scale.
    pub restored: Vec<Array2<f64>>,
    /// The scores of each channel.
    pub channels: Vec<ChannelResult>,
    /// PSNR with the MSE pooled over all channels.
    pub psnr_db: f64,
    /// Mean SSIM over the channels.
    pub ssim: f64,
    /// Pooled PSNR of the capture.
    pub captured_psnr_db: f64,
    /// `L`: electrons of a sharp pixel of value 1 behind the reference display.
    pub light_e: f64,
    /// SNR at that pixel, dB.
    pub snr_db: f64,
    /// `L · ltr_relative`: electrons of a sharp pixel of value 1 behind this display.
    pub electrons_per_unit: f64,
    /// The FFT grid of the restoration (the blur always runs on the linear grid).
    pub grid: PadGrid,
    /// Wall-clock time of the simulation, ms.
    pub elapsed_ms: f64,
}

/// Checks a photo and the settings before anything is computed (callers that must first
/// compute the PSFs check here before they do); returns the image size.
///
/// # Errors
/// [`SimError::InvalidField`] naming the first bad input.
pub fn check(
    photo: &[Array2<f64>],
    settings: &RestoreSettings,
) -> Result<(usize, usize), SimError> {
    let dim = validate_photo(photo)?;
    settings.capture.validate()?;
    let pixels = (dim.0 * dim.1) as u64;
    crate::core::budget::check(
        &format!("capturing and restoring a {}×{} photo", dim.1, dim.0),
        pixels.saturating_mul(crate::core::budget::RESTORE_BYTES_PER_PIXEL),
        "scale the photo down (a smaller maximum side)",
    )?;
    match settings.method {
        Method::Wiener { nsr } if !(nsr.is_finite() && nsr >= 0.0) => {
            return Err(SimError::field(
                "method.nsr",
                format!("must be a finite number ≥ 0 (got {nsr:?})"),
            ));
        }
        Method::Wiener { .. } => {}
        Method::Cg(cg) => cg.validate()?,
    }
    Ok(dim)
}

/// Checks the photo; returns its size.
fn validate_photo(photo: &[Array2<f64>]) -> Result<(usize, usize), SimError> {
    let Some(first) = photo.first() else {
        return Err(SimError::field("photo", "has no channels"));
    };
    let dim = first.dim();
    let win = 2 * quality::SSIM_RADIUS_PX + 1;
    if dim.0 < win || dim.1 < win {
        return Err(SimError::field(
            "photo",
            format!(
                "is {}×{} pixels; at least {win}×{win} are needed (the SSIM window)",
                dim.0, dim.1
            ),
        ));
    }
    for (c, plane) in photo.iter().enumerate() {
        if plane.dim() != dim {
            return Err(SimError::field(
                format!("photo[{c}]"),
                format!("is {:?}, channel 0 is {dim:?}", plane.dim()),
            ));
        }
        if let Some(v) = plane.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(SimError::field(
                format!("photo[{c}]"),
                format!("holds {v}; intensities must be finite and ≥ 0"),
            ));
        }
    }
    Ok(dim)
}

/// Checks the PSFs, one per photo channel.
fn validate_psfs(psfs: &[&Array2<f64>], channels: usize) -> Result<(), SimError> {
    if psfs.len() != channels {
        return Err(SimError::field(
            "psfs",
            format!("{} PSFs for a photo of {channels} channels", psfs.len()),
        ));
    }
    for (c, psf) in psfs.iter().enumerate() {
        if psf.is_empty() {
            return Err(SimError::field(format!("psfs[{c}]"), "is empty"));
        }
        if let Some(v) = psf.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(SimError::field(
                format!("psfs[{c}]"),
                format!("holds {v}; a PSF must be finite and ≥ 0"),
            ));
        }
        if !(psf.sum() > 0.0) {
            return Err(SimError::field(format!("psfs[{c}]"), "carries no light"));
        }
    }
    Ok(())
}

/// One channel: kernel spectrum, blur, exposure, restoration, scores.
/// The blur runs on the linear grid, where it is already exact; the restoration on `grid` (the
/// settings' padding), sharing the blur's kernel spectrum when the two grids coincide.
fn channel(
    c: usize,
    truth: &Array2<f64>,
    psf: &Array2<f64>,
    grids: (&PadGrid, &PadGrid),
    settings: &RestoreSettings,
    progress: &Progress,
    step: &(dyn Fn() + Sync),
) -> Result<(Array2<f64>, Array2<f64>, ChannelResult), SimError> {
    let (blur_grid, grid) = grids;
    let psf = psf / psf.sum();
    let blur_kernel = blur_grid.forward_kernel(&psf);
    let blurred = capture::blur(blur_grid, truth.view(), &blur_kernel);
    progress.check()?;
    let shot = capture::expose(blurred.view(), &settings.capture, c)?;
    drop(blurred);
    step();
    progress.check()?;
    let kernel = if grid == blur_grid {
        blur_kernel
    } else {
        drop(blur_kernel);
        grid.forward_kernel(&psf)
    };
    let (restored, report) = match settings.method {
        Method::Wiener { nsr } => (wiener::wiener(grid, shot.image.view(), &kernel, nsr)?, None),
        Method::Cg(cg_settings) => {
            let (x, r) = cg::cg(grid, shot.image.view(), &kernel, &cg_settings, progress)?;
            (x, Some(r))
        }
    };
    step();
    progress.check()?;
    let result = ChannelResult {
        psnr_db: quality::psnr_db(restored.view(), truth.view(), 1.0)?,
        ssim: quality::ssim(restored.view(), truth.view())?,
        captured_psnr_db: quality::psnr_db(shot.image.view(), truth.view(), 1.0)?,
        saturated_fraction: shot.saturated_fraction,
        cg: report,
    };
    step();
    Ok((shot.image, restored, result))
}

/// Captures `photo` through the display whose per-channel sensor PSFs are `psfs` and restores
/// it; see the module docs for the conventions.
///
/// ```
/// use ndarray::Array2;
/// use udc_studio::core::Progress;
/// use udc_studio::core::restore::{Light, RestoreSettings, simulate};
///
/// let photo = vec![Array2::from_shape_fn((32, 32), |(y, x)| ((x / 4 + y / 4) % 2) as f64)];
/// let mut psf = Array2::zeros((5, 5));
/// psf[[2, 2]] = 0.6; // the axis pixel of a 5×5 PSF is [2, 2]
/// psf[[2, 1]] = 0.2;
/// psf[[2, 3]] = 0.2;
/// let mut settings = RestoreSettings::default();
/// settings.capture.light = Light::SnrDb(40.0);
/// let r = simulate(&photo, &[&psf], &settings, &Progress::new())?;
/// assert!(r.psnr_db > r.captured_psnr_db); // deconvolution helps
/// # Ok::<(), udc_studio::core::SimError>(())
/// ```
///
/// # Errors
/// [`SimError::InvalidField`] naming the field for an empty or mismatched photo (`photo`,
/// `photo[c]`), bad PSFs (`psfs`, `psfs[c]`), bad capture settings (`capture.…`) or method
/// parameters (`method.…`); [`SimError::Cancelled`] when `progress` was cancelled.
pub fn simulate(
    photo: &[Array2<f64>],
    psfs: &[&Array2<f64>],
    settings: &RestoreSettings,
    progress: &Progress,
) -> Result<RestoreResult, SimError> {
    let start = Instant::now();
    let dim = check(photo, settings)?;
    validate_psfs(psfs, photo.len())?;
    progress.set(0.0);
    progress.check()?;
    let kernel_dim = psfs
        .iter()
        .fold((1, 1), |(h, w), p| (h.max(p.nrows()), w.max(p.ncols())));
    let grid = PadGrid::new(dim, kernel_dim, settings.padding);
    let blur_grid = PadGrid::new(dim, kernel_dim, Padding::Linear);
    let steps = 3 * photo.len();
    let done = AtomicUsize::new(0);
    let step = || {
        let d = done.fetch_add(1, Ordering::Relaxed) + 1;
        progress.set(d as f32 / steps as f32);
    };
    // Channels side by side; each also spreads its FFT rows and columns over the pool.
    let per_channel: Vec<_> = photo
        .par_iter()
        .zip(psfs.par_iter())
        .enumerate()
        .map(|(c, (truth, psf))| {
            channel(
                c,
                truth,
                psf,
                (&blur_grid, &grid),
                settings,
                progress,
                &step,
            )
        })
        .collect();
    let mut captured = Vec::with_capacity(photo.len());
    let mut restored = Vec::with_capacity(photo.len());
    let mut channels = Vec::with_capacity(photo.len());
    for r in per_channel {
        let (cap, res, numbers) = r?;
        captured.push(cap);
        restored.push(res);
        channels.push(numbers);
    }
    fn pairs<'a>(
        planes: &'a [Array2<f64>],
        truth: &'a [Array2<f64>],
    ) -> Vec<(ArrayView2<'a, f64>, ArrayView2<'a, f64>)> {
        planes
            .iter()
            .zip(truth)
            .map(|(a, b)| (a.view(), b.view()))
            .collect()
    }
    let psnr_db = quality::psnr_db_pooled(&pairs(&restored, photo), 1.0)?;
    let captured_psnr_db = quality::psnr_db_pooled(&pairs(&captured, photo), 1.0)?;
    let ssim = channels.iter().map(|c| c.ssim).sum::<f64>() / channels.len() as f64;
    let cap = &settings.capture;
    progress.set(1.0);
    Ok(RestoreResult {
        captured,
        restored,
        channels,
        psnr_db,
        ssim,
        captured_psnr_db,
        light_e: cap.light.electrons(cap.read_noise_e),
        snr_db: cap.light.snr_db(cap.read_noise_e),
        electrons_per_unit: cap.electrons_per_unit(),
        grid,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}
