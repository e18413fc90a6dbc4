//! Fitting the display to a measured PSF: the pitch, the open fraction (as a bias of the
//! opening's edges), the display's turn and the lens's defocus, by least squares of the
//! simulated PSF against the measured one over the central pixels, with each channel's
//! sub-pixel registration fitted beside them.
//!
//! A periodic display's PSF is a lattice of orders whose spacing is `λ f / T`: a pitch 10 % off
//! puts the model's orders between the measured ones, where least squares has no slope to
//! follow. So the pitch is first searched coarsely (the start's PSF read at other scales, −20 %
//! to +25 %, which is what a pitch change does to the orders), then Levenberg–Marquardt refines
//! every parameter together. Each uncertainty is one standard deviation from the curvature at
//! the minimum, `σ² (JᵀJ)⁻¹` with `σ²` the residual's variance: it assumes that what the model
//! leaves is noise, so a model that misses something (a second defect, stray light) reports
//! uncertainties smaller than its errors.

mod edge;
mod model;

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt, TerminationReason};
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use ndarray::Array2;

use self::model::{Fine, Model, Pose};
use super::PsfSet;
use super::compare::alignment;
use crate::SimError;
use crate::design::Design;
use crate::progress::Progress;
use crate::psf::route::Fraunhofer;

pub use edge::EdgeField;

/// How the fit runs.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// Side of the central window fitted, pixels (the set's side when larger).
    pub window_px: usize,
    /// Search the pitch coarsely before refining it (off: start from the design's pitch).
    pub search_pitch: bool,
    /// The most evaluations of the residuals the refinement may take, rounded up to a whole
    /// number per parameter and one (the solver counts them so); each Jacobian adds two
    /// displays and a rendering per parameter.
    pub max_evaluations: usize,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            window_px: 128,
            search_pitch: true,
            max_evaluations: 60,
        }
    }
}

/// A fitted value with its standard uncertainty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The value.
    pub value: f64,
    /// One standard deviation.
    pub sigma: f64,
}

/// What the fit found.
#[derive(Debug, Clone)]
pub struct FitResult {
    /// The display's pixel pitch, µm.
    pub pitch_um: Estimate,
    /// How far the opening's edges moved out (in, when negative) from the drawing, µm.
    pub edge_bias_um: Estimate,
    /// The open fraction that bias gives.
    pub open_fraction: Estimate,
    /// The display's turn against the camera, degrees counter-clockwise.
    pub rotation_deg: Estimate,
    /// Diameter of the defocus blur circle at the sensor, µm.
    pub blur_um: Estimate,
    /// The sensor's distance from focus, µm (`blur · F#`; which side is not known).
    pub defocus_um: Estimate,
    /// Each channel's sample move (the import's centring, as the fit reads it), `[rows, cols]`
    /// pixels.
    pub shifts_px: Vec<[f64; 2]>,
    /// Where each channel's light was centred in the camera's pixel before the import moved
    /// it, `[rows, cols]` pixels from the pixel's centre.
    pub axes_px: Vec<[f64; 2]>,
    /// The design's pitch and open fraction, where the fit started.
    pub start_pitch_um: f64,
    /// The design's open fraction.
    pub start_open_fraction: f64,
    /// The pitch the coarse search chose (the start's when it is off).
    pub searched_pitch_um: f64,
    /// `Σ r² / Σ m²` of the design as drawn (best registered), and of the fit.
    pub residual_start: f64,
    /// `Σ r² / Σ m²` of the fitted model.
    pub residual: f64,
    /// Model evaluations of the refinement.
    pub evaluations: usize,
    /// Whether the refinement met its tolerance (else it ran out of evaluations or stalled).
    pub converged: bool,
    /// Why the refinement stopped, in words.
    pub stopped: String,
    /// The fitted design: the start with the fitted pitch and the edges moved.
    pub design: Design,
    /// The measured PSF of each channel on the fit's window, and the fitted model's.
    pub measured: Vec<Array2<f64>>,
    /// The fitted model's PSF of each channel.
    pub fitted: Vec<Array2<f64>>,
}

/// The fitted parameters, in the order of the solver's vector.
const PITCH: usize = 0;
const BIAS: usize = 1;
const ROTATION: usize = 2;
const BLUR: usize = 3;
const SHIFTS: usize = 4;
/// Each channel's sample move (rows, columns), light's axis (rows, columns), gain and pedestal,
/// from [`SHIFTS`] on.
const PER_CHANNEL: usize = 6;

/// Fits `design`'s display to the measured `set`, the display's fine intensities transformed
/// on `route` (the rest of the fit, which takes most of its time, on the CPU).
///
/// # Errors
/// A set that fails its check, a design whose sampling fails on the set's grid, a cancel, the
/// route's refusals.
pub fn fit(
    design: &Design,
    set: &PsfSet,
    options: &FitOptions,
    route: &dyn Fraunhofer,
    progress: &Progress,
) -> Result<FitResult, SimError> {
    set.check()?;
    let model = Model::new(design, set, options.window_px, route, progress)?;
    let start_pitch = model.design().opening.pitch_um;
    let start_open = model.edge.open_fraction(0.0);
    let channels = model.measured.len();

    // The design as drawn, registered: where the residual starts.
    let fine0 = model.fine(start_pitch, 0.0)?;
    let upright = Pose {
        rotation_deg: 0.0,
        blur_um: 0.0,
        scale: 1.0,
    };
    let (residual_start, _) = registered(&model, &fine0, upright);
    progress.set(0.1);

    let mut searched = start_pitch;
    if options.search_pitch {
        // A pitch `k` times the start's draws the orders `1/k` as far apart: the start's
        // PSF read at `k` times its coordinates. The search compares the PSFs below half the
        // Nyquist frequency, which the light's place in its pixel hardly changes.
        let want: Vec<Array2<f64>> = model.measured.iter().map(model::low_passed).collect();
        let zero = vec![[0.0, 0.0]; channels];
        let mut best = f64::INFINITY;
        for step in 0..=90 {
            progress.check()?;
            let k = 0.8 + 0.005 * f64::from(step);
            let got = model.render(
                &fine0,
                Pose {
                    scale: k,
                    ..upright
                },
                &zero,
                &zero,
            );
            let moved: Vec<Array2<f64>> = got
                .iter()
                .zip(&want)
                .map(|(g, w)| {
                    let g = model::low_passed(g);
                    let [dy, dx] = alignment(w, &g);
                    model::low_passed(&super::shift::shifted(&g, dy, dx))
                })
                .collect();
            let r = residual_share(&moved, &want);
            if r < best {
                (best, searched) = (r, start_pitch * k);
            }
        }
    }
    let fine_searched = model.fine(searched, 0.0)?;
    let (_, shifts) = registered(&model, &fine_searched, upright);
    progress.set(0.25);

    let pixel_um = set.pixel_um;
    let mut x = vec![searched, 0.0, 0.0, pixel_um];
    // Each channel: its registration, a gain of 1 and no pedestal. The pedestal takes what
    // the import's background estimate left or took (a few thousandths of a count a pixel
    // add up over the window to percents of the light, which would otherwise read as a
    // different open fraction), the gain the normalisation that follows it.
    // The axis and the sample move both: an import centres the light by moving its samples,
    // which for an undersampled PSF is not what moving the light does (the pixels integrate
    // differently), so the model places the light where the camera had it, then moves the
    // samples as the import did.
    for s in &shifts {
        x.extend([s[0], s[1], 0.0, 0.0, 1.0, 0.0]);
    }
    // The solver stops after `patience · (parameters + 1)` evaluations of the residuals.
    let patience = options.max_evaluations.div_ceil(x.len() + 1).max(1);
    let problem = Problem {
        model: &model,
        x: DVector::from_vec(x),
        cache: std::cell::RefCell::new(None),
        evaluations: std::cell::Cell::new(0),
        max_evaluations: options.max_evaluations.max(1),
    };
    let (problem, report) = LevenbergMarquardt::new()
        .with_patience(patience)
        .minimize(problem);
    progress.check()?;
    if let TerminationReason::Numerical(what) = report.termination {
        return Err(SimError::Sampling(format!("the fit failed: {what}")));
    }
    let x = problem.x.clone();
    let residuals = problem.residuals_at(&x)?;
    let jacobian = problem.jacobian_at(&x)?;
    let n = x.len();
    let dof = (residuals.len().saturating_sub(n)).max(1) as f64;
    let variance = residuals.norm_squared() / dof;
    let covariance = (jacobian.transpose() * &jacobian)
        .try_inverse()
        .map(|c| c * variance);
    let sigma = |i: usize| {
        covariance
            .as_ref()
            .map_or(f64::INFINITY, |c| c[(i, i)].max(0.0).sqrt())
    };
    let (pitch, bias) = (x[PITCH], x[BIAS]);
    let cell = model.cell_um(pitch);
    let open = model.edge.open_fraction(bias / cell);
    // The open fraction's slope in the bias carries the bias's uncertainty over.
    let step = 0.05 * cell;
    let slope = (model.edge.open_fraction((bias + step) / cell)
        - model.edge.open_fraction((bias - step) / cell))
        / (2.0 * step);
    let f_number = design.optics.f_number;
    let blur = Estimate {
        value: x[BLUR].abs(),
        sigma: sigma(BLUR),
    };
    let fine = model.fine(pitch, bias)?;
    let fitted: Vec<Array2<f64>> = model
        .render(
            &fine,
            pose_of(&x, 1.0),
            &axes_of(&x, channels),
            &shifts_of(&x, channels),
        )
        .into_iter()
        .enumerate()
        .map(|(c, a)| {
            let (gain, pedestal) = levels_of(&x, c);
            a * gain + pedestal
        })
        .collect();
    let mut fitted_design = model.design_at(pitch, bias);
    fitted_design.optics = design.optics.clone();
    fitted_design.channels = design.channels.clone();
    progress.set(1.0);
    Ok(FitResult {
        pitch_um: Estimate {
            value: pitch,
            sigma: sigma(PITCH),
        },
        edge_bias_um: Estimate {
            value: bias,
            sigma: sigma(BIAS),
        },
        open_fraction: Estimate {
            value: open,
            sigma: (slope * sigma(BIAS)).abs(),
        },
        rotation_deg: Estimate {
            value: x[ROTATION],
            sigma: sigma(ROTATION),
        },
        blur_um: blur,
        defocus_um: Estimate {
            value: blur.value * f_number,
            sigma: blur.sigma * f_number,
        },
        shifts_px: shifts_of(&x, channels),
        axes_px: axes_of(&x, channels),
        start_pitch_um: start_pitch,
        start_open_fraction: start_open,
        searched_pitch_um: searched,
        residual_start,
        residual: residual_share(&fitted, &model.measured),
        evaluations: problem.evaluations.get(),
        converged: matches!(
            report.termination,
            TerminationReason::Converged { .. } | TerminationReason::Orthogonal
        ),
        stopped: format!("{:?}", report.termination),
        design: fitted_design,
        measured: model.measured.clone(),
        fitted,
    })
}

/// The residual share of `pose` with each channel registered on its measurement, and the
/// registrations.
fn registered(model: &Model, fine: &Fine, pose: Pose) -> (f64, Vec<[f64; 2]>) {
    let zero = vec![[0.0, 0.0]; model.measured.len()];
    let rendered = model.render(fine, pose, &zero, &zero);
    let shifts: Vec<[f64; 2]> = rendered
        .iter()
        .zip(&model.measured)
        .map(|(s, m)| alignment(m, s))
        .collect();
    let moved = model.render(fine, pose, &zero, &shifts);
    (residual_share(&moved, &model.measured), shifts)
}

/// `Σ (s − m)² / Σ m²` over every channel.
fn residual_share(simulated: &[Array2<f64>], measured: &[Array2<f64>]) -> f64 {
    let (mut r, mut e) = (0.0, 0.0);
    for (s, m) in simulated.iter().zip(measured) {
        r += s.iter().zip(m).map(|(a, b)| (a - b).powi(2)).sum::<f64>();
        e += m.iter().map(|v| v * v).sum::<f64>();
    }
    r / e.max(1e-300)
}

fn pose_of(x: &DVector<f64>, scale: f64) -> Pose {
    Pose {
        rotation_deg: x[ROTATION],
        blur_um: x[BLUR],
        scale,
    }
}

/// Channel `c`'s gain and pedestal.
fn levels_of(x: &DVector<f64>, c: usize) -> (f64, f64) {
    let at = SHIFTS + PER_CHANNEL * c;
    (x[at + 4], x[at + 5])
}

fn axes_of(x: &DVector<f64>, channels: usize) -> Vec<[f64; 2]> {
    (0..channels)
        .map(|c| {
            [
                x[SHIFTS + PER_CHANNEL * c + 2],
                x[SHIFTS + PER_CHANNEL * c + 3],
            ]
        })
        .collect()
}

fn shifts_of(x: &DVector<f64>, channels: usize) -> Vec<[f64; 2]> {
    (0..channels)
        .map(|c| [x[SHIFTS + PER_CHANNEL * c], x[SHIFTS + PER_CHANNEL * c + 1]])
        .collect()
}

/// Fine intensities with the (pitch, bias) they are of.
type Cached = ((f64, f64), std::rc::Rc<Fine>);

/// The least-squares problem the solver walks: residuals `model − measured` over every
/// channel's window.
struct Problem<'m, 'p> {
    model: &'m Model<'p>,
    x: DVector<f64>,
    /// The fine intensities of the last (pitch, bias), with the residuals at the last `x`.
    cache: std::cell::RefCell<Option<Cached>>,
    evaluations: std::cell::Cell<usize>,
    max_evaluations: usize,
}

impl Problem<'_, '_> {
    fn fine_at(&self, pitch: f64, bias: f64) -> Result<std::rc::Rc<Fine>, SimError> {
        if let Some((key, fine)) = self.cache.borrow().as_ref()
            && *key == (pitch, bias)
        {
            return Ok(fine.clone());
        }
        let fine = std::rc::Rc::new(self.model.fine(pitch, bias)?);
        *self.cache.borrow_mut() = Some(((pitch, bias), fine.clone()));
        Ok(fine)
    }

    fn residuals_with(&self, fine: &Fine, x: &DVector<f64>) -> DVector<f64> {
        let channels = self.model.measured.len();
        let rendered = self.model.render(
            fine,
            pose_of(x, 1.0),
            &axes_of(x, channels),
            &shifts_of(x, channels),
        );
        DVector::from_iterator(
            rendered.iter().map(|a| a.len()).sum(),
            rendered
                .iter()
                .zip(self.model.measured.iter().zip(&self.model.weights))
                .enumerate()
                .flat_map(|(c, (s, (m, w)))| {
                    let (gain, pedestal) = levels_of(x, c);
                    s.iter()
                        .zip(m.iter().zip(w))
                        .map(move |(a, (b, w))| (gain * a + pedestal - b) * w)
                }),
        )
    }

    fn residuals_at(&self, x: &DVector<f64>) -> Result<DVector<f64>, SimError> {
        let fine = self.fine_at(x[PITCH], x[BIAS])?;
        Ok(self.residuals_with(&fine, x))
    }

    /// Forward differences, each step a small fraction of what the parameter changes by.
    fn jacobian_at(&self, x: &DVector<f64>) -> Result<DMatrix<f64>, SimError> {
        let base = self.residuals_at(x)?;
        let fine = self.fine_at(x[PITCH], x[BIAS])?;
        let mut j = DMatrix::<f64>::zeros(base.len(), x.len());
        for i in 0..x.len() {
            self.model.progress.check()?;
            let step = match i {
                PITCH => 2e-4 * x[PITCH].abs().max(1.0),
                BIAS => 0.02 * self.model.cell_um(x[PITCH]),
                ROTATION => 0.02,
                BLUR => 0.05,
                _ => match (i - SHIFTS) % PER_CHANNEL {
                    0 | 1 => 0.01,
                    2 | 3 => 0.02,
                    4 => 1e-3,
                    _ => 1e-3 / self.model.measured[0].len() as f64,
                },
            };
            let mut moved = x.clone();
            moved[i] += step;
            let r = if i == PITCH || i == BIAS {
                // A new display: its own intensities, not the cache's.
                let f = self.model.fine(moved[PITCH], moved[BIAS])?;
                self.residuals_with(&f, &moved)
            } else {
                self.residuals_with(&fine, &moved)
            };
            j.set_column(i, &((r - &base) / step));
        }
        Ok(j)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, '_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.x.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let n = self.evaluations.get() + 1;
        self.evaluations.set(n);
        let share = 0.25 + 0.7 * (n as f32 / self.max_evaluations as f32).min(1.0);
        self.model.progress.set(share);
        match self.residuals_at(&self.x) {
            Ok(r) => Some(r),
            Err(SimError::Cancelled) => None,
            // A pitch or a bias that leaves no light (an opening biased shut) is a step too
            // far: residuals far above any PSF's make the solver take a shorter one.
            Err(_) => {
                let len = self.model.measured.iter().map(Array2::len).sum();
                Some(DVector::from_element(len, 1.0))
            }
        }
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        self.jacobian_at(&self.x).ok()
    }
}
