//! The V matrix and the λ0 optimizer of the phase workspace: background runs with progress and
//! Cancel, the allocation compared with the fixed and uniform plans, and Apply.

use crate::app::notice::Notice;
use std::sync::Arc;

use egui::TextureHandle;

use super::{ChannelSet, PhaseWorkspace, Quality};
use crate::app::job::{Finished, Job, JobError, Keyed};
use crate::core::figure::Panel;
use crate::core::phase::allocate::{channel_invertibility, plan_invertibility};
use crate::core::phase::geometry::{lenslet_count, uniform_counts};
use crate::core::phase::{
    Allocation, AllocationSettings, Lambda0, PhaseDesign, PhaseSampling, VMatrix, optimize_lambda0,
    v_matrix,
};
use crate::core::{Progress, SimError};

/// What a V matrix or optimizer run was started for.
pub(super) struct RunKey {
    design: PhaseDesign,
    quality: Quality,
    channels: ChannelSet,
}

/// The V matrix and the λ0 optimizer: their runs, results and message line.
#[derive(Default)]
pub(super) struct OptimizerState {
    /// The V matrix being computed.
    pub(super) v_job: Keyed<RunKey, VMatrix>,
    /// The V matrix on screen.
    pub(super) v: Option<ShownV>,
    /// The optimizer's run (V, then Algorithm 1).
    pub(super) opt_job: Keyed<RunKey, (VMatrix, Allocation)>,
    /// The optimizer's last result.
    pub(super) optimized: Option<OptimizerResult>,
    /// The latest message of either.
    pub(super) message: Option<Notice>,
}

/// The V matrix on screen and its picture.
pub struct ShownV {
    /// The design it was computed for (its λ0 plan does not matter).
    pub design: PhaseDesign,
    /// Preview or thesis sampling.
    pub quality: Quality,
    /// `v[j][k]`: invertibility with every lenslet folded at the j-th λ0, seen at the k-th λ.
    pub v: Arc<VMatrix>,
    /// V as a figure (`core::phase::figures::v_panel`) and its image's texture.
    pub panel: Arc<Panel>,
    pub(super) textures: Vec<TextureHandle>,
}

/// The optimizer's allocation and the plans it is compared with.
pub struct OptimizerResult {
    /// The design it was run for.
    pub design: PhaseDesign,
    /// Preview or thesis sampling of its V matrix.
    pub quality: Quality,
    /// The colour channels it kept invertible.
    pub channels: ChannelSet,
    /// Lenslets per grid wavelength, each lenslet's λ0 and the channels' invertibility.
    pub allocation: Allocation,
    /// Per-channel invertibility (A normalised to max 1) of every lenslet at 530 nm.
    pub fixed_530: [f64; 3],
    /// The same for the uniform plan.
    pub uniform: [f64; 3],
    /// How long the run took (V matrix included), in seconds.
    pub elapsed_s: f64,
}

/// The design with its λ0 plan replaced: V depends on everything else, not on the plan.
pub(super) fn without_plan(d: &PhaseDesign) -> PhaseDesign {
    let mut d = d.clone();
    d.lambda0 = Lambda0::Uniform;
    d
}

impl PhaseWorkspace {
    /// Computes V for the current design at the chosen quality, on a background thread.
    pub fn compute_v(&mut self, ctx: &egui::Context) {
        if self.optimizer.v_job.is_running() {
            return;
        }
        if let Err(e) = self.history.current().validate() {
            self.optimizer.message = Some(Notice::error(e.to_string()));
            return;
        }
        self.optimizer.message = None;
        let (key, job) = self.spawn_long("V matrix job", ctx, v_matrix);
        self.optimizer.v_job.start(key, job);
    }

    /// Runs the λ0 optimizer (V, then Algorithm 1) for the current design and channels.
    pub fn run_optimizer(&mut self, ctx: &egui::Context) {
        if self.optimizer.opt_job.is_running() {
            return;
        }
        if let Err(e) = self.history.current().validate() {
            self.optimizer.message = Some(Notice::error(e.to_string()));
            return;
        }
        let channels = match self.channel_list(self.channels) {
            Ok(c) => c,
            Err(e) => {
                self.optimizer.message =
                    Some(Notice::error(format!("cannot make the channels: {e}")));
                return;
            }
        };
        self.optimizer.message = None;
        let (key, job) = self.spawn_long("optimizer", ctx, move |d, sampling, p| {
            optimize_lambda0(d, sampling, &channels, &AllocationSettings::default(), p)
        });
        self.optimizer.opt_job.start(key, job);
    }

    /// Runs `job` on the current design at the chosen quality on a background thread; the
    /// key says what it runs for.
    fn spawn_long<T: Send + 'static>(
        &self,
        name: &'static str,
        ctx: &egui::Context,
        job: impl FnOnce(&PhaseDesign, &PhaseSampling, &Progress) -> Result<T, SimError>
        + Send
        + 'static,
    ) -> (RunKey, Job<T>) {
        let design = self.history.current().clone();
        let quality = self.quality;
        let (d, wake) = (design.clone(), ctx.clone());
        let job = Job::spawn(
            name,
            move || wake.request_repaint(),
            move |p| job(&d, &PhaseSampling::for_quality(quality), p),
        );
        let key = RunKey {
            design,
            quality,
            channels: self.channels,
        };
        (key, job)
    }

    /// Stops the V matrix and the optimizer; their last results stay.
    pub fn cancel_long_jobs(&mut self) {
        let any = self.optimizer.v_job.is_running() || self.optimizer.opt_job.is_running();
        // Stopping drops the job, which cancels it.
        self.optimizer.v_job.stop();
        self.optimizer.opt_job.stop();
        if any {
            self.optimizer.message = Some(Notice::info("cancelled"));
        }
    }

    fn show_v(&mut self, ctx: &egui::Context, design: PhaseDesign, quality: Quality, v: VMatrix) {
        let panel = Arc::new(crate::core::phase::figures::v_panel(&v));
        let textures = crate::app::widgets::figure::panel_textures(ctx, "phase-v", &panel);
        self.optimizer.v = Some(ShownV {
            design,
            quality,
            v: Arc::new(v),
            panel,
            textures,
        });
    }

    /// Takes a finished V matrix or optimizer run.
    pub(super) fn poll_optimizer(&mut self, ctx: &egui::Context) {
        if let Some(Finished {
            key,
            result,
            elapsed,
        }) = self.optimizer.v_job.finished()
        {
            match result {
                Ok(v) => {
                    let s = elapsed.as_secs_f64();
                    self.optimizer.message = Some(Notice::info(format!("V computed in {s:.1} s")));
                    self.show_v(ctx, key.design, key.quality, v);
                }
                Err(JobError::Cancelled) => {}
                Err(e) => self.optimizer.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(Finished {
            key,
            result,
            elapsed,
        }) = self.optimizer.opt_job.finished()
        {
            match result {
                Ok((v, allocation)) => {
                    let n = lenslet_count(&key.design);
                    let fixed_530 = plan_invertibility(&allocation.a, &vec![530.0; n]);
                    let uniform = channel_invertibility(&allocation.a, &uniform_counts(n));
                    let elapsed_s = elapsed.as_secs_f64();
                    self.optimizer.message =
                        Some(Notice::info(format!("optimized in {elapsed_s:.1} s")));
                    self.show_v(ctx, key.design.clone(), key.quality, v);
                    self.optimizer.optimized = Some(OptimizerResult {
                        design: key.design,
                        quality: key.quality,
                        channels: key.channels,
                        allocation,
                        fixed_530,
                        uniform,
                        elapsed_s,
                    });
                }
                Err(JobError::Cancelled) => {}
                Err(e) => self.optimizer.message = Some(Notice::error(e.to_string())),
            }
        }
    }

    /// Whether the optimizer's allocation fits the current design's lenslet count.
    pub fn can_apply(&self) -> bool {
        self.optimizer.optimized.as_ref().is_some_and(|o| {
            o.allocation.counts.iter().sum::<usize>() == lenslet_count(self.history.current())
        })
    }

    /// Uses the optimizer's allocation as the λ0 plan (one undo step); [`super::PhaseAction::ApplyOptimized`].
    pub(super) fn apply_optimized(&mut self) -> bool {
        if !self.can_apply() {
            return false;
        }
        let Some(o) = &self.optimizer.optimized else {
            return false;
        };
        let mut d = self.history.current().clone();
        d.lambda0 = Lambda0::Counts {
            counts: o.allocation.counts.clone(),
        };
        self.history.edit(d);
        true
    }
}
