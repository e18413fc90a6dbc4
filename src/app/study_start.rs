//! What New study… is opened with, as one workspace sends it to the Sweep workspace: the
//! design, its times on screen and the Restore view's settings and photo.

use std::sync::Arc;

use crate::app::widgets::photo::Photo;
use crate::core::Design;
use crate::core::phase::PhaseDesign;
use crate::core::sweep::study::{RestoreSetup, StudySubject, StudyTimes};

/// What New study… is opened with: the design, how long it took on screen, and, for a
/// display design, the Restore view's settings and photo (a study that restores uses them).
#[derive(Debug, Clone)]
pub struct StudyStart {
    /// The design to vary.
    pub subject: StudySubject,
    /// Its times on screen, to scale the estimate.
    pub times: StudyTimes,
    /// The Restore view's settings.
    pub restore: RestoreSetup,
    /// The Restore view's photo (`None`: the built-in one).
    pub photo: Option<Arc<Photo>>,
}

impl StudyStart {
    /// A study of `design` with nothing on screen yet.
    pub fn display(design: Design) -> StudyStart {
        StudyStart {
            subject: StudySubject::Display(Box::new(design)),
            times: StudyTimes::default(),
            restore: RestoreSetup::default(),
            photo: None,
        }
    }

    /// A study of the phase-mask `design` with nothing on screen yet.
    pub fn phase(design: PhaseDesign) -> StudyStart {
        StudyStart {
            subject: StudySubject::Phase(Box::new(design)),
            ..StudyStart::display(Design::default_toled())
        }
    }
}
