//! The invertibility score of §4.3.5 and the matrix V over (λ0, λ) (conventions.md §7).

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::chain::{Chain, Incidence, PhaseOptics};
use super::{Lambda0, PhaseDesign, PhaseSampling, SimError, wavelength_grid_nm};
use crate::Progress;
use rustfft::num_complex::Complex64;

use udc_fft::{complex_inverse_plan, complex_plan, real_plan};

/// One-sided MTF of a 1-D sensor PSF: `|DFT|` of the PSF normalised to sum 1, at DC and the
/// positive frequencies `k = 0 … P/2 − 1` (cycles per `P` pixels). Empty for a dark PSF.
pub fn mtf_one_sided(psf: &[f64]) -> Vec<f64> {
    let sum: f64 = psf.iter().sum();
    if psf.len() < 2 || !(sum > 0.0) || !sum.is_finite() {
        return Vec::new();
    }
    let plan = real_plan(psf.len());
    let mut input: Vec<f64> = psf.iter().map(|v| v / sum).collect();
    let mut spectrum = plan.make_output_vec();
    if plan.process(&mut input, &mut spectrum).is_err() {
        return Vec::new();
    }
    spectrum
        .iter()
        .take(psf.len() / 2)
        .map(|c| c.norm())
        .collect()
}

/// Invertibility of a PSF: the sum of its one-sided MTF (a delta scores `P/2`, a dark PSF 0).
pub fn invertibility_score(psf: &[f64]) -> f64 {
    mtf_one_sided(psf).iter().sum()
}

/// `v[j][k]`: invertibility with every lenslet folded at `lambda0_nm[j]`, seen at `lambda_nm[k]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VMatrix {
    /// Wavelengths `λ` the PSFs are seen at (columns), nm.
    pub lambda_nm: Vec<f64>,
    /// Folding wavelengths `λ0` (rows), nm.
    pub lambda0_nm: Vec<f64>,
    /// `v[j][k]`, one row per `λ0`.
    pub v: Vec<Vec<f64>>,
}

/// V over the 30-wavelength grid at normal incidence for `design`'s geometry, fold and step
/// (its own λ0 plan is replaced row by row). 900 propagations, in parallel, with progress.
///
/// # Errors
/// An invalid design, or [`SimError::Cancelled`].
pub fn v_matrix(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    progress: &Progress,
) -> Result<VMatrix, SimError> {
    let grid = wavelength_grid_nm();
    v_matrix_on(design, sampling, &grid, &grid, progress)
}

/// V on any wavelengths: rows `lambda0_nm`, columns `lambda_nm` (a few entries for tests and
/// previews; [`v_matrix`] is the 30 × 30 grid).
///
/// # Errors
/// An invalid design, or [`SimError::Cancelled`].
pub fn v_matrix_on(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    lambda0_nm: &[f64],
    lambda_nm: &[f64],
    progress: &Progress,
) -> Result<VMatrix, SimError> {
    v_matrix_through(
        &Chain::new(design, sampling)?,
        lambda0_nm,
        lambda_nm,
        progress,
    )
}

/// [`v_matrix_on`] for `chain`'s design and sampling, each propagation through the chain's
/// Bloch relay where one is attached and the plate takes it ([`Chain::mono_relayed`]: the
/// wrapped display; a plate of one λ0 under the lenslet period stays on the CPU, where it is
/// one lenslet's samples).
///
/// # Errors
/// An invalid design, [`SimError::Cancelled`], or the relay's refusals (memory, a lost device).
pub fn v_matrix_through(
    chain: &Chain,
    lambda0_nm: &[f64],
    lambda_nm: &[f64],
    progress: &Progress,
) -> Result<VMatrix, SimError> {
    let design = chain.design();
    let heights: Vec<Vec<f64>> = lambda0_nm
        .par_iter()
        .map(|&l0| {
            let mut d = design.clone();
            d.lambda0 = Lambda0::Fixed { nm: l0 };
            chain.heights_for(&d)
        })
        .collect::<Result<_, _>>()?;
    let cols = lambda_nm.len().max(1);
    let total = lambda0_nm.len() * lambda_nm.len();
    let done = AtomicUsize::new(0);
    let flat: Vec<f64> = (0..total)
        .into_par_iter()
        .map(|idx| {
            progress.check()?;
            let (j, k) = (idx / cols, idx % cols);
            let psf = chain.mono_relayed(
                PhaseOptics::DoubleMla,
                &heights[j],
                lambda_nm[k],
                Incidence::Pixel(0),
            )?;
            let finished = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress.set(finished as f32 / total as f32);
            Ok(invertibility_score(&psf.sensor))
        })
        .collect::<Result<_, SimError>>()?;
    Ok(VMatrix {
        lambda_nm: lambda_nm.to_vec(),
        lambda0_nm: lambda0_nm.to_vec(),
        v: flat.chunks(cols).map(<[f64]>::to_vec).collect(),
    })
}

/// Optical MTF of a 1-D complex aperture: `|autocorrelation|`, normalised by its value at τ = 0
/// (the transmitted power), for lags `0 … len − 1` samples. The teaching view of Lemma 1.
pub fn optical_mtf(aperture: &[Complex64]) -> Vec<f64> {
    let n = aperture.len();
    if n == 0 {
        return Vec::new();
    }
    let m = crate::psf::sampling::next_fast_size(2 * n);
    let mut buf = vec![Complex64::new(0.0, 0.0); m];
    buf[..n].copy_from_slice(aperture);
    complex_plan(m).process(&mut buf);
    for v in buf.iter_mut() {
        *v = Complex64::new(v.norm_sqr(), 0.0);
    }
    complex_inverse_plan(m).process(&mut buf);
    let zero = buf[0].norm();
    if !(zero > 0.0) {
        return vec![0.0; n];
    }
    buf.iter().take(n).map(|v| v.norm() / zero).collect()
}
