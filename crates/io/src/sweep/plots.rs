//! The plots beside a sweep's results, as PNG and SVG (plotters): a metric against one axis
//! with its spread over seeds, one line per group; and the Pareto front of two metrics.

use std::path::{Path, PathBuf};

use super::manifest::{CSV_FILE, Manifest};
use super::table::{ColumnKind, TableSchema, read_csv};
use crate::error::{IoError, TableError};
use udc_core::figure::{Axis, Mark, Panel, Series, palette};
use udc_core::sweep::summary::{ParetoPoint, SeriesSummary, pareto_front};
use udc_core::sweep::{PlotKind, PlotSpec, SweepJob};

/// The plots a spec asks for, or the defaults: the first metric against the first axis that
/// is not a seed, spread over the seed axis and grouped by the next axis; for `analyze`, the
/// Pareto front of mean AUC against LTR.
pub fn plots_for(m: &Manifest) -> Vec<PlotSpec> {
    if !m.spec.plots.is_empty() {
        return m.spec.plots.clone();
    }
    let mut out = Vec::new();
    let axes: Vec<&str> = m.schema.params.iter().map(|(n, _)| n.as_str()).collect();
    let is_seed = |a: &&str| a.ends_with("seed");
    let spread = axes.iter().copied().find(is_seed);
    let others: Vec<&str> = axes.iter().copied().filter(|a| !is_seed(a)).collect();
    let x = others.first().copied().or(spread);
    if let (Some(x), Some(y)) = (x, m.schema.metrics.first()) {
        out.push(PlotSpec {
            kind: PlotKind::MetricVsAxis,
            x: x.to_string(),
            y: y.clone(),
            group: others.get(1).map(|s| (*s).to_string()),
            spread: spread.filter(|s| *s != x).map(str::to_string),
            x_smaller_is_better: false,
        });
    }
    let has = |s: &str| m.schema.metrics.iter().any(|c| c == s);
    if m.spec.job == SweepJob::Analyze && has("ltr") && has("auc_radial_min_mean") {
        out.push(PlotSpec {
            kind: PlotKind::Pareto,
            x: "ltr".into(),
            y: "auc_radial_min_mean".into(),
            group: None,
            spread: None,
            x_smaller_is_better: false,
        });
    }
    out
}

/// A file name for a plot: `auc_radial_min_mean-vs-pitch-um`.
pub fn plot_stem(p: &PlotSpec) -> String {
    let clean = |s: &str| -> String {
        s.chars()
            .map(|c| {
                if c.is_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    };
    match p.kind {
        PlotKind::MetricVsAxis => format!("{}-vs-{}", clean(&p.y), clean(&p.x)),
        PlotKind::Pareto => format!("pareto-{}-{}", clean(&p.y), clean(&p.x)),
    }
}

/// What one plot draws, read from the table.
pub enum PlotData {
    /// Lines of mean with ± SD bands; categorical x labels when the axis is not numeric.
    Series {
        /// The spreads per group and x.
        summary: SeriesSummary,
        /// Labels of a categorical x axis, by position.
        x_labels: Option<Vec<String>>,
    },
    /// Every point and the front.
    Pareto {
        /// All points.
        points: Vec<ParetoPoint>,
        /// The front, by x.
        front: Vec<ParetoPoint>,
    },
}

fn column(schema: &TableSchema, name: &str) -> Option<Col> {
    if let Some(k) = schema.params.iter().position(|(n, _)| n == name) {
        return Some(Col::Param(k));
    }
    schema
        .metrics
        .iter()
        .position(|n| n == name)
        .map(Col::Metric)
}

#[derive(Clone, Copy)]
enum Col {
    Param(usize),
    Metric(usize),
}

/// Reads the plot's data from `dir/results.csv` in one pass.
///
/// # Errors
/// [`IoError::Table`] for a column the table lacks, or an unreadable table.
pub fn plot_data(dir: &Path, m: &Manifest, p: &PlotSpec) -> Result<PlotData, IoError> {
    let path = dir.join(CSV_FILE);
    let missing = |name: &str| IoError::Table {
        path: path.clone(),
        error: TableError::MissingColumn {
            plot: plot_stem(p),
            column: name.to_string(),
            axes: m.schema.params.iter().map(|(n, _)| n.clone()).collect(),
            metrics: m.schema.metrics.clone(),
        },
    };
    let x = column(&m.schema, &p.x).ok_or_else(|| missing(&p.x))?;
    let y = column(&m.schema, &p.y).ok_or_else(|| missing(&p.y))?;
    let group = match &p.group {
        Some(g) => Some(column(&m.schema, g).ok_or_else(|| missing(g))?),
        None => None,
    };
    // A categorical x: positions in the axis's value order.
    let x_labels: Option<Vec<String>> = match x {
        Col::Param(k)
            if m.schema
                .params
                .get(k)
                .is_some_and(|(_, t)| *t == ColumnKind::Text) =>
        {
            m.spec
                .axes
                .iter()
                .find(|a| a.param == p.x)
                .and_then(|a| udc_core::sweep::spec::axis_values(a).ok())
                .map(|v| v.iter().map(udc_core::sweep::ParamValue::to_arg).collect())
        }
        _ => None,
    };
    let value = |row: &super::Row, c: Col| -> f64 {
        match c {
            Col::Metric(k) => row.metrics.get(k).copied().unwrap_or(f64::NAN),
            Col::Param(k) => {
                let t = row.params.get(k).map_or("", String::as_str);
                match &x_labels {
                    Some(labels) if matches!(x, Col::Param(j) if j == k) => labels
                        .iter()
                        .position(|l| l == t)
                        .map_or(f64::NAN, |i| i as f64),
                    _ => t.parse().unwrap_or(f64::NAN),
                }
            }
        }
    };
    match p.kind {
        PlotKind::MetricVsAxis => {
            let mut summary = SeriesSummary::default();
            read_csv(&path, &m.schema, false, |row| {
                let g = match group {
                    Some(Col::Param(k)) => format!(
                        "{} {}",
                        p.group.as_deref().unwrap_or(""),
                        row.params.get(k).map_or("", String::as_str)
                    ),
                    Some(Col::Metric(k)) => {
                        format!("{}", row.metrics.get(k).copied().unwrap_or(f64::NAN))
                    }
                    None => String::new(),
                };
                summary.add(&g, value(&row, x), value(&row, y));
                Ok(())
            })?;
            Ok(PlotData::Series { summary, x_labels })
        }
        PlotKind::Pareto => {
            let mut points = Vec::new();
            read_csv(&path, &m.schema, false, |row| {
                points.push(ParetoPoint {
                    x: value(&row, x),
                    y: value(&row, y),
                    point: row.point,
                });
                Ok(())
            })?;
            let front = pareto_front(&points, p.x_smaller_is_better);
            Ok(PlotData::Pareto { points, front })
        }
    }
}

/// Draws every plot of the folder into `dir/plots/` as PNG and SVG; returns the files written.
///
/// # Errors
/// [`IoError`] for an unreadable table, a missing column or a file that cannot be written.
pub fn write_plots(dir: &Path, m: &Manifest) -> Result<Vec<PathBuf>, IoError> {
    let plots_dir = dir.join("plots");
    std::fs::create_dir_all(&plots_dir)
        .map_err(|e| IoError::file("create the plots folder", &plots_dir, e))?;
    let mut written = Vec::new();
    for p in plots_for(m) {
        let data = plot_data(dir, m, &p)?;
        written.extend(write_plot(
            &plots_dir,
            &plot_stem(&p),
            &p,
            &data,
            &plot_title(m, &p),
        )?);
    }
    Ok(written)
}

/// A plot's title in its file: `<sweep name>: y vs x`.
pub fn plot_title(m: &Manifest, p: &PlotSpec) -> String {
    let what = format!("{} vs {}", p.y, p.x);
    if m.spec.name.is_empty() {
        what
    } else {
        format!("{}: {what}", m.spec.name)
    }
}

/// Draws one plot of `data` as `plots_dir/<stem>.svg` and `.png` (the folder must exist);
/// returns both paths. For data that is no sweep's table (a reproduction's curves).
///
/// # Errors
/// [`IoError`] for a plot that cannot be drawn or a file that cannot be written.
pub fn write_plot(
    plots_dir: &Path,
    stem: &str,
    p: &PlotSpec,
    data: &PlotData,
    title: &str,
) -> Result<Vec<PathBuf>, IoError> {
    crate::figure::write_panel(plots_dir, stem, &panel_of(p, data, title))
}

/// The figure of one plot: each group's mean as a line with dots, and its mean ± SD band over the
/// plot's spread axis (seeds) when it names one; a Pareto plot's rows as a cloud and its front as a
/// line. The studio draws the same panel.
pub fn panel_of(p: &PlotSpec, data: &PlotData, title: &str) -> Panel {
    let mut x = Axis::new(p.x.clone(), None);
    let y = Axis::new(p.y.clone(), None);
    let series = match data {
        PlotData::Series { summary, x_labels } => {
            x.categories.clone_from(x_labels);
            summary
                .lines
                .iter()
                .enumerate()
                .map(|(i, (name, line))| Series {
                    name: if name.is_empty() {
                        p.y.clone()
                    } else {
                        name.clone()
                    },
                    colour: palette::series(i),
                    mark: Mark::LineAndPoints,
                    points: line.iter().map(|(x, s)| [x.0, s.mean()]).collect(),
                    // A band only over the axis the plot names as its spread (seeds):
                    // rows that differ in anything else are not one quantity's spread.
                    band: (p.spread.is_some() && line.values().any(|s| s.n > 1)).then(|| {
                        line.iter()
                            .map(|(x, s)| [x.0, s.mean() - s.sd(), s.mean() + s.sd()])
                            .collect()
                    }),
                })
                .collect()
        }
        PlotData::Pareto { points, front } => vec![
            Series {
                name: "rows".into(),
                colour: palette::series(0),
                mark: Mark::Points,
                points: points.iter().map(|q| [q.x, q.y]).collect(),
                band: None,
            },
            Series {
                name: "Pareto front".into(),
                colour: palette::series(1),
                mark: Mark::LineAndPoints,
                points: front.iter().map(|q| [q.x, q.y]).collect(),
                band: None,
            },
        ],
    };
    Panel {
        title: title.to_string(),
        x,
        y,
        series,
        annotations: Vec::new(),
        ..Panel::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(spread: Option<&str>) -> PlotSpec {
        PlotSpec {
            kind: PlotKind::MetricVsAxis,
            x: "pitch-um".into(),
            y: "auc".into(),
            group: Some("tiling".into()),
            spread: spread.map(str::to_string),
            x_smaller_is_better: false,
        }
    }

    #[test]
    fn a_band_spans_only_the_spread_axis_and_each_group_is_a_series() {
        let mut summary = SeriesSummary::default();
        for (group, y) in [
            ("tiling repeat", 0.1),
            ("tiling repeat", 0.3),
            ("tiling random", 0.5),
        ] {
            summary.add(group, 42.0, y);
        }
        let data = PlotData::Series {
            summary,
            x_labels: None,
        };
        let with = panel_of(&spec(Some("seed")), &data, "t");
        assert_eq!(with.series.len(), 2);
        let repeat = with
            .series
            .iter()
            .find(|s| s.name == "tiling repeat")
            .expect("group");
        assert_eq!(repeat.points, vec![[42.0, 0.2]]);
        // Mean ± the sample SD of 0.1 and 0.3: 0.2 ± 0.1·√2.
        let sd = 0.1 * 2f64.sqrt();
        let band = repeat.band.clone().expect("a band over the seeds");
        assert_eq!(band.len(), 1);
        assert!((band[0][1] - (0.2 - sd)).abs() < 1e-12 && (band[0][2] - (0.2 + sd)).abs() < 1e-12);
        // One row per x: nothing to spread.
        let random = with
            .series
            .iter()
            .find(|s| s.name == "tiling random")
            .expect("group");
        assert_eq!(random.band, None);
        // No spread axis named: rows that differ in something else make no band.
        let without = panel_of(&spec(None), &data, "t");
        assert!(without.series.iter().all(|s| s.band.is_none()));
        assert_eq!(without.x.title(), "pitch-um");
    }
}
