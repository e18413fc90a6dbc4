//! The menu bar: File, Edit and the active workspace's menus, View, Help and the workspace
//! switch. The workspaces fill in their own entries.

use super::*;

impl StudioApp {
    pub(super) fn menu_ui(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        let active = self.active;
        let labels = switch_labels(&self.workspaces);
        let shell = &mut self.shell;
        let Some(ws) = self.workspaces.iter_mut().find(|w| w.id() == active) else {
            return;
        };
        let mut switch = None;
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                ws.file_menu_ui(ui, shell, cmds);
                ui.separator();
                let quit = egui::Button::new("Quit")
                    .shortcut_text(ui.ctx().format_shortcut(&commands::QUIT));
                if ui.add(quit).clicked() {
                    cmds.push(Command::Quit);
                }
            });
            ui.menu_button("Edit", |ui| {
                let undo = egui::Button::new("Undo")
                    .shortcut_text(ui.ctx().format_shortcut(&commands::UNDO));
                if ui.add_enabled(ws.can_undo(), undo).clicked() {
                    cmds.push(Command::Undo);
                }
                let redo = egui::Button::new("Redo")
                    .shortcut_text(ui.ctx().format_shortcut(&commands::REDO));
                if ui.add_enabled(ws.can_redo(), redo).clicked() {
                    cmds.push(Command::Redo);
                }
                ws.edit_menu_ui(ui, cmds);
            });
            ws.menus_ui(ui, cmds);
            ui.menu_button("View", |ui| {
                let theme = if shell.settings.dark {
                    "Light theme"
                } else {
                    "Dark theme"
                };
                if ui.button(theme).clicked() {
                    cmds.push(Command::ToggleTheme);
                }
                let mut overlays = shell.settings.overlays;
                if ui
                    .checkbox(&mut overlays, "Teaching overlays and hints")
                    .clicked()
                {
                    cmds.push(Command::ToggleOverlays);
                }
                let mut rules = shell.settings.design_rules;
                if ui
                    .checkbox(&mut rules, "Design rules on the editor")
                    .on_hover_text(
                        "Red rings on the opening editor where the opening breaks the default \
                         design rules (2-µm features and gaps, no corner contacts); hover a \
                         ring for the rule, the value and the limit",
                    )
                    .clicked()
                {
                    cmds.push(Command::ToggleDesignRules);
                }
            });
            ui.menu_button("Help", |ui| {
                ui.set_max_width(420.0);
                ui.label(egui::RichText::new(ws.label()).strong());
                for (i, step) in ws.tour().iter().enumerate() {
                    ui.label(format!("{}. {step}", i + 1));
                }
                ui.separator();
                ui.label(egui::RichText::new("Keyboard").strong());
                egui::Grid::new("shortcuts").show(ui, |ui| {
                    for (keys, action) in ws.shortcuts() {
                        ui.monospace(*keys);
                        ui.label(*action);
                        ui.end_row();
                    }
                    for (keys, action) in
                        [("Ctrl+Z / Ctrl+Shift+Z", "undo / redo"), ("Ctrl+Q", "quit")]
                    {
                        ui.monospace(keys);
                        ui.label(action);
                        ui.end_row();
                    }
                });
            });
            ui.separator();
            for (id, label, about) in labels {
                if ui
                    .selectable_label(id == active, label)
                    .on_hover_text(about)
                    .clicked()
                {
                    switch = Some(id);
                }
            }
        });
        if let Some(id) = switch {
            self.active = id;
        }
    }
}

/// The switch's entries, in the shell's order.
fn switch_labels(
    workspaces: &[Box<dyn Workspace>],
) -> Vec<(WorkspaceId, &'static str, &'static str)> {
    workspaces
        .iter()
        .map(|w| (w.id(), w.label(), w.about()))
        .collect()
}
