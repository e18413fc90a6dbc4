//! The design-rule check of the file the Export-mask dialog would write (its region cut, tone
//! chosen, border redrawn, frame added), on a background job: the check `export --strict` and
//! `udc-studio drc FILE` run. A whole pupil of a random design takes a second or more, so the UI
//! thread only starts the check and draws its answer.

use crate::app::job::{Job, JobError, Keyed};
use crate::core::Progress;
use crate::core::design::Design;
use crate::io::mask::{ExportOptions, RulesCheck, check_written, frame_drawing, plan};

/// What the check reads: the design and the export's options.
#[derive(Debug, Clone, PartialEq)]
struct Key {
    design: Design,
    options: ExportOptions,
}

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
    running: Keyed<Key, RulesCheck>,
    done: Option<(Key, Result<RulesCheck, JobError>)>,
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
        if let Some((key, result)) = self.running.poll() {
            self.done = Some((key, result));
        }
        let is_now = |k: &Key| &k.design == design && &k.options == options;
        let answered = self.done.as_ref().is_some_and(|(k, _)| is_now(k));
        if answered || self.running.is_running_for(is_now) {
            return;
        }
        let key = Key {
            design: design.clone(),
            options: options.clone(),
        };
        let (d, o) = (key.design.clone(), key.options.clone());
        let wake = {
            let ctx = ctx.clone();
            move || ctx.request_repaint()
        };
        // A newer key replaces the check in flight (dropping it asks it to stop).
        let job = Job::spawn("written-mask check", wake, move |p| check_export(&d, &o, p));
        self.running.start(key, job);
    }

    /// Where the check of `design` under `options` stands.
    pub fn state(&self, design: &Design, options: &ExportOptions) -> WrittenState<'_> {
        match &self.done {
            Some((k, result)) if &k.design == design && &k.options == options => match result {
                Ok(check) => WrittenState::Done(check),
                Err(e) => WrittenState::Failed(e),
            },
            _ => WrittenState::Checking(self.running.job().map_or(0.0, Job::fraction)),
        }
    }

    /// Whether a check is in flight.
    pub fn is_checking(&self) -> bool {
        self.running.is_running()
    }
}
