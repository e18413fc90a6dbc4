//! Keeping the phase design between runs: `phase-design.json` in the studio's data directory,
//! written off the UI thread a few seconds after a change and on exit.

use crate::app::notice::Notice;
use std::path::Path;

use super::PhaseWorkspace;
use crate::app::autosave::create_parent;
use crate::core::phase::PhaseDesign;
use crate::io::IoError;
use crate::io::phase::design::{load_phase_design, save_phase_design};

/// The design kept at `path`, or the thesis's and a message when it cannot be read.
pub(super) fn load_design(path: Option<&Path>) -> (PhaseDesign, Option<Notice>) {
    let Some(p) = path.filter(|p| p.exists()) else {
        return (PhaseDesign::thesis(42.0, 1.0), None);
    };
    match load_phase_design(p) {
        Ok(loaded) => {
            let note = (!loaded.notes.is_empty()).then(|| Notice::info(loaded.notes.join("; ")));
            (loaded.design, note)
        }
        Err(e) => {
            // Kept aside: the next autosave would otherwise overwrite it.
            let kept = match crate::io::safe_file::keep_aside(p) {
                Ok(aside) => format!(
                    "kept it as {} beside it",
                    aside.file_name().unwrap_or_default().to_string_lossy()
                ),
                Err(e) => format!("it stays where it was ({e})"),
            };
            (
                PhaseDesign::thesis(42.0, 1.0),
                Some(Notice::error(format!(
                    "could not restore the phase design ({e}); {kept}; using the thesis's"
                ))),
            )
        }
    }
}

impl PhaseWorkspace {
    /// Saves the committed design now (on exit), when it is valid.
    pub fn save_now_blocking(&mut self) {
        let design = self.history.committed();
        if design.validate().is_ok() {
            self.autosave.save_now_blocking(design);
        }
    }

    /// Autosaves the committed design (never half a drag, never an invalid design) a few
    /// seconds after it changed.
    pub(super) fn autosave_tick(&mut self, ctx: &egui::Context) {
        let design = self.history.committed();
        if design.validate().is_err() {
            return;
        }
        if let Some(e) = self.autosave.tick(design, self.autosave_every, ctx) {
            self.message = Some(Notice::error(e));
        }
    }
}

/// Writes the phase design kept between runs.
pub(super) fn write_design(path: &Path, design: &PhaseDesign) -> Result<(), IoError> {
    create_parent(path)?;
    save_phase_design(path, design)
}
