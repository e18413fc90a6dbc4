//! The display mask's design-rule check on a background job, for the panels that show it: a
//! 512-cell random design takes about 0.1 s, several frames' worth, so the UI thread only
//! starts the check and draws its answer.

use crate::app::job::{Answered, Job, JobError};
use crate::core::design::{Design, Opening, Tiling};
use crate::core::mask::drc::{DrcReport, Rules, check};

/// What the check reads of a design: an optics or channel edit does not start a new one.
#[derive(Debug, Clone, PartialEq)]
struct Key {
    opening: Opening,
    tiling: Tiling,
}

impl Key {
    fn of(design: &Design) -> Self {
        Key {
            opening: design.opening.clone(),
            tiling: design.tiling.clone(),
        }
    }

    fn is_of(&self, design: &Design) -> bool {
        self.opening == design.opening && self.tiling == design.tiling
    }
}

/// Where the check of the current design stands.
#[derive(Debug, Clone, Copy)]
pub enum RulesState<'a> {
    /// Running (or about to): nothing to show yet.
    Checking,
    /// Done: the report of the current design.
    Done(&'a DrcReport),
    /// The job stopped without a report; why.
    Failed(&'a JobError),
}

/// One panel's background design-rule check, at the default rules (`udc-studio drc` checks a
/// fab's own).
#[derive(Default)]
pub struct RulesCheck {
    /// The check in flight, and the newest answer with what it is of.
    checks: Answered<Key, DrcReport>,
}

impl RulesCheck {
    /// Collects a finished check and starts one for `design` when its mask changed. Wakes
    /// `ctx` when a check finishes.
    pub fn update(&mut self, ctx: &egui::Context, design: &Design) {
        // A newer design replaces the check in flight (dropping it asks it to stop).
        self.checks.update(
            |k| k.is_of(design),
            || Key::of(design),
            |key| {
                let (opening, tiling) = (key.opening.clone(), key.tiling.clone());
                let ctx = ctx.clone();
                Job::spawn(
                    "design-rule check",
                    move || ctx.request_repaint(),
                    move |_| {
                        let mut d = Design::default_toled();
                        (d.opening, d.tiling) = (opening, tiling);
                        Ok::<_, JobError>(check(&d, &Rules::default()))
                    },
                )
            },
        );
    }

    /// Where the check of `design` stands (as of the last [`RulesCheck::update`]).
    pub fn state(&self, design: &Design) -> RulesState<'_> {
        match self.checks.answer_for(|k| k.is_of(design)) {
            Some(Ok(report)) => RulesState::Done(report),
            Some(Err(e)) => RulesState::Failed(e),
            None => RulesState::Checking,
        }
    }

    /// Whether a check is in flight.
    pub fn is_checking(&self) -> bool {
        self.checks.is_running()
    }
}
