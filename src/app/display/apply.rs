//! Carrying out the display workspace's actions, its file tasks and autosave.

use crate::app::notice::Notice;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::DisplayWorkspace;
use super::action::{DisplayAction, ExportKind};
use super::panels::Pinned;
use super::panels::views::ViewTab;
use crate::app::autosave::create_parent;
use crate::app::dialogs::{PendingDialog, Purpose};
use crate::app::job::{Job, JobError};
use crate::app::workspace::DroppedKind;
use crate::app::workspace::{Shell, WorkspaceId};
use crate::core::Design;
use crate::core::analysis::analyze::Quality;
use crate::core::display::opening_ops;
use crate::io::IoError;
use crate::io::design::{file as design_file, pattern, presets, spectral};
use crate::io::display::{export, report};

impl DisplayWorkspace {
    /// Whether `a` must wait for the unsaved-changes answer; it is then held until
    /// [`crate::app::Workspace::resume`].
    fn needs_confirm(&mut self, a: &DisplayAction, confirmed: bool, shell: &mut Shell) -> bool {
        if !confirmed && self.doc.is_dirty() {
            shell.confirm(WorkspaceId::Display, a.leaving_for());
            self.awaiting = Some(a.clone());
            return true;
        }
        false
    }

    /// Carries out `action` as if its menu item, shortcut or button had been used (asking
    /// first, where it would lose unsaved changes).
    pub fn act(&mut self, action: DisplayAction, shell: &mut Shell) {
        self.apply_one(action, false, shell);
    }

    fn edit_design(&mut self, d: Design) {
        if self.doc.edit(d) {
            self.submit();
        }
    }

    fn edit_cells(&mut self, f: impl FnOnce(&mut Vec<Vec<f64>>)) {
        let mut d = self.doc.design().clone();
        f(&mut d.opening.cells);
        self.edit_design(d);
    }

    fn ask(&mut self, purpose: Purpose, file_name: Option<String>, shell: &mut Shell) {
        if !shell.native_dialogs {
            shell.set_status(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        if self.files.dialog.is_none() {
            let dir = self
                .doc
                .path
                .as_ref()
                .and_then(|p| p.parent())
                .map(PathBuf::from);
            self.files.dialog = Some(PendingDialog::spawn(purpose, dir, file_name));
        }
    }

    fn wake(&self) -> impl Fn() + Send + 'static {
        let ctx = self.egui_ctx.clone();
        move || ctx.request_repaint()
    }

    pub(super) fn apply_one(&mut self, c: DisplayAction, confirmed: bool, shell: &mut Shell) {
        match c {
            DisplayAction::Edit(d) => self.edit_design(*d),
            DisplayAction::SetOptics(optics) => {
                let mut d = self.doc.design().clone();
                d.optics = optics;
                self.edit_design(d);
                shell.set_status(Notice::info("optics changed as advised (Ctrl+Z undoes it)"));
            }
            DisplayAction::New | DisplayAction::LoadPreset(_)
                if self.needs_confirm(&c, confirmed, shell) => {}
            DisplayAction::New => self.load_preset(presets::DEFAULT_PRESET, shell),
            DisplayAction::LoadPreset(name) => self.load_preset(&name, shell),
            DisplayAction::Open if self.needs_confirm(&c, confirmed, shell) => {}
            DisplayAction::Open => self.ask(Purpose::Open, None, shell),
            DisplayAction::OpenPath(_) if self.needs_confirm(&c, confirmed, shell) => {}
            DisplayAction::OpenPath(p) => self.open_path(p),
            DisplayAction::OpenDesign { .. } if self.needs_confirm(&c, confirmed, shell) => {}
            DisplayAction::OpenDesign { design, what } => {
                // Like a preset: a new document with no file (Save asks where), one undo step.
                self.doc.replace(*design, None);
                self.submit();
                shell.set_status(Notice::info(format!("opened {what} (Ctrl+Z goes back)")));
            }
            DisplayAction::NewStudy(field) => self.new_study(field, shell),
            DisplayAction::SweepParameter(field) => {
                let design = self.doc.design().clone();
                self.panels.one_axis_sweep.open(field, design);
            }
            DisplayAction::Save => match self.doc.path.clone() {
                Some(p) => self.save_to(p, shell),
                None => self.apply_one(DisplayAction::SaveAs, confirmed, shell),
            },
            DisplayAction::SaveAs => {
                let name = self
                    .doc
                    .path
                    .as_ref()
                    .and_then(|p| p.file_name())
                    .map(|n| n.to_string_lossy().into_owned());
                self.ask(Purpose::SaveAs, name, shell);
            }
            DisplayAction::ImportPattern => self.ask(Purpose::ImportPattern, None, shell),
            DisplayAction::ImportOpening(p) => self.import_opening(p),
            DisplayAction::LoadSpectral(step) => {
                self.files.spectral_step_nm = step;
                self.ask(Purpose::Spectral, None, shell);
            }
            DisplayAction::Export(kind) => self.ask(Purpose::Export(kind), None, shell),
            DisplayAction::ExportMask => self.panels.mask_export.open(),
            DisplayAction::WriteMask(None) => {
                let format = self.panels.mask_export.options().format;
                self.ask(Purpose::Mask(format), None, shell);
            }
            DisplayAction::WriteMask(Some(path)) => {
                let wake = self.wake();
                let design = self.doc.design().clone();
                self.panels.mask_export.start(&design, path, wake);
            }
            DisplayAction::SetTool(t) => self.tool = t,
            DisplayAction::Invert => self.edit_cells(|c| opening_ops::invert(c)),
            DisplayAction::Clear => self.edit_cells(|c| opening_ops::clear(c)),
            DisplayAction::Copy => {
                self.egui_ctx
                    .copy_text(opening_ops::to_text(&self.doc.design().opening.cells));
                shell.set_status(Notice::info("opening copied as text (# open, . closed)"));
            }
            DisplayAction::Paste(text) => match opening_ops::from_text(&text) {
                Ok(cells) => self.edit_cells(|c| *c = cells),
                Err(e) => shell.set_status(Notice::error(format!("cannot paste an opening: {e}"))),
            },
            DisplayAction::Reroll => {
                let mut d = self.doc.design().clone();
                d.tiling.seed = rand::random::<u32>() as u64;
                if !d.tiling.mode.is_random() {
                    shell.set_status(Notice::info("reroll changes the random tiling's seed; pick Random D4 or Random 4 to see it"));
                }
                self.edit_design(d);
            }
            DisplayAction::PinCompare => self.pin(shell),
            DisplayAction::ClearCompare => {
                self.results.pinned = None;
                self.results.pin_requested = false;
            }
        }
    }

    fn load_preset(&mut self, name: &str, shell: &mut Shell) {
        match presets::load_preset(name) {
            Ok(d) => {
                self.doc.replace(d, None);
                self.submit();
                shell.set_status(Notice::info(format!("preset {name} loaded")));
            }
            Err(e) => shell.set_status(Notice::error(e.to_string())),
        }
    }

    fn pin(&mut self, shell: &mut Shell) {
        match &self.results.shown {
            Some(s) if s.quality == Quality::Full && s.generation == self.worker.generation() => {
                self.results.pinned = Some(Pinned::now(s.design.clone(), s.analysis.clone()));
                shell.set_status(Notice::info(
                    "pinned as A: keep editing, then look at Compare",
                ));
            }
            _ => {
                self.results.pin_requested = true;
                shell.set_status(Notice::info(
                    "will pin as A when the full-quality result is ready",
                ));
            }
        }
    }

    /// Pins `design` (a study point's) as A: analysed at full quality on a job (on the PSFs'
    /// backend), then pinned;
    /// the current design and its results stay as they are.
    pub(super) fn pin_design(&mut self, design: Design, what: String, shell: &mut Shell) {
        shell.set_status(Notice::info(format!(
            "analysing {what} at full quality to pin it as A…"
        )));
        // On the PSFs' backend (View ▸ Compute PSFs on), as the design's own analysis.
        let route = shell.compute.current();
        let job = Job::spawn("pin analysis", self.wake(), move |p| {
            let options = crate::core::analysis::analyze::AnalyzeOptions::default();
            crate::core::analysis::analyze::analyze_with_route(&design, &options, route.as_ref(), p)
                .map(|a| Pinned::now(Arc::new(design), Arc::new(a)))
                .map_err(|e| JobError::Failed(e.to_string()))
        });
        self.results.pin_job = Some((what, job));
    }

    /// Takes a finished pin analysis.
    pub(super) fn poll_pin(&mut self, shell: &mut Shell) {
        let Some(done) = self.results.pin_job.as_ref().and_then(|(_, j)| j.poll()) else {
            return;
        };
        let what = self
            .results
            .pin_job
            .take()
            .map(|(w, _)| w)
            .unwrap_or_default();
        match done {
            Ok(p) => {
                self.results.pinned = Some(p);
                shell.set_status(Notice::info(format!(
                    "pinned {what} as A: Compare shows it against the current design (B)"
                )));
            }
            Err(e) => shell.set_status(Notice::error(format!("cannot pin {what}: {e}"))),
        }
    }

    /// Reads a design file on a background thread; the current design stays until it is valid.
    pub fn open_path(&mut self, path: PathBuf) {
        let p = path.clone();
        let task = Job::spawn("design reader", self.wake(), move |_| {
            design_file::load_design(&p).map(|d| (d, Some(p)))
        });
        self.files.load = Some(task);
    }

    /// Reads an opening (an image, or the axis pixel of a GDSII/DXF mask) on a background
    /// thread; it arrives as one undoable edit of the current design.
    fn import_opening(&mut self, path: PathBuf) {
        let mut design = self.doc.design().clone();
        let task = Job::spawn("opening reader", self.wake(), move |_| {
            let ext = path
                .extension()
                .map(|e| e.to_string_lossy().to_lowercase())
                .unwrap_or_default();
            let cells = if matches!(
                ext.as_str(),
                "gds" | "gds2" | "gdsii" | "oas" | "oasis" | "dxf"
            ) {
                crate::io::mask::import_opening(&path, &design)
            } else {
                pattern::load_pattern_png(&path)
            }?;
            design.opening.cells = cells;
            design.opening.polygons.clear();
            design.reconcile_subpixels();
            Ok::<_, JobError>((design, None))
        });
        self.files.load = Some(task);
    }

    fn save_to(&mut self, path: PathBuf, shell: &mut Shell) {
        let design = self.doc.design().clone();
        match design_file::save_design(&path, &design) {
            // A design file is a few kB: writing it is quicker than a frame.
            Ok(()) => {
                self.doc.mark_saved(path.clone());
                shell.settings.add_recent(&path);
                shell.save_settings();
                shell.set_status(Notice::info(format!("saved {}", path.display())));
            }
            Err(e) => shell.set_status(Notice::error(e.to_string())),
        }
    }

    fn export_to(&mut self, kind: ExportKind, path: PathBuf, shell: &mut Shell) {
        let Some(shown) = self.results.shown.clone() else {
            shell.set_status(Notice::error("nothing to export yet"));
            return;
        };
        let wake = self.wake();
        self.files.writes.spawn(wake, move || {
            let a = &shown.analysis;
            // One dialog, every channel: multi-channel images get the channel name appended.
            let per_channel = |write: fn(
                &std::path::Path,
                &ndarray::Array2<f64>,
            ) -> Result<(), crate::io::IoError>| {
                let mut written = Vec::new();
                for c in &a.channels {
                    let p = if a.channels.len() == 1 {
                        path.clone()
                    } else {
                        crate::io::safe_file::with_stem_suffix(&path, &format!("_{}", c.name))
                    };
                    write(&p, &c.psf).map_err(|e| e.to_string())?;
                    written.push(p.display().to_string());
                }
                Ok(format!("exported {}", written.join(", ")))
            };
            match kind {
                ExportKind::PsfExr => {
                    let done = match a.channels.as_slice() {
                        [r, g, b] => export::write_rgb_psf_exr(&path, [&r.psf, &g.psf, &b.psf]),
                        [one, ..] => export::write_psf_exr(&path, &one.psf),
                        [] => return Err("the result has no channels".to_string()),
                    };
                    done.map(|()| format!("exported {}", path.display()))
                        .map_err(|e| e.to_string())
                }
                ExportKind::PsfPng16 => per_channel(export::write_psf_png16),
                ExportKind::LogPsfPng => per_channel(export::write_log_psf_png),
                ExportKind::MtfCsv => export::write_mtf_csv(&path, a)
                    .map(|()| format!("exported {}", path.display()))
                    .map_err(|e| e.to_string()),
                ExportKind::NumbersJson => {
                    let text =
                        serde_json::to_string_pretty(&report::analysis_json(a)).unwrap_or_default();
                    crate::io::safe_file::write_atomic(&path, text.as_bytes())
                        .map(|()| format!("exported {}", path.display()))
                        .map_err(|e| e.to_string())
                }
            }
        });
    }

    /// Handles finished dialogs and tasks, and autosaves.
    pub(super) fn poll_files(&mut self, shell: &mut Shell) {
        if let Some(answer) = self.files.dialog.as_ref().and_then(PendingDialog::poll) {
            let purpose = self.files.dialog.take().map(|d| d.purpose);
            match (purpose, answer) {
                (Some(purpose), Ok(Some(path))) => self.dialog_done(purpose, path, shell),
                (_, Err(e)) => shell.set_status(Notice::error(e.to_string())),
                _ => {}
            }
        }
        if let Some(done) = self.files.load.as_ref().and_then(|t| t.poll()) {
            self.files.load = None;
            match done {
                Ok((design, Some(p))) => {
                    shell.settings.add_recent(&p);
                    shell.save_settings();
                    shell.set_status(Notice::info(format!("opened {}", p.display())));
                    self.doc.replace(design, Some(p));
                    self.submit();
                }
                // An imported opening: an edit of the current design, not a new document.
                Ok((design, None)) => {
                    self.edit_design(design);
                    shell.set_status(Notice::info("opening imported"));
                }
                Err(e) => shell.set_status(Notice::error(format!("cannot read: {e}"))),
            }
        }
        // Autosaves succeed silently and leave the other messages alone.
        if let Some(report) = self.files.writes.poll() {
            shell.set_status(report);
        }
        match self.panels.mask_export.poll() {
            Some(Ok(lines)) => shell.set_status(Notice::info(lines.join("; "))),
            Some(Err(e)) => shell.set_status(Notice::error(e.to_string())),
            None => {}
        }
        self.autosave_tick(shell);
    }

    fn dialog_done(&mut self, purpose: Purpose, path: PathBuf, shell: &mut Shell) {
        match purpose {
            Purpose::Open => self.open_path(path),
            Purpose::SaveAs => self.save_to(path, shell),
            Purpose::Export(kind) => self.export_to(kind, path, shell),
            Purpose::Mask(_) => self.apply_one(DisplayAction::WriteMask(Some(path)), true, shell),
            Purpose::ImportPattern => self.import_opening(path),
            // The Restore view and the sensor previewer ask and answer their own dialogs.
            Purpose::Photo | Purpose::Hdr => {}
            Purpose::Spectral => {
                let step = self.files.spectral_step_nm.max(1.0);
                match spectral::load_response_csv(&path) {
                    Ok(resp) => {
                        let lo = resp.wavelengths_nm.first().copied().unwrap_or(400.0);
                        let hi = resp.wavelengths_nm.last().copied().unwrap_or(700.0);
                        match spectral::sample_grid(lo, hi, step)
                            .and_then(|samples| spectral::channels_from_response(&resp, &samples))
                        {
                            Ok(ch) => {
                                let mut d = self.doc.design().clone();
                                d.channels = ch;
                                self.edit_design(d);
                            }
                            Err(e) => shell
                                .set_status(Notice::error(format!("{e} (in {})", path.display()))),
                        }
                    }
                    Err(e) => shell.set_status(Notice::error(e.to_string())),
                }
            }
        }
    }

    fn autosave_tick(&mut self, shell: &mut Shell) {
        let every = shell.autosave_every;
        if let Some(e) = self
            .files
            .autosave
            .tick(self.doc.design(), every, &self.egui_ctx)
        {
            shell.set_status(Notice::error(e));
        }
    }

    /// Writes the autosave now (on exit).
    pub fn autosave_now_blocking(&mut self) {
        self.files.autosave.save_now_blocking(self.doc.design());
    }

    /// A file dropped on the window: a design opens, an image or mask becomes the opening,
    /// a photo on the Restore view is its photo, a PSF set opens in the Measured tab; HDR
    /// scenes are not ours.
    pub(super) fn dropped_file(&mut self, p: &Path, kind: DroppedKind, shell: &mut Shell) -> bool {
        match kind {
            DroppedKind::Design => {
                self.apply_one(DisplayAction::OpenPath(p.to_path_buf()), false, shell)
            }
            DroppedKind::Image if self.panels.views.tab() == ViewTab::Restore => self
                .panels
                .views
                .restore
                .load_photo(p.to_path_buf(), &shell.ctx),
            DroppedKind::Image | DroppedKind::Mask => self.import_opening(p.to_path_buf()),
            DroppedKind::PsfSet => {
                self.left_tab = super::LeftTab::Measured;
                self.panels.measured.open(p, &shell.ctx);
            }
            _ => return false,
        }
        true
    }
}

/// The display design's autosave write.
pub(super) fn write_autosave(path: &Path, design: &Design) -> Result<(), IoError> {
    create_parent(path)?;
    design_file::save_design(path, design)
}
