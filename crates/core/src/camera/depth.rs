//! Depth dependence of the display blur (thesis §3.7, Fig. 3.31 and its Goodman derivation).
//!
//! Lens law `1/z1 + 1/z2 = 1/f` for an object at `z1`. **Focused on the object** (sensor at
//! `z2`), the PSF is the aperture's Fraunhofer pattern scaled by `λ·z2` instead of `λ·f`: the
//! blur measured at infinity grows by `psf_scale = z2/f` (built here as a lens of focal length
//! `z2` with the same pupil diameter). **Focused at infinity** (sensor at `f`), the point at `z1`
//! leaves a quadratic phase across the pupil: the diverging wave `exp(iπr²/(λz1))` meets the lens
//! `exp(−iπr²/(λf))` and the Fresnel propagation to the sensor adds `exp(iπr²/(λf))`, so the
//! pupil carries `exp(iπ r²/(λ z1))`, a defocus of `W(r) = r²/(2 λ z1)` waves (`W = R²/(2λz1)` at
//! the pupil's rim) and a geometric blur of diameter `D·f/z1` on the sensor. The defocused PSF is
//! the intensity of the FFT of that complex pupil, binned like every other PSF, on the route
//! handed in (`Fraunhofer::binned_complex`: the whole grid, the intensity having no mirror
//! symmetry).

use crate::Setting;
use ndarray::Array2;

use crate::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use crate::analysis::residual::{Deblur, channel_residuals, mean};
use crate::design::{Design, OpticsRecipe};
use crate::display::aperture::{Display, Extent, effective_cells, rasterise};
use crate::psf::route::Fraunhofer;
use crate::psf::sampling::WavelengthSampling;
use crate::{Progress, SimError};

/// Largest FFT side of the defocused PSF: it needs two dense complex `M×M` grids (512 MiB here),
/// unlike the analysis, which folds a sparse field column by column.
pub const MAX_DEFOCUS_FFT: usize = 4096;

/// Farthest object distance accepted, mm (10 km: indistinguishable from infinity).
pub const MAX_OBJECT_DISTANCE_MM: f64 = 1.0e7;

/// `z2 = 1/(1/f − 1/z1)`, mm.
///
/// # Errors
/// [`SimError::InvalidSetting`] (`object_distance_mm`) unless `f < z1` and both are finite.
pub fn image_distance_mm(focal_mm: f64, object_mm: f64) -> Result<f64, SimError> {
    if !(focal_mm.is_finite() && focal_mm > 0.0) {
        return Err(SimError::invalid(
            Setting::FocalMm,
            format!("must be a positive number of mm (got {focal_mm:?})"),
        ));
    }
    if !(object_mm.is_finite() && object_mm > focal_mm && object_mm <= MAX_OBJECT_DISTANCE_MM) {
        return Err(SimError::invalid(
            Setting::ObjectDistanceMm,
            format!(
                "must lie beyond the focal length ({focal_mm} mm) and within \
                 {MAX_OBJECT_DISTANCE_MM:e} mm (got {object_mm:?})"
            ),
        ));
    }
    Ok(1.0 / (1.0 / focal_mm - 1.0 / object_mm))
}

/// What [`depth_psfs`] computes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthSettings {
    /// Object distance `z1` from the lens, mm.
    pub object_distance_mm: f64,
    /// Noise-to-signal ratio of the Wiener filter behind `residual_rel`.
    pub nsr: f64,
    /// Sampling quality of every PSF.
    pub quality: Quality,
}

impl Default for DepthSettings {
    fn default() -> Self {
        DepthSettings {
            object_distance_mm: 100.0,
            nsr: crate::restore::THESIS_NSR,
            quality: Quality::Preview,
        }
    }
}

/// PSFs of a point at one depth and their residuals after deblurring with the infinity PSF.
#[derive(Debug, Clone)]
pub struct DepthResult {
    /// Channel names, in the design's order.
    pub channels: Vec<String>,
    /// `z1`, mm.
    pub object_distance_mm: f64,
    /// `f`, mm.
    pub focal_length_mm: f64,
    /// `z2` from the lens law, mm.
    pub image_distance_mm: f64,
    /// `z2 / f`: how much larger the focused PSF is than the infinity PSF.
    pub psf_scale: f64,
    /// Defocus at the pupil's rim when focused at infinity, `R²/(2 λ z1)`, waves, per channel
    /// (at its mean wavelength).
    pub defocus_waves: Vec<f64>,
    /// Geometric defocus blur diameter on the sensor, `D·f/z1`, µm.
    pub defocus_blur_um: f64,
    /// The restoration's kernel: object at infinity, focused at infinity.
    pub infinity: Vec<Array2<f64>>,
    /// Object at `z1`, focused on it.
    pub focused: Vec<Array2<f64>>,
    /// Object at `z1`, focused at infinity.
    pub defocused: Vec<Array2<f64>>,
    /// `focused` deblurred with the infinity PSF's Wiener filter.
    pub deblurred_focused: Vec<Array2<f64>>,
    /// `defocused` deblurred with the infinity PSF's Wiener filter.
    pub deblurred_defocused: Vec<Array2<f64>>,
    /// `residual_rel` of `focused` per channel.
    pub residual_rel_focused_per_channel: Vec<f64>,
    /// `residual_rel` of `defocused` per channel.
    pub residual_rel_defocused_per_channel: Vec<f64>,
    /// Mean over channels of `residual_rel_focused_per_channel`.
    pub residual_rel_focused: f64,
    /// Mean over channels of `residual_rel_defocused_per_channel`.
    pub residual_rel_defocused: f64,
    /// Share of each channel's defocused light inside the sensor window.
    pub defocused_energy_in_window: Vec<f64>,
    /// Sensor pixel pitch, µm.
    pub sensor_pixel_um: f64,
}

/// The design refocused on an object at `z1`: a lens of focal length `z2` with the same pupil.
///
/// # Errors
/// As [`image_distance_mm`].
pub fn design_focused_at(design: &Design, object_mm: f64) -> Result<Design, SimError> {
    let f = design.optics.focal_length_mm;
    let z2 = image_distance_mm(f, object_mm)?;
    let mut d = design.clone();
    d.optics.recipe = OpticsRecipe::Custom;
    d.optics.focal_length_mm = z2;
    d.optics.f_number = design.optics.f_number * z2 / f;
    Ok(d)
}

/// The infinity, focused and defocused PSFs of a point at `settings.object_distance_mm`: the
/// first two are analyses whose Fraunhofer step `route` computes; the defocused one carries a
/// complex pupil (the defocus phase), which the seam's real field does not, and stays on the CPU.
///
/// # Errors
/// Bad settings or design ([`SimError::InvalidSetting`]); [`SimError::Sampling`] when the defocus
/// phase is under-sampled by δ1 (the object is too close); [`SimError::Cancelled`].
pub fn depth_psfs(
    design: &Design,
    settings: &DepthSettings,
    route: &dyn Fraunhofer,
    progress: &Progress,
) -> Result<DepthResult, SimError> {
    design.validate()?;
    let op = &design.optics;
    let z1 = settings.object_distance_mm;
    let z2 = image_distance_mm(op.focal_length_mm, z1)?;
    if !(settings.nsr.is_finite() && settings.nsr >= 0.0) {
        return Err(SimError::invalid(
            Setting::Nsr,
            format!("must be a finite number ≥ 0 (got {:?})", settings.nsr),
        ));
    }
    let options = AnalyzeOptions {
        quality: settings.quality,
        expected_psf: false,
    };
    progress.set(0.0);
    let infinity = analyze_with_route(design, &options, route, &Progress::new())?;
    let channels: Vec<String> = infinity.channels.iter().map(|c| c.name.clone()).collect();
    let infinity: Vec<Array2<f64>> = infinity.channels.into_iter().map(|c| c.psf).collect();
    progress.set(0.25);
    progress.check()?;
    let focused_design = design_focused_at(design, z1)?;
    let focused: Vec<Array2<f64>> =
        analyze_with_route(&focused_design, &options, route, &Progress::new())?
            .channels
            .into_iter()
            .map(|c| c.psf)
            .collect();
    progress.set(0.5);
    progress.check()?;
    let (defocused, in_window) = defocused_psfs(design, settings.quality, z1, route, progress)?;
    progress.set(0.9);
    let filters = infinity
        .iter()
        .map(|k| Deblur::new(k, settings.nsr))
        .collect::<Result<Vec<_>, _>>()?;
    let (per_f, deblurred_focused) = channel_residuals(&filters, &focused)?;
    let (per_d, deblurred_defocused) = channel_residuals(&filters, &defocused)?;
    let r_um = 0.5 * op.pupil_diameter_um();
    let defocus_waves = design
        .channels
        .iter()
        .map(|c| r_um * r_um / (2.0 * c.mean_wavelength_nm() * 1e-3 * z1 * 1e3))
        .collect();
    progress.set(1.0);
    Ok(DepthResult {
        channels,
        object_distance_mm: z1,
        focal_length_mm: op.focal_length_mm,
        image_distance_mm: z2,
        psf_scale: z2 / op.focal_length_mm,
        defocus_waves,
        defocus_blur_um: op.pupil_diameter_um() * op.focal_length_mm / z1,
        infinity,
        focused,
        defocused,
        deblurred_focused,
        deblurred_defocused,
        residual_rel_focused: mean(&per_f),
        residual_rel_defocused: mean(&per_d),
        residual_rel_focused_per_channel: per_f,
        residual_rel_defocused_per_channel: per_d,
        defocused_energy_in_window: in_window,
        sensor_pixel_um: op.sensor_pixel_um,
    })
}

/// Sensor PSFs per channel of a point at `z1` with the sensor at `f`, and the share of each
/// channel's light inside the window.
///
/// # Errors
/// As [`depth_psfs`].
pub fn defocused_psfs(
    design: &Design,
    quality: Quality,
    object_mm: f64,
    route: &dyn Fraunhofer,
    progress: &Progress,
) -> Result<(Vec<Array2<f64>>, Vec<f64>), SimError> {
    let op = &design.optics;
    let mut warnings = Vec::new();
    let samplings = quality.plan(design, &mut warnings)?;
    let cells = effective_cells(&design.opening);
    let display = Display::from_design(design, &cells);
    let d_um = op.pupil_diameter_um();
    let field = rasterise(
        &display,
        Extent::Pupil { diameter_um: d_um },
        op.pupil_sample_um,
    );
    let z1_um = object_mm * 1e3;
    // The phase step between neighbouring samples at the rim, 2π R δ1/(λ z1), must stay below π.
    let lambda_min_um = samplings
        .iter()
        .flatten()
        .map(|s| s.wavelength_nm * 1e-3)
        .fold(f64::INFINITY, f64::min);
    let nearest_mm = d_um * op.pupil_sample_um / lambda_min_um * 1e-3;
    if object_mm < nearest_mm {
        return Err(SimError::Sampling(format!(
            "an object at {object_mm} mm puts more than half a wave of defocus between \
             neighbouring pupil samples; the nearest depth this sampling represents is \
             {nearest_mm:.1} mm (decrease optics.pupil_sample_um)"
        )));
    }
    let mut psfs = Vec::with_capacity(samplings.len());
    let mut in_window = Vec::with_capacity(samplings.len());
    for samp in &samplings {
        let w = samp.first().map_or(0, |s| s.binning.window_px);
        let mut acc = Array2::<f64>::zeros((w, w));
        let mut inside = 0.0;
        for ws in samp {
            progress.check()?;
            let (binned, total) =
                defocused_intensity(&field, ws, op.pupil_sample_um, z1_um, route, progress)?;
            acc.scaled_add(ws.weight / total, &binned);
            inside += ws.weight * binned.sum() / total;
        }
        let sum = acc.sum();
        if !(sum > 0.0) {
            return Err(SimError::Sampling(
                "no defocused light reaches the sensor window".into(),
            ));
        }
        acc /= sum;
        psfs.push(acc);
        in_window.push(inside);
    }
    Ok((psfs, in_window))
}

/// `|DFT_M(a · exp(iπr²/(λ z1)))|²` binned to the window by `route`, and its total over the
/// grid.
fn defocused_intensity(
    field: &crate::display::aperture::Field,
    ws: &WavelengthSampling,
    delta_um: f64,
    z1_um: f64,
    route: &dyn Fraunhofer,
    progress: &Progress,
) -> Result<(Array2<f64>, f64), SimError> {
    let m = ws.fft_size;
    if m > MAX_DEFOCUS_FFT {
        return Err(SimError::TooLarge(format!(
            "the defocused PSF at {} nm needs a dense {m}×{m} grid (at most {MAX_DEFOCUS_FFT}); \
             use preview quality or increase optics.fine_sample_um",
            ws.wavelength_nm
        )));
    }
    let (lo, hi) = field.extent();
    if lo < -(m as i64 / 2) || hi >= m as i64 / 2 {
        return Err(SimError::Sampling(format!(
            "the pupil does not fit the {m}-sample grid"
        )));
    }
    let lambda_um = ws.wavelength_nm * 1e-3;
    let k = std::f64::consts::PI * delta_um * delta_um / (lambda_um * z1_um);
    let defocused = field.with_phase(|ix, iy| k * (ix * ix + iy * iy) as f64);
    let binned = route.binned_complex(&defocused, m, &ws.binning, progress)?;
    Ok((binned.sensor, binned.total))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lens_law_gives_the_thesis_distances() {
        let z2 = image_distance_mm(5.56, 100.0).expect("valid");
        assert!((z2 - 5.8873).abs() < 1e-3, "{z2}");
        assert!(z2 / 5.56 - 1.0 < 0.10);
        let z2 = image_distance_mm(5.56, 1000.0).expect("valid");
        assert!((z2 - 5.5911).abs() < 1e-3, "{z2}");
        assert!(image_distance_mm(5.56, 5.0).is_err());
        assert!(image_distance_mm(5.56, f64::NAN).is_err());
        assert!(image_distance_mm(f64::INFINITY, 100.0).is_err());
    }
}
