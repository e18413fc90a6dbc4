//! The display workspace's menu entries: its files, its opening edits, presets and Compare.

use super::DisplayWorkspace;
use super::action::{self, DisplayAction, ExportKind};
use crate::app::workspace::Shell;
use crate::core::analysis::analyze::Quality;
use crate::io::design::presets;

impl DisplayWorkspace {
    pub(super) fn file_menu(&mut self, ui: &mut egui::Ui, shell: &Shell) {
        let actions = &mut self.queued;
        let item = |ui: &mut egui::Ui, label: &str, shortcut: Option<&egui::KeyboardShortcut>| {
            let mut b = egui::Button::new(label);
            if let Some(s) = shortcut {
                b = b.shortcut_text(ui.ctx().format_shortcut(s));
            }
            ui.add(b).clicked()
        };
        if item(ui, "New", Some(&action::NEW)) {
            actions.push(DisplayAction::New);
        }
        if item(ui, "Open…", Some(&action::OPEN)) {
            actions.push(DisplayAction::Open);
        }
        ui.menu_button("Open recent", |ui| {
            if shell.settings.recent.is_empty() {
                ui.label("(none yet)");
            }
            for p in &shell.settings.recent {
                if ui.button(p.display().to_string()).clicked() {
                    actions.push(DisplayAction::OpenPath(p.clone()));
                }
            }
        });
        if item(ui, "Save", Some(&action::SAVE)) {
            actions.push(DisplayAction::Save);
        }
        if item(ui, "Save as…", Some(&action::SAVE_AS)) {
            actions.push(DisplayAction::SaveAs);
        }
        ui.separator();
        if item(ui, "Import opening (image, GDSII, OASIS, DXF)…", None) {
            actions.push(DisplayAction::ImportPattern);
        }
        if item(ui, "Export mask…", None) {
            actions.push(DisplayAction::ExportMask);
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
                    actions.push(DisplayAction::Export(kind));
                }
            }
        });
    }

    pub(super) fn edit_menu(&mut self, ui: &mut egui::Ui) {
        let actions = &mut self.queued;
        ui.separator();
        if ui.button("Copy opening").clicked() {
            actions.push(DisplayAction::Copy);
        }
        if ui.button("Invert opening (I)").clicked() {
            actions.push(DisplayAction::Invert);
        }
        if ui.button("Clear opening (Del)").clicked() {
            actions.push(DisplayAction::Clear);
        }
    }

    pub(super) fn extra_menus(&mut self, ui: &mut egui::Ui) {
        let actions = &mut self.queued;
        ui.menu_button("Presets", |ui| {
            let list = presets::list();
            for group in presets::PresetGroup::ALL {
                ui.menu_button(group.label(), |ui| {
                    for (name, _, desc) in list.iter().filter(|p| p.1 == group) {
                        if ui.button(*name).on_hover_text(desc).clicked() {
                            actions.push(DisplayAction::LoadPreset(name.to_string()));
                        }
                    }
                });
            }
        });
        ui.menu_button("Study", |ui| {
            if ui
                .button("New study…")
                .on_hover_text(
                    "Vary this design over DPI, tiling, seeds or any of its numbers in the \
                     Sweep workspace: a results folder that resumes, filled live",
                )
                .clicked()
            {
                actions.push(DisplayAction::NewStudy(None));
            }
        });
        ui.menu_button("Compare", |ui| {
            let pin = egui::Button::new("Pin current design as A")
                .shortcut_text(ui.ctx().format_shortcut(&action::PIN));
            if ui.add(pin).clicked() {
                actions.push(DisplayAction::PinCompare);
            }
            if ui
                .add_enabled(self.results.pinned.is_some(), egui::Button::new("Clear A"))
                .clicked()
            {
                actions.push(DisplayAction::ClearCompare);
            }
        });
    }
}
