//! Saturation and exposure bracketing (thesis §3.7, Fig. 3.30).
//!
//! A scene with specular highlights is blurred by the display's PSF and exposed so that
//! `clip_percent` % of the pixels reach the full well in at least one channel. The clipped capture
//! breaks the linear blur model, and Wiener restoration rings around every highlight. Exposure
//! bracketing restores linearity: `brackets` exposures spaced `step_ev` stops apart around the
//! base exposure are merged by summing the electrons of every exposure that did not clip at a
//! pixel over the sum of their exposure factors (the maximum-likelihood estimate for Poisson
//! counts), which is linear up to the shortest exposure's full well. Both are restored with the
//! same Wiener filter and compared with the blurred-free truth.
//!
//! Scores are on the base exposure's range: truth and restoration are clipped to `[0, 1]` (1 =
//! the base exposure's full well) before PSNR and SSIM, because that is the picture a designer
//! shows; ringing inside that range is what the scores see.

use crate::Setting;
use ndarray::{Array2, Zip};

use crate::SimError;
use crate::restore::capture::{CaptureSettings, Light, blur, expose};
use crate::restore::quality::{PlanesQuality, planes_quality};
use crate::restore::spectrum::{PadGrid, Padding};
use crate::restore::wiener::wiener;
use crate::sensor::scene::percentile_of;

/// A pixel counts as clipped at this share of the full well (noise reaches the clip before the
/// mean does).
const CLIP_SHARE: f64 = 0.98;

/// What [`saturation_study`] does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SaturationSettings {
    /// Share of pixels (%) clipped in the base exposure.
    pub clip_percent: f64,
    /// Number of bracketed exposures (odd counts centre on the base exposure).
    pub brackets: usize,
    /// Spacing of the exposures, in stops (EV).
    pub step_ev: f64,
    /// Noise-to-signal ratio of the Wiener filter.
    pub nsr: f64,
    /// Seed of the photon and read noise.
    pub seed: u64,
}

impl Default for SaturationSettings {
    fn default() -> Self {
        SaturationSettings {
            clip_percent: 2.0,
            brackets: 3,
            step_ev: 2.0,
            nsr: crate::restore::THESIS_NSR,
            seed: 0,
        }
    }
}

impl SaturationSettings {
    /// Checks every setting.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] naming the setting.
    pub fn validate(&self) -> Result<(), SimError> {
        let p = self.clip_percent;
        if !(p.is_finite() && p > 0.0 && p < 50.0) {
            return Err(SimError::invalid(
                Setting::ClipPercent,
                format!("must be above 0 and below 50 % (got {p:?})"),
            ));
        }
        if !(2..=9).contains(&self.brackets) {
            return Err(SimError::invalid(
                Setting::Brackets,
                format!("must be 2 to 9 exposures (got {})", self.brackets),
            ));
        }
        let s = self.step_ev;
        if !(s.is_finite() && s > 0.0 && s <= 6.0) {
            return Err(SimError::invalid(
                Setting::StepEv,
                format!("must be above 0 and at most 6 stops (got {s:?})"),
            ));
        }
        if !(self.nsr.is_finite() && self.nsr >= 0.0) {
            return Err(SimError::invalid(
                Setting::Nsr,
                format!("must be a finite number ≥ 0 (got {:?})", self.nsr),
            ));
        }
        Ok(())
    }

    /// Exposure factors relative to the base exposure, shortest first.
    pub fn factors(&self) -> Vec<f64> {
        let mid = (self.brackets as f64 - 1.0) / 2.0;
        (0..self.brackets)
            .map(|i| 2f64.powf(self.step_ev * (i as f64 - mid)))
            .collect()
    }
}

/// A capture and its restoration, with their scores.
#[derive(Debug, Clone)]
pub struct SaturationRun {
    /// The capture, one plane per channel (1 = the base exposure's full well).
    pub captured: Vec<Array2<f64>>,
    /// Its Wiener restoration.
    pub restored: Vec<Array2<f64>>,
    /// PSNR of the restoration against the truth, both clipped to `[0, 1]`, dB.
    pub psnr_db: f64,
    /// Mean SSIM over channels, same clipping.
    pub ssim: f64,
    /// Share of pixels left clipped (any channel): clipped in every exposure.
    pub clipped_fraction: f64,
}

/// The single clipped exposure against the bracketed HDR merge.
#[derive(Debug, Clone)]
pub struct SaturationResult {
    /// The truth on the base exposure's scale (1 = full well after the blur), unclipped.
    pub truth: Vec<Array2<f64>>,
    /// One exposure clipped at the full well.
    pub clipped: SaturationRun,
    /// The bracketed exposures merged into one linear image.
    pub bracketed: SaturationRun,
    /// The exposure factors used, shortest first.
    pub factors: Vec<f64>,
}

/// Simulates and restores the clipped and the bracketed capture of `scene` through `psfs`.
///
/// # Errors
/// [`SimError::InvalidSetting`] for bad settings, an empty or black scene or a PSF count that does
/// not match the planes.
pub fn saturation_study(
    scene: &[Array2<f64>],
    psfs: &[&Array2<f64>],
    settings: &SaturationSettings,
) -> Result<SaturationResult, SimError> {
    settings.validate()?;
    let Some(first) = scene.first() else {
        return Err(SimError::invalid("scene", "has no planes"));
    };
    let dim = first.dim();
    if dim.0 < 16 || dim.1 < 16 || scene.iter().any(|p| p.dim() != dim) {
        return Err(SimError::invalid(
            "scene",
            "needs planes of one size, at least 16×16",
        ));
    }
    if psfs.len() != scene.len() {
        return Err(SimError::invalid(
            "psfs",
            format!("{} PSFs for {} planes", psfs.len(), scene.len()),
        ));
    }
    let kernel_dim = psfs
        .iter()
        .fold((1, 1), |(h, w), p| (h.max(p.nrows()), w.max(p.ncols())));
    let grid = PadGrid::new(dim, kernel_dim, Padding::Double);
    let kernels: Vec<_> = psfs
        .iter()
        .map(|p| {
            let s = p.sum();
            grid.forward_kernel(&p.mapv(|v| v / s))
        })
        .collect();
    let blurred: Vec<Array2<f64>> = scene
        .iter()
        .zip(&kernels)
        .map(|(t, k)| blur(&grid, t.view(), k))
        .collect();
    // Scale so that the brightest channel of `clip_percent` % of the pixels passes the full well.
    let mut brightest = Array2::<f64>::zeros(dim);
    for b in &blurred {
        Zip::from(&mut brightest)
            .and(b)
            .for_each(|m, v| *m = m.max(*v));
    }
    let level = percentile_of(&brightest, 100.0 - settings.clip_percent);
    if !(level > 0.0 && level.is_finite()) {
        return Err(SimError::invalid("scene", "is black where it should clip"));
    }
    let truth: Vec<Array2<f64>> = scene.iter().map(|p| p / level).collect();
    let blurred: Vec<Array2<f64>> = blurred.iter().map(|p| p / level).collect();
    let capture = CaptureSettings {
        light: Light::ElectronsAtPeak(crate::restore::capture::FULL_WELL_E),
        seed: settings.seed,
        ..CaptureSettings::default()
    };
    let factors = settings.factors();
    let base = vec![1.0];
    let restore = |(captured, lost): (Vec<Array2<f64>>, f64)| -> Result<SaturationRun, SimError> {
        let restored = captured
            .iter()
            .zip(&kernels)
            .map(|(c, k)| wiener(&grid, c.view(), k, settings.nsr))
            .collect::<Result<Vec<_>, _>>()?;
        score(&truth, captured, restored, lost)
    };
    let clipped = restore(merge(&blurred, &base, &capture, 0)?)?;
    let bracketed = restore(merge(&blurred, &factors, &capture, 1)?)?;
    Ok(SaturationResult {
        truth,
        clipped,
        bracketed,
        factors,
    })
}

/// Exposes every plane at every factor and merges the unclipped exposures per pixel:
/// `Σ electrons / Σ factors` over the exposures below the clip (the shortest one where all clip).
fn merge(
    blurred: &[Array2<f64>],
    factors: &[f64],
    capture: &CaptureSettings,
    stream: usize,
) -> Result<(Vec<Array2<f64>>, f64), SimError> {
    let mut out = Vec::with_capacity(blurred.len());
    let mut lost = Array2::<bool>::from_elem(blurred.first().map_or((0, 0), Array2::dim), false);
    for (c, plane) in blurred.iter().enumerate() {
        let mut sum = Array2::<f64>::zeros(plane.dim());
        let mut weight = Array2::<f64>::zeros(plane.dim());
        let mut shortest: Option<Array2<f64>> = None;
        for (i, &f) in factors.iter().enumerate() {
            let exposed = plane.mapv(|v| v * f);
            // Distinct noise per exposure, channel and run.
            let channel = (stream * 16 + i) * 8 + c;
            let shot = expose(exposed.view(), capture, channel)?.image;
            Zip::from(&mut sum)
                .and(&mut weight)
                .and(&shot)
                .for_each(|s, w, v| {
                    if *v < CLIP_SHARE {
                        *s += v;
                        *w += f;
                    }
                });
            if shortest.is_none() {
                shortest = Some(shot.mapv(|v| v / f));
            }
        }
        let fallback = shortest.unwrap_or_else(|| Array2::zeros(plane.dim()));
        let merged = Zip::from(&sum)
            .and(&weight)
            .and(&fallback)
            .map_collect(|s, w, f| if *w > 0.0 { s / w } else { *f });
        Zip::from(&mut lost)
            .and(&weight)
            .for_each(|l, w| *l |= *w == 0.0);
        out.push(merged);
    }
    let lost_fraction = lost.iter().filter(|v| **v).count() as f64 / lost.len().max(1) as f64;
    Ok((out, lost_fraction))
}

fn score(
    truth: &[Array2<f64>],
    captured: Vec<Array2<f64>>,
    restored: Vec<Array2<f64>>,
    clipped_fraction: f64,
) -> Result<SaturationRun, SimError> {
    let clip = |p: &Array2<f64>| p.mapv(|v| v.clamp(0.0, 1.0));
    let t: Vec<Array2<f64>> = truth.iter().map(clip).collect();
    let r: Vec<Array2<f64>> = restored.iter().map(clip).collect();
    let PlanesQuality { psnr_db, ssim } = planes_quality(&r, &t)?;
    Ok(SaturationRun {
        psnr_db,
        ssim,
        clipped_fraction,
        captured,
        restored,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brackets_centre_on_the_base_exposure() {
        let s = SaturationSettings::default();
        assert_eq!(s.factors(), vec![0.25, 1.0, 4.0]);
        let bad = SaturationSettings {
            clip_percent: f64::NAN,
            ..s
        };
        assert!(bad.validate().is_err());
    }
}
