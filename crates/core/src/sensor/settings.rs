//! What [`super::run`] simulates: the sensor, the exposure, the strategies and their knobs.

use super::{Cfa, Exposure, SensorSpec};
use crate::Setting;
use crate::SimError;

/// How the analog gain is chosen (§5.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GainStrategy {
    /// Base gain 1 everywhere: the conventional sensor (`const-gain`).
    Base,
    /// The sensor's maximum gain everywhere (`max-gain`): low read noise, bright regions clip.
    Maximum,
    /// Base gain on even rows, maximum gain on odd rows (Hajisharif et al. 2014), each pixel then
    /// taken from its own row or interpolated from the rows above and below (`alt-gain`).
    AlternatingRows,
    /// Two-shot ROI (§5.4.1): a snapshot at base gain, then one gain per ROI from eq. 5.3 with
    /// η = [`SensorSettings::eta`] (`vary-gain`).
    Roi,
    /// Single-shot per pixel (§5.4.1): along each row, the gain of pixel k+1 comes from the
    /// readout of pixel k by eq. 5.3 with η = [`SensorSettings::eta_per_pixel`]; base gain at the
    /// start of a row and after a saturated pixel (`pixel-gain`).
    PerPixel,
}

impl GainStrategy {
    /// The short name used in strategy names (e.g. `vary-gain`).
    pub fn label(self) -> &'static str {
        match self {
            GainStrategy::Base => "const-gain",
            GainStrategy::Maximum => "max-gain",
            GainStrategy::AlternatingRows => "alt-gain",
            GainStrategy::Roi => "vary-gain",
            GainStrategy::PerPixel => "pixel-gain",
        }
    }
}

/// How pixels are binned (§5.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinStrategy {
    /// Every pixel read on its own (`no-bin`).
    None,
    /// `n×n` bins everywhere (`bin-N`).
    Uniform(usize),
    /// Per ROI, the bin (1, 2, 4 or 8) whose pitch is optimal for the ROI's light level and gain
    /// (§5.5.1, [`super::pitch`]) (`vary-bin`).
    Roi,
}

impl BinStrategy {
    /// The short name used in strategy names (e.g. `bin-2`).
    pub fn label(self) -> String {
        match self {
            BinStrategy::None => "no-bin".into(),
            BinStrategy::Uniform(n) => format!("bin-{n}"),
            BinStrategy::Roi => "vary-bin".into(),
        }
    }
}

/// How a bin's pixels are combined (Table 5.1).
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BinMode {
    /// Analog sum of the N pixels' charge, read once at the amplifier gain `ĝ` that
    /// [`AdditiveGain`] chooses: `g/N` (the default) or `g` (conventions.md §8).
    #[strum(serialize = "additive")]
    AnalogAdditive,
    /// Analog average of the N pixels, read once at gain `g`.
    #[strum(serialize = "average")]
    AnalogAverage,
    /// Every pixel read at gain `g`, the N readouts averaged: the best of the three when the
    /// gain is free (§5.5.2), and what the thesis's best results use.
    #[default]
    Digital,
}

impl BinMode {
    /// The short name shown in the studio and in reports.
    pub fn label(self) -> &'static str {
        self.into()
    }

    /// The amplifier gain a bin of `pixels` pixels is read at when the pixel gain is `gain`:
    /// for additive binning `gain / pixels` or `gain` as `additive` says, `gain` otherwise.
    pub fn amplifier_gain(self, gain: f64, pixels: usize, additive: AdditiveGain) -> f64 {
        match (self, additive) {
            (BinMode::AnalogAdditive, AdditiveGain::Scaled) => gain / pixels.max(1) as f64,
            (BinMode::AnalogAdditive, AdditiveGain::Same)
            | (BinMode::AnalogAverage | BinMode::Digital, _) => gain,
        }
    }
}

/// The amplifier gain `ĝ` of an analog additive bin of N pixels whose pixel gain is `g`. The
/// thesis compares both (Fig. 5.4b, §5.6); Table 5.1's read-noise term is `σ_post²/(N² ĝ²)`.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AdditiveGain {
    /// `ĝ = g/N`: the N-pixel sum fills the ADC at the same light per pixel as one pixel at `g`
    /// (no extra saturation); its read noise `σ_post²/g²` is then average binning's, N× digital
    /// binning's (§5.5.2).
    #[default]
    #[strum(serialize = "scaled")]
    Scaled,
    /// `ĝ = g`, the gain of the other modes: the least read noise, `σ_post²/(N² g²)`, N× below
    /// digital binning's, but the sum saturates at `l_wc/(N g)` electrons per pixel, N× sooner.
    #[strum(serialize = "same")]
    Same,
}

impl AdditiveGain {
    /// The short name shown in the studio and in reports (`scaled`, `same`).
    pub fn label(self) -> &'static str {
        self.into()
    }
}

/// Which statistic of an ROI's base-gain snapshot is the light level `l̂` that eq. 5.3 turns into
/// the ROI's gain. The thesis says only that the gain comes from the snapshot's light level.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RoiLight {
    /// The brightest 2×2 block of the ROI: eq. 5.3 then bounds the saturation of the ROI's
    /// brightest pixels by its tail probability, the thesis's intent ("saturates with a small
    /// probability").
    #[default]
    #[strum(serialize = "brightest")]
    Brightest,
    /// The 99th percentile (nearest rank) of the ROI's 2×2 blocks: a higher gain for the rest,
    /// at the cost of the brightest 1 % of the ROI, which may saturate.
    #[strum(serialize = "p99")]
    P99,
    /// The mean of the ROI: the gain for its typical pixel; whatever is brighter than the mean
    /// by more than `η√l̂` saturates.
    #[strum(serialize = "mean")]
    Mean,
}

impl RoiLight {
    /// The short name shown in the studio and in reports (`brightest`, `p99`, `mean`).
    pub fn label(self) -> &'static str {
        self.into()
    }
}

/// One readout strategy: a gain rule and a bin rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Strategy {
    /// How the analog gain is chosen.
    pub gain: GainStrategy,
    /// How pixels are binned.
    pub bin: BinStrategy,
}

impl Strategy {
    /// `gain/bin`, e.g. `vary-gain/vary-bin`: the names of Table 5.4's columns.
    pub fn name(&self) -> String {
        format!("{}/{}", self.gain.label(), self.bin.label())
    }

    /// The four columns of Table 5.4: constant or ROI gain × no or ROI binning.
    pub fn table54() -> Vec<Strategy> {
        use BinStrategy as B;
        use GainStrategy as G;
        vec![
            Strategy {
                gain: G::Base,
                bin: B::None,
            },
            Strategy {
                gain: G::Roi,
                bin: B::None,
            },
            Strategy {
                gain: G::Base,
                bin: B::Roi,
            },
            Strategy {
                gain: G::Roi,
                bin: B::Roi,
            },
        ]
    }

    /// Table 5.4's four and the other baselines: maximum gain, alternating rows, per-pixel gain,
    /// uniform 2×2 binning.
    pub fn all() -> Vec<Strategy> {
        use BinStrategy as B;
        use GainStrategy as G;
        let mut v = Strategy::table54();
        v.extend([
            Strategy {
                gain: G::Maximum,
                bin: B::None,
            },
            Strategy {
                gain: G::AlternatingRows,
                bin: B::None,
            },
            Strategy {
                gain: G::PerPixel,
                bin: B::None,
            },
            Strategy {
                gain: G::Base,
                bin: B::Uniform(2),
            },
        ]);
        v
    }
}

/// Everything [`super::run`] needs besides the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorSettings {
    /// The sensor's pixel, noise and ADC parameters.
    pub sensor: SensorSpec,
    /// How the scene's radiance becomes electrons.
    pub exposure: Exposure,
    /// Side of the square ROIs (gain map, bin map and per-ROI SSIM), unit pixels.
    pub roi_px: usize,
    /// η of eq. 5.3 for ROI gains (2: ≈ 2.2 % of a flat ROI saturates).
    pub eta: f64,
    /// η of eq. 5.3 for the single-shot per-pixel gain (the thesis: 4).
    pub eta_per_pixel: f64,
    /// SNR threshold of the optimal-pitch analysis (the thesis: 4).
    pub snr_t: f64,
    /// Seed of every random draw (photons, read noise, the snapshot).
    pub seed: u64,
    /// Exponent of the display and metric tone curve (Table 5.4: 1/3.2).
    pub gamma: f64,
    /// The ground truth's mean maps to this before the tone curve (Table 5.4: 0.05).
    pub display_mean: f64,
    /// How vary-bin and uniform strategies combine a bin.
    pub bin_mode: BinMode,
    /// The amplifier gain of additive bins (used only when `bin_mode` is additive).
    pub additive_gain: AdditiveGain,
    /// Which snapshot statistic of an ROI sets its gain (vary-gain).
    pub roi_light: RoiLight,
    /// What to simulate, in order; by default Table 5.4's four.
    pub strategies: Vec<Strategy>,
    /// The colour filter array: none (a monochrome sensor on the scene's luminance, the
    /// default) or an RGGB Bayer mosaic (see [`super::colour`]).
    pub cfa: Cfa,
}

impl Default for SensorSettings {
    /// Table 5.4's setting (conventions.md §8): its sensor, mean at 5 % of the full well, ROI 128,
    /// η 2 (per pixel 4), SNR_t 4, γ 1/3.2, the four strategies; digital binning (additive bins
    /// at `ĝ = g/N`), ROI gains from the brightest snapshot block.
    fn default() -> Self {
        SensorSettings {
            sensor: SensorSpec::table54(),
            exposure: Exposure::default(),
            roi_px: 128,
            eta: 2.0,
            eta_per_pixel: 4.0,
            snr_t: 4.0,
            seed: 0,
            gamma: 1.0 / 3.2,
            display_mean: 0.05,
            bin_mode: BinMode::default(),
            additive_gain: AdditiveGain::default(),
            roi_light: RoiLight::default(),
            strategies: Strategy::table54(),
            cfa: Cfa::None,
        }
    }
}

/// Bin sides the vary-bin strategy chooses from (pitches 1, 2, 4 and 8 unit pixels).
pub const BIN_SIZES: [usize; 4] = [1, 2, 4, 8];

/// Smallest and largest ROI side, pixels.
pub const ROI_PX_RANGE: (usize, usize) = (16, 4096);

impl SensorSettings {
    /// Checks every field; errors name it (`roi_px`, `sensor.full_well_e`, `strategies[4].bin`…).
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        self.sensor.validate()?;
        self.exposure.validate()?;
        let (lo, hi) = ROI_PX_RANGE;
        if !(lo..=hi).contains(&self.roi_px) {
            return Err(SimError::invalid(
                Setting::RoiPx,
                format!("must be {lo} … {hi} pixels (got {:?})", self.roi_px),
            ));
        }
        for (field, v) in [
            (Setting::Eta, self.eta),
            (Setting::EtaPerPixel, self.eta_per_pixel),
        ] {
            if !(v.is_finite() && (0.0..=1e3).contains(&v)) {
                return Err(SimError::invalid(
                    field,
                    format!("must be 0 … 1000 (got {v:?})"),
                ));
            }
        }
        // An SNR threshold below 0.01 or above 10⁶ asks for nothing or for the impossible.
        if !(self.snr_t.is_finite() && (0.01..=1e6).contains(&self.snr_t)) {
            return Err(SimError::invalid(
                Setting::SnrT,
                format!("must be 0.01 … 1e6 (got {:?})", self.snr_t),
            ));
        }
        if !(self.gamma.is_finite() && self.gamma > 0.0 && self.gamma <= 1.0) {
            return Err(SimError::invalid(
                "gamma",
                format!("must be in (0, 1] (got {:?})", self.gamma),
            ));
        }
        if !(self.display_mean.is_finite() && self.display_mean > 0.0 && self.display_mean <= 1.0) {
            return Err(SimError::invalid(
                "display_mean",
                format!("must be in (0, 1] (got {:?})", self.display_mean),
            ));
        }
        if self.strategies.is_empty() {
            return Err(SimError::invalid("strategies", "is empty"));
        }
        for (i, s) in self.strategies.iter().enumerate() {
            if let BinStrategy::Uniform(n) = s.bin
                && !BIN_SIZES.contains(&n)
            {
                return Err(SimError::invalid(
                    format!("strategies[{i}].bin"),
                    format!("a uniform bin is 1, 2, 4 or 8 pixels wide (got {n})"),
                ));
            }
            let row_wise = matches!(
                s.gain,
                GainStrategy::AlternatingRows | GainStrategy::PerPixel
            );
            if row_wise && !matches!(s.bin, BinStrategy::None | BinStrategy::Uniform(1)) {
                return Err(SimError::invalid(
                    format!("strategies[{i}].bin"),
                    format!("{} reads single pixels; it cannot bin", s.gain.label()),
                ));
            }
        }
        Ok(())
    }

    /// The same settings for a preview of a scene downscaled from `full` to `preview` pixels
    /// (`(rows, cols)`): the ROI shrinks by the same factor (at least 16 px), so the gain and bin
    /// maps cover the same parts of the scene.
    pub fn for_preview(&self, full: (usize, usize), preview: (usize, usize)) -> SensorSettings {
        let factor = preview.0.max(preview.1) as f64 / full.0.max(full.1).max(1) as f64;
        let roi = ((self.roi_px as f64 * factor).round() as usize).max(ROI_PX_RANGE.0);
        SensorSettings {
            roi_px: roi.min(self.roi_px),
            ..self.clone()
        }
    }
}
