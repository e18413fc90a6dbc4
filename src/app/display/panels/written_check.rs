//! The design-rule check of the file the Export-mask dialog would write (its region cut, tone
//! chosen, border redrawn, frame added), on a background job: the check `export --strict` and
//! `udc-studio drc FILE` run. A whole pupil of a random design takes a second or more, so the UI
//! thread only starts the check and draws its answer.

use super::mask_preview::{ExportKey, ask};
use crate::app::job::{Answered, Job, JobError};
use crate::core::Progress;
use crate::core::design::Design;
use crate::io::mask::{ExportOptions, RulesCheck, check_written, frame_drawing, plan};

/// Where the check of the file to be written stands.
#[derive(Debug, Clone, Copy)]
pub enum WrittenState<'a> {
    /// Running: its progress in `[0, 1]`.
    Checking(f32),
    /// Done.
    Done(&'a RulesCheck),
    /// The check stopped without a report (a layout the options cannot make); why.
    Failed(&'a JobError),
}

/// The dialog's background check of the written geometry.
#[derive(Default)]
pub struct WrittenCheck {
    /// The check in flight, and the newest answer with what it is of.
    checks: Answered<ExportKey, RulesCheck>,
}

/// Lays out `design` as `options` say and checks what would be written.
///
/// # Errors
/// A layout or frame the options cannot make, or a cancel.
pub fn check_export(
    design: &Design,
    options: &ExportOptions,
    progress: &Progress,
) -> Result<RulesCheck, JobError> {
    let o = options.resolved(design).map_err(|e| e.to_string())?;
    let layout = plan(design, &o).map_err(crate::io::IoError::from)?;
    let frame = frame_drawing(&layout, &o, &design.name).map_err(crate::io::IoError::from)?;
    Ok(check_written(design, &layout, &o, &frame, progress)?)
}

impl WrittenCheck {
    /// Collects a finished check and starts one when the design or the options changed.
    pub fn update(&mut self, ctx: &egui::Context, design: &Design, options: &ExportOptions) {
        ask(
            &mut self.checks,
            ctx,
            (design, options),
            "written-mask check",
            check_export,
        );
    }

    /// Where the check of `design` under `options` stands.
    pub fn state(&self, design: &Design, options: &ExportOptions) -> WrittenState<'_> {
        match self.checks.answer_for(|k| k.is_of(design, options)) {
            Some(Ok(check)) => WrittenState::Done(check),
            Some(Err(e)) => WrittenState::Failed(e),
            None => WrittenState::Checking(self.checks.job().map_or(0.0, Job::fraction)),
        }
    }

    /// Whether a check is in flight.
    pub fn is_checking(&self) -> bool {
        self.checks.is_running()
    }
}
