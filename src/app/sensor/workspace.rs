//! How the sensor workspace plugs into the studio's shell.

use super::SensorWorkspace;

use crate::app::notice::Notice;
use crate::app::workspace::DroppedKind;

impl crate::app::workspace::Workspace for SensorWorkspace {
    fn id(&self) -> crate::app::WorkspaceId {
        crate::app::WorkspaceId::Sensor
    }

    fn label(&self) -> &'static str {
        "Sensor previewer"
    }

    fn about(&self) -> &'static str {
        "Chapter 5: spatially-varying gain and binning on HDR scenes"
    }

    fn hint(&self) -> &'static str {
        "Ready. Open an HDR scene (.hdr, .exr) or drop one on the window; the four readouts \
         update as you change the light and the maps."
    }

    fn tour(&self) -> &'static [&'static str] {
        &[
            "Open an HDR scene (.hdr or .exr) on the left, or drop one on the window.",
            "Set the exposure and the sensor: the previewer picks a gain and a bin size per \
             region from the local brightness.",
            "Compare captures shows conventional readout against spatially-varying gain and \
             binning, with their SNR and the maps.",
            "Optimal pitch reproduces Fig. 5.3: which pixel size suits which light level.",
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
            ("sensor_controls", Self::controls_ui),
            ("sensor_numbers", Self::numbers_ui),
            Self::views_ui,
        );
    }

    fn file_menu_ui(&mut self, ui: &mut egui::Ui, shell: &crate::app::Shell) {
        if ui
            .add_enabled(self.dialog.is_none(), egui::Button::new("Open HDR scene…"))
            .clicked()
        {
            if shell.native_dialogs {
                self.act(super::SensorAction::AskHdr);
            } else {
                self.message = Some(Notice::error("file dialogs are disabled in this session"));
            }
        }
    }

    /// Carries out what the panels queued: every change of the settings, through the history,
    /// and the pictures and dialogs they ask for.
    fn apply(&mut self, _shell: &mut crate::app::Shell) {
        self.apply_queued();
    }

    /// Undo and redo act on the settings (sensor, exposure, ROI, η, binning, seed).
    fn undo(&mut self) {
        self.act(super::SensorAction::Undo);
    }

    fn redo(&mut self) {
        self.act(super::SensorAction::Redo);
    }

    fn can_undo(&self) -> bool {
        SensorWorkspace::can_undo(self)
    }

    fn can_redo(&self) -> bool {
        SensorWorkspace::can_redo(self)
    }

    fn open_dropped(
        &mut self,
        path: &std::path::Path,
        kind: DroppedKind,
        shell: &mut crate::app::Shell,
    ) -> bool {
        if kind == DroppedKind::HdrScene {
            self.load_scene(path.to_path_buf(), &shell.ctx);
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
