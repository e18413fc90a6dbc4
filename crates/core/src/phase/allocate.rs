//! Allocation of folding wavelengths to lenslets: the log-barrier method of eqs. 4.9–4.11 and
//! Algorithm 1, exactly as conventions.md §7 specifies it, then rounding to the lenslet count.

use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

use super::invertibility::VMatrix;
use super::{GRID_FIRST_NM, GRID_LEN, GRID_STEP_NM, SimError, wavelength_grid_nm};
use crate::design::Channel;

type Vec30 = SVector<f64, GRID_LEN>;
type Mat30 = SMatrix<f64, GRID_LEN, GRID_LEN>;
type Mat3x30 = SMatrix<f64, 3, GRID_LEN>;

/// Parameters of Algorithm 1 (conventions.md's values by default).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AllocationSettings {
    /// ℓ1 weight q (the thesis's α).
    pub q: f64,
    /// First barrier parameter t, doubled after every stage.
    pub t0: f64,
    /// Barrier stages (t doubles after each).
    pub stages: usize,
    /// A stage stops when f changes by less than this between Newton steps.
    pub tolerance: f64,
    /// Most Newton steps per stage.
    pub max_steps: usize,
}

impl Default for AllocationSettings {
    fn default() -> Self {
        AllocationSettings {
            q: 0.1,
            t0: 0.01,
            stages: 20,
            tolerance: 1e-3,
            max_steps: 999,
        }
    }
}

/// The optimizer's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Allocation {
    /// The continuous solution x (≥ 0), one value per grid wavelength.
    pub x: Vec<f64>,
    /// Lenslets per grid wavelength, summing to the lenslet count.
    pub counts: Vec<usize>,
    /// λ0 of every lenslet, ascending (the order the thesis assigns them in).
    pub lambda0_nm: Vec<f64>,
    /// `A · counts / L` per channel (A normalised to max 1): R, G, B.
    pub channel_invertibility: [f64; 3],
    /// The last stage's barrier parameter and Newton steps per stage.
    pub final_t: f64,
    /// Newton steps taken in each stage.
    pub steps_per_stage: Vec<usize>,
    /// The normalised channel matrix A (3 × 30) the allocation was made for.
    pub a: Vec<Vec<f64>>,
}

/// `A = Wᵀ Vᵀ` normalised to max 1: `A[c][j]` is channel c's invertibility with every lenslet
/// folded at grid wavelength j. Channel weights at wavelengths between grid points are split
/// linearly between the two neighbours.
///
/// # Errors
/// A channel wavelength outside 401–691 nm, or a matrix without a positive entry.
pub fn channel_matrix(v: &VMatrix, channels: &[Channel]) -> Result<Vec<Vec<f64>>, SimError> {
    if channels.len() != 3 {
        return Err(SimError::invalid(
            "channels",
            format!("the allocation needs R, G and B; got {}", channels.len()),
        ));
    }
    let mut a = vec![vec![0.0; GRID_LEN]; 3];
    for (c, ch) in channels.iter().enumerate() {
        let sum: f64 = ch.weights.iter().sum();
        for (&l, &w) in ch.wavelengths_nm.iter().zip(&ch.weights) {
            let p = (l - GRID_FIRST_NM) / GRID_STEP_NM;
            if !(p >= -1e-9 && p <= (GRID_LEN - 1) as f64 + 1e-9) {
                return Err(SimError::invalid(
                    format!("channels[{c}]"),
                    format!("wavelength {l:?} nm is outside the grid 401–691 nm"),
                ));
            }
            let lo = (p.floor().max(0.0) as usize).min(GRID_LEN - 1);
            let hi = (lo + 1).min(GRID_LEN - 1);
            let frac = (p - lo as f64).clamp(0.0, 1.0);
            for (j, row) in v.v.iter().enumerate() {
                let inv = row[lo] * (1.0 - frac) + row[hi] * frac;
                a[c][j] += w / sum * inv;
            }
        }
    }
    let max = a.iter().flatten().copied().fold(0.0, f64::max);
    if !(max > 0.0) || !max.is_finite() {
        return Err(SimError::Sampling(
            "the invertibility matrix has no positive entry".into(),
        ));
    }
    for row in &mut a {
        for v in row.iter_mut() {
            *v /= max;
        }
    }
    Ok(a)
}

fn as_matrix(a: &[Vec<f64>]) -> Mat3x30 {
    Mat3x30::from_fn(|r, c| a[r][c])
}

/// The barrier objective `f = t‖Ax − 1‖² + t q Σx − Σ log x`.
pub fn barrier_objective(a: &[Vec<f64>], x: &[f64], t: f64, q: f64) -> f64 {
    let am = as_matrix(a);
    let xv = Vec30::from_column_slice(x);
    let r = am * xv - SVector::<f64, 3>::repeat(1.0);
    t * r.norm_squared() + t * q * xv.sum() - x.iter().map(|v| v.ln()).sum::<f64>()
}

/// The gradient Algorithm 1 steps along: `t·Aᵀ(Ax − 1) + t q − 1/x`.
pub fn barrier_gradient(a: &[Vec<f64>], x: &[f64], t: f64, q: f64) -> Vec<f64> {
    let am = as_matrix(a);
    let xv = Vec30::from_column_slice(x);
    let g = am.transpose() * (am * xv - SVector::<f64, 3>::repeat(1.0)) * t;
    (0..GRID_LEN).map(|i| g[i] + t * q - 1.0 / x[i]).collect()
}

/// Algorithm 1 on the normalised channel matrix `a` (from [`channel_matrix`]), then rounding to
/// `lenslets` counts.
///
/// # Errors
/// A malformed matrix, zero lenslets, or a Hessian that is not positive definite.
pub fn allocate(
    a: &[Vec<f64>],
    lenslets: usize,
    settings: &AllocationSettings,
) -> Result<Allocation, SimError> {
    if a.len() != 3 || a.iter().any(|r| r.len() != GRID_LEN) {
        return Err(SimError::Sampling("A must be 3 × 30".into()));
    }
    if lenslets == 0 {
        return Err(SimError::invalid("lenslets", "must be at least 1"));
    }
    let am = as_matrix(a);
    let ata: Mat30 = am.transpose() * am;
    let mut x = vec![1.0; GRID_LEN];
    let mut t = settings.t0;
    let mut steps_per_stage = Vec::with_capacity(settings.stages);
    for stage in 0..settings.stages {
        if stage > 0 {
            t *= 2.0;
        }
        let mut f_prev = barrier_objective(a, &x, t, settings.q);
        let mut steps = 0;
        while steps < settings.max_steps {
            let g = Vec30::from_vec(barrier_gradient(a, &x, t, settings.q));
            let mut hess = ata * t;
            for i in 0..GRID_LEN {
                hess[(i, i)] += 1.0 / (x[i] * x[i]);
            }
            let chol = hess.cholesky().ok_or_else(|| {
                SimError::Sampling("the barrier Hessian is not positive definite".into())
            })?;
            let step = chol.solve(&g);
            let candidate: Vec<f64> = (0..GRID_LEN).map(|i| x[i] - step[i]).collect();
            steps += 1;
            // A full step that leaves the feasible set is undone and ends the stage.
            if candidate.iter().any(|&v| v <= 0.0) {
                break;
            }
            x = candidate;
            let f = barrier_objective(a, &x, t, settings.q);
            let converged = (f_prev - f).abs() < settings.tolerance;
            f_prev = f;
            if converged {
                break;
            }
        }
        steps_per_stage.push(steps);
    }
    let sum: f64 = x.iter().sum();
    let shares: Vec<f64> = x.iter().map(|v| v / sum * lenslets as f64).collect();
    let counts = super::geometry::round_to_total(&shares, lenslets);
    let grid = wavelength_grid_nm();
    Ok(Allocation {
        channel_invertibility: channel_invertibility(a, &counts),
        lambda0_nm: super::geometry::expand_counts(&counts, &grid),
        x,
        counts,
        final_t: t,
        steps_per_stage,
        a: a.to_vec(),
    })
}

/// The whole job behind "run optimizer": V for the design's geometry and fold, the channel
/// matrix for `channels` (R, G, B, e.g. a response on the grid), Algorithm 1 and the rounding to
/// the design's lenslet count. Progress covers V, which is nearly all of the time.
///
/// # Errors
/// An invalid design or channels, or [`SimError::Cancelled`].
pub fn optimize_lambda0(
    design: &super::PhaseDesign,
    sampling: &super::PhaseSampling,
    channels: &[Channel],
    settings: &AllocationSettings,
    progress: &crate::Progress,
) -> Result<(VMatrix, Allocation), SimError> {
    let chain = super::chain::Chain::new(design, sampling)?;
    optimize_lambda0_through(&chain, channels, settings, progress)
}

/// [`optimize_lambda0`] for `chain`'s design and sampling, its V through the chain's Bloch
/// relay where one is attached ([`super::invertibility::v_matrix_through`]).
///
/// # Errors
/// As [`optimize_lambda0`], and the relay's refusals (memory, a lost device).
pub fn optimize_lambda0_through(
    chain: &super::chain::Chain,
    channels: &[Channel],
    settings: &AllocationSettings,
    progress: &crate::Progress,
) -> Result<(VMatrix, Allocation), SimError> {
    let grid = super::wavelength_grid_nm();
    let v = super::invertibility::v_matrix_through(chain, &grid, &grid, progress)?;
    let a = channel_matrix(&v, channels)?;
    let allocation = allocate(&a, super::geometry::lenslet_count(chain.design()), settings)?;
    Ok((v, allocation))
}

/// `A · counts / Σcounts` per channel: the normalised invertibility of a count allocation.
pub fn channel_invertibility(a: &[Vec<f64>], counts: &[usize]) -> [f64; 3] {
    let total: usize = counts.iter().sum();
    let mut out = [0.0; 3];
    if total == 0 {
        return out;
    }
    for (c, row) in a.iter().enumerate().take(3) {
        out[c] = row
            .iter()
            .zip(counts)
            .map(|(v, &n)| v * n as f64)
            .sum::<f64>()
            / total as f64;
    }
    out
}

/// Per-channel invertibility of any per-lenslet λ0 list: the mean over lenslets of the channel
/// matrix `a` (3 × grid) at the grid wavelength nearest each λ0 (530 nm → the 531 nm row, as the
/// CLI's fixed-530 comparison). Equals `channel_invertibility` for counts.
pub fn plan_invertibility(a: &[Vec<f64>], lambda0_nm: &[f64]) -> [f64; 3] {
    let mut out = [0.0; 3];
    if lambda0_nm.is_empty() {
        return out;
    }
    for &l in lambda0_nm {
        // The nearest grid row (conventions.md §7: a fixed 530 nm design is scored on the 531 row).
        let j = ((l - GRID_FIRST_NM) / GRID_STEP_NM)
            .round()
            .clamp(0.0, (GRID_LEN - 1) as f64) as usize;
        for (c, row) in a.iter().enumerate().take(3) {
            out[c] += row[j];
        }
    }
    out.map(|v| v / lambda0_nm.len() as f64)
}
