//! Capture and restore (thesis §3.5, conventions.md §5): what a photo looks like through the display
//! and how much of it deconvolution gets back. One entry point, [`simulate`], serves the CLI, the
//! studio, the tests and the benches.
//!
//! Three steps, as the thesis (conventions.md §5, "denoise, then deblur"): per colour channel the
//! sharp plane is blurred by the channel's sensor PSF (linear FFT convolution, [`spectrum`]) and
//! exposed at a light level with photon and read noise, full well and ADC ([`capture`]); then all
//! channels together are denoised by BM3D (CBM3D for R, G, B: the colour variant groups blocks
//! on the luminance, so it needs every channel at once; [`denoise`]); then per channel the
//! denoised plane is restored by Wiener deconvolution ([`wiener`]) or by gradient-regularised
//! least squares ([`cg`]), and everything is scored against the sharp plane with PSNR and SSIM
//! ([`quality`]).
//!
//! **Photos are linear intensities in `[0, 1]`**, `[row, col]`, one plane per channel, exactly as
//! the thesis feeds its 8-bit dataset to the simulation: no sRGB decoding. A pixel of value 1
//! collects `L · ltr_relative` electrons (see [`capture::CaptureSettings`]); captures and
//! restorations are divided by that number, so they share the ground truth's scale and PSNR uses
//! a peak of 1. PSFs follow the crate's convention (axis pixel at `[W/2, W/2]`) and are
//! normalised to sum 1 here, so the blur keeps the mean brightness.
//!
//! **Our scale and the thesis's.** This is chapter 4's scale (every capture reads ≈ 1 at white).
//! Chapter 3 gain-normalised at the reference display instead, so its captures and its comparison
//! image (truth × open ratio / 0.2072) are `r = ltr_relative` times ours: its σ² table is divided
//! by `r²` before BM3D sees our capture ([`denoise`] derives it), and a PSNR taken there (peak 1
//! on `r`-scaled images: MSE `r²` times ours) sits `20·log10(r)` dB below ours for the same
//! restoration. In the thesis's own runs `r` = open ratio / 0.2072 (its reference display), so
//! its chapter-3 PSNRs are 1.2 dB below ours for the 150-DPI T-OLED (5/21) and further below for
//! brighter openings: ours compare displays on equal footing, the thesis's favour the dimmer.

pub mod capture;
pub mod cg;
pub mod denoise;
pub mod quality;
pub mod spectrum;
pub mod wiener;

use crate::Setting;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;

pub use capture::{CaptureSettings, Light};
pub use cg::{CgReport, CgSettings, LinearBlur, cg_with};
pub use denoise::{Denoise, DenoiseUsed, Recipe, Sigma2};
use spectrum::Spectrum;
pub use spectrum::{PadGrid, Padding};
pub use wiener::THESIS_NSR;

use crate::{Progress, SimError};

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
#[derive(Debug, Clone, PartialEq)]
pub struct RestoreSettings {
    /// Sensor, light level and noise of the capture.
    pub capture: CaptureSettings,
    /// The restoration algorithm.
    pub method: Method,
    /// Zero padding of the FFT grid: conventions.md §5's 2× by default ([`Padding::Double`]);
    /// [`Padding::Linear`] is the smallest grid on which the blur is exactly linear, faster, and
    /// changes Wiener's output only near the borders and conjugate gradients' not at all.
    pub padding: Padding,
    /// The denoising between capture and deblurring: by default the thesis's chapter 3, BM3D
    /// with [`denoise::ICCP21_SIGMA2`] at the light level. [`Denoise::None`] deblurs the raw
    /// capture (the Wiener or CG step alone).
    pub denoise: Denoise,
}

impl Default for RestoreSettings {
    fn default() -> Self {
        RestoreSettings {
            capture: CaptureSettings::default(),
            method: Method::default(),
            padding: Padding::default(),
            denoise: Denoise::thesis(Recipe::Iccp21),
        }
    }
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
    /// PSNR of the denoised capture (still blurred); `None` without a denoiser.
    pub denoised_psnr_db: Option<f64>,
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
    /// The denoised capture per channel, what the deblurring started from; **empty** when
    /// [`Denoise::None`] (then the deblurring started from `captured`).
    pub denoised: Vec<Array2<f64>>,
    /// The denoising this run did, with the σ² BM3D got on the capture's scale.
    pub denoise: DenoiseUsed,
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
    /// Pooled PSNR of the denoised capture; `None` without a denoiser.
    pub denoised_psnr_db: Option<f64>,
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
    crate::budget::check(
        &format!("capturing and restoring a {}×{} photo", dim.1, dim.0),
        pixels.saturating_mul(crate::budget::RESTORE_BYTES_PER_PIXEL),
        "scale the photo down (a smaller maximum side)",
    )?;
    match settings.method {
        Method::Wiener { nsr } if !(nsr.is_finite() && nsr >= 0.0) => {
            return Err(SimError::field(
                Setting::MethodNsr,
                format!("must be a finite number ≥ 0 (got {nsr:?})"),
            ));
        }
        Method::Wiener { .. } => {}
        Method::Cg(cg) => cg.validate()?,
    }
    settings.denoise.validate()?;
    Ok(dim)
}

/// Checks the photo; returns its size.
fn validate_photo(photo: &[Array2<f64>]) -> Result<(usize, usize), SimError> {
    let Some(first) = photo.first() else {
        return Err(SimError::field(Setting::Photo, "has no channels"));
    };
    let dim = first.dim();
    let win = 2 * quality::SSIM_RADIUS_PX + 1;
    if dim.0 < win || dim.1 < win {
        return Err(SimError::field(
            Setting::Photo,
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

/// One channel after the exposure.
struct Exposed {
    /// The capture on the ground truth's scale.
    image: Array2<f64>,
    saturated_fraction: f64,
    /// The blur's kernel spectrum, kept for the deblurring when both run on the same grid.
    kernel: Option<Spectrum>,
}

/// One channel's blur and exposure. The blur runs on the linear grid, where it is already exact.
fn expose_channel(
    c: usize,
    truth: &Array2<f64>,
    psf: &Array2<f64>,
    grids: (&PadGrid, &PadGrid),
    settings: &RestoreSettings,
    progress: &Progress,
) -> Result<Exposed, SimError> {
    let (blur_grid, grid) = grids;
    let psf = psf / psf.sum();
    let blur_kernel = blur_grid.forward_kernel(&psf);
    let blurred = capture::blur(blur_grid, truth.view(), &blur_kernel);
    progress.check()?;
    let shot = capture::expose(blurred.view(), &settings.capture, c)?;
    Ok(Exposed {
        image: shot.image,
        saturated_fraction: shot.saturated_fraction,
        kernel: (grid == blur_grid).then_some(blur_kernel),
    })
}

/// One channel's deblurring on `grid` (the settings' padding), from `input` (the denoised
/// capture, or the capture itself), reusing the blur's kernel spectrum when given.
fn deblur_channel(
    input: &Array2<f64>,
    psf: &Array2<f64>,
    kernel: Option<Spectrum>,
    grid: &PadGrid,
    method: Method,
    progress: &Progress,
) -> Result<(Array2<f64>, Option<CgReport>), SimError> {
    let kernel = kernel.unwrap_or_else(|| grid.forward_kernel(&(psf / psf.sum())));
    match method {
        Method::Wiener { nsr } => Ok((wiener::wiener(grid, input.view(), &kernel, nsr)?, None)),
        Method::Cg(cg_settings) => {
            let (x, r) = cg::cg(grid, input.view(), &kernel, &cg_settings, progress)?;
            Ok((x, Some(r)))
        }
    }
}

/// The shares of the progress bar: exposure, denoising, deblurring (scores are quick). BM3D is
/// the slow step (≈ 1 s for a 512² colour photo, against ≈ 0.1 s for the exposure and Wiener;
/// CG's 60 iterations about 0.3 s for 256²).
fn progress_shares(settings: &RestoreSettings) -> [f32; 3] {
    let denoise = match settings.denoise {
        Denoise::None => 0.0,
        Denoise::Bm3d { .. } => 6.0,
    };
    let deblur = match settings.method {
        Method::Wiener { .. } => 1.0,
        Method::Cg(_) => 3.0,
    };
    let total = 1.0 + denoise + deblur;
    [1.0 / total, denoise / total, deblur / total]
}

/// Captures `photo` through the display whose per-channel sensor PSFs are `psfs` and restores
/// it; see the module docs for the conventions.
///
/// ```
/// use ndarray::Array2;
/// use udc_core::Progress;
/// use udc_core::restore::{Light, RestoreSettings, simulate};
///
/// let photo = vec![Array2::from_shape_fn((32, 32), |(y, x)| ((x / 4 + y / 4) % 2) as f64)];
/// let mut psf = Array2::zeros((5, 5));
/// psf[[2, 2]] = 0.6; // the axis pixel of a 5×5 PSF is [2, 2]
/// psf[[2, 1]] = 0.2;
/// psf[[2, 3]] = 0.2;
/// let mut settings = RestoreSettings::default();
/// settings.capture.light = Light::SnrDb(40.0);
/// let r = simulate(&photo, &[&psf], &settings, &Progress::new())?;
/// assert!(r.psnr_db > r.captured_psnr_db); // denoising and deconvolution help
/// assert_eq!(r.denoised.len(), 1); // BM3D by default, as the thesis
/// # Ok::<(), udc_core::SimError>(())
/// ```
///
/// # Errors
/// [`SimError::InvalidField`] naming the field for an empty or mismatched photo (`photo`,
/// `photo[c]`), bad PSFs (`psfs`, `psfs[c]`), bad capture settings (`capture.…`), method
/// parameters (`method.…`) or σ² (`denoise.sigma2`); [`SimError::TooLarge`] when the denoiser
/// would exceed the memory budget; [`SimError::Cancelled`] when `progress` was cancelled.
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
    let [expose_share, denoise_share, _] = progress_shares(settings);
    let cap = &settings.capture;
    let snr_db = cap.light.snr_db(cap.read_noise_e);
    let denoise = settings.denoise.applied(snr_db, cap.ltr_relative);
    let channels_done = AtomicUsize::new(0);
    let per_channel = |start: f32, share: f32| {
        let d = channels_done.fetch_add(1, Ordering::Relaxed) + 1;
        progress.set(start + share * d as f32 / photo.len() as f32);
    };
    // Exposure: channels side by side; each also spreads its FFT rows and columns over the pool.
    let exposed: Vec<Exposed> = photo
        .par_iter()
        .zip(psfs.par_iter())
        .enumerate()
        .map(|(c, (truth, psf))| {
            let e = expose_channel(c, truth, psf, (&blur_grid, &grid), settings, progress)?;
            per_channel(0.0, expose_share);
            Ok(e)
        })
        .collect::<Result<_, SimError>>()?;
    progress.check()?;
    let mut captured = Vec::with_capacity(photo.len());
    let mut saturated = Vec::with_capacity(photo.len());
    let mut kernels = Vec::with_capacity(photo.len());
    for e in exposed {
        captured.push(e.image);
        saturated.push(e.saturated_fraction);
        kernels.push(e.kernel);
    }
    // Denoising sees every channel at once: CBM3D groups blocks on the luminance.
    let denoised = match denoise.sigma2 {
        None => Vec::new(),
        Some(sigma2) => {
            let _span = progress.span(expose_share, expose_share + denoise_share);
            crate::denoise::bm3d(&captured, sigma2, progress)?
        }
    };
    progress.check()?;
    let inputs = if denoised.is_empty() {
        &captured
    } else {
        &denoised
    };
    let deblur_start = expose_share + denoise_share;
    channels_done.store(0, Ordering::Relaxed);
    // Deblurring and scores: channels side by side again.
    let deblurred: Vec<(Array2<f64>, ChannelResult)> = inputs
        .par_iter()
        .zip(psfs.par_iter())
        .zip(kernels.into_par_iter())
        .enumerate()
        .map(|(c, ((input, psf), kernel))| {
            let (x, cg) = deblur_channel(input, psf, kernel, &grid, settings.method, progress)?;
            let truth = photo[c].view();
            let numbers = ChannelResult {
                psnr_db: quality::psnr_db(x.view(), truth, 1.0)?,
                ssim: quality::ssim(x.view(), truth)?,
                captured_psnr_db: quality::psnr_db(captured[c].view(), truth, 1.0)?,
                denoised_psnr_db: denoised
                    .get(c)
                    .map(|d| quality::psnr_db(d.view(), truth, 1.0))
                    .transpose()?,
                saturated_fraction: saturated[c],
                cg,
            };
            per_channel(deblur_start, 1.0 - deblur_start);
            Ok((x, numbers))
        })
        .collect::<Result<_, SimError>>()?;
    progress.check()?;
    let (restored, channels): (Vec<Array2<f64>>, Vec<ChannelResult>) =
        deblurred.into_iter().unzip();
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
    let denoised_psnr_db = if denoised.is_empty() {
        None
    } else {
        Some(quality::psnr_db_pooled(&pairs(&denoised, photo), 1.0)?)
    };
    let ssim = channels.iter().map(|c| c.ssim).sum::<f64>() / channels.len() as f64;
    progress.set(1.0);
    Ok(RestoreResult {
        captured,
        denoised,
        denoise,
        restored,
        channels,
        psnr_db,
        ssim,
        captured_psnr_db,
        denoised_psnr_db,
        light_e: cap.light.electrons(cap.read_noise_e),
        snr_db,
        electrons_per_unit: cap.electrons_per_unit(),
        grid,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}
