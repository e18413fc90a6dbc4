//! How the Sweep workspace plugs into the studio's shell: its layout, File menu entries and
//! dropped folders.

use std::path::Path;

use super::SweepWorkspace;
use crate::app::workspace::{DroppedKind, Request, Shell, Workspace, WorkspaceId};

impl Workspace for SweepWorkspace {
    fn id(&self) -> WorkspaceId {
        WorkspaceId::Sweep
    }

    fn label(&self) -> &'static str {
        "Sweep results"
    }

    fn about(&self) -> &'static str {
        "Issue 19: the table and plots of a `udc-studio sweep` results folder; open any \
         row's design"
    }

    fn hint(&self) -> &'static str {
        "Ready. New study from the current design…, or File > Open sweep results… (a folder \
         written by `udc-studio sweep SPEC --out DIR`), or drop the folder on the window."
    }

    fn tour(&self) -> &'static [&'static str] {
        &[
            "Study > New study… in Display layouts (or New study from the current design… \
             here): pick axes and metrics, see the points and the time it expects, Run. The \
             table and plots fill as the points finish; Cancel and Resume keep every point.",
            "Or run a sweep on the command line: udc-studio sweep SPEC.toml --out DIR.",
            "File > Open sweep results… and choose DIR (or drop it, its sweep.json or its \
             results.csv on the window).",
            "Click a column's header to sort by it (again: the other way); type in Filter to \
             keep rows: random-4, ltr>0.5, seed<3, tiling=repeat.",
            "The plots follow the filter: the spec's plots, then your own (pick x and y; \
             Pareto shows the front of the two).",
            "Open on a row rebuilds its design and opens it in Display layouts (Ctrl+Z there \
             goes back).",
        ]
    }

    fn shortcuts(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }

    fn ui(&mut self, ui: &mut egui::Ui, shell: &mut Shell) {
        // Jobs are taken here, before drawing, so a finished read shows in this frame.
        self.poll(shell);
        self.panels_ui(ui, shell);
        if let Some(run) = self.study_dialog.ui(ui.ctx()) {
            self.start_study(run, shell);
        }
    }

    fn request(&mut self, request: Request, _shell: &mut Shell) {
        if let Request::NewStudy { start, field } = request {
            self.study_dialog.open(*start);
            if let Some(f) = field {
                self.study_dialog.only(f);
            }
        }
    }

    fn file_menu_ui(&mut self, ui: &mut egui::Ui, shell: &Shell) {
        if ui
            .add_enabled(
                self.dialog.is_none(),
                egui::Button::new("Open sweep results…"),
            )
            .on_hover_text("A folder written by udc-studio sweep SPEC --out DIR")
            .clicked()
        {
            self.actions.push(super::SweepAction::AskFolder);
        }
        let last = shell.settings.last_sweep.clone();
        let label = match &last {
            Some(p) => format!("Reopen {}", p.display()),
            None => "Reopen last sweep (none yet)".into(),
        };
        if ui
            .add_enabled(
                last.is_some() && !self.load.is_running(),
                egui::Button::new(label),
            )
            .clicked()
            && let Some(p) = last
        {
            self.actions.push(super::SweepAction::OpenFolder(p));
        }
    }

    /// Carries out what its panels and menus queued.
    fn apply(&mut self, shell: &mut Shell) {
        self.apply_queued(shell);
    }

    /// The results are read-only: nothing to undo.
    fn can_undo(&self) -> bool {
        false
    }

    fn can_redo(&self) -> bool {
        false
    }

    fn open_dropped(&mut self, path: &Path, kind: DroppedKind, shell: &mut Shell) -> bool {
        if kind == DroppedKind::SweepResults {
            self.open_folder(path, shell.waker());
            return true;
        }
        false
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}
