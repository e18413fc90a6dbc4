//! The one entry point of chapter 3: a design in, every number and picture of it out.
//! The studio, the CLI, the tests and the benches all call [`analyze`] / [`analyze_with`].

use crate::Setting;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use ndarray::Array2;
use rayon::prelude::*;

use crate::SimError;
use crate::analysis::expected::expected_channel_psf;
use crate::analysis::metrics::{invertibility_loss, ltr, mean_lowest_h, open_fraction};
use crate::analysis::mtf::{Mtf, mtf_of};
use crate::design::Design;
use crate::display::aperture::{Display, Extent, effective_cells, pupil_sample_count, rasterise};
use crate::progress::Progress;
use crate::psf::channel_psf_by;
use crate::psf::route::{Fraunhofer, PsfRoute};
use crate::psf::sampling::{WavelengthSampling, plan};
use crate::psf::warning::{SamplingWarning, WarningKind};

/// Full quality follows the design's sampling. Preview is the cheapest sampling that still
/// agrees with it: twice the fine spacing where the PSF's intensity is oversampled enough for
/// that to change nothing measurable, the design's spacing otherwise, and FFT sizes
/// never rounded. Same physics; conventions.md §2 ("Preview quality") gives the rule and
/// its numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Quality {
    /// Every FFT at the design's own fine spacing and size.
    #[default]
    Full,
    /// Twice the fine spacing where that keeps the numbers, full quality's sampling elsewhere:
    /// for interactive editing.
    Preview,
}

/// How far below its Nyquist spacing `λN/2` the preview's doubled spacing must stay. The
/// intensity's spectrum reaches `1/(λN)`; pixels summed from 2 fine samples instead of 4 weigh
/// that spectrum's upper part differently (the discrete box's transfer departs from the pixel's
/// by about `(π u δ2)²/2`), and with the spacing at half the Nyquist spacing or finer the AUC
/// moves by under 2 % and `L_inv`, by then near 0, by under 10⁻³. Measured over the presets
/// from f/4 to f/16: at f/6 (0.71 of the Nyquist spacing) the AUC still moved 3.3 % and
/// `L_inv` 47 %; at f/2.5 (1.7×, aliased) 15–35 % and 3×.
const PREVIEW_NYQUIST_FRACTION: f64 = 0.5;

impl Quality {
    /// How the UI names it.
    pub fn label(self) -> &'static str {
        match self {
            Quality::Preview => "preview",
            Quality::Full => "full quality",
        }
    }

    /// Whether this quality doubles the design's fine spacing: only a preview, only where the
    /// sensor pixel holds an even number of fine samples, and only where the doubled spacing
    /// stays within one half (`PREVIEW_NYQUIST_FRACTION`) of the intensity's Nyquist spacing
    /// `λN/2` at the design's shortest wavelength.
    pub fn doubles_spacing(self, design: &Design) -> bool {
        if self == Quality::Full {
            return false;
        }
        let op = &design.optics;
        let spp = (op.sensor_pixel_um / op.fine_sample_um).round() as usize;
        let shortest_um = design
            .channels
            .iter()
            .flat_map(|c| c.wavelengths_nm.iter())
            .fold(f64::INFINITY, |a, &l| a.min(l))
            * 1e-3;
        let nyquist_um = shortest_um * op.f_number / 2.0;
        spp >= 2
            && spp.is_multiple_of(2)
            && 2.0 * op.fine_sample_um <= PREVIEW_NYQUIST_FRACTION * nyquist_um
    }

    /// The target fine spacing at this quality, µm.
    pub fn fine_sample_um(self, design: &Design) -> f64 {
        let fine_um = design.optics.fine_sample_um;
        if self.doubles_spacing(design) {
            2.0 * fine_um
        } else {
            fine_um
        }
    }

    /// The design's per-channel, per-wavelength sampling at this quality: the one place that
    /// turns a quality into FFT sizes and spacings.
    ///
    /// # Errors
    /// As [`plan`].
    pub fn plan(
        self,
        design: &Design,
        warnings: &mut Vec<SamplingWarning>,
    ) -> Result<Vec<Vec<WavelengthSampling>>, SimError> {
        plan(design, self.fine_sample_um(design), warnings)
    }
}

/// How [`analyze_with`] runs: quality and optional extras.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AnalyzeOptions {
    /// Sampling quality of the run.
    pub quality: Quality,
    /// Also compute the closed-form expected PSF of a random tiling (ignored for `repeat`).
    pub expected_psf: bool,
}

impl Default for AnalyzeOptions {
    fn default() -> Self {
        AnalyzeOptions {
            quality: Quality::Full,
            expected_psf: true,
        }
    }
}

/// Everything computed for one colour channel.
#[derive(Debug, Clone)]
pub struct ChannelAnalysis {
    /// Channel name as given in the design (e.g. "R").
    pub name: String,
    /// Weighted mean wavelength (the peak wavelength for a single-wavelength channel).
    pub wavelength_nm: f64,
    /// Every wavelength sampled for this channel, nm.
    pub wavelengths_nm: Vec<f64>,
    /// FFT size per sampled wavelength.
    pub fft_sizes: Vec<usize>,
    /// Real fine spacing at the channel's first wavelength, µm.
    pub fine_um: f64,
    /// Sensor PSF, `[row, col]`, sums to 1, axis at `[W/2, W/2]`.
    pub psf: Array2<f64>,
    /// Expected PSF of the random tiling, when requested and the tiling is random.
    pub expected_psf: Option<Array2<f64>>,
    /// MTF of the sensor PSF with its slices, radial statistics and AUC.
    pub mtf: Mtf,
    /// Fraction of the channel's light inside the sensor window, before normalising
    /// (conventions.md §2).
    pub energy_in_window: f64,
    /// Mean of the lowest 30 % of `H` for this channel alone.
    pub invertibility: f64,
}

/// The result of [`analyze`].
#[derive(Debug, Clone)]
pub struct Analysis {
    /// One entry per colour channel, in the design's order.
    pub channels: Vec<ChannelAnalysis>,
    /// Intensity transmittance of one tile (= open area fraction for binary cells).
    pub open_fraction: f64,
    /// Light transmittance ratio over the pupil.
    pub ltr: f64,
    /// `L_inv`, pooled over the channels (eq. 3.9).
    pub invertibility_loss: f64,
    /// Sampling and energy warnings and notes, one per kind, naming design fields by their paths;
    /// `advice::advise` adds their fixes.
    pub warnings: Vec<SamplingWarning>,
    /// Wall-clock time of the analysis, ms.
    pub elapsed_ms: f64,
    /// The quality the analysis ran at.
    pub quality: Quality,
    /// Side of the square sensor window, in sensor pixels.
    pub window_px: usize,
    /// Sensor pixel pitch, µm.
    pub sensor_pixel_um: f64,
    /// Pupil diameter in µm and in δ1 samples.
    pub pupil_diameter_um: f64,
    /// Display tiles (of the full period) inside the pupil.
    pub tiles_in_pupil: f64,
}

/// [`analyze_with`] at full quality, with the expected PSF.
///
/// # Errors
/// See [`analyze_with`].
pub fn analyze(design: &Design, progress: &Progress) -> Result<Analysis, SimError> {
    analyze_with(design, &AnalyzeOptions::default(), progress)
}

/// Analyses a design: PSF per channel, MTF, AUC, LTR, invertibility and sampling warnings.
///
/// ```
/// use udc_core::{Design, Progress};
/// use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
///
/// let design = Design::default_toled(); // the T-OLED pixel, 150 DPI, thesis optics
/// let options = AnalyzeOptions { quality: Quality::Preview, expected_psf: false };
/// let a = analyze_with(&design, &options, &Progress::new())?;
/// assert_eq!(a.channels.len(), 3);
/// assert!((a.open_fraction - 5.0 / 21.0).abs() < 1e-12); // a 5-of-21-cell slit
/// assert!((a.channels[0].psf.sum() - 1.0).abs() < 1e-9); // each PSF sums to 1
/// # Ok::<(), udc_core::SimError>(())
/// ```
///
/// # Errors
/// [`SimError::InvalidSetting`] for a bad design, [`SimError::Sampling`] / [`SimError::TooLarge`]
/// when the sampling cannot represent it, [`SimError::Cancelled`] when `progress` was cancelled.
pub fn analyze_with(
    design: &Design,
    options: &AnalyzeOptions,
    progress: &Progress,
) -> Result<Analysis, SimError> {
    analyze_within(design, options, progress, &Limits::REPORTED).map(|(a, _)| a)
}

/// [`analyze_with`] with every PSF's Fraunhofer step computed by `route`: a CPU route
/// ([`PsfRoute::Auto`] is what [`analyze_with`] does; the routes agree to rounding, and the
/// tests check that they do) or a transform implemented outside the core.
///
/// # Errors
/// As [`analyze_with`], and `route`'s own.
pub fn analyze_with_route(
    design: &Design,
    options: &AnalyzeOptions,
    route: &dyn Fraunhofer,
    progress: &Progress,
) -> Result<Analysis, SimError> {
    analyze_routed(design, options, route, progress, &Limits::REPORTED).map(|(a, _)| a)
}

/// The energy fractions beyond which the analysis warns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Limits {
    /// Least share of a channel's light inside the window.
    pub min_energy_in_window: f64,
    /// Largest share of a channel's light in the outer band of the fine grid.
    pub max_edge_energy: f64,
}

impl Limits {
    /// What [`analyze_with`] reports (conventions.md §2).
    pub const REPORTED: Limits = Limits {
        min_energy_in_window: 0.98,
        max_edge_energy: 0.02,
    };
}

/// [`analyze_with`], and the kinds of energy warning the analysis would raise at `strict`
/// limits (advice checks that its fix resolves a warning with a margin).
pub(crate) fn analyze_within(
    design: &Design,
    options: &AnalyzeOptions,
    progress: &Progress,
    strict: &Limits,
) -> Result<(Analysis, Vec<WarningKind>), SimError> {
    analyze_routed(design, options, &PsfRoute::Auto, progress, strict)
}

fn analyze_routed(
    design: &Design,
    options: &AnalyzeOptions,
    route: &dyn Fraunhofer,
    progress: &Progress,
    strict: &Limits,
) -> Result<(Analysis, Vec<WarningKind>), SimError> {
    let start = Instant::now();
    design.validate()?;
    progress.set(0.0);
    let op = &design.optics;
    let mut warnings = Vec::new();

    let samplings = options.quality.plan(design, &mut warnings)?;

    let cells = effective_cells(&design.opening);
    let display = Display::from_design(design, &cells);
    let d_um = op.pupil_diameter_um();
    let cell_um = design.opening.cell_um();
    if cell_um < op.pupil_sample_um * 0.999 {
        warnings.push(SamplingWarning::warning(
            WarningKind::CellsFinerThanSampling,
            format!(
                "display cells ({cell_um:.2} µm) are finer than the pupil sampling ({} µm): their \
                 diffraction is averaged and aliased; set optics.pupil_sample_um ≤ {cell_um:.2}",
                op.pupil_sample_um
            ),
        ));
    }
    let field = rasterise(
        &display,
        Extent::Pupil { diameter_um: d_um },
        op.pupil_sample_um,
    );
    let pupil = pupil_sample_count(d_um, op.pupil_sample_um);
    let energy = field.energy();
    if !(energy > 0.0) {
        return Err(SimError::invalid(
            Setting::OpeningCells,
            "no light passes: every cell is closed",
        ));
    }
    progress.check()?;

    let want_expected = options.expected_psf && design.tiling.mode.is_random();
    let total_steps: usize =
        samplings.iter().map(Vec::len).sum::<usize>() * if want_expected { 2 } else { 1 };
    let done = AtomicUsize::new(0);
    let step = |k: usize| {
        let d = done.fetch_add(k, Ordering::Relaxed) + k;
        progress.set(d as f32 / total_steps.max(1) as f32);
    };
    // Channels run side by side: each is a few FFTs too small to keep both cores busy alone.
    let results: Vec<Result<(ChannelAnalysis, f64), SimError>> = design
        .channels
        .par_iter()
        .zip(samplings.par_iter())
        .map(|(ch, samp)| {
            let psf = channel_psf_by(route, &field, samp, progress, || step(1))?;
            let expected_psf = if want_expected {
                let e = expected_channel_psf(
                    &display,
                    (d_um, op.pupil_sample_um),
                    samp,
                    route,
                    progress,
                )?;
                step(samp.len());
                Some(e)
            } else {
                None
            };
            let mtf = mtf_of(&psf.sensor);
            let invertibility = mean_lowest_h([&mtf.power]);
            Ok((
                ChannelAnalysis {
                    name: ch.name.clone(),
                    wavelength_nm: ch.mean_wavelength_nm(),
                    wavelengths_nm: ch.wavelengths_nm.clone(),
                    fft_sizes: samp.iter().map(|s| s.fft_size).collect(),
                    fine_um: samp[0].fine_um,
                    psf: psf.sensor,
                    expected_psf,
                    mtf,
                    energy_in_window: psf.energy_in_window,
                    invertibility,
                },
                psf.edge_energy,
            ))
        })
        .collect();
    let mut channels = Vec::with_capacity(results.len());
    let mut edge_energy = Vec::with_capacity(results.len());
    for r in results {
        let (c, edge) = r?;
        channels.push(c);
        edge_energy.push(edge);
    }
    let energy_warnings_at =
        |limits| energy_warnings(design, &samplings, &channels, &edge_energy, limits);
    let strict_kinds = energy_warnings_at(strict).iter().map(|w| w.kind).collect();
    warnings.extend(energy_warnings_at(&Limits::REPORTED));
    progress.check()?;
    let loss = invertibility_loss(channels.iter().map(|c| &c.mtf.power));
    let period = design.opening.pitch_um + design.tiling.wiring_gap_um;
    progress.set(1.0);
    let analysis = Analysis {
        open_fraction: open_fraction(&cells),
        ltr: ltr(energy, pupil),
        invertibility_loss: loss,
        warnings,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
        quality: options.quality,
        window_px: op.window_px,
        sensor_pixel_um: op.sensor_pixel_um,
        pupil_diameter_um: d_um,
        tiles_in_pupil: pupil * op.pupil_sample_um.powi(2) / (period * period),
        channels,
    };
    Ok((analysis, strict_kinds))
}

/// "2.1 % of channel R's" or "14.1 % of channel R's and 8.8 % of channel G's".
fn shares(items: &[(f64, &str)]) -> String {
    let each: Vec<String> = items
        .iter()
        .map(|(f, name)| format!("{:.1} % of channel {name}'s", 100.0 * f))
        .collect();
    match each.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => each.join(""),
    }
}

/// The light-outside-window and aliasing warnings, one per kind over all channels.
fn energy_warnings(
    design: &Design,
    samplings: &[Vec<WavelengthSampling>],
    channels: &[ChannelAnalysis],
    edge_energy: &[f64],
    limits: &Limits,
) -> Vec<SamplingWarning> {
    let op = &design.optics;
    let mut out = Vec::new();
    let outside: Vec<(f64, &str)> = channels
        .iter()
        .filter(|c| c.energy_in_window < limits.min_energy_in_window)
        .map(|c| (1.0 - c.energy_in_window, c.name.as_str()))
        .collect();
    if !outside.is_empty() {
        // The narrowest grid, in sensor pixels, bounds the window.
        let (grid_px, l) = samplings
            .iter()
            .flatten()
            .map(|s| {
                (
                    s.fft_size as f64 / s.binning.samples_per_px as f64,
                    s.wavelength_nm,
                )
            })
            .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
        let hint = if (op.window_px as f64) < grid_px.round() {
            format!(
                "enlarge optics.window_px (the FFT grid at {l} nm allows {:.0})",
                grid_px.round()
            )
        } else {
            format!(
                "the window already fills the FFT grid at {l} nm: decrease \
                 optics.pupil_sample_um and enlarge optics.window_px together"
            )
        };
        out.push(SamplingWarning::about_the_crop(
            WarningKind::LightOutsideWindow,
            op,
            &format!(
                "{} light falls outside the {}-pixel window",
                shares(&outside),
                op.window_px
            ),
            &format!("the window is smaller than the diffraction orders that carry energy; {hint}"),
        ));
    }
    let aliased: Vec<(f64, &str)> = channels
        .iter()
        .zip(edge_energy)
        .filter(|(_, e)| **e > limits.max_edge_energy)
        .map(|(c, e)| (*e, c.name.as_str()))
        .collect();
    if !aliased.is_empty() {
        let widths: Vec<String> = channels
            .iter()
            .zip(edge_energy)
            .filter(|(_, e)| **e > limits.max_edge_energy)
            .map(|(c, _)| {
                let m = c.fft_sizes.first().copied().unwrap_or(0);
                format!("{:.0}", m as f64 * c.fine_um)
            })
            .collect();
        out.push(SamplingWarning::about_the_crop(
            WarningKind::Aliasing,
            op,
            &format!(
                "{} light reaches the edge of the fine grid ({} µm wide) and wraps around (PSF \
                 aliasing)",
                shares(&aliased),
                widths.join(", ")
            ),
            "the grid (λf/δ1) is narrower than the light; decrease optics.pupil_sample_um",
        ));
    }
    out
}
