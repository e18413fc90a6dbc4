//! How the phase-mask workspace plugs into the studio's shell.

use super::PhaseWorkspace;
use crate::app::workspace::DroppedKind;

impl crate::app::workspace::Workspace for PhaseWorkspace {
    fn id(&self) -> crate::app::WorkspaceId {
        crate::app::WorkspaceId::Phase
    }

    fn label(&self) -> &'static str {
        "Phase masks"
    }

    fn about(&self) -> &'static str {
        "Chapter 4: folded double microlens arrays around a T-OLED"
    }

    fn hint(&self) -> &'static str {
        "Ready. Set the pitch, fold and λ0 plan on the left; the PSFs update live. Run the \
         optimizer for a λ0 plan against chromatic aberration."
    }

    fn tour(&self) -> &'static [&'static str] {
        &[
            "The left sets the two microlens arrays: pitch, focal length, fold thickness T and \
             each lenslet's folding wavelength λ0.",
            "The centre shows the PSFs and MTFs of the masks against the bare T-OLED (dashed); \
             the right lists their light and sharpness.",
            "V matrix and optimizer chooses λ0 per lenslet against chromatic aberration \
             (Algorithm 1); Apply makes it the plan.",
            "Capture & restore sends a photo through the masks; Export the plate writes CSV, \
             PNG, GDSII or STL.",
            "Study > New study… varies this design's fold, λ0 plan or pitch in the Sweep \
             workspace; Open on a row brings a point back here.",
        ]
    }

    fn shortcuts(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }

    fn ui(&mut self, ui: &mut egui::Ui, _shell: &mut crate::app::Shell) {
        // Jobs are taken here, not in a panel: a tab that is not shown is not drawn.
        let ctx = ui.ctx().clone();
        self.poll(&ctx);
        crate::app::workspace::three_panels(
            self,
            ui,
            ("phase_controls", Self::controls_ui),
            ("phase_numbers", Self::numbers_ui),
            Self::views_ui,
        );
    }

    /// Carries out what the panels queued: every change of the design, through the history.
    fn apply(&mut self, shell: &mut crate::app::Shell) {
        self.apply_queued();
        self.send_study(shell);
    }

    fn menus_ui(&mut self, ui: &mut egui::Ui) {
        ui.menu_button("Study", |ui| {
            if ui
                .button("New study…")
                .on_hover_text(
                    "Vary this design's fold, λ0 plan or pitch and record its numbers at \
                     every combination (the Sweep workspace runs it)",
                )
                .clicked()
            {
                self.ask_study();
                ui.close();
            }
        });
    }

    /// A study point's design opens here as one undo step.
    fn request(&mut self, request: crate::app::workspace::Request, shell: &mut crate::app::Shell) {
        if let crate::app::workspace::Request::OpenPhaseDesign { design, what } = request {
            self.set_design(*design);
            shell.set_status(crate::app::notice::Notice::info(format!(
                "opened {what} (Ctrl+Z goes back)"
            )));
        }
    }

    /// Undo and redo act on the phase parameters.
    fn undo(&mut self) {
        PhaseWorkspace::undo(self);
    }

    fn redo(&mut self) {
        PhaseWorkspace::redo(self);
    }

    fn can_undo(&self) -> bool {
        PhaseWorkspace::can_undo(self)
    }

    fn can_redo(&self) -> bool {
        PhaseWorkspace::can_redo(self)
    }

    fn save_now_blocking(&mut self) {
        PhaseWorkspace::save_now_blocking(self);
    }

    /// Photos go to the capture view, CSV files become the sensor response; anything else is
    /// left to the other workspaces (a design `.json` to the display, an HDR to the sensor).
    fn open_dropped(
        &mut self,
        path: &std::path::Path,
        kind: DroppedKind,
        shell: &mut crate::app::Shell,
    ) -> bool {
        match kind {
            DroppedKind::Image => {
                self.show(super::PhaseView::Capture);
                self.load_capture_photo(path.to_path_buf(), &shell.ctx);
                true
            }
            DroppedKind::Table => {
                self.load_response_from(path.to_path_buf(), &shell.ctx);
                true
            }
            _ => false,
        }
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}
