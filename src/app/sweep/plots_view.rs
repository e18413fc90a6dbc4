//! The Sweep workspace's plots: the view's figure panels (the same the CLI's PNG and SVG files
//! are drawn from, computed over the filtered rows), drawn with egui_plot so they follow the
//! filter and can be hovered.

use super::derive::title;
use super::{SweepAction, SweepCtx};
use crate::app::widgets::figure::{PlotFrame, panel_plot_ui};
use crate::core::sweep::summary::{ParetoPoint, SeriesSummary};
use crate::io::sweep::plots::PlotData;

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
                        let (response, transform) =
                            panel_plot_ui(ui, ("sweep_plot", k, name), panel, frame);
                        match data {
                            Ok(PlotData::Pareto { points, .. }) => {
                                pareto_pick(&response, &transform, points, t, ctx);
                            }
                            Ok(PlotData::Series { summary, x_labels }) => {
                                let means = means(summary, x_labels.as_deref());
                                series_pick(&response, &transform, &means, spec, ctx);
                            }
                            Err(_) => {}
                        }
                    }
                    (Ok(_), None) => {}
                }
            }
        });
    }
}

/// The Pareto point nearest the pointer, within `PICK_PX` on screen: its row's parameters
/// as a tooltip, and a click opens its design.
fn pareto_pick(
    response: &egui::Response,
    transform: &egui_plot::PlotTransform,
    points: &[ParetoPoint],
    table: &super::table::SweepTable,
    ctx: &mut SweepCtx<'_>,
) {
    let Some(pointer) = response.hover_pos() else {
        return;
    };
    let to_screen =
        |x: f64, y: f64| transform.position_from_point(&egui_plot::PlotPoint::new(x, y));
    let Some(p) = nearest(points, |p| (p.x, p.y), to_screen, pointer, PICK_PX) else {
        return;
    };
    let Some(index) = table.rows.iter().position(|r| r.point == p.point) else {
        return;
    };
    let row = &table.rows[index];
    let params: Vec<String> = table
        .columns()
        .into_iter()
        .filter(|c| matches!(c, super::table::Column::Param(_)))
        .map(|c| format!("{} = {}", table.name(c), table.text(row, c)))
        .collect();
    response.clone().on_hover_ui_at_pointer(|ui| {
        ui.label(egui::RichText::new(format!("point {}", p.point)).strong());
        for line in &params {
            ui.label(line);
        }
        ui.weak("click: open its design");
    });
    if response.clicked() {
        ctx.actions.push(SweepAction::OpenRow(index));
    }
}

/// How near the pointer a point must be to be picked, points on screen.
const PICK_PX: f32 = 8.0;

/// One plotted mean of a metric-against-axis plot: its line's group value, its x as the table
/// spells it, and its spread.
#[derive(Debug, Clone, PartialEq)]
struct Mean {
    /// The group's value (`random-d4`), empty without groups.
    group: String,
    /// The x position drawn.
    x: f64,
    /// The x value as the table spells it (`200`, `repeat`).
    x_text: String,
    /// Mean of the rows there.
    mean: f64,
    /// Their sample standard deviation.
    sd: f64,
    /// How many rows.
    n: usize,
}

/// Every plotted mean of a series plot.
fn means(summary: &SeriesSummary, x_labels: Option<&[String]>) -> Vec<Mean> {
    let mut out = Vec::new();
    for (label, line) in &summary.lines {
        // The line's label is "group value" (`tiling random-d4`).
        let group = label.split_once(' ').map_or("", |(_, v)| v).to_string();
        for (x, spread) in line {
            if spread.n == 0 {
                continue;
            }
            let x_text = match x_labels {
                Some(labels) => labels.get(x.0 as usize).cloned().unwrap_or_default(),
                None => x.0.to_string(),
            };
            out.push(Mean {
                group: group.clone(),
                x: x.0,
                x_text,
                mean: spread.mean(),
                sd: spread.sd(),
                n: spread.n,
            });
        }
    }
    out
}

/// The mean nearest the pointer: its group, x, mean ± SD and row count as a tooltip; a click
/// filters the table to its rows (each opens or pins from there).
fn series_pick(
    response: &egui::Response,
    transform: &egui_plot::PlotTransform,
    means: &[Mean],
    spec: &crate::core::sweep::PlotSpec,
    ctx: &mut SweepCtx<'_>,
) {
    let Some(pointer) = response.hover_pos() else {
        return;
    };
    let to_screen =
        |x: f64, y: f64| transform.position_from_point(&egui_plot::PlotPoint::new(x, y));
    let Some(m) = nearest(means, |m| (m.x, m.mean), to_screen, pointer, PICK_PX) else {
        return;
    };
    let mut filter = format!("{}={}", spec.x, m.x_text);
    if let Some(g) = &spec.group
        && !m.group.is_empty()
    {
        filter.push_str(&format!(" {g}={}", m.group));
    }
    // A mean of one row is that row: a click opens it, as a Pareto point's does.
    let single = (m.n == 1)
        .then(|| ctx.table.and_then(|t| row_of(t, spec, m)))
        .flatten();
    response.clone().on_hover_ui_at_pointer(|ui| {
        ui.label(egui::RichText::new(&filter).strong());
        ui.label(format!(
            "{}: mean {} ± {} (SD) over {} {}",
            spec.y,
            super::table::format_number(m.mean),
            super::table::format_number(m.sd),
            m.n,
            if m.n == 1 { "row" } else { "rows" }
        ));
        ui.weak(if single.is_some() {
            "click: open its design"
        } else {
            "click: show these rows in the table, each of which opens"
        });
    });
    if response.clicked() {
        ctx.actions.push(match single {
            Some(index) => SweepAction::OpenRow(index),
            None => SweepAction::Filter(filter),
        });
    }
}

/// The row a one-row mean stands for: its x and group values (the table's index).
fn row_of(
    table: &super::table::SweepTable,
    spec: &crate::core::sweep::PlotSpec,
    m: &Mean,
) -> Option<usize> {
    let x = table.column(&spec.x)?;
    let group = match &spec.group {
        Some(g) if !m.group.is_empty() => Some(table.column(g)?),
        _ => None,
    };
    table.rows.iter().position(|r| {
        let n = table.number(r, x);
        let same_x = if n.is_nan() {
            table.text(r, x) == m.x_text
        } else {
            n == m.x
        };
        same_x && group.is_none_or(|g| table.text(r, g) == m.group)
    })
}

/// The item drawn nearest `pointer` (at `xy` by `to_screen`), if one is within `reach` on
/// screen.
fn nearest<T>(
    items: &[T],
    xy: impl Fn(&T) -> (f64, f64),
    to_screen: impl Fn(f64, f64) -> egui::Pos2,
    pointer: egui::Pos2,
    reach: f32,
) -> Option<&T> {
    items
        .iter()
        .map(|p| {
            let (x, y) = xy(p);
            (p, to_screen(x, y).distance(pointer))
        })
        .filter(|(_, d)| *d <= reach)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(p, _)| p)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pointer_picks_the_nearest_point_within_reach() {
        let points: Vec<ParetoPoint> = [(0.0, 0.0, 4), (1.0, 1.0, 7), (1.1, 1.0, 9)]
            .into_iter()
            .map(|(x, y, point)| ParetoPoint { x, y, point })
            .collect();
        // 100 screen points per unit, y downwards.
        let to_screen = |x: f64, y: f64| egui::pos2(100.0 * x as f32, -100.0 * y as f32);
        let at = |x: f32, y: f32| egui::pos2(x, y);
        let pick = |p| nearest(&points, |q| (q.x, q.y), to_screen, p, 8.0).map(|q| q.point);
        assert_eq!(pick(at(2.0, -3.0)), Some(4));
        assert_eq!(pick(at(103.0, -100.0)), Some(7), "nearer 7 than 9");
        assert_eq!(pick(at(108.0, -100.0)), Some(9));
        assert_eq!(pick(at(50.0, -50.0)), None, "nothing within reach");
    }

    #[test]
    fn each_group_and_x_is_one_mean_that_filters_to_its_rows() {
        let mut summary = SeriesSummary::default();
        for (g, x, y) in [
            ("tiling repeat", 150.0, 1.0),
            ("tiling repeat", 150.0, 3.0),
            ("tiling random-d4", 300.0, 5.0),
        ] {
            summary.add(g, x, y);
        }
        let m = means(&summary, None);
        assert_eq!(m.len(), 2);
        let repeat = m.iter().find(|m| m.group == "repeat").expect("its mean");
        assert_eq!(
            (repeat.x_text.as_str(), repeat.mean, repeat.n),
            ("150", 2.0, 2)
        );
        assert!((repeat.sd - 2f64.sqrt()).abs() < 1e-12);
        // A categorical axis names its positions.
        let mut cat = SeriesSummary::default();
        cat.add("", 1.0, 0.5);
        let labels = ["wiener".to_string(), "cg".to_string()];
        assert_eq!(means(&cat, Some(&labels))[0].x_text, "cg");
    }
}
