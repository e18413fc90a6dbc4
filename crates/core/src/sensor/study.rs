//! The bin-size study of Fig. 5.4: one region of a scene captured at bin sizes 1, 2, 4 and 8
//! across light levels, with the bin the optimal-pitch theory predicts ([`super::pitch`]) beside
//! the bin that scores best; and, at one dim light level, the binning modes at a small and a
//! large gain side by side (Fig. 5.4b).
//!
//! Each capture reads the region as one ROI with one gain and one bin size everywhere, through
//! the same noise model, ADC and tone curve as [`super::run`]. Light levels are the region's
//! mean light in e⁻/µm²; the predicted bin is [`super::pitch::optimal_bin`] at `l0 = 2·mean`
//! (the derivation's sinusoid has mean `l0/2`), as the vary-bin strategy uses it. "Best" is the
//! highest SSIM (the thesis marks the best LPIPS, which the studio does not compute).

use ndarray::Array2;
use rayon::prelude::*;

use super::binning::read_regions;
use super::metrics::{self, SSIM_WINDOW_PX, ToneCurve};
use super::noise::{Adc, expose_frame};
use super::pitch::optimal_bin;
use super::{AdditiveGain, BIN_SIZES, BinMode, RoiGrid, SensorSettings};
use crate::{Progress, SimError};

/// What to sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct StudySpec {
    /// The region's mean light levels, e⁻/µm² (Fig. 5.4a: dim to bright).
    pub lights_e_per_um2: Vec<f64>,
    /// How the sweep's bins are combined (Fig. 5.4a: analog additive).
    pub sweep_mode: BinMode,
    /// The pixel gain of the sweep (1 = base).
    pub sweep_gain: f64,
    /// The light of the mode comparison, e⁻/µm² (Fig. 5.4b: 20).
    pub modes_light_e_per_um2: f64,
    /// The small and the large gain of the mode comparison.
    pub modes_gains: [f64; 2],
}

impl Default for StudySpec {
    /// Fig. 5.4's setting: 1 … 200 e⁻/µm², additive binning at base gain (at the settings'
    /// additive gain); the modes at 20 e⁻/µm² with gains 1 and 16.
    fn default() -> Self {
        StudySpec {
            lights_e_per_um2: vec![1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0],
            sweep_mode: BinMode::AnalogAdditive,
            sweep_gain: 1.0,
            modes_light_e_per_um2: 20.0,
            modes_gains: [1.0, 16.0],
        }
    }
}

impl StudySpec {
    /// Checks every field; errors name it (`lights_e_per_um2[2]`, `modes_gains[1]`, …).
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for the first bad field.
    pub fn validate(&self, max_gain: f64) -> Result<(), SimError> {
        if self.lights_e_per_um2.is_empty() || self.lights_e_per_um2.len() > 32 {
            return Err(SimError::invalid(
                "lights_e_per_um2",
                "give 1 … 32 light levels",
            ));
        }
        let light_ok = |l: f64| l.is_finite() && l > 0.0 && l <= 1e6;
        for (i, l) in self.lights_e_per_um2.iter().enumerate() {
            if !light_ok(*l) {
                return Err(SimError::invalid(
                    format!("lights_e_per_um2[{i}]"),
                    format!("must be above 0 and at most 1e6 e⁻/µm² (got {l:?})"),
                ));
            }
        }
        if !light_ok(self.modes_light_e_per_um2) {
            return Err(SimError::invalid(
                "modes_light_e_per_um2",
                format!(
                    "must be above 0 and at most 1e6 e⁻/µm² (got {:?})",
                    self.modes_light_e_per_um2
                ),
            ));
        }
        let gains = [("sweep_gain", self.sweep_gain)].into_iter().chain([
            ("modes_gains[0]", self.modes_gains[0]),
            ("modes_gains[1]", self.modes_gains[1]),
        ]);
        for (field, g) in gains {
            if !(g.is_finite() && (1.0..=max_gain).contains(&g)) {
                return Err(SimError::invalid(
                    field,
                    format!("must be 1 … {max_gain} (the sensor's gains; got {g:?})"),
                ));
            }
        }
        Ok(())
    }
}

/// One capture of the study.
#[derive(Debug, Clone)]
pub struct StudyCapture {
    /// The region's mean light, e⁻/µm².
    pub light_e_per_um2: f64,
    /// Bin side, unit pixels.
    pub bin: usize,
    /// How the bin was combined.
    pub mode: BinMode,
    /// The amplifier gain of an additive bin (`scaled` for the other modes, where it does not
    /// apply).
    pub additive_gain: AdditiveGain,
    /// The pixel gain.
    pub gain: f64,
    /// The capture through the tone curve, `[0, 1]`.
    pub display: Array2<f64>,
    /// SSIM against the noise-free region.
    pub ssim: f64,
    /// PSNR against the noise-free region, dB.
    pub psnr_db: f64,
    /// Fraction of the region's pixels whose bin saturated.
    pub saturated_fraction: f64,
}

/// Per light level: the bin the theory predicts and the bin that scored best.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BinChoice {
    /// The region's mean light, e⁻/µm².
    pub light_e_per_um2: f64,
    /// [`optimal_bin`] at `l0 = 2·light`.
    pub predicted_bin: usize,
    /// The bin of the highest SSIM.
    pub best_bin: usize,
}

/// The study's result.
#[derive(Debug, Clone)]
pub struct BinStudy {
    /// The noise-free region through the tone curve (the same at every light: the curve
    /// normalises the mean).
    pub truth_display: Array2<f64>,
    /// Fig. 5.4a: every light level × every bin size, light-major.
    pub sweep: Vec<StudyCapture>,
    /// Predicted and best bin per light level.
    pub choices: Vec<BinChoice>,
    /// Fig. 5.4b: additive binning at ĝ = g/N and at the same gain g, average and digital
    /// binning, × the two gains × every bin size.
    pub modes: Vec<StudyCapture>,
}

/// Runs the study on `region` (relative luminance, `[row, col]`) with the sensor, seed and tone
/// curve of `settings`.
///
/// # Errors
/// [`SimError::InvalidSetting`] for bad settings, a bad spec, or a region that is smaller than
/// 8 bins of 8 pixels on a side, negative, non-finite or black; [`SimError::Cancelled`].
pub fn bin_study(
    region: &Array2<f64>,
    settings: &SensorSettings,
    spec: &StudySpec,
    progress: &Progress,
) -> Result<BinStudy, SimError> {
    settings.validate()?;
    spec.validate(settings.sensor.max_gain)?;
    let (h, w) = region.dim();
    let min_side = 8 * BIN_SIZES[BIN_SIZES.len() - 1];
    if h.min(w) < min_side.max(SSIM_WINDOW_PX) || h.max(w) > 4096 {
        return Err(SimError::invalid(
            "region",
            format!("must be {min_side} … 4096 pixels on a side (got {w}×{h})"),
        ));
    }
    if region.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(SimError::invalid(
            "region",
            "holds a negative or non-finite value",
        ));
    }
    let mean = region.mean().unwrap_or(0.0);
    if !(mean > 0.0) {
        return Err(SimError::invalid("region", "is black; nothing to capture"));
    }
    let sensor = &settings.sensor;
    let adc = Adc::of(sensor);
    let grid = RoiGrid::new((h, w), h.max(w));
    let tone = ToneCurve {
        scale: settings.display_mean / mean,
        gamma: settings.gamma,
    };
    let truth_display = tone.apply(region);
    let area_um2 = sensor.unit_pixel_area_um2();
    let mut jobs: Vec<(f64, usize, BinMode, AdditiveGain, f64)> = Vec::new();
    for &l in &spec.lights_e_per_um2 {
        for &n in &BIN_SIZES {
            jobs.push((
                l,
                n,
                spec.sweep_mode,
                settings.additive_gain,
                spec.sweep_gain,
            ));
        }
    }
    let sweep_len = jobs.len();
    let modes = [
        (BinMode::AnalogAdditive, AdditiveGain::Scaled),
        (BinMode::AnalogAdditive, AdditiveGain::Same),
        (BinMode::AnalogAverage, AdditiveGain::Scaled),
        (BinMode::Digital, AdditiveGain::Scaled),
    ];
    for (mode, additive) in modes {
        for &g in &spec.modes_gains {
            for &n in &BIN_SIZES {
                jobs.push((spec.modes_light_e_per_um2, n, mode, additive, g));
            }
        }
    }
    let total = jobs.len() as f32;
    let done = std::sync::atomic::AtomicUsize::new(0);
    let captures = jobs
        .par_iter()
        .map(|&(light, bin, mode, additive_gain, gain)| {
            progress.check()?;
            // One exposure per light level, shared by its bins and modes (common random
            // numbers: the bins differ by their readout only).
            let level = spec
                .lights_e_per_um2
                .iter()
                .position(|l| *l == light)
                .unwrap_or(spec.lights_e_per_um2.len());
            let scale = light * area_um2 / mean;
            let electrons = region.mapv(|v| v * scale);
            let frame = expose_frame(electrons.view(), sensor, settings.seed, 100 + level as u64);
            let readout = read_regions(
                &frame,
                &grid,
                &Array2::from_elem((1, 1), gain),
                &Array2::from_elem((1, 1), bin),
                mode,
                additive_gain,
                &adc,
            );
            // Display in the units of the truth: electrons back to relative luminance.
            let capture = readout.estimate_e.mapv(|v| v / scale);
            let scores = metrics::score(&capture, region, &tone, &grid)?;
            let display = tone.apply(&capture);
            let d = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            progress.set(d as f32 / total);
            Ok(StudyCapture {
                light_e_per_um2: light,
                bin,
                mode,
                additive_gain,
                gain,
                display,
                ssim: scores.worst_roi_ssim,
                psnr_db: scores.psnr_db,
                saturated_fraction: readout.saturated_fraction(),
            })
        })
        .collect::<Result<Vec<_>, SimError>>()?;
    let (sweep, modes) = {
        let mut all = captures;
        let modes = all.split_off(sweep_len);
        (all, modes)
    };
    let choices = spec
        .lights_e_per_um2
        .iter()
        .map(|&l| {
            let best_bin = sweep
                .iter()
                .filter(|c| c.light_e_per_um2 == l)
                .max_by(|a, b| a.ssim.total_cmp(&b.ssim))
                .map_or(1, |c| c.bin);
            BinChoice {
                light_e_per_um2: l,
                predicted_bin: optimal_bin(2.0 * l, sensor, spec.sweep_gain, settings.snr_t),
                best_bin,
            }
        })
        .collect();
    Ok(BinStudy {
        truth_display,
        sweep,
        choices,
        modes,
    })
}
