//! What the Sweep workspace shows, computed from the table in memory on a job: the rows the
//! filter keeps in sort order, and each plot's data over those rows. The same
//! [`crate::io::sweep::plots::PlotData`] the CLI's PNG plots draw, so the two agree.

use std::collections::HashMap;
use std::sync::Arc;

use super::table::{Column, Filter, Sort, SweepTable};
use crate::app::error::StudioError;
use crate::core::Progress;
use crate::core::figure::Panel;
use crate::core::sweep::summary::{ParetoPoint, SeriesSummary, pareto_front};
use crate::core::sweep::{PlotKind, PlotSpec};
use crate::io::sweep::plots::{PlotData, panel_of};
use crate::io::sweep::table::ColumnKind;

/// What the view asks for: the filter box's text, the sort order and the plots.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewRequest {
    /// The filter box's text.
    pub filter: String,
    /// The sort order.
    pub sort: Sort,
    /// The plots to draw, the spec's own first, then the user's pick.
    pub plots: Vec<PlotSpec>,
}

/// A computed view.
pub struct View {
    /// What it was computed for.
    pub request: ViewRequest,
    /// The shown rows, indices into the table's rows, in sort order.
    pub rows: Vec<usize>,
    /// Each plot with its data, or why it cannot be drawn (a column the table lacks).
    pub plots: Vec<(PlotSpec, Result<PlotData, StudioError>)>,
    /// The figure of each plot whose data is there, in the order of `plots`: what the
    /// workspace draws (the CLI's files draw the same panels).
    pub panels: Vec<Option<Panel>>,
    /// The widest cell of each column over every row, in characters (errors capped at 60),
    /// so the table's columns do not change width as it scrolls or filters.
    pub widest: HashMap<Column, usize>,
}

/// Computes the view of `table` that `request` asks for.
///
/// # Errors
/// Only cancellation (a newer request).
pub fn derive(
    table: &Arc<SweepTable>,
    request: ViewRequest,
    progress: &Progress,
) -> Result<View, crate::core::SimError> {
    let rows = table.view(&Filter::parse(&request.filter), request.sort);
    progress.check()?;
    let plots: Vec<_> = request
        .plots
        .iter()
        .map(|p| (p.clone(), plot_data(table, &rows, p)))
        .collect();
    let panels = plots
        .iter()
        .map(|(p, d)| d.as_ref().ok().map(|d| panel_of(p, d, &title(p))))
        .collect();
    progress.check()?;
    Ok(View {
        request,
        rows,
        plots,
        panels,
        widest: widest(table),
    })
}

/// A plot's title on screen: `y vs x`, or `Pareto: y vs x`.
pub fn title(spec: &PlotSpec) -> String {
    match spec.kind {
        PlotKind::MetricVsAxis => format!("{} vs {}", spec.y, spec.x),
        PlotKind::Pareto => format!("Pareto: {} vs {}", spec.y, spec.x),
    }
}

/// See [`View::widest`]; metrics are formatted to at most 12 characters.
fn widest(table: &SweepTable) -> HashMap<Column, usize> {
    let mut out: HashMap<Column, usize> = HashMap::new();
    for c in table.columns() {
        let w = match c {
            Column::Metric(_) => 10,
            Column::Point => table.rows.len().max(1).to_string().len(),
            Column::Param(k) => table
                .rows
                .iter()
                .map(|r| r.params.get(k).map_or(0, |t| t.chars().count()))
                .max()
                .unwrap_or(0),
            Column::Error => table
                .rows
                .iter()
                .map(|r| r.error.chars().count().min(60))
                .max()
                .unwrap_or(0),
        };
        out.insert(c, w);
    }
    out
}

/// The labels of a word axis (a tiling, a preset), in the spec's value order, else in the
/// order the rows first show them.
fn word_labels(table: &SweepTable, rows: &[usize], name: &str, k: usize) -> Vec<String> {
    let from_spec = table
        .manifest
        .spec
        .axes
        .iter()
        .find(|a| a.param == name)
        .and_then(|a| crate::core::sweep::spec::axis_values(a).ok())
        .map(|v| {
            v.iter()
                .map(crate::core::sweep::ParamValue::to_arg)
                .collect::<Vec<_>>()
        });
    let mut labels = from_spec.unwrap_or_default();
    for r in rows.iter().filter_map(|i| table.rows.get(*i)) {
        if let Some(t) = r.params.get(k)
            && !labels.contains(t)
        {
            labels.push(t.clone());
        }
    }
    labels
}

/// One plot's data over the shown rows.
///
/// # Errors
/// A column the table lacks, by name.
pub fn plot_data(
    table: &SweepTable,
    rows: &[usize],
    p: &PlotSpec,
) -> Result<PlotData, StudioError> {
    let missing = |n: &str| StudioError::NoColumn(n.to_string());
    let x = table.column(&p.x).ok_or_else(|| missing(&p.x))?;
    let y = table.column(&p.y).ok_or_else(|| missing(&p.y))?;
    let group = match &p.group {
        Some(g) => Some(table.column(g).ok_or_else(|| missing(g))?),
        None => None,
    };
    let x_labels = match x {
        Column::Param(k)
            if table
                .manifest
                .schema
                .params
                .get(k)
                .is_some_and(|(_, t)| *t == ColumnKind::Text) =>
        {
            Some(word_labels(table, rows, &p.x, k))
        }
        _ => None,
    };
    let x_of = |r: &crate::io::sweep::Row| match (&x_labels, x) {
        (Some(labels), c) => {
            let t = table.text(r, c);
            labels
                .iter()
                .position(|l| *l == t)
                .map_or(f64::NAN, |i| i as f64)
        }
        (None, c) => table.number(r, c),
    };
    let shown = rows.iter().filter_map(|i| table.rows.get(*i));
    match p.kind {
        PlotKind::MetricVsAxis => {
            let mut summary = SeriesSummary::default();
            for r in shown {
                let g = match (group, &p.group) {
                    (Some(c), Some(name)) => format!("{name} {}", table.text(r, c)),
                    _ => String::new(),
                };
                summary.add(&g, x_of(r), table.number(r, y));
            }
            Ok(PlotData::Series { summary, x_labels })
        }
        PlotKind::Pareto => {
            let points: Vec<ParetoPoint> = shown
                .map(|r| ParetoPoint {
                    x: x_of(r),
                    y: table.number(r, y),
                    point: r.point,
                })
                .collect();
            let front = pareto_front(&points, p.x_smaller_is_better);
            Ok(PlotData::Pareto { points, front })
        }
    }
}
