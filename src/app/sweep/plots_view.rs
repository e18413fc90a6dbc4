//! The Sweep workspace's plots, drawn with egui_plot from the view's data (the CLI's PNGs are
//! not loaded: these follow the filter and can be hovered): a metric against an axis as mean
//! lines with their min–max band per group, and a Pareto plot as points with the front.

use egui::Color32;
use egui_plot::{FilledArea, Legend, Line, Plot, PlotPoints, Points};

use super::SweepWorkspace;
use crate::core::sweep::{PlotKind, PlotSpec};
use crate::io::sweep::plots::PlotData;

/// The most rows a Pareto plot draws as points.
const MAX_POINTS_DRAWN: usize = 5000;

/// Line colours, one per group (the CLI's plots use the same).
const PALETTE: [Color32; 6] = [
    Color32::from_rgb(31, 119, 180),
    Color32::from_rgb(214, 39, 40),
    Color32::from_rgb(44, 160, 44),
    Color32::from_rgb(148, 103, 189),
    Color32::from_rgb(255, 127, 14),
    Color32::from_rgb(23, 190, 207),
];

impl SweepWorkspace {
    /// The plot picker and every plot side by side.
    pub(super) fn plots_ui(&mut self, ui: &mut egui::Ui) {
        let Some(t) = self.table.clone() else {
            ui.weak("The plots appear here once a sweep is open.");
            return;
        };
        let names: Vec<String> = t
            .columns()
            .into_iter()
            .filter(|c| !matches!(c, super::table::Column::Error))
            .map(|c| t.name(c).to_string())
            .collect();
        ui.horizontal_wrapped(|ui| {
            ui.label("Your plot:");
            pick_ui(ui, "y", &mut self.custom.y, &names);
            ui.label("against");
            pick_ui(ui, "x", &mut self.custom.x, &names);
            ui.checkbox(&mut self.custom.pareto, "Pareto")
                .on_hover_text("Every row as a point, and the front no other row beats in both");
        });
        let Some(view) = &self.view else {
            ui.spinner();
            return;
        };
        let n = view.plots.len().max(1);
        ui.columns(n, |cols| {
            for (k, (ui, (spec, data))) in cols.iter_mut().zip(&view.plots).enumerate() {
                ui.label(egui::RichText::new(title(spec)).strong());
                match data {
                    Ok(d) => plot_ui(ui, k, spec, d),
                    Err(e) => {
                        ui.colored_label(ui.visuals().error_fg_color, e.to_string());
                    }
                }
            }
        });
    }
}

fn title(spec: &PlotSpec) -> String {
    match spec.kind {
        PlotKind::MetricVsAxis => format!("{} vs {}", spec.y, spec.x),
        PlotKind::Pareto => format!("Pareto: {} vs {}", spec.y, spec.x),
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

fn plot_ui(ui: &mut egui::Ui, k: usize, spec: &PlotSpec, data: &PlotData) {
    let labels = match data {
        PlotData::Series {
            x_labels: Some(l), ..
        } => Some(l.clone()),
        _ => None,
    };
    // A legend only where there is something to tell apart; one line needs none (the title
    // names it) and its box would hide a small plot.
    let groups = match data {
        PlotData::Series { summary, .. } => summary.lines.len(),
        PlotData::Pareto { .. } => 2,
    };
    let mut plot = Plot::new(("sweep_plot", k, title(spec)));
    if groups > 1 {
        plot = plot.legend(Legend::default().position(egui_plot::Corner::RightBottom));
    }
    // The axis titles after the ticks, which replace the axes.
    let mut plot =
        crate::app::widgets::plot::with_nice_ticks(plot.height(ui.available_height().max(120.0)))
            .x_axis_label(spec.x.clone())
            .y_axis_label(spec.y.clone());
    if let Some(labels) = labels {
        // A word axis (a tiling): its values sit at 0, 1, 2… and are named there.
        plot = plot.x_axis_formatter(move |mark, _| {
            let i = mark.value.round();
            if (mark.value - i).abs() < 1e-9 && i >= 0.0 {
                labels.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        });
    }
    plot.show(ui, |pl| match data {
        PlotData::Series { summary, .. } => {
            for (g, (name, line)) in summary.lines.iter().enumerate() {
                let color = PALETTE[g % PALETTE.len()];
                let label = if name.is_empty() {
                    spec.y.clone()
                } else {
                    name.clone()
                };
                let xs: Vec<f64> = line.keys().map(|x| x.0).collect();
                let lo: Vec<f64> = line.values().map(|s| s.min).collect();
                let hi: Vec<f64> = line.values().map(|s| s.max).collect();
                if line.values().any(|s| s.n > 1) {
                    pl.add(
                        FilledArea::new(format!("{label} min–max"), &xs, &lo, &hi)
                            .fill_color(color.gamma_multiply(0.25)),
                    );
                }
                let mean: PlotPoints = line.iter().map(|(x, s)| [x.0, s.mean()]).collect();
                pl.line(Line::new(label.clone(), mean).color(color).width(2.0));
                let dots: PlotPoints = line.iter().map(|(x, s)| [x.0, s.mean()]).collect();
                pl.points(Points::new(label, dots).color(color).radius(3.0));
            }
        }
        PlotData::Pareto { points, front } => {
            // Every frame draws them: beyond a few thousand, an even sample shows the cloud as
            // well and keeps scrolling the table smooth; the front is always drawn whole.
            let step = points.len().div_ceil(MAX_POINTS_DRAWN).max(1);
            let all: PlotPoints = points
                .iter()
                .step_by(step)
                .filter(|p| p.x.is_finite() && p.y.is_finite())
                .map(|p| [p.x, p.y])
                .collect();
            let name = if step > 1 {
                format!("rows (1 in {step})")
            } else {
                "rows".to_string()
            };
            pl.points(Points::new(name, all).color(PALETTE[0]).radius(3.0));
            let f: PlotPoints = front.iter().map(|p| [p.x, p.y]).collect();
            pl.line(Line::new("Pareto front", f).color(PALETTE[1]).width(2.0));
        }
    });
}
