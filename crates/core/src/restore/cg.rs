//! A second restoration: gradient-regularised least squares
//! `min_x ||k ∗ x − y||² + λ ||∇x||²`, solved by conjugate gradients on the normal equations
//! `(AᵀA + λ DᵀD) x = Aᵀy`. Unlike Wiener, `A` is the *linear* 'same' convolution (zero outside
//! the image, cropped back), so the solver never pretends the photo is periodic or padded with
//! black; `D` takes forward differences inside the image only (no difference across the border,
//! so a flat image costs nothing). Both FFT convolutions reuse the kernel spectrum of the blur.
//! Because every convolution is exactly linear, the result does not depend on the padding of the
//! grid: [`super::Padding::Linear`] is the fast choice.

use crate::Setting;
use ndarray::{Array2, ArrayView2, Zip};
use rayon::prelude::*;

use super::spectrum::{PadGrid, Spectrum};
use crate::{Progress, SimError};

/// Settings of the solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgSettings {
    /// Weight of the gradient penalty (`λ`), relative to a PSF that sums to 1.
    pub lambda: f64,
    /// At most this many iterations.
    pub iterations: usize,
    /// Stop early once `||r|| ≤ tolerance · ||Aᵀy||` (`r` the residual of the normal equations).
    pub tolerance: f64,
}

impl Default for CgSettings {
    /// `λ = 0.002`, a middle ground: on the committed 256×256 photo behind the random-D4 T-OLED
    /// it gives 17.6 dB at 28 dB SNR and 23.7 dB at 36 dB (Wiener with the thesis nsr: 14.7 and
    /// 20.0); `λ = 0.005` suits the noisier levels better, `0.0005` the cleaner ones. There
    /// the tolerance 1e-4 stops the solver after 35–50 iterations, below the cap of 60.
    fn default() -> Self {
        CgSettings {
            lambda: 0.002,
            iterations: 60,
            tolerance: 1e-4,
        }
    }
}

impl CgSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for a negative or non-finite `λ` (`method.lambda`), zero
    /// iterations (`method.iterations`) or a negative or non-finite tolerance
    /// (`method.tolerance`).
    pub fn validate(&self) -> Result<(), SimError> {
        if !(self.lambda.is_finite() && self.lambda >= 0.0) {
            return Err(SimError::invalid(
                Setting::MethodLambda,
                format!("must be a finite number ≥ 0 (got {:?})", self.lambda),
            ));
        }
        if self.iterations == 0 {
            return Err(SimError::invalid("method.iterations", "must be at least 1"));
        }
        if !(self.tolerance.is_finite() && self.tolerance >= 0.0) {
            return Err(SimError::invalid(
                "method.tolerance",
                format!("must be a finite number ≥ 0 (got {:?})", self.tolerance),
            ));
        }
        Ok(())
    }
}

/// What the solver did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CgReport {
    /// Iterations run before the tolerance or the iteration limit stopped the solver.
    pub iterations: usize,
    /// `||k ∗ x − y||² + λ||∇x||²` at the start and after every iteration; conjugate gradients
    /// never let it grow.
    pub objective: Vec<f64>,
    /// `||r|| / ||Aᵀy||` at the start and after every iteration.
    pub relative_residual: Vec<f64>,
}

/// `Σ a·b` in fixed chunks summed in order: the same bits whatever the thread count.
fn dot(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
    const CHUNK: usize = 1 << 14;
    match (a.as_slice(), b.as_slice()) {
        (Some(a), Some(b)) => {
            let partial: Vec<f64> = a
                .par_chunks(CHUNK)
                .zip(b.par_chunks(CHUNK))
                .map(|(x, y)| x.iter().zip(y).map(|(p, q)| p * q).sum())
                .collect();
            partial.iter().sum()
        }
        _ => a.iter().zip(b.iter()).map(|(p, q)| p * q).sum(),
    }
}

/// `DᵀD x`: the negated Laplacian with no flux through the image border.
fn grad_normal(x: &Array2<f64>) -> Array2<f64> {
    let (h, w) = x.dim();
    let mut out = Array2::<f64>::zeros((h, w));
    out.axis_iter_mut(ndarray::Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(i, mut row)| {
            for j in 0..w {
                let c = x[[i, j]];
                let mut acc = 0.0;
                if i > 0 {
                    acc += c - x[[i - 1, j]];
                }
                if i + 1 < h {
                    acc += c - x[[i + 1, j]];
                }
                if j > 0 {
                    acc += c - x[[i, j - 1]];
                }
                if j + 1 < w {
                    acc += c - x[[i, j + 1]];
                }
                row[j] = acc;
            }
        });
    out
}

/// A linear blur `A` from the sharp image to the capture (both the capture's shape), as the
/// solver needs it: the blur, its adjoint, and optionally a cheaper `AᵀA`.
pub trait LinearBlur: Sync {
    /// `A x`.
    fn blur(&self, x: &Array2<f64>) -> Array2<f64>;
    /// `Aᵀ z`.
    fn adjoint(&self, z: &Array2<f64>) -> Array2<f64>;
    /// `AᵀA x` (override when a precomputed normal operator is cheaper).
    fn normal(&self, x: &Array2<f64>) -> Array2<f64> {
        self.adjoint(&self.blur(x))
    }
}

/// The shift-invariant blur of the display workspace: a kernel spectrum on a padded grid.
pub struct Convolution<'a> {
    /// The padded FFT grid the kernel lives on.
    pub grid: &'a PadGrid,
    /// The kernel's half spectrum on `grid`.
    pub kernel: &'a Spectrum,
}

impl LinearBlur for Convolution<'_> {
    /// Blur, linear, cropped.
    fn blur(&self, x: &Array2<f64>) -> Array2<f64> {
        self.grid.filter(x.view(), |i, v| v * self.kernel.data[i])
    }

    /// Correlation with the kernel, linear, cropped.
    fn adjoint(&self, z: &Array2<f64>) -> Array2<f64> {
        self.grid
            .filter(z.view(), |i, v| v * self.kernel.data[i].conj())
    }
}

struct NormalOperator<'a, B: LinearBlur> {
    blur: &'a B,
    lambda: f64,
}

impl<B: LinearBlur> NormalOperator<'_, B> {
    fn adjoint(&self, z: &Array2<f64>) -> Array2<f64> {
        self.blur.adjoint(z)
    }

    /// `(AᵀA + λ DᵀD) x`.
    fn apply(&self, x: &Array2<f64>) -> Array2<f64> {
        let mut m = self.blur.normal(x);
        if self.lambda > 0.0 {
            m.scaled_add(self.lambda, &grad_normal(x));
        }
        m
    }
}

/// Restores one channel by conjugate gradients, starting from the capture itself. Negative
/// values are clipped to 0 at the end, as Wiener does. `progress` is checked every iteration.
///
/// # Errors
/// [`SimError::InvalidSetting`] for bad settings (see [`CgSettings::validate`]);
/// [`SimError::Cancelled`].
pub fn cg(
    grid: &PadGrid,
    captured: ArrayView2<'_, f64>,
    kernel: &Spectrum,
    settings: &CgSettings,
    progress: &Progress,
) -> Result<(Array2<f64>, CgReport), SimError> {
    cg_with(&Convolution { grid, kernel }, captured, settings, progress)
}

/// [`cg`] for any linear blur: the same solver, regulariser and stopping rule.
///
/// # Errors
/// As [`cg`].
pub fn cg_with<B: LinearBlur>(
    blur: &B,
    captured: ArrayView2<'_, f64>,
    settings: &CgSettings,
    progress: &Progress,
) -> Result<(Array2<f64>, CgReport), SimError> {
    cg_from(blur, captured, captured.to_owned(), settings, progress)
}

/// [`cg_with`] started from `start` instead of the capture: for an `A` whose unknown is larger
/// than its capture (a 'full' boundary, where the estimate reaches beyond the sensor), `start`
/// has the unknown's shape.
///
/// # Errors
/// As [`cg_with`].
pub fn cg_from<B: LinearBlur>(
    blur: &B,
    captured: ArrayView2<'_, f64>,
    start: Array2<f64>,
    settings: &CgSettings,
    progress: &Progress,
) -> Result<(Array2<f64>, CgReport), SimError> {
    settings.validate()?;
    let CgSettings {
        lambda,
        iterations,
        tolerance,
    } = *settings;
    let op = NormalOperator { blur, lambda };
    let y = captured.to_owned();
    let b = op.adjoint(&y);
    let yy = dot(&y, &y);
    let b_norm = dot(&b, &b).sqrt();
    let mut x = start;
    let mut r = &b - &op.apply(&x);
    // f(x) = xᵀMx − 2bᵀx + yᵀy and Mx = b − r, so f = yᵀy − bᵀx − rᵀx: no extra convolution.
    let objective = |x: &Array2<f64>, r: &Array2<f64>| yy - dot(&b, x) - dot(r, x);
    let mut rr = dot(&r, &r);
    let relative = |rr: f64| {
        if b_norm > 0.0 {
            rr.sqrt() / b_norm
        } else {
            0.0
        }
    };
    let mut report = CgReport {
        iterations: 0,
        objective: vec![objective(&x, &r)],
        relative_residual: vec![relative(rr)],
    };
    let mut p = r.clone();
    for _ in 0..iterations {
        if relative(rr) <= tolerance || rr == 0.0 {
            break;
        }
        progress.check()?;
        let mp = op.apply(&p);
        let pmp = dot(&p, &mp);
        if !(pmp > 0.0) {
            // p lies in the null space of a λ = 0 problem: nothing left to gain.
            break;
        }
        let alpha = rr / pmp;
        x.scaled_add(alpha, &p);
        r.scaled_add(-alpha, &mp);
        let rr_new = dot(&r, &r);
        let beta = rr_new / rr;
        rr = rr_new;
        Zip::from(&mut p)
            .and(&r)
            .par_for_each(|p, r| *p = r + beta * *p);
        report.iterations += 1;
        report.objective.push(objective(&x, &r));
        report.relative_residual.push(relative(rr));
    }
    x.mapv_inplace(|v| v.max(0.0));
    Ok((x, report))
}

#[cfg(test)]
mod tests {
    use super::super::spectrum::Padding;
    use super::*;

    #[test]
    fn the_normal_operator_is_symmetric() {
        // ⟨u, M v⟩ = ⟨M u, v⟩ is what conjugate gradients needs; a circular-vs-linear mix-up in
        // the adjoint breaks it at the borders.
        let dim = (13, 17);
        let kernel = Array2::from_shape_fn((6, 5), |(y, x)| 1.0 + ((y * 3 + x) % 4) as f64);
        let kernel = &kernel / kernel.sum();
        let grid = PadGrid::new(dim, kernel.dim(), Padding::Linear);
        let k = grid.forward_kernel(&kernel);
        let conv = Convolution {
            grid: &grid,
            kernel: &k,
        };
        let op = NormalOperator {
            blur: &conv,
            lambda: 0.3,
        };
        let u = Array2::from_shape_fn(dim, |(y, x)| ((y * 7 + x * 11) % 5) as f64 - 2.0);
        let v = Array2::from_shape_fn(dim, |(y, x)| ((y * 5 + x * 3) % 7) as f64 - 3.0);
        let a = dot(&u, &op.apply(&v));
        let b = dot(&op.apply(&u), &v);
        assert!((a - b).abs() < 1e-9 * a.abs().max(1.0), "{a} vs {b}");
    }
}
