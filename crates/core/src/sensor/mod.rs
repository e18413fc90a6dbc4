//! Sensor previewer: spatially-varying gain and binning on HDR scenes (thesis chapter 5,
//! conventions.md §8). One entry point, [`run`], serves the CLI, the studio, the tests and the
//! benches.
//!
//! **What is simulated.** By default the simulation runs on **luminance**
//! ([`Scene::luminance`]: `0.2126 R + 0.7152 G + 0.0722 B` of the linear scene), as a monochrome
//! sensor sees it; the thesis's Table 5.4 scores grey images the same way. With
//! [`SensorSettings::cfa`] = [`Cfa::Rggb`] it is a Bayer colour sensor: an RGGB mosaic of the
//! RGB scene, same-colour binning ([`cfa`]), a demosaic ([`demosaic`]) and scores on the
//! luminance of the demosaiced capture and per channel ([`colour`]). The scene's relative
//! radiance is mapped to expected photo-electrons per unit pixel by an explicit [`Exposure`]
//! (Table 5.4: the image mean at 5 % of the full well). Electrons are always per *unit* pixel
//! (the sensor's smallest pixel, [`SensorSpec::unit_pixel_um`]); light per area is e⁻/µm².
//!
//! **Noise** ([`noise`]): eq. 5.1 with Poisson photons, pre- and post-amplifier read noise, gain,
//! a 5 % black level and a 12-bit ADC whose range is the full well at base gain. One exposure is
//! drawn per run and every strategy reads it (common random numbers); the two-shot snapshot is a
//! second exposure. Each image row has its own ChaCha8 stream per exposure, so a seed gives the
//! same result bit for bit on any number of threads.
//!
//! **Strategies** ([`Strategy`]): a gain rule ([`gain`]: base, maximum, alternating rows, two-shot
//! ROI by eq. 5.3, single-shot per pixel) and a bin rule ([`binning`]: none, uniform, per ROI from
//! the optimal-pitch theory of [`pitch`]) in one of Table 5.1's modes. The ROI rules read a
//! snapshot at base gain (averaged over 2×2 pixels); an ROI's gain comes from its brightest
//! block (or the statistic [`RoiLight`] names), its bin from its mean light `m` analysed at
//! `l0 = 2m` (the derivation's sinusoid has mean `l0/2`) with the ROI's gain. Additive bins are
//! read at `ĝ = g/N` or `g` ([`AdditiveGain`]).
//!
//! **Saturation** is reported per pixel (the fraction of pixels whose own or whose bin's code hit
//! the top) and per ROI (the fraction of the grid's ROIs, each counted once whatever its size,
//! that hold at least one saturated pixel). [`flat_patch`] checks eq. 5.3's η on a flat patch.
//!
//! **Scores** ([`metrics`]): every capture (and the truth, the noise-free electrons) goes through
//! the display tone curve `clamp(x · display_mean / mean(truth), 0, 1)^γ` (Table 5.4: 0.05 and
//! γ = 1/3.2); PSNR over the image, SSIM per ROI, the worst ROI and the area-weighted mean.

pub mod binning;
pub mod cfa;
pub mod colour;
pub mod demosaic;
pub mod figures;
pub mod flat;
pub mod gain;
pub mod maps;
pub mod memory;
pub mod metrics;
pub mod noise;
pub mod pitch;
pub mod roi;
pub mod scene;
pub mod settings;
pub mod spec;
pub mod study;

use std::borrow::Cow;
use std::time::Instant;

use ndarray::{Array2, Axis};
use rayon::prelude::*;

pub use binning::Readout;
pub use cfa::Cfa;
pub use colour::{ChannelScores, ColourCapture, ColourTruth};
pub use flat::{FlatPatch, FlatPatchSpec, flat_patch};
pub use gain::Snapshot;
pub use memory::{
    FIXED_BYTES_PER_PIXEL, HANDOVER_BYTES_PER_PIXEL, Held, STRATEGY_BYTES_PER_PIXEL, check_budget,
    peak_bytes,
};
pub use metrics::ToneCurve;
pub use roi::RoiGrid;
pub use scene::{Exposure, Scene};
pub use settings::{
    AdditiveGain, BIN_SIZES, BinMode, BinStrategy, GainStrategy, RoiLight, SensorSettings, Strategy,
};
pub use spec::{PRESET_NAMES, SensorSpec};

use crate::{Progress, SimError};

/// Longest side of the studio's preview scene, pixels: [`run`] on a scene
/// [`Scene::downscaled`] to this (with [`SensorSettings::for_preview`]) is the fast path.
pub const PREVIEW_MAX_SIDE_PX: usize = 640;

/// One strategy's capture and scores.
#[derive(Debug, Clone)]
pub struct StrategyResult {
    /// [`Strategy::name`]: `const-gain/no-bin`, `vary-gain/no-bin`, `const-gain/vary-bin`,
    /// `vary-gain/vary-bin` for Table 5.4's four.
    pub name: String,
    /// The gain and bin rules used.
    pub strategy: Strategy,
    /// The estimate `l̂`, electrons per unit pixel (the scale of [`SensorRun::electrons`]).
    pub capture: Array2<f64>,
    /// The run's tone curve ([`SensorRun::tone`]), which [`StrategyResult::display`] applies.
    pub tone: ToneCurve,
    /// Pixel gain per pixel (1 where constant; additive bins are read at the `ĝ` of
    /// [`SensorSettings::additive_gain`]).
    pub gain_map: Array2<f32>,
    /// Bin side per pixel, unit pixels: 1, 2, 4 or 8.
    pub bin_map: Array2<u8>,
    /// Whether a pixel (or its bin) saturated.
    pub saturated: Array2<bool>,
    /// SSIM per ROI, `[roi row, roi col]`.
    pub roi_ssim: Array2<f64>,
    /// Lowest ROI SSIM, the metric of Table 5.4.
    pub worst_roi_ssim: f64,
    /// Area-weighted mean of `roi_ssim`.
    pub mean_ssim: f64,
    /// PSNR of [`StrategyResult::display`] against [`SensorRun::truth_display`], peak 1.
    pub psnr_db: f64,
    /// Fraction of pixels that saturated (of `saturated`).
    pub saturated_fraction: f64,
    /// Fraction of the ROIs (each counted once) with at least one saturated pixel.
    pub saturated_roi_fraction: f64,
    /// The brightest unsaturated level at the lowest gain used over the lowest read-noise floor
    /// used (Table 5.1 at `l* = 0` with the gain and bin of each pixel), dB.
    pub dynamic_range_db: f64,
    /// With a colour filter array: the raw mosaic, the demosaiced RGB capture and the scores
    /// per channel (then `capture` is the luminance of the demosaiced capture).
    pub colour: Option<ColourCapture>,
}

impl StrategyResult {
    /// The capture through the tone curve, `[0, 1]`.
    pub fn display(&self) -> Array2<f64> {
        self.tone.apply(&self.capture)
    }

    /// What a picture of the capture shows: its R, G, B through the tone curve on a colour
    /// sensor, else [`StrategyResult::display`].
    pub fn display_planes(&self) -> Vec<Array2<f64>> {
        match &self.colour {
            Some(c) => c.display_rgb(&self.tone).into(),
            None => vec![self.display()],
        }
    }
}

/// The result of [`run`] (and of [`run_with`], whose strategies are what its hand-over kept).
#[derive(Debug, Clone)]
pub struct SensorRun<S = StrategyResult> {
    /// The exposed scene: expected electrons per unit pixel (noise-free, not clipped).
    pub electrons: Array2<f64>,
    /// One result per strategy, in the order asked for.
    pub strategies: Vec<S>,
    /// Side of the square ROIs, unit pixels.
    pub roi_px: usize,
    /// The ROI grid (`rows × cols` ROIs).
    pub grid: RoiGrid,
    /// Electrons per unit pixel per unit of scene luminance (what the exposure chose).
    pub electrons_per_radiance: f64,
    /// The tone curve used for `display` and the metrics.
    pub tone: ToneCurve,
    /// The snapshot of the two-shot strategies (`None` when no strategy needed it).
    pub snapshot: Option<Snapshot>,
    /// Wall-clock time of the run, ms.
    pub elapsed_ms: f64,
    /// The colour filter array simulated.
    pub cfa: Cfa,
    /// With a colour filter array: the scene's RGB electrons and their mosaic (then
    /// `electrons` is their luminance).
    pub colour_truth: Option<ColourTruth>,
}

impl<S> SensorRun<S> {
    /// The tone-mapped ground truth, `[0, 1]`: the tone curve over [`SensorRun::electrons`].
    pub fn truth_display(&self) -> Array2<f64> {
        self.tone.apply(&self.electrons)
    }

    /// What a picture of the ground truth shows: its R, G, B through the tone curve on a
    /// colour sensor, else [`SensorRun::truth_display`].
    pub fn truth_display_planes(&self) -> Vec<Array2<f64>> {
        match &self.colour_truth {
            Some(t) => t.display_rgb(&self.tone).into(),
            None => vec![self.truth_display()],
        }
    }
}

/// Reads the capture `frame` with one strategy.
fn read_strategy(
    strategy: &Strategy,
    frame: &noise::Frame,
    snapshot: Option<&Snapshot>,
    grid: &RoiGrid,
    settings: &SensorSettings,
) -> Readout {
    let sensor = &settings.sensor;
    match strategy.gain {
        GainStrategy::PerPixel => match settings.cfa {
            Cfa::None => gain::read_per_pixel(frame, sensor, settings.eta_per_pixel),
            Cfa::Rggb => cfa::read_per_pixel(frame, sensor, settings.eta_per_pixel),
        },
        GainStrategy::AlternatingRows => match settings.cfa {
            Cfa::None => gain::read_alternating_rows(frame, sensor, 1.0, sensor.max_gain),
            Cfa::Rggb => cfa::read_alternating_rows(frame, sensor, 1.0, sensor.max_gain),
        },
        GainStrategy::Base | GainStrategy::Maximum | GainStrategy::Roi => {
            let dim = (grid.rows, grid.cols);
            let roi_gain = Array2::from_shape_fn(dim, |(r, c)| match strategy.gain {
                GainStrategy::Maximum => sensor.max_gain,
                GainStrategy::Roi => gain::gain_for_light(
                    snapshot.map_or(0.0, |s| s.roi_light_e(settings.roi_light)[[r, c]]),
                    settings.eta,
                    sensor.full_well_e,
                    sensor.max_gain,
                ),
                _ => 1.0,
            });
            let roi_bin = Array2::from_shape_fn(dim, |(r, c)| match strategy.bin {
                BinStrategy::None => 1,
                BinStrategy::Uniform(n) => n,
                BinStrategy::Roi => {
                    let mean_e = snapshot.map_or(0.0, |s| s.roi_mean_e[[r, c]]);
                    let l0 = 2.0 * mean_e / sensor.unit_pixel_area_um2();
                    pitch::optimal_bin(l0, sensor, roi_gain[[r, c]], settings.snr_t)
                }
            });
            let adc = noise::Adc::of(sensor);
            let read = match settings.cfa {
                Cfa::None => binning::read_regions,
                Cfa::Rggb => cfa::read_regions,
            };
            let additive = settings.additive_gain;
            read(
                frame,
                grid,
                &roi_gain,
                &roi_bin,
                settings.bin_mode,
                additive,
                &adc,
            )
        }
    }
}

/// See [`StrategyResult::dynamic_range_db`].
fn dynamic_range_db(readout: &Readout, settings: &SensorSettings) -> f64 {
    let sensor = &settings.sensor;
    let (g_min, floor) = readout
        .gain
        .axis_iter(Axis(0))
        .into_par_iter()
        .zip(readout.bin.axis_iter(Axis(0)).into_par_iter())
        .map(|(g_row, b_row)| {
            let mut acc = (f64::INFINITY, f64::INFINITY);
            let mut last = None;
            for (g, b) in g_row.iter().zip(b_row.iter()) {
                if last == Some((*g, *b)) {
                    continue;
                }
                last = Some((*g, *b));
                let (g, pixels) = (f64::from(*g), usize::from(*b).pow(2));
                let (mode, additive) = (settings.bin_mode, settings.additive_gain);
                let sigma = binning::read_sigma_e(mode, additive, sensor, g, pixels);
                acc = (acc.0.min(g), acc.1.min(sigma));
            }
            acc
        })
        .reduce(
            || (f64::INFINITY, f64::INFINITY),
            |a, b| (a.0.min(b.0), a.1.min(b.1)),
        );
    gain::ratio_db(sensor.full_well_e / g_min.max(1.0) / floor)
}

/// Simulates every strategy of `settings` on `scene` and scores it; see the module docs.
///
/// ```
/// use ndarray::Array2;
/// use udc_core::Progress;
/// use udc_core::sensor::{Scene, SensorSettings, run};
///
/// // A dark left half and a bright right half.
/// let plane = Array2::from_shape_fn((64, 96), |(_, x)| if x < 48 { 0.01 } else { 1.0 });
/// let scene = Scene { planes: vec![plane] };
/// let settings = SensorSettings { roi_px: 32, ..SensorSettings::default() };
/// let r = run(&scene, &settings, &Progress::new())?;
/// assert_eq!(r.strategies[0].name, "const-gain/no-bin");
/// let (constant, varying) = (&r.strategies[0], &r.strategies[3]);
/// assert!(varying.worst_roi_ssim > constant.worst_roi_ssim);
/// # Ok::<(), udc_core::SimError>(())
/// ```
///
/// # Errors
/// As [`run_with`].
pub fn run(
    scene: &Scene,
    settings: &SensorSettings,
    progress: &Progress,
) -> Result<SensorRun, SimError> {
    run_with(scene, settings, progress, Held::Kept, Ok::<_, SimError>)
}

/// [`run`], handing each strategy's result to `keep` the moment it is scored and keeping what
/// `keep` returns. Strategies run one after another (each spreads its rows over the pool), so
/// a hand-over that writes the images and keeps only numbers holds one strategy at a time:
/// say so with `held` = [`Held::HandedOver`], and the budget counts one. An owned `scene` of
/// a monochrome run becomes the exposed scene in place, without a copy.
///
/// ```
/// use ndarray::Array2;
/// use udc_core::{Progress, SimError};
/// use udc_core::sensor::{Held, Scene, SensorSettings, run_with};
///
/// let plane = Array2::from_shape_fn((64, 96), |(_, x)| if x < 48 { 0.01 } else { 1.0 });
/// let scene = Scene { planes: vec![plane] };
/// let settings = SensorSettings { roi_px: 32, ..SensorSettings::default() };
/// // Keep each strategy's name and worst ROI SSIM; its capture and maps are let go.
/// let r = run_with(scene, &settings, &Progress::new(), Held::HandedOver, |s| {
///     Ok::<_, SimError>((s.name, s.worst_roi_ssim))
/// })?;
/// assert_eq!(r.strategies.len(), 4);
/// assert!(r.strategies[3].1 > r.strategies[0].1);
/// # Ok::<(), SimError>(())
/// ```
///
/// # Errors
/// [`SimError::InvalidSetting`] naming the field for bad settings (`roi_px`,
/// `sensor.full_well_e`, `exposure.fill`, `strategies[i].bin`, …) or a bad scene (`scene`,
/// `scene.planes[c]`: empty, smaller than 11×11, mismatched, negative or non-finite, black);
/// [`SimError::TooLarge`] above the memory budget ([`peak_bytes`]); [`SimError::Cancelled`]
/// when `progress` was cancelled; and whatever `keep` returns.
pub fn run_with<'a, S, E: From<SimError>>(
    scene: impl Into<Cow<'a, Scene>>,
    settings: &SensorSettings,
    progress: &Progress,
    held: Held,
    mut keep: impl FnMut(StrategyResult) -> Result<S, E>,
) -> Result<SensorRun<S>, E> {
    let start = Instant::now();
    let scene: Cow<'a, Scene> = scene.into();
    settings.validate()?;
    scene.validate(metrics::SSIM_WINDOW_PX)?;
    let (rows, cols) = scene.dim();
    let is_colour = colour::is_colour(settings.cfa);
    let scene_planes = match &scene {
        Cow::Owned(_) if !is_colour => 0,
        s => s.planes.len(),
    };
    check_budget((rows, cols), scene_planes, settings, held)?;
    progress.set(0.0);
    progress.check()?;
    let sensor = &settings.sensor;
    let (mut electrons, scene) = match scene {
        Cow::Owned(s) if !is_colour => (s.into_luminance(), None),
        s => (s.luminance(), Some(s)),
    };
    let electrons_per_radiance = settings
        .exposure
        .electrons_per_radiance(&electrons, sensor)?;
    electrons.par_mapv_inplace(|v| v * electrons_per_radiance);
    let mean_e = electrons.mean().unwrap_or(0.0);
    if !(mean_e > 0.0 && mean_e.is_finite()) {
        return Err(SimError::invalid(
            "scene",
            format!("exposes to a mean of {mean_e} electrons; nothing to simulate"),
        )
        .into());
    }
    let tone = ToneCurve {
        scale: settings.display_mean / mean_e,
        gamma: settings.gamma,
    };
    let grid = RoiGrid::new(electrons.dim(), settings.roi_px);
    let steps = settings.strategies.len() as f32 + 2.0;
    // A colour sensor is exposed to the mosaic of the RGB scene (see `colour`), in f64. Its
    // truth is made (in f32, the scene's f64 planes let go as they are converted) before the
    // exposure is drawn, so that the scene and the draws are never held at once.
    let mosaic_e = match (is_colour, &scene) {
        (true, Some(scene)) => Some(colour::expose_mosaic(
            scene,
            &electrons,
            electrons_per_radiance,
        )),
        _ => None,
    };
    let colour_truth = match (&mosaic_e, scene) {
        (Some(mosaic_e), Some(scene)) => {
            let planes = match scene {
                Cow::Owned(s) => s.planes.into_iter().map(Cow::Owned).collect(),
                Cow::Borrowed(s) => s.planes.iter().map(Cow::Borrowed).collect(),
            };
            Some(colour::truth(planes, mosaic_e, electrons_per_radiance))
        }
        _ => None,
    };
    let sensed = mosaic_e.as_ref().map_or(electrons.view(), |m| m.view());
    let frame = noise::expose_frame(sensed, sensor, settings.seed, noise::stream::CAPTURE);
    progress.set(1.0 / steps);
    progress.check()?;
    let needs_snapshot = settings
        .strategies
        .iter()
        .any(|s| s.gain == GainStrategy::Roi || s.bin == BinStrategy::Roi);
    let snapshot = needs_snapshot.then(|| match settings.cfa {
        Cfa::None => gain::take_snapshot(electrons.view(), sensor, &grid, settings.seed),
        Cfa::Rggb => cfa::take_snapshot(sensed, sensor, &grid, settings.seed),
    });
    drop(mosaic_e);
    progress.set(2.0 / steps);
    let mut strategies = Vec::with_capacity(settings.strategies.len());
    for (i, strategy) in settings.strategies.iter().enumerate() {
        progress.check()?;
        let readout = read_strategy(strategy, &frame, snapshot.as_ref(), &grid, settings);
        let (readout, colour) = colour::develop(readout, colour_truth.as_ref(), &tone, &grid)?;
        let scores = metrics::score(&readout.estimate_e, &electrons, &tone, &grid)?;
        let saturated_fraction = readout.saturated_fraction();
        let saturated_roi_fraction = grid.fraction_with_any(&readout.saturated);
        let dynamic_range_db = dynamic_range_db(&readout, settings);
        let result = StrategyResult {
            name: strategy.name(),
            strategy: *strategy,
            capture: readout.estimate_e,
            tone,
            gain_map: readout.gain,
            bin_map: readout.bin,
            saturated: readout.saturated,
            roi_ssim: scores.roi_ssim,
            worst_roi_ssim: scores.worst_roi_ssim,
            mean_ssim: scores.mean_ssim,
            psnr_db: scores.psnr_db,
            saturated_fraction,
            saturated_roi_fraction,
            dynamic_range_db,
            colour,
        };
        strategies.push(keep(result)?);
        progress.set((i as f32 + 3.0) / steps);
    }
    progress.check()?;
    progress.set(1.0);
    Ok(SensorRun {
        electrons,
        strategies,
        roi_px: settings.roi_px,
        grid,
        electrons_per_radiance,
        tone,
        snapshot,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
        cfa: settings.cfa,
        colour_truth,
    })
}
