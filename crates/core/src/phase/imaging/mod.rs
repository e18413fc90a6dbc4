//! Photos captured through a phase-mask design and restored (thesis §4.5, Figs. 4.6 and 4.10,
//! Tables 4.1 and 4.2). One entry point per step, shared by the CLI, the studio, tests and benches:
//! [`phase_blur`] builds the imaging operator of a design, [`capture`] exposes a scene through it,
//! [`restore`] inverts it and [`capture_and_restore`] scores one light level.
//!
//! The model:
//! - **Channels.** As the thesis (§4.4.1), each colour channel integrates the wavelengths
//!   weighted by the sensor's spectral response (the thesis response on the 401:10:691 grid by
//!   default); the peak wavelengths R 610, G 530, B 470 nm are a 10× faster approximation that
//!   favours a fixed 530 nm plate (its green is then exactly the design wavelength).
//! - **Operator.** A T-OLED is a slit grating along x and fully open along y, so the blur acts on
//!   each image row alone: row `y` of the capture is `K · x_row` with `K[i, j]` the energy that
//!   sensor pixel `i` receives from the direction imaged on pixel `j` (eq. 4.12), computed by the
//!   chain for every direction of the scene (the double MLA's image inversion included). Along y
//!   the open main lens is the only aperture: no blur. A scene `w` columns wide fills the
//!   directions `j − P/2 ∈ [−w/2, w/2)` and is seen on the same `w` sensor pixels; light that
//!   lands outside them is lost. `K` holds absolute energies (fractions of the light on the
//!   main-lens opening), the polariser's ½ included for the double MLA.
//! - **Light and noise.** The light level `N` is the number of photons an open display aperture
//!   would pass to a pixel of value 1. Electrons are `Poisson(N · K x)` plus read noise
//!   N(0, 4.87²), clipped at the full well 15 506 e⁻ (it binds only above ≈ 30 000 photons).
//!   The gain `1/(N·LTR)` makes every setup's capture read ≈ 1 at white (§4.5, conventions.md
//!   §5: "inversely proportional to the LTR of each setup"), and the 12-bit ADC is the thesis's
//!   `floor(y·4095)/4095` on that scale, clipped at 0 (not at 1: white plus noise keeps its
//!   value, as the thesis's model).
//! - **Denoising** ([`Denoise`], conventions.md §5). By default BM3D on the captured colour
//!   image, all channels together (CBM3D), told the capture's own noise variance at white,
//!   `1/(N·LTR) + σ_read²/(N·LTR)² + 1/(12·4095²)` ([`capture_noise`]). The authors' table
//!   [`ICCV23_SIGMA2`](crate::restore::denoise::ICCV23_SIGMA2) stays as
//!   [`Denoise::authors_table`]: captures are already on chapter 4's scale (white ≈ 1), so it
//!   needs no conversion, and its row (like λ's) is the one nearest the SNR
//!   `20 log10(N/√(N + 4.87²))` of `N`: 250 / 650 / 1600 / 4000 / 10 000 photons give
//!   23.6 / 28.0 / 32.0 / 36.0 / 40.0 dB, the rows 24 … 40 dB.
//! - **Restoration.** Conjugate gradients on `min ‖A x − y‖² + λ ‖∇x‖²` with `A = K / LTR`, the
//!   display workspace's solver ([`crate::restore::cg_with`]), per colour channel. After
//!   BM3D, the thesis's λ per row ([`ICCV23_LAMBDA`]), 150 iterations, tolerance 1e-6. Without a
//!   denoiser the regulariser follows the noise: `λ = 30 / (N · LTR)` (30 × the variance of a
//!   white pixel of the capture), clamped to `[1e-5, 1]`, at most 80 iterations, tolerance 1e-4.
//!   The factor was chosen on the astronaut photo at preview sampling, sweeping 0.05 … 60: PSNR
//!   rises to about 20 and is flat beyond for every setup (the bare T-OLED and the double MLA
//!   alike), so no setup is favoured.
//! - **Scores.** PSNR (MSE pooled over channels, peak 1) and SSIM (mean over channels) on the
//!   columns inside the field of view (eq. 4.13 for the design's κ; the bare T-OLED is scored on
//!   the same columns as a double MLA of its pitch), every row.

use crate::Setting;
use std::ops::Range;

use ndarray::{Array2, Axis};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::chain::{Chain, Incidence, PhaseOptics};
use super::geometry::lambda0_per_lenslet;
use super::{
    AllocationSettings, Lambda0, POLARISER_TRANSMISSION, PhaseDesign, PhaseSampling, SimError,
    optimize_lambda0_through,
};
use crate::Progress;
use crate::design::Channel;
use crate::restore::capture::snr_db_of;
use crate::restore::capture::{FULL_WELL_E, READ_NOISE_E};
use crate::restore::denoise::{
    ICCV23_CG_ITERATIONS, ICCV23_CG_TOLERANCE, ICCV23_LAMBDA, nearest_row,
};
use crate::restore::quality::planes_quality;
use crate::restore::{CgSettings, Denoise, DenoiseUsed, LinearBlur, cg_from, cg_with};

mod setups;
mod unpassed;
pub use setups::{CompareRow, Lambda0Plan, LensletOrder, Setup, compare_setups, thesis_setups};
pub use unpassed::{UNPASSED_MTF, unpassed_frequencies, unpassed_mse};

/// The light levels the thesis names (photons on an open display aperture per pixel).
pub const THESIS_PHOTONS: [f64; 4] = [250.0, 650.0, 1600.0, 10_000.0];
/// The range the studio's slider and the CLI accept.
pub const PHOTONS_RANGE: (f64, f64) = (10.0, 1.0e6);
/// ADC resolution of the thesis's simulated sensor.
pub const ADC_BITS: u32 = 12;
/// `λ = LAMBDA_SCALE / (N · LTR)`: the regulariser per unit noise variance.
pub const LAMBDA_SCALE: f64 = 30.0;
/// Iterations of the solver without a denoiser (it usually stops earlier on its tolerance).
pub const CG_ITERATIONS: usize = 80;

/// The denoising of the phase masks' captures (chapter 4): BM3D told each capture's own noise
/// ([`Sigma2::Matched`](crate::restore::Sigma2::Matched), conventions.md §5).
pub fn thesis_denoise() -> Denoise {
    Denoise::default()
}

/// The SNR in dB that picks a light level's row of the thesis tables: that of `photons` with the
/// thesis camera's read noise (the photons on an open display aperture, as the thesis names its
/// levels, not those behind the setup).
pub fn photons_snr_db(photons: f64) -> f64 {
    snr_db_of(photons, READ_NOISE_E)
}

/// The light level and noise of a capture at `photons` through a setup of `ltr`, as the
/// denoiser's σ² needs them. Phase captures are on chapter 4's scale, so no LTR conversion
/// (`ltr_relative` 1); a white pixel collects `photons · ltr` electrons.
pub fn capture_noise(photons: f64, ltr: f64) -> crate::restore::CaptureNoise {
    crate::restore::CaptureNoise {
        snr_db: photons_snr_db(photons),
        ltr_relative: 1.0,
        white_e: photons * ltr,
        read_noise_e: READ_NOISE_E,
        adc_step: 1.0 / f64::from((1u32 << ADC_BITS) - 1),
    }
}

/// The imaging operator of one setup on a scene `width` columns wide.
#[derive(Debug, Clone)]
pub struct PhaseBlur {
    /// Per channel, `[sensor pixel, direction]` (absolute energies): `width` sensor pixels by
    /// `width + 2·margin` directions, the scene's `width` in the middle.
    pub channels: Vec<Array2<f64>>,
    /// Directions on each side of the scene that the restoration solves for too (thesis
    /// §4.4.1's 'full' boundary: the estimate reaches beyond the sensor, then is cropped); 0 for
    /// a closed world where the scene is all there is.
    pub margin: usize,
    /// Name of each channel, in the order of `channels`.
    pub channel_names: Vec<String>,
    /// Light transmittance ratio: the mean over channels of the light that leaves the main-lens
    /// opening at normal incidence, the polariser's ½ included (≈ 0.476 for the thesis design,
    /// 0.238 for the bare T-OLED).
    pub ltr: f64,
    /// Columns (directions) inside the field of view: where the scores are taken.
    pub valid: Range<usize>,
    /// Green (middle channel) column energies before the polariser: the light of each direction
    /// that reaches the scene's sensor columns.
    pub green_column_energy: Vec<f64>,
    /// Per channel, the PSF of the axis direction over the whole sensor (every pixel, not only
    /// the scene's columns): the setup's MTF, which the scene's window would truncate.
    pub axis_psf: Vec<Vec<f64>>,
    /// The optics the operator was computed for (double MLA or bare T-OLED).
    pub optics: PhaseOptics,
}

impl PhaseBlur {
    /// The scene's width: its columns, the sensor pixels it is seen on.
    pub fn width(&self) -> usize {
        self.channels.first().map_or(0, Array2::nrows)
    }

    /// Channel `c`'s operator on the scene's own directions: `width × width`.
    pub fn scene_operator(&self, c: usize) -> ndarray::ArrayView2<'_, f64> {
        let k = &self.channels[c];
        let w = self.width();
        k.slice_axis(Axis(1), ndarray::Slice::from(self.margin..self.margin + w))
    }
}

/// Columns of a `width`-wide scene inside the field of view of eq. 4.13 for `design`'s κ.
pub fn field_of_view_columns(design: &PhaseDesign, width: usize) -> Range<usize> {
    let half = (design.fov_deg() / 2.0).to_radians().sin();
    let max_j = half * design.camera.focal_length_um() / design.camera.pixel_um;
    let half_w = (width / 2) as f64;
    let lo = (half_w - max_j).ceil().max(0.0) as usize;
    let hi = ((half_w + max_j).floor() as usize + 1).min(width);
    lo.min(hi)..hi
}

/// The operator of `design` through `optics` (the double MLA or the bare T-OLED) for a scene
/// `width` columns wide: `width` directions × every channel wavelength, in parallel.
///
/// # Errors
/// An invalid design or channel, a scene wider than the sensor, or [`SimError::Cancelled`].
pub fn phase_blur(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    channels: &[Channel],
    optics: PhaseOptics,
    width: usize,
    progress: &Progress,
) -> Result<PhaseBlur, SimError> {
    phase_blur_full(design, sampling, channels, optics, width, 0, progress)
}

/// [`phase_blur`] with `margin` more directions on each side of the scene, whose light the
/// scene's `width` sensor pixels also receive: the restoration then solves for them too and
/// crops them off (thesis §4.4.1's 'full' boundary). `margin` 0 is [`phase_blur`].
///
/// # Errors
/// As [`phase_blur`], and a margin that reaches directions beyond ±90°.
pub fn phase_blur_full(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    channels: &[Channel],
    optics: PhaseOptics,
    width: usize,
    margin: usize,
    progress: &Progress,
) -> Result<PhaseBlur, SimError> {
    let chain = Chain::new(design, sampling)?;
    phase_blur_on(&chain, channels, optics, width, margin, progress)
}

/// [`phase_blur_full`] on a sampled chain: the one whose Bloch relay runs on a device
/// ([`Chain::with_relay`]) computes the operator's directions there.
///
/// # Errors
/// As [`phase_blur_full`].
pub fn phase_blur_on(
    chain: &Chain,
    channels: &[Channel],
    optics: PhaseOptics,
    width: usize,
    margin: usize,
    progress: &Progress,
) -> Result<PhaseBlur, SimError> {
    let design = chain.design();
    let pixels = design.camera.pixels;
    let reach = (width / 2 + margin) as f64 * design.camera.pixel_um;
    if !(reach < design.camera.focal_length_um()) {
        return Err(SimError::invalid(
            "margin",
            format!(
                "{margin} directions beyond a {width}-column scene reach past 90° (at most {})",
                (design.camera.focal_length_um() / design.camera.pixel_um) as usize - width / 2
            ),
        ));
    }
    if width < 8 || width > pixels {
        return Err(SimError::invalid(
            "width",
            format!("the scene is {width} columns; it must be 8 … {pixels} (the sensor)"),
        ));
    }
    if channels.is_empty() {
        return Err(SimError::invalid(
            "channels",
            "at least one channel is needed",
        ));
    }
    let first = pixels / 2 - width / 2;
    let polariser = match optics {
        PhaseOptics::DoubleMla => POLARISER_TRANSMISSION,
        PhaseOptics::Toled | PhaseOptics::SingleMask => 1.0,
    };
    // Every wavelength once, with each channel's normalised weight.
    let mut wavelengths: Vec<f64> = channels
        .iter()
        .flat_map(|c| c.wavelengths_nm.iter().copied())
        .collect();
    wavelengths.sort_by(f64::total_cmp);
    wavelengths.dedup();
    let weight = |c: &Channel, l: f64| -> f64 {
        let sum: f64 = c.weights.iter().sum();
        c.wavelengths_nm
            .iter()
            .zip(&c.weights)
            .filter(|(w, _)| **w == l)
            .map(|(_, w)| w / sum)
            .sum()
    };
    // Directions are numbered from the left margin; the scene's axis is `margin + width / 2`.
    let directions = width + 2 * margin;
    let axis = margin + width / 2;
    let incidences: Vec<Incidence> = (0..directions)
        .map(|j| Incidence::Pixel(j as i64 - axis as i64))
        .collect();
    // Per direction: each channel's column, its total transmission and, for the axis direction
    // alone, its PSF over the whole sensor. Wavelength by wavelength, all directions at once, so
    // the plate's transmission is formed once per wavelength; each column still sums its
    // wavelengths in ascending order.
    let mut columns: Vec<Column> = (0..directions)
        .map(|j| {
            let whole = if j == axis { pixels } else { 0 };
            (
                vec![vec![0.0; width]; channels.len()],
                vec![0.0; channels.len()],
                vec![vec![0.0; whole]; channels.len()],
            )
        })
        .collect();
    let share = |i: usize| i as f32 / wavelengths.len() as f32;
    for (done, &l) in wavelengths.iter().enumerate() {
        let (psfs, axis_psf) = {
            // Each wavelength's directions fill its share of the bar as they finish.
            let _span = progress.span(share(done), share(done + 1));
            // Only the scene's columns of each PSF enter K (the lenslet period then transforms
            // only their samples); the axis direction's whole-sensor PSF is the MTF's.
            let heights = chain.heights_um();
            let window = first..first + width;
            let psfs =
                chain.mono_directions_on(optics, heights, l, &incidences, window, progress)?;
            (psfs, chain.mono(optics, heights, l, incidences[axis]))
        };
        let weights: Vec<f64> = channels
            .iter()
            .map(|ch| weight(ch, l) * polariser)
            .collect();
        columns
            .par_iter_mut()
            .zip(&psfs)
            .for_each(|((cols, transmission, whole), psf)| {
                for (c, &w) in weights.iter().enumerate() {
                    if w > 0.0 {
                        for (v, s) in cols[c].iter_mut().zip(&psf.sensor[first..first + width]) {
                            *v += w * s;
                        }
                        for (v, s) in whole[c].iter_mut().zip(&axis_psf.sensor) {
                            *v += w * s;
                        }
                        transmission[c] += w * psf.total_energy;
                    }
                }
            });
        progress.set(share(done + 1));
    }
    let ltr = columns[axis].1.iter().sum::<f64>() / channels.len() as f64;
    let green = channels.len() / 2;
    let mats = (0..channels.len())
        .map(|c| Array2::from_shape_fn((width, directions), |(i, j)| columns[j].0[c][i]))
        .collect();
    Ok(PhaseBlur {
        channels: mats,
        margin,
        channel_names: channels.iter().map(|c| c.name.clone()).collect(),
        ltr,
        valid: field_of_view_columns(design, width),
        green_column_energy: columns[margin..margin + width]
            .iter()
            .map(|(cols, _, _)| cols[green].iter().sum::<f64>() / polariser)
            .collect(),
        axis_psf: std::mem::take(&mut columns[axis].2),
        optics,
    })
}

/// One direction of the operator: each channel's column on the scene's pixels, each channel's
/// total transmission, and (the axis direction only, else empty) each channel's PSF over the
/// whole sensor.
type Column = (Vec<Vec<f64>>, Vec<f64>, Vec<Vec<f64>>);

/// One channel's `A = K / LTR` acting on image rows, with its normal matrix precomputed.
struct RowBlur {
    /// `Kᵀ / LTR`, so that `A X = X · kt` for rows `X`.
    kt: Array2<f64>,
    /// `AᵀA` as a right factor: `X · gram`.
    gram: Array2<f64>,
}

impl RowBlur {
    fn new(k: &Array2<f64>, ltr: f64) -> Self {
        let kt = k.t().mapv(|v| v / ltr);
        let gram = kt.dot(&kt.t());
        RowBlur { kt, gram }
    }

    /// `X · m`, rows in parallel blocks.
    fn right(x: &Array2<f64>, m: &Array2<f64>) -> Array2<f64> {
        let mut out = Array2::zeros((x.nrows(), m.ncols()));
        out.axis_chunks_iter_mut(Axis(0), 64)
            .into_par_iter()
            .zip(x.axis_chunks_iter(Axis(0), 64).into_par_iter())
            .for_each(|(mut o, xi)| o.assign(&xi.dot(m)));
        out
    }
}

impl LinearBlur for RowBlur {
    fn blur(&self, x: &Array2<f64>) -> Array2<f64> {
        Self::right(x, &self.kt)
    }

    fn adjoint(&self, z: &Array2<f64>) -> Array2<f64> {
        Self::right(z, &self.kt.t().to_owned())
    }

    fn normal(&self, x: &Array2<f64>) -> Array2<f64> {
        Self::right(x, &self.gram)
    }
}

fn check_scene(blur: &PhaseBlur, scene: &[Array2<f64>]) -> Result<(), SimError> {
    let width = blur.width();
    if scene.len() != blur.channels.len() {
        return Err(SimError::invalid(
            Setting::Photo,
            format!(
                "has {} planes; the setup has {} channels",
                scene.len(),
                blur.channels.len()
            ),
        ));
    }
    for plane in scene {
        if plane.ncols() != width || plane.nrows() < 8 {
            return Err(SimError::invalid(
                Setting::Photo,
                format!(
                    "is {}×{} px; the operator was built for {width} columns and needs ≥ 8 rows",
                    plane.ncols(),
                    plane.nrows()
                ),
            ));
        }
        if plane.iter().any(|v| !v.is_finite()) {
            return Err(SimError::invalid(
                Setting::Photo,
                "holds a non-finite value",
            ));
        }
    }
    Ok(())
}

fn check_photons(photons: f64) -> Result<(), SimError> {
    let (lo, hi) = PHOTONS_RANGE;
    if photons.is_finite() && (lo..=hi).contains(&photons) {
        Ok(())
    } else {
        Err(SimError::invalid(
            "photons",
            format!("{photons:?} is outside {lo} … {hi} photons per pixel"),
        ))
    }
}

/// The scene (linear planes in [0, 1], one per channel) as the sensor reads it at `photons`,
/// gained by `1/(photons · LTR)` and quantised to 12 bits (module docs): a white pixel reads ≈ 1
/// whatever the setup's LTR.
///
/// # Errors
/// A scene that does not fit the operator, a light level outside [`PHOTONS_RANGE`].
pub fn capture(
    blur: &PhaseBlur,
    scene: &[Array2<f64>],
    photons: f64,
    seed: u64,
) -> Result<Vec<Array2<f64>>, SimError> {
    check_scene(blur, scene)?;
    check_photons(photons)?;
    if !(blur.ltr > 0.0) {
        return Err(SimError::invalid("ltr", "the setup passes no light"));
    }
    // White reads ≈ 1 in every setup: the gain 1/(N·LTR) of conventions.md §5.
    let gain = 1.0 / (photons * blur.ltr);
    let levels = f64::from((1u32 << ADC_BITS) - 1);
    let read = Normal::new(0.0, READ_NOISE_E)
        .map_err(|e| SimError::invalid("read_noise_e", e.to_string()))?;
    Ok(blur
        .channels
        .iter()
        .zip(scene)
        .enumerate()
        .map(|(c, (_, plane))| {
            // The scene is what there is: its own directions, none from the margin.
            let mean = RowBlur::right(plane, &blur.scene_operator(c).t().to_owned());
            let mut out = Array2::zeros(mean.dim());
            out.axis_iter_mut(Axis(0))
                .into_par_iter()
                .zip(mean.axis_iter(Axis(0)).into_par_iter())
                .enumerate()
                .for_each(|(y, (mut o, m))| {
                    let mut rng = ChaCha8Rng::seed_from_u64(seed);
                    rng.set_stream(((c as u64) << 40) ^ y as u64);
                    for (o, m) in o.iter_mut().zip(m) {
                        let mean_e = (m * photons).max(0.0);
                        let shot = Poisson::new(mean_e).map_or(mean_e, |p| p.sample(&mut rng));
                        let electrons = (shot + read.sample(&mut rng)).min(FULL_WELL_E);
                        *o = ((electrons * gain * levels).floor() / levels).max(0.0);
                    }
                });
            out
        })
        .collect())
}

/// The regulariser without a denoiser, for a light level and an LTR (see the module docs).
pub fn regulariser(photons: f64, ltr: f64) -> f64 {
    (LAMBDA_SCALE / (photons * ltr)).clamp(1e-5, 1.0)
}

/// The solver's settings after `denoise` at `photons` through a setup of `ltr`: the thesis's
/// chapter 4 after BM3D, the noise-following rule of [`regulariser`] without (module docs).
pub fn cg_settings(photons: f64, ltr: f64, denoise: Denoise) -> CgSettings {
    match denoise {
        Denoise::Bm3d { .. } => CgSettings {
            lambda: ICCV23_LAMBDA[nearest_row(photons_snr_db(photons))],
            iterations: ICCV23_CG_ITERATIONS,
            tolerance: ICCV23_CG_TOLERANCE,
        },
        Denoise::None => CgSettings {
            lambda: regulariser(photons, ltr),
            iterations: CG_ITERATIONS,
            tolerance: 1e-4,
        },
    }
}

/// A restoration of a capture: what the deblurring started from and what it gave.
#[derive(Debug, Clone)]
pub struct Restoration {
    /// The denoised capture per channel; **empty** without a denoiser.
    pub denoised: Vec<Array2<f64>>,
    /// The conjugate-gradient restoration per channel.
    pub restored: Vec<Array2<f64>>,
    /// The denoising done, with the σ² BM3D got (on the capture's scale, white ≈ 1).
    pub denoise: DenoiseUsed,
    /// The solver's settings.
    pub cg: CgSettings,
}

/// Denoises a capture (every channel together) as `denoise` says, then restores every channel
/// by conjugate gradients through the same operator. `progress` runs from 0 to 1 over both
/// (BM3D takes most of it) and cancels either.
///
/// # Errors
/// A capture that does not fit the operator, a bad `denoise`, or [`SimError::Cancelled`].
pub fn restore(
    blur: &PhaseBlur,
    captured: &[Array2<f64>],
    photons: f64,
    denoise: Denoise,
    progress: &Progress,
) -> Result<Restoration, SimError> {
    check_scene(blur, captured)?;
    check_photons(photons)?;
    denoise.validate()?;
    let used = denoise.applied(&capture_noise(photons, blur.ltr))?;
    // BM3D's share of the time: ≈ 1 s for a 512² colour image against a few hundred ms of CG.
    let deblur_start = if used.sigma2.is_some() { 0.7 } else { 0.0 };
    let denoised = match used.sigma2 {
        None => Vec::new(),
        Some(sigma2) => {
            let _span = progress.span(0.0, deblur_start);
            crate::denoise::bm3d(captured, sigma2, progress)?
        }
    };
    progress.check()?;
    let inputs = if denoised.is_empty() {
        captured
    } else {
        &denoised
    };
    let settings = cg_settings(photons, blur.ltr, denoise);
    let n = blur.channels.len().max(1) as f32;
    let mut restored = Vec::with_capacity(blur.channels.len());
    for (c, (k, y)) in blur.channels.iter().zip(inputs).enumerate() {
        let op = RowBlur::new(k, blur.ltr);
        let x = if blur.margin == 0 {
            cg_with(&op, y.view(), &settings, progress)?.0
        } else {
            // The 'full' boundary: start from the capture with its edge columns carried into
            // the margins, solve on the wider support, keep the scene's columns.
            let m = blur.margin;
            let w = y.ncols();
            let start = Array2::from_shape_fn((y.nrows(), w + 2 * m), |(r, j)| {
                y[[r, j.saturating_sub(m).min(w - 1)]]
            });
            let wide = cg_from(&op, y.view(), start, &settings, progress)?.0;
            wide.slice_axis(Axis(1), ndarray::Slice::from(m..m + w))
                .to_owned()
        };
        restored.push(x);
        progress.set(deblur_start + (1.0 - deblur_start) * (c + 1) as f32 / n);
    }
    Ok(Restoration {
        denoised,
        restored,
        denoise: used,
        cg: settings,
    })
}

/// One light level: the capture, the restoration and their scores.
#[derive(Debug, Clone)]
pub struct RestoreRun {
    /// Light level: photons on an open display aperture per pixel.
    pub photons: f64,
    /// PSNR of the restoration on the field of view (MSE pooled over channels, peak 1).
    pub psnr_db: f64,
    /// Mean SSIM over channels on the field of view.
    pub ssim: f64,
    /// PSNR of the capture itself against the scene.
    pub captured_psnr_db: f64,
    /// PSNR of the denoised capture (still blurred) against the scene; `None` without a
    /// denoiser.
    pub denoised_psnr_db: Option<f64>,
    /// The capture per channel, gained so that a white pixel reads ≈ 1.
    pub captured: Vec<Array2<f64>>,
    /// The denoised capture per channel; **empty** without a denoiser.
    pub denoised: Vec<Array2<f64>>,
    /// The conjugate-gradient restoration per channel.
    pub restored: Vec<Array2<f64>>,
    /// The denoising done, with the σ² BM3D got.
    pub denoise: DenoiseUsed,
    /// The solver's settings.
    pub cg: CgSettings,
}

/// PSNR and mean SSIM of `test` against `truth` on the columns `valid`.
///
/// # Errors
/// Planes of different sizes or a field narrower than the SSIM window.
pub fn scores(
    test: &[Array2<f64>],
    truth: &[Array2<f64>],
    valid: &Range<usize>,
) -> Result<(f64, f64), SimError> {
    let crop = |a: &Array2<f64>| {
        a.slice_axis(Axis(1), ndarray::Slice::from(valid.clone()))
            .to_owned()
    };
    let a: Vec<Array2<f64>> = test.iter().map(crop).collect();
    let b: Vec<Array2<f64>> = truth.iter().map(crop).collect();
    let q = planes_quality(&a, &b)?;
    Ok((q.psnr_db, q.ssim))
}

/// Captures `scene` at `photons`, denoises it as `denoise` says ([`thesis_denoise`] is the
/// thesis's), restores it and scores all three.
///
/// # Errors
/// As [`capture`] and [`restore`].
pub fn capture_and_restore(
    blur: &PhaseBlur,
    scene: &[Array2<f64>],
    photons: f64,
    seed: u64,
    denoise: Denoise,
    progress: &Progress,
) -> Result<RestoreRun, SimError> {
    denoise.validate()?;
    progress.set(0.0);
    let captured = capture(blur, scene, photons, seed)?;
    progress.check()?;
    let Restoration {
        denoised,
        restored,
        denoise,
        cg,
    } = {
        let _span = progress.span(0.05, 1.0);
        restore(blur, &captured, photons, denoise, progress)?
    };
    let (psnr_db, ssim) = scores(&restored, scene, &blur.valid)?;
    let (captured_psnr_db, _) = scores(&captured, scene, &blur.valid)?;
    let denoised_psnr_db = if denoised.is_empty() {
        None
    } else {
        Some(scores(&denoised, scene, &blur.valid)?.0)
    };
    if !(psnr_db.is_finite() || psnr_db == f64::INFINITY) || !ssim.is_finite() {
        return Err(SimError::Sampling(format!(
            "the scores at {photons} photons are not finite (PSNR {psnr_db}, SSIM {ssim})"
        )));
    }
    Ok(RestoreRun {
        photons,
        psnr_db,
        ssim,
        captured_psnr_db,
        denoised_psnr_db,
        captured,
        denoised,
        restored,
        denoise,
        cg,
    })
}
