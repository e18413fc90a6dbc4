//! The plots beside a sweep's results, as PNG and SVG (plotters): a metric against one axis
//! with its spread over seeds, one line per group; and the Pareto front of two metrics.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::manifest::{CSV_FILE, Manifest};
use super::table::{ColumnKind, TableSchema, read_csv};
use crate::error::{IoError, PlotError, TableError};
use udc_core::sweep::summary::{ParetoPoint, SeriesSummary, pareto_front};
use udc_core::sweep::{PlotKind, PlotSpec, SweepJob};

/// Plot size in pixels (PNG) and user units (SVG).
const SIZE: (u32, u32) = (960, 600);
/// Line colours, one per group.
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

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
    /// Lines of mean with min–max bands; categorical x labels when the axis is not numeric.
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

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

/// Draws every plot of the folder into `dir/plots/` as PNG and SVG; returns the files written.
///
/// # Errors
/// [`IoError`] for an unreadable table, a missing column or a file that cannot be written.
pub fn write_plots(dir: &Path, m: &Manifest) -> Result<Vec<PathBuf>, IoError> {
    register_font();
    let plots_dir = dir.join("plots");
    std::fs::create_dir_all(&plots_dir)
        .map_err(|e| IoError::file("create the plots folder", &plots_dir, e))?;
    let mut written = Vec::new();
    for p in plots_for(m) {
        let data = plot_data(dir, m, &p)?;
        let what = format!("{} vs {}", p.y, p.x);
        let title = if m.spec.name.is_empty() {
            what
        } else {
            format!("{}: {what}", m.spec.name)
        };
        written.extend(write_plot(&plots_dir, &plot_stem(&p), &p, &data, &title)?);
    }
    Ok(written)
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
    register_font();
    let svg_path = plots_dir.join(format!("{stem}.svg"));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(&root, p, data, title).map_err(|e| plot_error(&svg_path, e))?;
        root.present()
            .map_err(|e| plot_error(&svg_path, PlotError::Draw(e.to_string())))?;
    }
    crate::safe_file::write_atomic(&svg_path, svg.as_bytes())?;
    let png_path = plots_dir.join(format!("{stem}.png"));
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(&root, p, data, title).map_err(|e| plot_error(&png_path, e))?;
        root.present()
            .map_err(|e| plot_error(&png_path, PlotError::Draw(e.to_string())))?;
    }
    let img = image::RgbImage::from_raw(SIZE.0, SIZE.1, rgb)
        .ok_or_else(|| plot_error(&png_path, PlotError::BufferSize))?;
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(|e| plot_error(&png_path, PlotError::Encode(e)))?;
    crate::safe_file::write_atomic(&png_path, &bytes)?;
    Ok(vec![svg_path, png_path])
}

fn plot_error(path: &Path, error: PlotError) -> IoError {
    IoError::Plot {
        path: path.to_path_buf(),
        error,
    }
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1e-12)
    };
    (lo - pad, hi + pad)
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The frame every plot shares: title, margins, label areas, linear axes over the ranges.
fn chart_on<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    x: (f64, f64),
    y: (f64, f64),
) -> Result<Chart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    ChartBuilder::on(root)
        .caption(title, ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
}

/// The legend every plot draws, over its series.
fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    p: &PlotSpec,
    data: &PlotData,
    title: &str,
) -> Result<(), PlotError> {
    // plotters' error type depends on the backend, so its text is what is kept.
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| PlotError::Draw(e.to_string());
    root.fill(&WHITE).map_err(e)?;
    match data {
        PlotData::Series { summary, x_labels } => {
            let xs = summary.lines.values().flat_map(|l| l.keys().map(|k| k.0));
            let ys = summary
                .lines
                .values()
                .flat_map(|l| l.values().flat_map(|s| [s.min, s.max]));
            let (x0, x1) = bounds(xs);
            let (y0, y1) = bounds(ys);
            let mut chart = chart_on(root, title, (x0, x1), (y0, y1)).map_err(e)?;
            let labels = x_labels.clone();
            let fmt_x = move |v: &f64| match &labels {
                Some(l) => {
                    let i = v.round();
                    if (v - i).abs() < 1e-6 && i >= 0.0 {
                        l.get(i as usize).cloned().unwrap_or_default()
                    } else {
                        String::new()
                    }
                }
                None => format!("{}", (v * 1e4).round() / 1e4),
            };
            chart
                .configure_mesh()
                .x_desc(p.x.as_str())
                .y_desc(p.y.as_str())
                .x_label_formatter(&fmt_x)
                .label_style(("sans-serif", 16))
                .draw()
                .map_err(e)?;
            for (i, (name, line)) in summary.lines.iter().enumerate() {
                let color = PALETTE[i % PALETTE.len()];
                if p.spread.is_some() {
                    let mut band: Vec<(f64, f64)> =
                        line.iter().map(|(x, s)| (x.0, s.max)).collect();
                    band.extend(line.iter().rev().map(|(x, s)| (x.0, s.min)));
                    chart
                        .draw_series(std::iter::once(Polygon::new(band, color.mix(0.18))))
                        .map_err(e)?;
                }
                let mean: Vec<(f64, f64)> = line.iter().map(|(x, s)| (x.0, s.mean())).collect();
                let series = chart
                    .draw_series(LineSeries::new(mean.clone(), color.stroke_width(2)))
                    .map_err(e)?;
                if !name.is_empty() {
                    series.label(name.clone()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                }
                chart
                    .draw_series(
                        mean.iter()
                            .map(|&(x, y)| Circle::new((x, y), 4, color.filled())),
                    )
                    .map_err(e)?;
            }
            if summary.lines.keys().any(|k| !k.is_empty()) {
                legend(&mut chart).map_err(e)?;
            }
        }
        PlotData::Pareto { points, front } => {
            let (x0, x1) = bounds(points.iter().map(|q| q.x));
            let (y0, y1) = bounds(points.iter().map(|q| q.y));
            let mut chart = chart_on(root, title, (x0, x1), (y0, y1)).map_err(e)?;
            chart
                .configure_mesh()
                .x_desc(p.x.as_str())
                .y_desc(p.y.as_str())
                .label_style(("sans-serif", 16))
                .draw()
                .map_err(e)?;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|q| Circle::new((q.x, q.y), 3, PALETTE[0].mix(0.5).filled())),
                )
                .map_err(e)?
                .label("points")
                .legend(|(x, y)| Circle::new((x + 10, y), 3, PALETTE[0].filled()));
            chart
                .draw_series(LineSeries::new(
                    front.iter().map(|q| (q.x, q.y)),
                    PALETTE[1].stroke_width(2),
                ))
                .map_err(e)?
                .label("Pareto front")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], PALETTE[1].stroke_width(2))
                });
            chart
                .draw_series(
                    front
                        .iter()
                        .map(|q| Circle::new((q.x, q.y), 5, PALETTE[1].filled())),
                )
                .map_err(e)?;
            legend(&mut chart).map_err(e)?;
        }
    }
    Ok(())
}
