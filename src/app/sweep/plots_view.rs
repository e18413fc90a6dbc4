//! The Sweep workspace's plots: the view's figure panels (the same the CLI's PNG and SVG files
//! are drawn from, computed over the filtered rows), drawn with egui_plot so they follow the
//! filter and can be hovered.

use super::derive::title;
use super::{SweepAction, SweepCtx};
use crate::app::widgets::figure::{PlotFrame, panel_ui_in};

/// The bottom panel: the user's plot picker and every plot side by side.
#[derive(Default)]
pub struct PlotsPanel;

impl PlotsPanel {
    /// Draws the panel.
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut SweepCtx<'_>) {
        let Some(t) = ctx.table else {
            ui.weak("The plots appear here once a sweep is open.");
            return;
        };
        let names: Vec<String> = t
            .columns()
            .into_iter()
            .filter(|c| !matches!(c, super::table::Column::Error))
            .map(|c| t.name(c).to_string())
            .collect();
        let mut custom = ctx.custom.clone();
        ui.horizontal_wrapped(|ui| {
            ui.label("Your plot:");
            pick_ui(ui, "y", &mut custom.y, &names);
            ui.label("against");
            pick_ui(ui, "x", &mut custom.x, &names);
            ui.checkbox(&mut custom.pareto, "Pareto")
                .on_hover_text("Every row as a point, and the front no other row beats in both");
        });
        if &custom != ctx.custom {
            ctx.actions.push(SweepAction::Custom(custom));
        }
        let Some(view) = ctx.view else {
            ui.spinner();
            return;
        };
        let n = view.plots.len().max(1);
        ui.columns(n, |cols| {
            for (k, (ui, ((spec, data), panel))) in cols
                .iter_mut()
                .zip(view.plots.iter().zip(&view.panels))
                .enumerate()
            {
                let name = title(spec);
                ui.label(egui::RichText::new(&name).strong());
                match (data, panel) {
                    (Err(e), _) => {
                        ui.colored_label(ui.visuals().error_fg_color, e.to_string());
                    }
                    (Ok(_), Some(panel)) => {
                        // The legend above the plot: never over the points (a group's line, a
                        // Pareto front), and a click on a name hides its series.
                        let legend = if panel.wants_legend() { 48.0 } else { 0.0 };
                        let frame = PlotFrame {
                            legend_above: panel.wants_legend(),
                            ..PlotFrame::tall((ui.available_height() - legend).max(120.0))
                        };
                        panel_ui_in(ui, ("sweep_plot", k, name), panel, frame);
                    }
                    (Ok(_), None) => {}
                }
            }
        });
    }
}

/// A combo box of the table's columns.
fn pick_ui(ui: &mut egui::Ui, id: &str, value: &mut String, names: &[String]) {
    egui::ComboBox::from_id_salt(("sweep_pick", id))
        .selected_text(value.as_str())
        .width(150.0)
        .show_ui(ui, |ui| {
            for n in names {
                ui.selectable_value(value, n.clone(), n);
            }
        });
}
