//! Keeping the phase design between runs: `phase-design.json` in the studio's data directory,
//! written off the UI thread a few seconds after a change and on exit.

use crate::app::notice::Notice;
use std::path::Path;
use std::time::Instant;

use super::{PhaseWorkspace, same};
use crate::app::job::Job;
use crate::core::phase::PhaseDesign;
use crate::io::phase_design::{load_phase_design, save_phase_design};

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
    /// Saves the committed design now (on exit).
    pub fn save_now_blocking(&mut self) {
        if let Some(path) = &self.design_path
            && self.committed.validate().is_ok()
            && write_design(path, &self.committed).is_ok()
        {
            self.saved = self.committed.clone();
        }
    }

    pub(super) fn autosave_tick(&mut self, ctx: &egui::Context) {
        if let Some(done) = self.save_task.as_ref().and_then(Job::poll) {
            self.save_task = None;
            if let Err(e) = done {
                self.message = Some(Notice::error(e.to_string()));
            }
        }
        let Some(path) = self.design_path.clone() else {
            return;
        };
        if self.save_task.is_some()
            || same(&self.saved, &self.committed)
            || self.committed.validate().is_err()
        {
            return;
        }
        let due = self.last_save + self.autosave_every;
        let now = Instant::now();
        if now < due {
            ctx.request_repaint_after(due - now);
            return;
        }
        self.saved = self.committed.clone();
        self.last_save = now;
        let design = self.committed.clone();
        let wake = ctx.clone();
        self.save_task = Some(Job::spawn(
            "phase autosave",
            move || wake.request_repaint(),
            move |_| write_design(&path, &design),
        ));
    }
}

fn write_design(path: &std::path::Path, design: &PhaseDesign) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    save_phase_design(path, design).map_err(|e| format!("cannot save the phase design: {e}"))
}
