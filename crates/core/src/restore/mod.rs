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
//! **Memory.** Channels are captured and deblurred one after another (each spreads its
//! transforms over the pool); the convolutions hold the row spectra of one strip of columns,
//! never a whole padded spectrum ([`spectrum::PadGrid::convolve`]); the denoiser takes over the
//! capture's planes. Planes are held in the photo's type: `f64`, or `f32` for camera-size photos
//! (the CLI's choice). [`simulate_with`] hands the capture and the denoised capture to its caller
//! as soon as each is done and lets them go, so a 4096 × 4096 photo holds its own planes, the
//! denoised ones and the restoration at most: 9 samples a pixel ([`crate::budget`]).
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
pub mod figures;
pub mod light;
pub mod quality;
pub mod spectrum;
pub mod wiener;

use crate::{Sample, Setting};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use ndarray::Array2;
use rayon::prelude::*;

pub use capture::{CaptureSettings, Light};
pub use cg::{CgReport, CgSettings, LinearBlur, cg_from, cg_with};
pub use denoise::{CaptureNoise, Denoise, DenoiseUsed, Recipe, Sigma2};
pub use spectrum::{KernelRows, PadGrid, Padding};
pub use wiener::THESIS_NSR;

use crate::{Progress, SimError};

/// Which restoration algorithm, by name: what a user picks (the command's `--method`, the
/// Restore view's choice, a study's axis); [`Method`] carries its settings.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum RestoreMethod {
    /// Wiener deconvolution with `--nsr` (the thesis).
    #[default]
    Wiener,
    /// Gradient-regularised least squares by conjugate gradients (`--lambda`, `--iterations`).
    Cg,
}

impl RestoreMethod {
    /// Both, in the order menus list them.
    pub const ALL: [RestoreMethod; 2] = [RestoreMethod::Wiener, RestoreMethod::Cg];

    /// The command's and the spec files' spelling (`wiener`, `cg`).
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// Its name on screen.
    pub fn label(self) -> &'static str {
        match self {
            RestoreMethod::Wiener => "Wiener",
            RestoreMethod::Cg => "CG least squares",
        }
    }
}

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
    /// The denoising between capture and deblurring: by default BM3D told the capture's own
    /// noise variance at white ([`Sigma2::Matched`]); the authors' chapter-3 table
    /// [`denoise::ICCP21_SIGMA2`] is [`Denoise::authors_table`]. [`Denoise::None`] deblurs the
    /// raw capture (the Wiener or CG step alone).
    pub denoise: Denoise,
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

/// The result of [`simulate`], its planes in the photo's sample type.
#[derive(Debug, Clone)]
pub struct RestoreResult<T = f64> {
    /// Per channel, on the ground truth's scale (empty from [`simulate_with`], which hands it
    /// over instead).
    pub captured: Vec<Array2<T>>,
    /// The denoised capture per channel, what the deblurring started from; **empty** when
    /// [`Denoise::None`] (then the deblurring started from `captured`), and from
    /// [`simulate_with`].
    pub denoised: Vec<Array2<T>>,
    /// The denoising this run did, with the σ² BM3D got on the capture's scale.
    pub denoise: DenoiseUsed,
    /// Restoration per channel, on the ground truth's scale.
    pub restored: Vec<Array2<T>>,
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
/// [`SimError::InvalidSetting`] naming the first bad input.
pub fn check<T: Sample>(
    photo: &[Array2<T>],
    settings: &RestoreSettings,
) -> Result<(usize, usize), SimError> {
    let dim = validate_photo(photo)?;
    settings.capture.validate()?;
    check_memory::<T>(dim, settings, crate::budget::RESTORE_SAMPLES_PER_PIXEL)?;
    match settings.method {
        Method::Wiener { nsr } => wiener::check_nsr(nsr)?,
        Method::Cg(cg) => cg.validate()?,
    }
    settings.denoise.validate()?;
    Ok(dim)
}

/// Refuses a run over the memory budget: `samples` photo-sized samples per pixel (the photo's
/// type), or conjugate gradients' `f64` spectra.
fn check_memory<T: Sample>(
    dim: (usize, usize),
    settings: &RestoreSettings,
    samples: u64,
) -> Result<(), SimError> {
    use crate::budget::{RESTORE_CG_BYTES_PER_PIXEL, RESTORE_FIXED_BYTES};
    let per_pixel = match settings.method {
        Method::Wiener { .. } => samples * std::mem::size_of::<T>() as u64,
        Method::Cg(_) => RESTORE_CG_BYTES_PER_PIXEL,
    };
    crate::budget::check(
        &format!("capturing and restoring a {}×{} photo", dim.1, dim.0),
        ((dim.0 * dim.1) as u64)
            .saturating_mul(per_pixel)
            .saturating_add(RESTORE_FIXED_BYTES),
        "scale the photo down (a smaller maximum side)",
    )
}

/// Photos up to this many pixels (2 megapixels) have their channels captured and deblurred side
/// by side, which keeps both cores busy through each transform's serial steps; larger ones one
/// channel after another, so that one channel's transforms are in memory at a time (the budget
/// counts one strip: [`crate::budget::RESTORE_FIXED_BYTES`]).
const SIDE_BY_SIDE_MAX_PIXELS: usize = 1 << 21;

/// Checks the photo; returns its size.
fn validate_photo<T: Sample>(photo: &[Array2<T>]) -> Result<(usize, usize), SimError> {
    let Some(first) = photo.first() else {
        return Err(SimError::invalid(Setting::Photo, "has no channels"));
    };
    let dim = first.dim();
    let win = 2 * quality::SSIM_RADIUS_PX + 1;
    if dim.0 < win || dim.1 < win {
        return Err(SimError::invalid(
            Setting::Photo,
            format!(
                "is {}×{} pixels; at least {win}×{win} are needed (the SSIM window)",
                dim.0, dim.1
            ),
        ));
    }
    for (c, plane) in photo.iter().enumerate() {
        if plane.dim() != dim {
            return Err(SimError::invalid(
                format!("photo[{c}]"),
                format!("is {:?}, channel 0 is {dim:?}", plane.dim()),
            ));
        }
        if let Some(v) = plane
            .iter()
            .map(|v| (*v).into())
            .find(|v: &f64| !(v.is_finite() && *v >= 0.0))
        {
            return Err(SimError::invalid(
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
        return Err(SimError::invalid(
            "psfs",
            format!("{} PSFs for a photo of {channels} channels", psfs.len()),
        ));
    }
    for (c, psf) in psfs.iter().enumerate() {
        if psf.is_empty() {
            return Err(SimError::invalid(format!("psfs[{c}]"), "is empty"));
        }
        if let Some(v) = psf.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(SimError::invalid(
                format!("psfs[{c}]"),
                format!("holds {v}; a PSF must be finite and ≥ 0"),
            ));
        }
        if !(psf.sum() > 0.0) {
            return Err(SimError::invalid(format!("psfs[{c}]"), "carries no light"));
        }
    }
    Ok(())
}

/// Restores a capture made elsewhere (a real one, through a measured PSF): BM3D at `sigma2`
/// when it is given, then `method`'s deblurring of each plane with its PSF on `padding`'s grid.
/// The same steps as [`simulate_with`] after its exposure.
///
/// # Errors
/// No plane, planes of different sizes or non-finite samples, PSFs that are not one per plane
/// or carry no light, a bad σ² or method setting, cancellation.
pub fn restore_capture<T: Sample>(
    captured: Vec<Array2<T>>,
    psfs: &[&Array2<f64>],
    method: Method,
    padding: Padding,
    sigma2: Option<f64>,
    progress: &Progress,
) -> Result<Vec<Array2<T>>, SimError> {
    let Some(dim) = captured.first().map(Array2::dim) else {
        return Err(SimError::invalid("capture", "has no plane"));
    };
    if dim.0 == 0 || dim.1 == 0 {
        return Err(SimError::invalid("capture", "is empty"));
    }
    for (c, p) in captured.iter().enumerate() {
        if p.dim() != dim {
            return Err(SimError::invalid(
                format!("capture plane {c}"),
                format!("is {:?}, plane 0 is {dim:?}", p.dim()),
            ));
        }
        if p.iter().any(|v| !Into::<f64>::into(*v).is_finite()) {
            return Err(SimError::invalid(
                format!("capture plane {c}"),
                "holds a sample that is not a finite number",
            ));
        }
    }
    validate_psfs(psfs, captured.len())?;
    if let Method::Wiener { nsr } = method {
        wiener::check_nsr(nsr)?;
    }
    let kernel_dim = psfs
        .iter()
        .fold((1, 1), |(h, w), p| (h.max(p.nrows()), w.max(p.ncols())));
    let grid = PadGrid::new(dim, kernel_dim, padding);
    progress.set(0.0);
    let inputs = match sigma2 {
        Some(s2) => {
            if !crate::denoise::sigma2_in_range(s2) {
                return Err(SimError::invalid(
                    "sigma2",
                    format!("must be a positive finite noise variance, got {s2}"),
                ));
            }
            let _span = progress.span(0.0, 0.7);
            crate::denoise::bm3d_owned(captured, s2, progress)?
        }
        None => captured,
    };
    progress.check()?;
    inputs
        .iter()
        .zip(psfs)
        .map(|(input, psf)| {
            deblur_channel(input, psf, None, &grid, method, progress).map(|(x, _)| x)
        })
        .collect()
}

/// One channel's deblurring on `grid` (the settings' padding), from `input` (the denoised
/// capture, or the capture itself), reusing the blur's kernel rows when they are on `grid`.
fn deblur_channel<T: Sample>(
    input: &Array2<T>,
    psf: &Array2<f64>,
    kernel: Option<KernelRows>,
    grid: &PadGrid,
    method: Method,
    progress: &Progress,
) -> Result<(Array2<T>, Option<CgReport>), SimError> {
    let psf = psf / psf.sum();
    match method {
        Method::Wiener { nsr } => {
            let kernel = kernel.unwrap_or_else(|| grid.kernel_rows(&psf));
            Ok((
                wiener::wiener_streamed(grid, input.view(), &kernel, nsr)?,
                None,
            ))
        }
        Method::Cg(cg_settings) => {
            // Conjugate gradients apply the blur 2 × iterations times: they keep the whole
            // kernel spectrum and work in f64 (their budget says so).
            let kernel = grid.forward_kernel(&psf);
            let input = input.mapv(Into::<f64>::into);
            let (x, r) = cg::cg(grid, input.view(), &kernel, &cg_settings, progress)?;
            Ok((x.mapv(T::from_f64), Some(r)))
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
/// it; see the module docs for the conventions. The planes may be `f64` or `f32` (a
/// camera-size photo: [`simulate_with`] is the route that also holds no intermediate planes).
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
/// [`SimError::InvalidSetting`] naming the field for an empty or mismatched photo (`photo`,
/// `photo[c]`), bad PSFs (`psfs`, `psfs[c]`), bad capture settings (`capture.…`), method
/// parameters (`method.…`) or σ² (`denoise.sigma2`); [`SimError::TooLarge`] when the run
/// would exceed the memory budget; [`SimError::Cancelled`] when `progress` was cancelled.
pub fn simulate<T: Sample>(
    photo: &[Array2<T>],
    psfs: &[&Array2<f64>],
    settings: &RestoreSettings,
    progress: &Progress,
) -> Result<RestoreResult<T>, SimError> {
    // This route also keeps the capture and the denoised capture.
    let dim = check(photo, settings)?;
    check_memory::<T>(dim, settings, crate::budget::RESTORE_KEPT_SAMPLES_PER_PIXEL)?;
    let mut captured = Vec::new();
    let mut denoised = Vec::new();
    let mut result = simulate_with(photo, psfs, settings, progress, |which, planes| {
        match which {
            Intermediate::Captured => captured = planes.to_vec(),
            Intermediate::Denoised => denoised = planes.to_vec(),
        }
        Ok::<(), SimError>(())
    })?;
    result.captured = captured;
    result.denoised = denoised;
    Ok(result)
}

/// The planes [`simulate_with`] hands over as soon as they are complete.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Intermediate {
    /// The capture per channel, on the ground truth's scale.
    Captured,
    /// The denoised capture per channel (only when a denoiser runs).
    Denoised,
}

/// [`simulate`] that gives each intermediate result to `keep` the moment it is complete and
/// then lets it go: the result's `captured` and `denoised` are empty. So a caller that writes
/// them out (the CLI's `--out`) never holds the photo's four stages at once: a 4096 × 4096
/// colour photo in `f32` runs in about 40 bytes a pixel ([`crate::budget`]). An error `keep`
/// returns stops the run and is returned.
///
/// # Errors
/// As [`simulate`], and whatever `keep` returns.
pub fn simulate_with<T: Sample, E: From<SimError>>(
    photo: &[Array2<T>],
    psfs: &[&Array2<f64>],
    settings: &RestoreSettings,
    progress: &Progress,
    mut keep: impl FnMut(Intermediate, &[Array2<T>]) -> Result<(), E>,
) -> Result<RestoreResult<T>, E> {
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
    let [expose_share, denoise_share, deblur_share] = progress_shares(settings);
    let cap = &settings.capture;
    let noise = CaptureNoise::of(cap);
    let snr_db = noise.snr_db;
    let denoise = settings.denoise.applied(&noise)?;
    let n = photo.len();
    let side_by_side = dim.0 * dim.1 <= SIDE_BY_SIDE_MAX_PIXELS;
    let channels_done = AtomicUsize::new(0);
    let channel_done = |start: f32, share: f32| {
        let d = channels_done.fetch_add(1, Ordering::Relaxed) + 1;
        progress.set(start + share * d as f32 / n as f32);
    };
    // Exposure. The blur runs on the linear grid, where it is exact.
    let expose_one = |c: usize| {
        let psf = psfs[c];
        let kernel = blur_grid.kernel_rows(&(psf / psf.sum()));
        let blurred = blur_grid.convolve(photo[c].view(), &kernel, |y, k| y * k);
        progress.check()?;
        let shot = capture::expose(blurred.view(), cap, c)?;
        channel_done(0.0, expose_share);
        Ok((shot, (grid == blur_grid).then_some(kernel)))
    };
    let exposed: Vec<_> = if side_by_side {
        (0..n)
            .into_par_iter()
            .map(expose_one)
            .collect::<Result<_, SimError>>()?
    } else {
        (0..n).map(expose_one).collect::<Result<_, SimError>>()?
    };
    let mut captured = Vec::with_capacity(n);
    let mut saturated = Vec::with_capacity(n);
    let mut kernels = Vec::with_capacity(n);
    for (shot, kernel) in exposed {
        captured.push(shot.image);
        saturated.push(shot.saturated_fraction);
        kernels.push(kernel);
    }
    let captured_psnr_db = captured
        .iter()
        .zip(photo)
        .map(|(a, b)| quality::psnr_db(a.view(), b.view(), 1.0))
        .collect::<Result<Vec<f64>, SimError>>()?;
    let pooled_captured = quality::psnr_db_planes(&captured, photo, 1.0)?;
    keep(Intermediate::Captured, &captured)?;
    progress.check()?;
    // Denoising sees every channel at once: CBM3D groups blocks on the luminance.
    let (inputs, denoised_psnr_db, pooled_denoised) = match denoise.sigma2 {
        None => (captured, vec![None; n], None),
        Some(sigma2) => {
            let denoised = {
                let _span = progress.span(expose_share, expose_share + denoise_share);
                crate::denoise::bm3d_owned(captured, sigma2, progress)?
            };
            let each = denoised
                .iter()
                .zip(photo)
                .map(|(a, b)| quality::psnr_db(a.view(), b.view(), 1.0).map(Some))
                .collect::<Result<Vec<Option<f64>>, SimError>>()?;
            let pooled = quality::psnr_db_planes(&denoised, photo, 1.0)?;
            keep(Intermediate::Denoised, &denoised)?;
            (denoised, each, Some(pooled))
        }
    };
    progress.check()?;
    let deblur_start = expose_share + denoise_share;
    channels_done.store(0, Ordering::Relaxed);
    // Deblurring and scores; each input goes once its channel is done.
    let deblur_one = |(c, (input, kernel)): (usize, (Array2<T>, Option<KernelRows>))| {
        let (x, cg) = deblur_channel(&input, psfs[c], kernel, &grid, settings.method, progress)?;
        drop(input);
        let truth = photo[c].view();
        let numbers = ChannelResult {
            psnr_db: quality::psnr_db(x.view(), truth, 1.0)?,
            ssim: quality::ssim(x.view(), truth)?,
            captured_psnr_db: captured_psnr_db[c],
            denoised_psnr_db: denoised_psnr_db[c],
            saturated_fraction: saturated[c],
            cg,
        };
        channel_done(deblur_start, deblur_share);
        progress.check()?;
        Ok((x, numbers))
    };
    let work = inputs.into_iter().zip(kernels).enumerate();
    let deblurred: Vec<_> = if side_by_side {
        let work: Vec<_> = work.collect();
        work.into_par_iter()
            .map(deblur_one)
            .collect::<Result<_, SimError>>()?
    } else {
        work.map(deblur_one).collect::<Result<_, SimError>>()?
    };
    let (restored, channels): (Vec<Array2<T>>, Vec<ChannelResult>) = deblurred.into_iter().unzip();
    let psnr_db = quality::psnr_db_planes(&restored, photo, 1.0)?;
    let ssim = channels.iter().map(|c| c.ssim).sum::<f64>() / channels.len() as f64;
    progress.set(1.0);
    Ok(RestoreResult {
        captured: Vec::new(),
        denoised: Vec::new(),
        denoise,
        restored,
        channels,
        psnr_db,
        ssim,
        captured_psnr_db: pooled_captured,
        denoised_psnr_db: pooled_denoised,
        light_e: cap.light.electrons(cap.read_noise_e),
        snr_db,
        electrons_per_unit: cap.electrons_per_unit(),
        grid,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}
