//! The flat-patch check of eq. 5.3's η (conventions.md §8). The 2.2 % the thesis quotes for
//! η = 2 is the probability that one pixel whose light level is exactly the `l̂` its gain was
//! chosen for saturates: a per-pixel probability, to be checked on a flat patch, not a fraction
//! of a whole image. [`flat_patch`] exposes a flat patch at `l* = l̂`, reads it at eq. 5.3's gain
//! with the noise and ADC model of [`super::noise`] (Monte Carlo, seeded), and sets the measured
//! fraction beside two numbers:
//!
//! - **`predicted`**, the model's own probability, computed without sampling. A readout of a sum
//!   of `N` pixels (`N` = 1 without binning) saturates when its amplified signal
//!   `a·(S + n_pre) + n_post` reaches the ADC's top code, `T = (2^bits − 1.5 − i0)·q` electrons at
//!   base gain (`q` electrons per code; codes round half up). Here `S ~ Poisson(N l*)` clipped at
//!   `N l_wc`, `n_pre ~ N(0, N σ_pre²)`, `n_post ~ N(0, σ_post²)` and `a` is the gain per electron
//!   of the sum: `g` for one pixel, `ĝ` for an additive bin, `g/N` for an average bin. So
//!   `P = Σ_k Poisson(k; N l*) · Q((T − a·min(k, N l_wc)) / √(a² N σ_pre² + σ_post²))`: the
//!   Poisson tail convolved with the Gaussian read noise. A digital bin saturates when any of its
//!   `N` independently read pixels does: `1 − (1 − P₁)^N`. The clip at `N l_wc` is exact for one
//!   pixel; for a sum it stands in for each pixel's own clip, which only matters where the pixels
//!   nearly fill their wells at gain 1 and saturate anyway.
//! - **`gaussian_tail`**, eq. 5.3's own number `1 − Φ(η)` (2.28 % at η = 2, "≈ 2.2 %"): the
//!   thesis approximates the amplified signal by a Gaussian of variance `g² l̂` and drops the read
//!   noise. It holds for one pixel whose gain eq. 5.3 did not clamp. The Poisson tail is heavier
//!   than the Gaussian one (skewness `1/√l̂`: about `Q(η − (η² − 1)/(6√l̂))`), so at a few hundred
//!   electrons `predicted` is a little above it (≈ 2.4 % at 400 e⁻ on Table 5.4's sensor) and
//!   meets it as `l̂` grows.

use crate::Setting;
use ndarray::Array2;

use super::noise::{Adc, expose_frame, stream};
use super::roi::RoiGrid;
use super::{AdditiveGain, BIN_SIZES, BinMode, SensorSpec, binning, gain};
use crate::{Progress, SimError};

/// Smallest and largest side of the flat patch, pixels.
pub const FLAT_PATCH_SIDE_RANGE: (usize, usize) = (16, 4096);

/// Brightest flat patch, electrons per unit pixel: far beyond any full well, and small enough
/// that the exact tail sums a few hundred thousand Poisson terms at most.
pub const FLAT_PATCH_MAX_LIGHT_E: f64 = 1e7;

/// What [`flat_patch`] exposes and how it reads it.
#[derive(Debug, Clone, PartialEq)]
pub struct FlatPatchSpec {
    /// The patch's light level `l*`, electrons per unit pixel; also the `l̂` eq. 5.3 sets the
    /// gain for.
    pub light_e: f64,
    /// η of eq. 5.3 (2: the thesis's 2.2 %).
    pub eta: f64,
    /// Side of the square bins, unit pixels: 1 (no binning), 2, 4 or 8.
    pub bin_px: usize,
    /// How a bin's pixels are combined (ignored for 1-pixel bins).
    pub bin_mode: BinMode,
    /// The amplifier gain of additive bins.
    pub additive_gain: AdditiveGain,
    /// Side of the square patch, unit pixels (a multiple of `bin_px`).
    pub side_px: usize,
    /// Seed of the photon and read noise.
    pub seed: u64,
    /// The pixel gain `g`, instead of eq. 5.3's gain for `light_e` and `eta` (Table 5.1's
    /// variances are compared at a chosen gain).
    pub gain: Option<f64>,
}

impl Default for FlatPatchSpec {
    /// 400 e⁻ per pixel, η = 2, no binning, a 512×512 patch (262 144 readouts: a standard
    /// error of 0.03 percentage points at 2.3 %), seed 0.
    fn default() -> Self {
        FlatPatchSpec {
            light_e: 400.0,
            eta: 2.0,
            bin_px: 1,
            bin_mode: BinMode::default(),
            additive_gain: AdditiveGain::default(),
            side_px: 512,
            seed: 0,
            gain: None,
        }
    }
}

impl FlatPatchSpec {
    /// Checks every field; errors name it (`light_e`, `eta`, `bin_px`, `side_px`, `gain`).
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        let l = self.light_e;
        if !(l.is_finite() && (0.0..=FLAT_PATCH_MAX_LIGHT_E).contains(&l)) {
            return Err(SimError::invalid(
                Setting::LightE,
                format!("must be 0 … {FLAT_PATCH_MAX_LIGHT_E:e} electrons per pixel (got {l:?})"),
            ));
        }
        if !(self.eta.is_finite() && (0.0..=1e3).contains(&self.eta)) {
            return Err(SimError::invalid(
                Setting::Eta,
                format!("must be 0 … 1000 (got {:?})", self.eta),
            ));
        }
        if !BIN_SIZES.contains(&self.bin_px) {
            return Err(SimError::invalid(
                Setting::BinPx,
                format!("a bin is 1, 2, 4 or 8 pixels wide (got {})", self.bin_px),
            ));
        }
        if let Some(g) = self.gain
            && !(g.is_finite() && g > 0.0 && g <= 1e6)
        {
            return Err(SimError::invalid(
                Setting::Gain,
                format!("must be a finite gain in (0, 1e6] (got {g:?})"),
            ));
        }
        let (lo, hi) = FLAT_PATCH_SIDE_RANGE;
        if !(lo..=hi).contains(&self.side_px) || !self.side_px.is_multiple_of(self.bin_px) {
            return Err(SimError::invalid(
                Setting::SidePx,
                format!(
                    "must be {lo} … {hi} pixels and a multiple of the bin side {} (got {})",
                    self.bin_px, self.side_px
                ),
            ));
        }
        Ok(())
    }
}

/// The result of [`flat_patch`]; fractions are in `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlatPatch {
    /// The pixel gain eq. 5.3 gives for `light_e` and `eta`, clamped to `[1, max gain]`.
    pub gain: f64,
    /// The gain the readouts are amplified at: `gain`, or `ĝ` for additive bins.
    pub amplifier_gain: f64,
    /// Measured: the fraction of the patch's pixels whose readout (or whose bin's) saturated.
    pub saturated_fraction: f64,
    /// The model's probability that one readout saturates (Poisson tail convolved with the
    /// Gaussian read noise; see the module docs).
    pub predicted: f64,
    /// Eq. 5.3's Gaussian approximation `1 − Φ(η)`, meant for one pixel at an unclamped gain.
    pub gaussian_tail: f64,
    /// Independent readouts in the patch: its pixels, or its bins.
    pub readouts: usize,
    /// Standard error of `saturated_fraction` if `predicted` is right: `√(p(1 − p)/readouts)`.
    pub standard_error: f64,
    /// Measured: the sample variance of the per-pixel estimate `l̂` over the readouts, e⁻².
    pub variance_e2: f64,
    /// Table 5.1's variance of `l̂` for this bin, mode and amplifier gain, e⁻² (no ADC term).
    pub table51_variance_e2: f64,
    /// Standard error of `variance_e2` if Table 5.1 is right and `l̂` nearly Gaussian:
    /// `σ² √(2/(readouts − 1))`.
    pub variance_standard_error_e2: f64,
}

/// `Q(x) = 1 − Φ(x)`, the standard normal upper tail.
fn upper_tail(x: f64) -> f64 {
    0.5 * libm::erfc(x / std::f64::consts::SQRT_2)
}

/// `P(a·min(K, cap_e) + σ Z ≥ top_e)` for `K ~ Poisson(mean_e)`, `Z ~ N(0, 1)`, summed over `K`
/// out to where the Poisson weights fall below 1e-17 of the mode's.
fn poisson_gauss_tail(mean_e: f64, cap_e: f64, a: f64, sigma_e: f64, top_e: f64) -> f64 {
    let q = |k: f64| {
        let x = top_e - a * k.min(cap_e);
        if sigma_e > 0.0 {
            upper_tail(x / sigma_e)
        } else {
            f64::from(u8::from(x <= 0.0))
        }
    };
    if !(mean_e > 0.0) {
        return q(0.0);
    }
    // Weights relative to the mode's, by the ratio of neighbouring Poisson terms: no factorials.
    let mode = mean_e.floor();
    let (mut total, mut hit) = (1.0, q(mode));
    let (mut w, mut k) = (1.0, mode);
    loop {
        k += 1.0;
        w *= mean_e / k;
        if w < 1e-17 {
            break;
        }
        total += w;
        hit += w * q(k);
    }
    (w, k) = (1.0, mode);
    while k > 0.0 {
        w *= k / mean_e;
        k -= 1.0;
        if w < 1e-17 {
            break;
        }
        total += w;
        hit += w * q(k);
    }
    (hit / total).clamp(0.0, 1.0)
}

/// The model's probability that one readout of a flat patch at `light_e` saturates, read at
/// pixel gain `gain` in `bin_px`-wide bins (see the module docs).
pub fn predicted_saturation(
    light_e: f64,
    gain: f64,
    bin_px: usize,
    bin_mode: BinMode,
    additive_gain: AdditiveGain,
    sensor: &SensorSpec,
) -> f64 {
    let adc = Adc::of(sensor);
    let top_e = (adc.max_code - 0.5 - adc.black_dn) * adc.e_per_dn;
    let n = bin_px.max(1).pow(2);
    let amp = bin_mode.amplifier_gain(gain, n, additive_gain);
    let (pre2, post2) = (sensor.sigma_pre_e.powi(2), sensor.sigma_post_e.powi(2));
    let sum_tail = |pixels: usize, a: f64| {
        let p = pixels as f64;
        let sigma = (a * a * p * pre2 + post2).sqrt();
        poisson_gauss_tail(p * light_e, p * sensor.full_well_e, a, sigma, top_e)
    };
    match bin_mode {
        _ if n == 1 => sum_tail(1, amp),
        BinMode::Digital => 1.0 - (1.0 - sum_tail(1, amp)).powi(n as i32),
        BinMode::AnalogAdditive => sum_tail(n, amp),
        BinMode::AnalogAverage => sum_tail(n, amp / n as f64),
    }
}

/// Exposes a flat patch at `spec.light_e`, reads it at the gain eq. 5.3 gives for that light
/// with `spec.eta` (or at `spec.gain`; binned as `spec` says) through `sensor`'s noise and ADC
/// model, and returns the measured and predicted saturated fractions, and the measured variance
/// of the estimate beside Table 5.1's. The one entry point of the CLI's `sensor flat-patch`, the
/// studio's flat-patch check, the tests and `reproduce table5.1`.
///
/// ```
/// use udc_core::Progress;
/// use udc_core::sensor::{FlatPatchSpec, SensorSpec, flat_patch};
///
/// let spec = FlatPatchSpec { light_e: 400.0, eta: 2.0, side_px: 256, ..FlatPatchSpec::default() };
/// let r = flat_patch(&spec, &SensorSpec::table54(), &Progress::new())?;
/// assert!((r.saturated_fraction - r.predicted).abs() < 5.0 * r.standard_error);
/// # Ok::<(), udc_core::SimError>(())
/// ```
///
/// # Errors
/// [`SimError::InvalidSetting`] naming the field of `spec` (`light_e`, `eta`, `bin_px`,
/// `side_px`) or of the sensor (`sensor.…`); [`SimError::TooLarge`] past the memory budget;
/// [`SimError::Cancelled`] when `progress` was cancelled.
pub fn flat_patch(
    spec: &FlatPatchSpec,
    sensor: &SensorSpec,
    progress: &Progress,
) -> Result<FlatPatch, SimError> {
    spec.validate()?;
    sensor.validate()?;
    let side = spec.side_px;
    crate::budget::check(
        &format!("a {side}×{side} flat patch"),
        ((side * side) as u64)
            .saturating_mul(super::FIXED_BYTES_PER_PIXEL + super::STRATEGY_BYTES_PER_PIXEL),
        "use a smaller patch",
    )?;
    progress.set(0.0);
    progress.check()?;
    let g = spec.gain.unwrap_or_else(|| {
        gain::gain_for_light(spec.light_e, spec.eta, sensor.full_well_e, sensor.max_gain)
    });
    let electrons = Array2::from_elem((side, side), spec.light_e);
    let frame = expose_frame(electrons.view(), sensor, spec.seed, stream::CAPTURE);
    progress.set(0.5);
    progress.check()?;
    // ROIs only to spread the readout over threads: every ROI has the same gain and bins.
    let grid = RoiGrid::new((side, side), 64usize.max(spec.bin_px).min(side));
    let dim = (grid.rows, grid.cols);
    let readout = binning::read_regions(
        &frame,
        &grid,
        &Array2::from_elem(dim, g),
        &Array2::from_elem(dim, spec.bin_px),
        spec.bin_mode,
        spec.additive_gain,
        &Adc::of(sensor),
    );
    let n = spec.bin_px * spec.bin_px;
    let predicted = predicted_saturation(
        spec.light_e,
        g,
        spec.bin_px,
        spec.bin_mode,
        spec.additive_gain,
        sensor,
    );
    let readouts = side * side / n;
    let amplifier_gain = spec.bin_mode.amplifier_gain(g, n, spec.additive_gain);
    // Every pixel of a bin carries the bin's estimate: one sample per bin, its first pixel.
    let b = spec.bin_px;
    let samples: Vec<f64> = readout
        .estimate_e
        .indexed_iter()
        .filter(|((y, x), _)| y % b == 0 && x % b == 0)
        .map(|(_, v)| *v)
        .collect();
    let count = samples.len().max(2) as f64;
    let mean = samples.iter().sum::<f64>() / count;
    let variance_e2 = samples.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0);
    let table51_variance_e2 =
        binning::variance(spec.bin_mode, spec.light_e, sensor, amplifier_gain, n);
    progress.set(1.0);
    Ok(FlatPatch {
        gain: g,
        amplifier_gain,
        saturated_fraction: readout.saturated_fraction(),
        predicted,
        gaussian_tail: upper_tail(spec.eta),
        readouts,
        standard_error: (predicted * (1.0 - predicted) / readouts as f64).sqrt(),
        variance_e2,
        table51_variance_e2,
        variance_standard_error_e2: table51_variance_e2 * (2.0 / (count - 1.0)).sqrt(),
    })
}
