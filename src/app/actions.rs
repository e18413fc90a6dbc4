//! Applying commands, the unsaved-changes prompt, file tasks and autosave.

use crate::app::notice::Notice;
use std::path::PathBuf;
use std::time::Instant;

use super::StudioApp;
use super::commands::{Command, ExportKind};
use super::dialogs::{PendingDialog, Purpose};
use super::job::{Job, JobError};
use super::panels::Pinned;
use super::panels::views::ViewTab;
use crate::core::Design;
use crate::core::analyze::Quality;
use crate::core::opening_ops;
use crate::io::{design_file, export, pattern, presets, report, spectral};

impl StudioApp {
    /// Applies the frame's commands, in order.
    pub(super) fn apply(&mut self, cmds: Vec<Command>) {
        for c in cmds {
            self.apply_one(c, false);
        }
    }

    fn needs_confirm(&mut self, c: &Command, confirmed: bool) -> bool {
        if !confirmed && self.doc.is_dirty() {
            self.session.confirm = Some(c.clone());
            return true;
        }
        false
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

    fn set_status(&mut self, notice: Notice) {
        self.session.status = Some(notice);
        self.session.status_is_simulation_error = false;
    }

    fn ask(&mut self, purpose: Purpose, file_name: Option<String>) {
        if !self.session.native_dialogs {
            self.set_status(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        if self.session.dialog.is_none() {
            let dir = self
                .doc
                .path
                .as_ref()
                .and_then(|p| p.parent())
                .map(PathBuf::from);
            self.session.dialog = Some(PendingDialog::spawn(purpose, dir, file_name));
        }
    }

    fn wake(&self) -> impl Fn() + Send + 'static {
        let ctx = self.egui_ctx.clone();
        move || ctx.request_repaint()
    }

    pub(super) fn apply_one(&mut self, c: Command, confirmed: bool) {
        match c {
            Command::Edit(d) => self.edit_design(*d),
            Command::Undo => {
                if self.doc.undo() {
                    self.submit();
                }
            }
            Command::Redo => {
                if self.doc.redo() {
                    self.submit();
                }
            }
            Command::New | Command::LoadPreset(_) if self.needs_confirm(&c, confirmed) => {}
            Command::New => self.load_preset(presets::DEFAULT_PRESET),
            Command::LoadPreset(name) => self.load_preset(&name),
            Command::Open if self.needs_confirm(&c, confirmed) => {}
            Command::Open => self.ask(Purpose::Open, None),
            Command::OpenPath(_) if self.needs_confirm(&c, confirmed) => {}
            Command::OpenPath(p) => self.open_path(p),
            Command::Save => match self.doc.path.clone() {
                Some(p) => self.save_to(p),
                None => self.apply_one(Command::SaveAs, confirmed),
            },
            Command::SaveAs => {
                let name = self
                    .doc
                    .path
                    .as_ref()
                    .and_then(|p| p.file_name())
                    .map(|n| n.to_string_lossy().into_owned());
                self.ask(Purpose::SaveAs, name);
            }
            Command::ImportPattern => self.ask(Purpose::ImportPattern, None),
            Command::ImportOpening(p) => self.import_opening(p),
            Command::LoadSpectral(step) => {
                self.session.spectral_step_nm = step;
                self.ask(Purpose::Spectral, None);
            }
            Command::Export(kind) => self.ask(Purpose::Export(kind), None),
            Command::ExportMask => self.panels.mask_export.open(),
            Command::WriteMask(None) => {
                let format = self.panels.mask_export.options().format;
                self.ask(Purpose::Mask(format), None);
            }
            Command::WriteMask(Some(path)) => {
                let wake = self.wake();
                let design = self.doc.design().clone();
                self.panels.mask_export.start(&design, path, wake);
            }
            Command::SetTool(t) => self.view.tool = t,
            Command::Invert => self.edit_cells(|c| opening_ops::invert(c)),
            Command::Clear => self.edit_cells(|c| opening_ops::clear(c)),
            Command::Copy => {
                self.egui_ctx
                    .copy_text(opening_ops::to_text(&self.doc.design().opening.cells));
                self.set_status(Notice::info("opening copied as text (# open, . closed)"));
            }
            Command::Paste(text) => match opening_ops::from_text(&text) {
                Ok(cells) => self.edit_cells(|c| *c = cells),
                Err(e) => self.set_status(Notice::error(format!("cannot paste an opening: {e}"))),
            },
            Command::Reroll => {
                let mut d = self.doc.design().clone();
                d.tiling.seed = rand::random::<u32>() as u64;
                if !d.tiling.mode.is_random() {
                    self.set_status(Notice::info("reroll changes the random tiling's seed; pick Random D4 or Random 4 to see it"));
                }
                self.edit_design(d);
            }
            Command::PinCompare => self.pin(),
            Command::ClearCompare => {
                self.results.pinned = None;
                self.results.pin_requested = false;
            }
            Command::ToggleTheme => {
                self.view.settings.dark = !self.view.settings.dark;
                let v = if self.view.settings.dark {
                    egui::Visuals::dark()
                } else {
                    egui::Visuals::light()
                };
                self.egui_ctx.set_visuals(v);
                self.save_settings();
            }
            Command::ToggleOverlays => {
                self.view.settings.overlays = !self.view.settings.overlays;
                self.save_settings();
            }
            Command::Quit if self.needs_confirm(&c, confirmed) => {}
            Command::Quit => {
                self.session.quit_confirmed = true;
                self.egui_ctx
                    .send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    fn save_settings(&mut self) {
        if let Err(e) = self.view.settings.save(&self.session.dirs) {
            self.set_status(Notice::error(format!("cannot save settings: {e}")));
        }
    }

    fn load_preset(&mut self, name: &str) {
        match presets::load_preset(name) {
            Ok(d) => {
                self.doc.replace(d, None);
                self.submit();
                self.set_status(Notice::info(format!("preset {name} loaded")));
            }
            Err(e) => self.set_status(Notice::error(e.to_string())),
        }
    }

    fn pin(&mut self) {
        match &self.results.shown {
            Some(s) if s.quality == Quality::Full && s.generation == self.worker.generation() => {
                self.results.pinned = Some(Pinned {
                    design: s.design.clone(),
                    analysis: s.analysis.clone(),
                });
                self.set_status(Notice::info(
                    "pinned as A: keep editing, then look at Compare",
                ));
            }
            _ => {
                self.results.pin_requested = true;
                self.set_status(Notice::info(
                    "will pin as A when the full-quality result is ready",
                ));
            }
        }
    }

    /// The Export-mask dialog (its options and whether an export runs).
    pub fn mask_export(&self) -> &super::panels::mask_export::MaskExportDialog {
        &self.panels.mask_export
    }

    /// Reads a design file on a background thread; the current design stays until it is valid.
    pub fn open_path(&mut self, path: PathBuf) {
        let p = path.clone();
        let task = Job::spawn("design reader", self.wake(), move |_| {
            design_file::load_design(&p).map(|d| (d, Some(p)))
        });
        self.session.load = Some(task);
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
            let cells = if matches!(ext.as_str(), "gds" | "gds2" | "gdsii" | "dxf") {
                crate::io::mask::import_opening(&path, &design)
            } else {
                pattern::load_pattern_png(&path)
            }?;
            design.opening.cells = cells;
            design.opening.polygons.clear();
            Ok::<_, JobError>((design, None))
        });
        self.session.load = Some(task);
    }

    fn save_to(&mut self, path: PathBuf) {
        let design = self.doc.design().clone();
        match design_file::save_design(&path, &design) {
            // A design file is a few kB: writing it is quicker than a frame.
            Ok(()) => {
                self.doc.mark_saved(path.clone());
                self.view.settings.add_recent(&path);
                self.save_settings();
                self.set_status(Notice::info(format!("saved {}", path.display())));
            }
            Err(e) => self.set_status(Notice::error(e.to_string())),
        }
    }

    fn export_to(&mut self, kind: ExportKind, path: PathBuf) {
        let Some(shown) = self.results.shown.clone() else {
            self.set_status(Notice::error("nothing to export yet"));
            return;
        };
        let wake = self.wake();
        self.session.writes.spawn(wake, move || {
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
    pub(super) fn poll_session(&mut self) {
        if let Some(answer) = self.session.dialog.as_ref().and_then(PendingDialog::poll) {
            let purpose = self.session.dialog.take().map(|d| d.purpose);
            if let (Some(purpose), Some(path)) = (purpose, answer) {
                self.dialog_done(purpose, path);
            }
        }
        if let Some(done) = self.session.load.as_ref().and_then(|t| t.poll()) {
            self.session.load = None;
            match done {
                Ok((design, Some(p))) => {
                    self.view.settings.add_recent(&p);
                    self.save_settings();
                    self.set_status(Notice::info(format!("opened {}", p.display())));
                    self.doc.replace(design, Some(p));
                    self.submit();
                }
                // An imported opening: an edit of the current design, not a new document.
                Ok((design, None)) => {
                    self.edit_design(design);
                    self.set_status(Notice::info("opening imported"));
                }
                Err(e) => self.set_status(Notice::error(format!("cannot read: {e}"))),
            }
        }
        // Autosaves succeed silently and leave the other messages alone.
        if let Some(report) = self.session.writes.poll() {
            self.set_status(report);
        }
        match self.panels.mask_export.poll() {
            Some(Ok(lines)) => self.set_status(Notice::info(lines.join("; "))),
            Some(Err(e)) => self.set_status(Notice::error(e)),
            None => {}
        }
        self.autosave_tick();
    }

    fn dialog_done(&mut self, purpose: Purpose, path: PathBuf) {
        match purpose {
            Purpose::Open => self.open_path(path),
            Purpose::SaveAs => self.save_to(path),
            Purpose::Export(kind) => self.export_to(kind, path),
            Purpose::Mask(_) => self.apply_one(Command::WriteMask(Some(path)), true),
            Purpose::ImportPattern => self.import_opening(path),
            Purpose::Photo => self
                .panels
                .views
                .restore
                .load_photo(path, &self.egui_ctx.clone()),
            Purpose::Hdr => self.sensor.load_scene(path, &self.egui_ctx.clone()),
            Purpose::Spectral => {
                let step = self.session.spectral_step_nm.max(1.0);
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
                            Err(e) => self
                                .set_status(Notice::error(format!("{e} (in {})", path.display()))),
                        }
                    }
                    Err(e) => self.set_status(Notice::error(e.to_string())),
                }
            }
        }
    }

    fn autosave_tick(&mut self) {
        let changed = self.session.autosaved.as_ref() != Some(self.doc.design());
        if !changed {
            return;
        }
        let due = self.session.last_autosave + self.session.autosave_every;
        let now = Instant::now();
        if now < due {
            self.egui_ctx.request_repaint_after(due - now);
            return;
        }
        let Some(path) = self.session.dirs.autosave_path() else {
            return;
        };
        let design = self.doc.design().clone();
        self.session.autosaved = Some(design.clone());
        self.session.last_autosave = now;
        let wake = self.wake();
        self.session.writes.spawn(wake, move || {
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir).map_err(|e| format!("autosave failed: {e}"))?;
            }
            design_file::save_design(&path, &design)
                .map(|()| String::new())
                .map_err(|e| format!("autosave failed: {e}"))
        });
    }

    /// Writes the autosave now (on exit).
    pub fn autosave_now_blocking(&mut self) {
        if let Some(path) = self.session.dirs.autosave_path() {
            if let Some(dir) = path.parent() {
                let _ = std::fs::create_dir_all(dir);
            }
            if design_file::save_design(&path, self.doc.design()).is_ok() {
                self.session.autosaved = Some(self.doc.design().clone());
            }
        }
    }

    /// Files dropped on the window: designs open, images become the opening.
    pub(super) fn dropped_files(&mut self, ctx: &egui::Context, cmds: &mut Vec<Command>) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        for p in dropped {
            let ext = p
                .extension()
                .map(|e| e.to_string_lossy().to_lowercase())
                .unwrap_or_default();
            let photo_ext = matches!(ext.as_str(), "png" | "jpg" | "jpeg");
            if ext == "json" {
                cmds.push(Command::OpenPath(p));
            } else if ext == "hdr" || ext == "exr" {
                // An HDR scene only makes sense to the sensor previewer.
                self.sensor.load_scene(p, ctx);
                self.view.workspace = super::Workspace::Sensor;
            } else if photo_ext && self.panels.views.tab() == ViewTab::Restore {
                // On the Restore view a dropped picture is a photo, elsewhere an opening.
                self.panels.views.restore.load_photo(p, ctx);
            } else {
                cmds.push(Command::ImportOpening(p));
            }
        }
    }

    /// The window's close button asks first when there are unsaved changes.
    pub(super) fn close_request(&mut self, ctx: &egui::Context, cmds: &mut Vec<Command>) {
        if ctx.input(|i| i.viewport().close_requested())
            && !self.session.quit_confirmed
            && self.doc.is_dirty()
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            cmds.push(Command::Quit);
        }
    }

    /// The unsaved-changes prompt.
    pub(super) fn confirm_ui(&mut self, ctx: &egui::Context, _cmds: &mut [Command]) {
        let Some(pending) = self.session.confirm.clone() else {
            return;
        };
        let what = match &pending {
            Command::Quit => "quitting",
            Command::New => "starting a new design",
            Command::LoadPreset(_) => "loading the preset",
            _ => "opening another design",
        };
        let mut choice = None;
        egui::Modal::new(egui::Id::unique("unsaved-changes")).show(ctx, |ui| {
            ui.heading("Unsaved changes");
            ui.label(format!(
                "\"{}\" has changes that are not saved to a file. They stay in the autosave and in undo, \
                 but save them before {what}?",
                self.doc.design().name
            ));
            ui.horizontal(|ui| {
                if self.doc.path.is_some() && ui.button("Save").clicked() {
                    choice = Some(UnsavedChoice::Save);
                }
                if ui.button("Discard changes").clicked() {
                    choice = Some(UnsavedChoice::Discard);
                }
                if ui.button("Cancel").clicked() || ui.input(|i| i.key_pressed(egui::Key::Escape)) {
                    choice = Some(UnsavedChoice::Cancel);
                }
            });
        });
        match choice {
            Some(UnsavedChoice::Save) => {
                self.session.confirm = None;
                self.apply_one(Command::Save, true);
                if !self.doc.is_dirty() {
                    self.apply_one(pending, true);
                }
            }
            Some(UnsavedChoice::Discard) => {
                self.session.confirm = None;
                self.apply_one(pending, true);
            }
            Some(UnsavedChoice::Cancel) => self.session.confirm = None,
            None => {}
        }
    }
}

/// The answers of the unsaved-changes prompt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum UnsavedChoice {
    Save,
    Discard,
    Cancel,
}
