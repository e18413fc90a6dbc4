//! The display workspace's menu entries: its files, its opening edits, presets and Compare.

use super::DisplayWorkspace;
use crate::app::commands::{self, Command, ExportKind};
use crate::app::workspace::Shell;
use crate::core::analysis::analyze::Quality;
use crate::io::presets;

impl DisplayWorkspace {
    pub(super) fn file_menu(&mut self, ui: &mut egui::Ui, shell: &Shell, cmds: &mut Vec<Command>) {
        let item = |ui: &mut egui::Ui, label: &str, shortcut: Option<&egui::KeyboardShortcut>| {
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
            if shell.settings.recent.is_empty() {
                ui.label("(none yet)");
            }
            for p in &shell.settings.recent {
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
        if item(ui, "Import opening (image, GDSII, OASIS, DXF)…", None) {
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
    }

    pub(super) fn edit_menu(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
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
    }

    pub(super) fn extra_menus(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        ui.menu_button("Presets", |ui| {
            let list = presets::list();
            for group in presets::PresetGroup::ALL {
                ui.menu_button(group.label(), |ui| {
                    for (name, _, desc) in list.iter().filter(|p| p.1 == group) {
                        if ui.button(*name).on_hover_text(desc).clicked() {
                            cmds.push(Command::LoadPreset(name.to_string()));
                        }
                    }
                });
            }
        });
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
    }
}
