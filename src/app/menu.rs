//! The menu bar: File, Edit, Presets, View and the workspace switch.

use super::*;

impl StudioApp {
    pub(super) fn menu_ui(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                let item =
                    |ui: &mut egui::Ui, label: &str, shortcut: Option<&egui::KeyboardShortcut>| {
                        let mut b = egui::Button::new(label);
                        if let Some(s) = shortcut {
                            b = b.shortcut_text(ui.ctx().format_shortcut(s));
                        }
                        ui.add(b).clicked()
                    };
                if item(ui, "New", Some(&commands::NEW)) {
                    cmds.push(Command::New);
                }
                if item(ui, "Open…", Some(&commands::OPEN)) {
                    cmds.push(Command::Open);
                }
                ui.menu_button("Open recent", |ui| {
                    if self.view.settings.recent.is_empty() {
                        ui.label("(none yet)");
                    }
                    for p in &self.view.settings.recent {
                        if ui.button(p.display().to_string()).clicked() {
                            cmds.push(Command::OpenPath(p.clone()));
                        }
                    }
                });
                if item(ui, "Save", Some(&commands::SAVE)) {
                    cmds.push(Command::Save);
                }
                if item(ui, "Save as…", Some(&commands::SAVE_AS)) {
                    cmds.push(Command::SaveAs);
                }
                ui.separator();
                if item(ui, "Import opening (image, GDSII, DXF)…", None) {
                    cmds.push(Command::ImportPattern);
                }
                if item(ui, "Export mask…", None) {
                    cmds.push(Command::ExportMask);
                }
                ui.menu_button("Export", |ui| {
                    let full = self
                        .results
                        .shown
                        .as_ref()
                        .is_some_and(|s| s.quality == Quality::Full);
                    for kind in ExportKind::ALL {
                        if ui
                            .add_enabled(full, egui::Button::new(kind.label()))
                            .clicked()
                        {
                            cmds.push(Command::Export(kind));
                        }
                    }
                });
                ui.separator();
                if item(ui, "Quit", Some(&commands::QUIT)) {
                    cmds.push(Command::Quit);
                }
            });
            ui.menu_button("Edit", |ui| {
                let undo = egui::Button::new("Undo")
                    .shortcut_text(ui.ctx().format_shortcut(&commands::UNDO));
                if ui.add_enabled(self.doc.can_undo(), undo).clicked() {
                    cmds.push(Command::Undo);
                }
                let redo = egui::Button::new("Redo")
                    .shortcut_text(ui.ctx().format_shortcut(&commands::REDO));
                if ui.add_enabled(self.doc.can_redo(), redo).clicked() {
                    cmds.push(Command::Redo);
                }
                ui.separator();
                if ui.button("Copy opening").clicked() {
                    cmds.push(Command::Copy);
                }
                if ui.button("Invert opening (I)").clicked() {
                    cmds.push(Command::Invert);
                }
                if ui.button("Clear opening (Del)").clicked() {
                    cmds.push(Command::Clear);
                }
            });
            ui.menu_button("Presets", |ui| {
                for (name, desc) in presets::list() {
                    if ui.button(name).on_hover_text(desc).clicked() {
                        cmds.push(Command::LoadPreset(name.to_string()));
                    }
                }
            });
            ui.menu_button("View", |ui| {
                let theme = if self.view.settings.dark {
                    "Light theme"
                } else {
                    "Dark theme"
                };
                if ui.button(theme).clicked() {
                    cmds.push(Command::ToggleTheme);
                }
                let mut overlays = self.view.settings.overlays;
                if ui
                    .checkbox(&mut overlays, "Teaching overlays and hints")
                    .clicked()
                {
                    cmds.push(Command::ToggleOverlays);
                }
            });
            ui.separator();
            ui.selectable_value(
                &mut self.view.workspace,
                Workspace::Display,
                "Display layouts",
            )
            .on_hover_text("Chapter 3: draw, tile, analyse, restore, optimize");
            ui.selectable_value(&mut self.view.workspace, Workspace::Phase, "Phase masks")
                .on_hover_text("Chapter 4: folded double microlens arrays around a T-OLED");
            ui.selectable_value(
                &mut self.view.workspace,
                Workspace::Sensor,
                "Sensor previewer",
            )
            .on_hover_text("Chapter 5: spatially-varying gain and binning on HDR scenes");
            ui.separator();
            ui.menu_button("Compare", |ui| {
                let pin = egui::Button::new("Pin current design as A")
                    .shortcut_text(ui.ctx().format_shortcut(&commands::PIN));
                if ui.add(pin).clicked() {
                    cmds.push(Command::PinCompare);
                }
                if ui
                    .add_enabled(self.results.pinned.is_some(), egui::Button::new("Clear A"))
                    .clicked()
                {
                    cmds.push(Command::ClearCompare);
                }
            });
        });
    }
}
