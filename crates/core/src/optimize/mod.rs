//! The opening optimizer of thesis §3.4.2 (conventions.md §6): sigmoid-relaxed cells under a fixed,
//! seeded tiling; loss `α_area (mean g − c)² + α_inv L_inv + α_data L_top10`; analytic gradients
//! through the FFTs ([`model`], [`data`]); Adam; an area target that falls from 1 by 0.05 every
//! five epochs; and a final binarisation that keeps the target open fraction.
//!
//! [`optimize`] is the one entry point (studio, CLI, tests and benches).

pub mod adam;
pub mod data;
pub mod figures;
pub mod model;
pub mod reserve;

use crate::{Setting, SettingPath};
use std::ops::ControlFlow;
use std::time::Instant;

use crate::SimError;
use crate::analysis::analyze::Quality;
use crate::analysis::metrics::open_fraction;
use crate::design::Design;
use crate::progress::Progress;
use crate::psf::route::Fraunhofer;
use adam::Adam;
pub use data::DataSet;
pub use model::Model;

/// Weights of the three loss terms (conventions.md §6: 10 / 0.01 / 10).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LossWeights {
    /// `α_area`, weight of the area term `(mean g − c)²`.
    pub area: f64,
    /// `α_inv`, weight of the invertibility loss `L_inv`.
    pub inv: f64,
    /// `α_data`, weight of the data loss (used only when a data set is given).
    pub data: f64,
}

impl Default for LossWeights {
    fn default() -> Self {
        LossWeights {
            area: 10.0,
            inv: 0.01,
            data: 10.0,
        }
    }
}

/// Where the logits start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Start {
    /// Every logit +1: all open (the thesis, and its ablation's best).
    #[default]
    AllOpen,
    /// The design's current opening: logit +2 where open, −2 where closed.
    Current,
}

/// What the loss sees of the logits.
///
/// Under the plain sigmoid relaxation the optimum is a uniform grey pixel (a dimmed open
/// aperture has the best PSF of all), so the final threshold turns an excellent grey mask into
/// an arbitrary binary one (T-OLED random-4, 150 epochs, iccp21: relaxed `L_inv` −0.73,
/// binarised −0.134, AUC R 0.057; straight-through: −0.143, AUC R 0.070). The straight-through estimator evaluates the loss on the mask binarised
/// at the current area target and passes its gradient straight to the sigmoid, so the loss
/// reported is that of a pattern that can be built, and the final threshold changes nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Relaxation {
    /// The loss of the mask binarised at the current area target, its gradient passed straight
    /// to the sigmoid (the default).
    #[default]
    StraightThrough,
    /// The loss of the grey mask `g` itself (conventions.md §6 read literally).
    Sigmoid,
}

/// Everything that steers an [`optimize`] run; the defaults are the thesis's (conventions.md §6).
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizeSettings {
    /// How the loss sees the logits.
    pub relaxation: Relaxation,
    /// Epochs to run (the thesis: 150).
    pub epochs: usize,
    /// Final open fraction `c` of the pixel (the thesis: 0.2).
    pub target_open_fraction: f64,
    /// Weights of the area, invertibility and data terms.
    pub weights: LossWeights,
    /// Adam learning rate (the thesis: 1).
    pub learning_rate: f64,
    /// Adam's first-moment decay (the thesis: 0.5).
    pub beta1: f64,
    /// Adam's second-moment decay.
    pub beta2: f64,
    /// The area target falls by `area_step` every `area_every_epochs` epochs, from 1 to `c`.
    pub area_step: f64,
    /// Epochs between two steps of the area target.
    pub area_every_epochs: usize,
    /// Where the logits start.
    pub start: Start,
    /// Preview doubles the fine spacing (a quarter of the FFT work), as in
    /// [`crate::analysis::analyze::Quality`].
    pub quality: Quality,
    /// Reserve room for three equal R, G, B emitters of at least this many µm² each in the
    /// opaque area (0 = no constraint); the result carries their placement.
    pub reserve_subpixels_um2: f64,
}

impl Default for OptimizeSettings {
    fn default() -> Self {
        OptimizeSettings {
            relaxation: Relaxation::StraightThrough,
            epochs: 150,
            target_open_fraction: 0.2,
            weights: LossWeights::default(),
            learning_rate: 1.0,
            beta1: 0.5,
            beta2: 0.999,
            area_step: 0.05,
            area_every_epochs: 5,
            start: Start::AllOpen,
            quality: Quality::Full,
            reserve_subpixels_um2: 0.0,
        }
    }
}

/// The largest loss weight accepted.
pub const MAX_LOSS_WEIGHT: f64 = 1e6;

impl OptimizeSettings {
    /// Checks every setting's range.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] naming the first bad setting.
    pub fn validate(&self) -> Result<(), SimError> {
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(SimError::invalid(
                    name,
                    format!("must be a positive number, got {v:?}"),
                ))
            }
        };
        let non_negative = |name: SettingPath, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(SimError::invalid(name, format!("must be ≥ 0, got {v:?}")))
            }
        };
        if !(1..=100_000).contains(&self.epochs) {
            return Err(SimError::invalid(
                Setting::Epochs,
                format!("must be 1 … 100000, got {}", self.epochs),
            ));
        }
        let c = self.target_open_fraction;
        if !(c > 0.0 && c <= 1.0) {
            return Err(SimError::invalid(
                Setting::TargetOpenFraction,
                format!("must be in (0, 1], got {c}"),
            ));
        }
        for (name, w) in [
            (Setting::WeightArea, self.weights.area),
            (Setting::WeightInv, self.weights.inv),
            (Setting::WeightData, self.weights.data),
        ] {
            non_negative(name.into(), w)?;
            // Losses are O(1); a weight past this only overflows the sum.
            if w > MAX_LOSS_WEIGHT {
                return Err(SimError::invalid(
                    name,
                    format!("must be at most {MAX_LOSS_WEIGHT:e}, got {w:?}"),
                ));
            }
        }
        positive("learning_rate", self.learning_rate)?;
        non_negative("area_step".into(), self.area_step)?;
        for (name, b) in [("beta1", self.beta1), ("beta2", self.beta2)] {
            if !(0.0..1.0).contains(&b) {
                return Err(SimError::invalid(
                    name,
                    format!("must be in [0, 1), got {b}"),
                ));
            }
        }
        if self.area_every_epochs == 0 {
            return Err(SimError::invalid("area_every_epochs", "must be ≥ 1"));
        }
        let r = self.reserve_subpixels_um2;
        if !(r.is_finite() && r >= 0.0) {
            return Err(SimError::invalid(
                "reserve_subpixels_um2",
                format!("must be zero (off) or a positive number of µm² (got {r:?})"),
            ));
        }
        Ok(())
    }

    /// The area target at `epoch` (0-based): `max(c, 1 − step·floor(epoch / every))`.
    pub fn area_target(&self, epoch: usize) -> f64 {
        let steps = (epoch / self.area_every_epochs) as f64;
        (1.0 - self.area_step * steps).max(self.target_open_fraction)
    }
}

/// One epoch of the run, as the studio plots it.
#[derive(Debug, Clone, PartialEq)]
pub struct EpochReport {
    /// Epoch index, 0-based.
    pub epoch: usize,
    /// Epochs planned for the run.
    pub epochs: usize,
    /// Area target `c` used in this epoch.
    pub area_target: f64,
    /// Weighted total loss.
    pub loss_total: f64,
    /// `L_inv`, unweighted (negative; more negative is better).
    pub loss_inv: f64,
    /// `(mean g − c)²`, unweighted.
    pub loss_area: f64,
    /// Data loss, unweighted; `None` without a data set.
    pub loss_data: Option<f64>,
    /// Mean of the relaxed mask `g` (its open fraction).
    pub open_fraction: f64,
    /// The relaxed mask `g`, `N×N` row-major, before this epoch's step.
    pub mask: Vec<f64>,
}

/// The losses of one opening as an [`Objective`] sees it, without a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Score {
    /// `L_inv`, unweighted (negative; more negative is better).
    pub loss_inv: f64,
    /// Data loss, unweighted; `None` without a data set.
    pub loss_data: Option<f64>,
    /// Mean transmittance of the cells scored.
    pub open_fraction: f64,
}

/// The design a run started from and its result, scored alike at one sampling quality.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scores {
    /// The sampling both were scored at.
    pub quality: Quality,
    /// The start design's opening (`None` when no light passes it).
    pub start: Option<Score>,
    /// The binarised opening of the result.
    pub result: Score,
}

/// The outcome of [`optimize`].
#[derive(Debug, Clone)]
pub struct Optimized {
    /// The input design with the binarised opening (polygons dropped).
    pub design: Design,
    /// The relaxed mask at the end, `N×N` row-major.
    pub relaxed: Vec<f64>,
    /// Every epoch run, in order.
    pub history: Vec<EpochReport>,
    /// True when the caller stopped the run before the last epoch.
    pub stopped_early: bool,
    /// Wall-clock time of the run, ms.
    pub elapsed_ms: f64,
    /// Start and result at the run's own sampling: the scale of [`Optimized::history`].
    pub at_run_quality: Scores,
    /// Start and result at full quality: the `L_inv` that [`crate::analysis::analyze::analyze_with`]
    /// reports (and the studio's numbers show) for each design. The epochs' losses are those of
    /// the mask before each step, and a preview run's are at another sampling, so a summary of
    /// the run must come from here, not from its last epoch.
    pub at_full_quality: Scores,
}

fn sigmoid(x: f64) -> f64 {
    1.0 / (1.0 + (-x).exp())
}

/// Opens the `round(c·N²)` cells with the largest relaxed values (ties by position).
pub fn binarise(relaxed: &[f64], n: usize, open_fraction: f64) -> Vec<Vec<f64>> {
    let k = ((open_fraction * (n * n) as f64).round() as usize).min(n * n);
    let mut order: Vec<usize> = (0..relaxed.len()).collect();
    order.sort_by(|&a, &b| relaxed[b].total_cmp(&relaxed[a]).then(a.cmp(&b)));
    let mut cells = vec![vec![0.0; n]; n];
    for &i in order.iter().take(k) {
        cells[i / n][i % n] = 1.0;
    }
    cells
}

/// The differentiable model and the optional data set of one run, ready to evaluate.
pub struct Objective<'a> {
    /// The differentiable image-formation model of the design.
    pub model: Model<'a>,
    /// Training patches for the data loss, if any.
    pub data: Option<&'a DataSet>,
    /// Weights of the loss terms.
    pub weights: LossWeights,
    /// How the loss sees the logits.
    pub relaxation: Relaxation,
}

/// Loss terms and the gradient with respect to the logits.
#[derive(Debug, Clone)]
pub struct Step {
    /// Weighted sum of the terms below.
    pub loss_total: f64,
    /// `L_inv`, unweighted.
    pub loss_inv: f64,
    /// `(mean g − c)²`, unweighted.
    pub loss_area: f64,
    /// Data loss, unweighted; `None` without a data set.
    pub loss_data: Option<f64>,
    /// `∂(loss_total)/∂logit` per cell, `N×N` row-major.
    pub grad_logits: Vec<f64>,
}

impl<'a> Objective<'a> {
    /// Builds the model of `design` at `quality` (the cells are the variables), its window
    /// transforms on `route`.
    ///
    /// # Errors
    /// As [`Model::new`]; [`SimError::InvalidSetting`] for a bad design.
    pub fn new(
        design: &Design,
        quality: Quality,
        weights: LossWeights,
        relaxation: Relaxation,
        data: Option<&'a DataSet>,
        route: &'a dyn Fraunhofer,
    ) -> Result<Self, SimError> {
        design.validate()?;
        let mut warnings = Vec::new();
        let samplings = quality.plan(design, &mut warnings)?;
        Ok(Objective {
            model: Model::new(design, &samplings, route)?,
            data,
            weights,
            relaxation,
        })
    }

    /// The losses of `cells` (`N×N` row-major transmittances) with no gradient.
    ///
    /// # Errors
    /// As [`Model::forward`] (no light through the cells, a bad sampling).
    pub fn score(&self, cells: &[f64]) -> Result<Score, SimError> {
        let fwd = self.model.forward(cells)?;
        let loss_data = self.data.map(|d| d.loss(&fwd.psfs(), false).0);
        let loss_inv = fwd.loss_inv;
        self.model.recycle(fwd);
        Ok(Score {
            loss_inv,
            loss_data,
            open_fraction: cells.iter().sum::<f64>() / cells.len().max(1) as f64,
        })
    }

    /// The start's and the result's scores (the start's opening as the simulation sees it,
    /// polygons included).
    fn scores(
        &self,
        quality: Quality,
        start: &Design,
        result: &Design,
    ) -> Result<Scores, SimError> {
        let flat = |cells: Vec<Vec<f64>>| cells.into_iter().flatten().collect::<Vec<f64>>();
        let start_cells = flat(crate::display::aperture::effective_cells(&start.opening));
        Ok(Scores {
            quality,
            // A start that lets no light through has no loss to compare with; the result has.
            start: self.score(&start_cells).ok(),
            result: self.score(&flat(result.opening.cells.clone()))?,
        })
    }

    /// The loss at `logits` for area target `c`, and its gradient.
    ///
    /// # Errors
    /// As [`Model::forward`].
    pub fn step(&self, logits: &[f64], c: f64) -> Result<Step, SimError> {
        let g: Vec<f64> = logits.iter().map(|&x| sigmoid(x)).collect();
        let count = g.len().max(1) as f64;
        let mean = g.iter().sum::<f64>() / count;
        let loss_area = (mean - c) * (mean - c);
        let w = self.weights;
        let fwd = match self.relaxation {
            Relaxation::StraightThrough => {
                let b: Vec<f64> = binarise(&g, self.model.n, c)
                    .into_iter()
                    .flatten()
                    .collect();
                self.model.forward(&b)?
            }
            Relaxation::Sigmoid => self.model.forward(&g)?,
        };
        // The data loss's gradient joins L_inv's at the PSFs.
        let (loss_data, extra) = match self.data {
            Some(d) if w.data > 0.0 => {
                let (loss, grads) = d.loss(&fwd.psfs(), true);
                let scaled = grads.map(|gs| gs.into_iter().map(|g| g * w.data).collect::<Vec<_>>());
                (Some(loss), scaled)
            }
            Some(d) => (Some(d.loss(&fwd.psfs(), false).0), None),
            None => (None, None),
        };
        let grad_model = self.model.backward(&fwd, w.inv, extra.as_deref())?;
        let loss_inv = fwd.loss_inv;
        self.model.recycle(fwd);
        let area_grad = w.area * 2.0 * (mean - c) / count;
        let grad_logits = g
            .iter()
            .zip(&grad_model)
            .map(|(gi, gm)| (gm + area_grad) * gi * (1.0 - gi))
            .collect();
        Ok(Step {
            loss_total: w.area * loss_area
                + w.inv * loss_inv
                + loss_data.map_or(0.0, |d| w.data * d),
            loss_inv,
            loss_area,
            loss_data,
            grad_logits,
        })
    }
}

/// Optimizes `design`'s opening under its own pitch, tiling (seed fixed) and optics, the model's
/// window transforms and their adjoints on `route` (the CPU's [`crate::psf::route::PsfRoute`],
/// or a device through the seam). `on_epoch` sees every epoch and may stop the run early (the
/// result so far is returned); cancelling `progress` aborts with [`SimError::Cancelled`].
///
/// # Errors
/// [`SimError::InvalidSetting`] for bad settings or design, sampling errors, cancellation, the
/// route's refusals.
pub fn optimize(
    design: &Design,
    settings: &OptimizeSettings,
    data: Option<&DataSet>,
    route: &dyn Fraunhofer,
    progress: &Progress,
    mut on_epoch: impl FnMut(&EpochReport) -> ControlFlow<()>,
) -> Result<Optimized, SimError> {
    let start = Instant::now();
    settings.validate()?;
    progress.set(0.0);
    let objective = Objective::new(
        design,
        settings.quality,
        settings.weights,
        settings.relaxation,
        data,
        route,
    )?;
    let n = objective.model.n;
    let cells = (n * n) as f64;
    if settings.target_open_fraction * cells < 1.0 {
        return Err(SimError::invalid(
            Setting::TargetOpenFraction,
            format!(
                "{:?} of the {n}×{n} cells opens none; at least {:.4} (one cell) is needed",
                settings.target_open_fraction,
                1.0 / cells
            ),
        ));
    }
    let mut logits: Vec<f64> = match settings.start {
        Start::AllOpen => vec![1.0; n * n],
        Start::Current => design
            .opening
            .cells
            .iter()
            .flatten()
            .map(|&v| if v >= 0.5 { 2.0 } else { -2.0 })
            .collect(),
    };
    let mut adam = Adam::new(
        logits.len(),
        settings.learning_rate,
        settings.beta1,
        settings.beta2,
    );
    let mut history = Vec::with_capacity(settings.epochs);
    let mut stopped_early = false;
    for epoch in 0..settings.epochs {
        progress.check()?;
        let c = settings.area_target(epoch);
        let step = objective.step(&logits, c)?;
        if !(step.loss_total.is_finite() && step.grad_logits.iter().all(|g| g.is_finite())) {
            return Err(SimError::NonFinite {
                what: format!("the loss at epoch {}", epoch + 1),
                value: step.loss_total,
                hint: "lower the loss weights or the learning rate",
            });
        }
        let mask: Vec<f64> = logits.iter().map(|&x| sigmoid(x)).collect();
        let report = EpochReport {
            epoch,
            epochs: settings.epochs,
            area_target: c,
            loss_total: step.loss_total,
            loss_inv: step.loss_inv,
            loss_area: step.loss_area,
            loss_data: step.loss_data,
            open_fraction: mask.iter().sum::<f64>() / mask.len().max(1) as f64,
            mask,
        };
        adam.step(&mut logits, &step.grad_logits);
        progress.set((epoch + 1) as f32 / settings.epochs as f32);
        let flow = on_epoch(&report);
        history.push(report);
        if flow.is_break() && epoch + 1 < settings.epochs {
            stopped_early = true;
            break;
        }
    }
    let relaxed: Vec<f64> = logits.iter().map(|&x| sigmoid(x)).collect();
    let mut out = design.clone();
    out.opening.cells = binarise(&relaxed, n, settings.target_open_fraction);
    out.opening.polygons.clear();
    // The old placement belongs to the old opening.
    out.subpixels = None;
    if settings.reserve_subpixels_um2 > 0.0 {
        let (cells, sp) = reserve::reserve_subpixels(
            std::mem::take(&mut out.opening.cells),
            &relaxed,
            out.opening.pitch_um,
            settings.reserve_subpixels_um2,
        )?;
        out.opening.cells = cells;
        out.subpixels = Some(sp);
    }
    out.name = format!("{} (optimized)", design.name);
    out.description = format!(
        "Optimized from \"{}\" for {} epochs (L_inv weight {}, data weight {}), open fraction {:.3}. {}",
        design.name,
        history.len(),
        settings.weights.inv,
        if data.is_some() {
            settings.weights.data
        } else {
            0.0
        },
        open_fraction(&out.opening.cells),
        design.description
    );
    progress.check()?;
    let at_run_quality = objective.scores(settings.quality, design, &out)?;
    let at_full_quality = match settings.quality {
        Quality::Full => at_run_quality,
        Quality::Preview => Objective::new(
            design,
            Quality::Full,
            settings.weights,
            settings.relaxation,
            data,
            route,
        )?
        .scores(Quality::Full, design, &out)?,
    };
    Ok(Optimized {
        design: out,
        relaxed,
        history,
        stopped_early,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
        at_run_quality,
        at_full_quality,
    })
}
