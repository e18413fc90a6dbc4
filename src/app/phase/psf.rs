//! The channel PSFs of the phase workspace: every parameter change runs them at preview
//! sampling at once, then at the thesis sampling, on a background job; a newer change cancels
//! the running one, and results of older parameters are dropped.

use crate::app::notice::Notice;
use std::sync::Arc;
use std::time::Instant;

use super::{ChannelSet, PhaseWorkspace, Quality};
use crate::app::history::Snapshot;
use crate::app::job::{Job, JobError, Keyed};
use crate::core::SimError;
use crate::core::phase::{
    Incidence, PhaseDesign, PhaseOptics, PhasePsfs, PhaseSampling, phase_psfs,
};

/// PSFs on screen, with what they were computed for.
pub struct ShownPsfs {
    /// Generation of the parameters they were computed for (older than the newest: stale).
    pub generation: u64,
    /// Preview or thesis sampling.
    pub quality: Quality,
    /// The design they were computed for.
    pub design: PhaseDesign,
    /// The optical chain: double MLA, or the single mask of Lemma 1.
    pub optics: PhaseOptics,
    /// The colour channels they were computed for.
    pub channels: ChannelSet,
    /// The channel PSFs through the design and through the bare T-OLED, with their MTFs.
    pub psfs: Arc<PhasePsfs>,
    /// How long the computation took, in milliseconds.
    pub elapsed_ms: f64,
}

/// What a PSF run was started for.
pub(super) struct PsfKey {
    generation: u64,
    /// Preview or thesis sampling.
    pub(super) quality: Quality,
    design: PhaseDesign,
    optics: PhaseOptics,
    channels: ChannelSet,
}

/// What the newest generation was started for (compared in place with the controls each frame).
struct Submitted {
    design: PhaseDesign,
    channels: ChannelSet,
    single_mask: bool,
    angle_deg: f64,
    target: Quality,
}

/// The PSF runs and the PSFs on screen.
#[derive(Default)]
pub(super) struct PsfState {
    /// What the newest generation was started for.
    submitted: Option<Submitted>,
    /// Counts parameter changes: a result of an older generation is stale.
    pub(super) generation: u64,
    /// The PSFs of the newest parameters and the milliseconds they took.
    pub(super) job: Keyed<PsfKey, (PhasePsfs, f64)>,
    /// The PSFs on screen.
    pub(super) shown: Option<ShownPsfs>,
}

impl PhaseWorkspace {
    /// Starts the PSFs of the controls' parameters when they changed since the last start
    /// (compared in place each frame).
    pub(super) fn resubmit_psfs(&mut self, ctx: &egui::Context) {
        let unchanged = self.psf.submitted.as_ref().is_some_and(|s| {
            s.design.same(self.history.current())
                && s.channels == self.channels
                && s.single_mask == self.single_mask
                && s.angle_deg.to_bits() == self.angle_deg.to_bits()
                && s.target == self.quality
        });
        if unchanged {
            return;
        }
        self.psf.submitted = Some(Submitted {
            design: self.history.current().clone(),
            channels: self.channels,
            single_mask: self.single_mask,
            angle_deg: self.angle_deg,
            target: self.quality,
        });
        // Whatever happens next, results of older parameters are stale.
        self.psf.generation += 1;
        // Dropping the running job cancels it.
        self.psf.job.stop();
        if let Err(e) = self.history.current().validate() {
            self.message = Some(Notice::error(e.to_string()));
            return;
        }
        if !(self.angle_deg.is_finite() && self.angle_deg.abs() <= 80.0) {
            self.message = Some(Notice::error(format!(
                "the angle {} ° is outside -80 to 80 °",
                self.angle_deg
            )));
            return;
        }
        if self.message.as_ref().is_some_and(Notice::is_error) {
            self.message = None;
        }
        self.start(Quality::Preview, ctx);
    }

    fn start(&mut self, quality: Quality, ctx: &egui::Context) {
        let Some(sub) = &self.psf.submitted else {
            return;
        };
        let design = sub.design.clone();
        let set = sub.channels;
        let angle = sub.angle_deg;
        let channels = match self.channel_list(set) {
            Ok(c) => c,
            Err(e) => {
                self.message = Some(Notice::error(format!("cannot make the channels: {e}")));
                return;
            }
        };
        self.psf.job.stop();
        let optics = self.optics();
        let wake = ctx.clone();
        let d = design.clone();
        let job = Job::spawn(
            "PSF job",
            move || wake.request_repaint(),
            move |p| {
                let t0 = Instant::now();
                let sampling = PhaseSampling::for_quality(quality);
                let r = phase_psfs(
                    &d,
                    &sampling,
                    &channels,
                    optics,
                    Incidence::AngleDeg(angle),
                    p,
                )?;
                Ok::<_, SimError>((r, t0.elapsed().as_secs_f64() * 1e3))
            },
        );
        self.psf.job.start(
            PsfKey {
                generation: self.psf.generation,
                quality,
                design,
                optics,
                channels: set,
            },
            job,
        );
    }

    /// Cancels the running PSF job; the last result stays.
    pub fn cancel_psfs(&mut self) {
        if self.psf.job.is_running() {
            self.psf.job.stop();
            self.message = Some(Notice::info("PSF run cancelled; the last result stays"));
        }
    }

    /// Takes finished PSFs of the newest parameters; at preview quality, starts the thesis's.
    pub(super) fn poll_psfs(&mut self, ctx: &egui::Context) {
        let Some((job, done)) = self.psf.job.poll() else {
            return;
        };
        match done {
            Ok((psfs, ms)) if job.generation == self.psf.generation => {
                self.psf.shown = Some(ShownPsfs {
                    generation: job.generation,
                    quality: job.quality,
                    design: job.design,
                    optics: job.optics,
                    channels: job.channels,
                    psfs: Arc::new(psfs),
                    elapsed_ms: ms,
                });
                if self.message.as_ref().is_some_and(Notice::is_error) {
                    self.message = None;
                }
                if job.quality == Quality::Preview && self.quality == Quality::Full {
                    self.start(Quality::Full, ctx);
                }
            }
            Ok(_) | Err(JobError::Cancelled) => {}
            Err(e) => self.message = Some(Notice::error(e.to_string())),
        }
    }
}
