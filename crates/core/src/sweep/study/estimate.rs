//! What a study costs before it runs, from the engine's own models: each axis value's work
//! relative to the design's, times the time the design took on screen.
//!
//! - An analysis's work is its column transforms over every sampled wavelength (the PSF
//!   route's dominant term, `psf::route`), from each value's sampling plan.
//! - A phase-mask point's work is its display-plane samples times the sensor directions
//!   (`PhaseSampling`): the fold and the pitch keep it, the quality scales it. A λ0 plan whose
//!   relay differs from the design's (a plan falls back from the lenslet period to the
//!   wrapped display) or the optimizer's allocation is not modelled: the estimate is then a
//!   lower bound, and says so.
//! - A restoring point adds the Restore view's last run.

use crate::SimError;
use crate::analysis::analyze::Quality;
use crate::design::Design;
use crate::phase::geometry::display_aperture_um;
use crate::phase::{Lambda0Plan, PhaseDesign, PhaseSampling};
use crate::sweep::SweepJob;

use super::{Study, StudyAxis, StudySubject};

/// What a study is expected to cost before it runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudyEstimate {
    /// The points.
    pub points: u64,
    /// Seconds to run them all on this machine, one after another (the runner shares them
    /// among the cores).
    pub seconds: f64,
    /// Whether some points do work the model does not know (the optimizer's allocation, a
    /// slower relay): `seconds` is then a lower bound.
    pub at_least: bool,
    /// Working memory of the largest point, bytes.
    pub bytes_per_point: u64,
}

/// How long the design took on screen, to scale the model by.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StudyTimes {
    /// The design's analysis (display) or channel PSFs (phase masks), ms, and the quality
    /// they ran at.
    pub on_screen: Option<(f64, Quality)>,
    /// The Restore view's last capture and restoration, ms.
    pub restore_ms: Option<f64>,
}

/// Modelled work of one analysis, in complex multiply-adds, and the bytes of its largest
/// field and transform.
fn display_work(design: &Design, quality: Quality) -> Result<(f64, u64), SimError> {
    let mut warnings = Vec::new();
    let plan = quality.plan(design, &mut warnings)?;
    let mut ops = 0.0;
    let mut largest = 0usize;
    for s in plan.iter().flatten() {
        let m = s.fft_size;
        let mf = m as f64;
        ops += (m / 2 + 1) as f64 * (crate::psf::zoom::fft_ops(m) + 3.0 * mf) + 8.0 * mf * mf;
        largest = largest.max(m);
    }
    // One complex field of the largest FFT size and its transform.
    let bytes = 2 * 16 * (largest as u64).pow(2);
    Ok((ops, bytes))
}

/// Modelled work of one phase-mask point: display samples times sensor directions, and the
/// bytes of a few complex display fields.
fn phase_work(design: &PhaseDesign, quality: Quality) -> (f64, u64) {
    let s = PhaseSampling::for_quality(quality);
    let samples = (display_aperture_um(design) / s.display_sample_um).max(1.0);
    let ops = samples * s.fine_per_pixel as f64;
    (ops, 4 * 16 * samples as u64)
}

impl Study {
    /// The quality its points analyse at (`restore` has no preview).
    fn quality(&self) -> Quality {
        if self.full || self.job() == SweepJob::Restore {
            Quality::Full
        } else {
            Quality::Preview
        }
    }

    /// The study's cost before it runs; `None` when a time it scales by is not known yet
    /// (nothing on screen, or a restoring study before the Restore view has run).
    ///
    /// # Errors
    /// A value whose sampling cannot be planned.
    pub fn estimate(&self, times: &StudyTimes) -> Result<Option<StudyEstimate>, SimError> {
        let Some((reference_ms, reference_quality)) = times.on_screen else {
            return Ok(None);
        };
        let restore_ms = if self.job() == SweepJob::Restore {
            match times.restore_ms {
                Some(ms) => ms,
                None => return Ok(None),
            }
        } else {
            0.0
        };
        let (ratio, bytes, at_least) = match &self.subject {
            StudySubject::Display(d) => self.display_ratio(d, reference_quality)?,
            StudySubject::Phase(d) => self.phase_ratio(d, reference_quality),
        };
        let points = self.points();
        let per_point_ms = ratio * reference_ms.max(0.0) + restore_ms.max(0.0);
        Ok(Some(StudyEstimate {
            points,
            seconds: points as f64 * per_point_ms / 1e3,
            at_least,
            bytes_per_point: bytes,
        }))
    }

    /// Mean work of a point over the design's on-screen analysis, the largest point's bytes.
    fn display_ratio(
        &self,
        design: &Design,
        reference: Quality,
    ) -> Result<(f64, u64, bool), SimError> {
        let q = self.quality();
        let (base_ops, base_bytes) = display_work(design, q)?;
        let (reference_ops, _) = display_work(design, reference)?;
        let mut ratio = base_ops / reference_ops.max(1.0);
        let mut bytes = base_bytes;
        for a in &self.axes {
            let variants = a.variants(design);
            if variants.is_empty() {
                continue;
            }
            let mut sum = 0.0;
            for d in &variants {
                let d = d
                    .as_ref()
                    .map_err(|e| SimError::invalid(a.param(), e.to_string()))?;
                let (ops, b) = display_work(d, q)?;
                sum += ops / base_ops.max(1.0);
                bytes = bytes.max(b);
            }
            ratio *= sum / variants.len() as f64;
        }
        Ok((ratio, bytes, false))
    }

    /// The same for a phase-mask design.
    fn phase_ratio(&self, design: &PhaseDesign, reference: Quality) -> (f64, u64, bool) {
        let q = self.quality();
        let (base_ops, mut bytes) = phase_work(design, q);
        let (reference_ops, _) = phase_work(design, reference);
        let mut ratio = base_ops / reference_ops.max(1.0);
        // One λ0 for every lenslet takes the lenslet period; any other plan the wrapped
        // display, which the model does not cost.
        let own_fixed = matches!(design.lambda0, crate::phase::Lambda0::Fixed { .. });
        let mut at_least = false;
        for a in &self.axes {
            if let StudyAxis::Lambda0(plans) = a {
                at_least |= plans.iter().any(|p| {
                    *p == Lambda0Plan::Optimized || matches!(p, Lambda0Plan::Fixed(_)) != own_fixed
                });
                continue;
            }
            let variants: Vec<PhaseDesign> =
                a.phase_variants(design).into_iter().flatten().collect();
            if variants.is_empty() {
                continue;
            }
            let mut sum = 0.0;
            for d in &variants {
                let (ops, b) = phase_work(d, q);
                sum += ops / base_ops.max(1.0);
                bytes = bytes.max(b);
            }
            ratio *= sum / variants.len() as f64;
        }
        (ratio, bytes, at_least)
    }
}
