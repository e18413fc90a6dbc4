//! A figure panel ([`udc_core::figure::Panel`]) drawn to files with plotters: SVG and PNG at
//! 960×600, on white, with egui's own Ubuntu font (no system fonts), the axes' titles with
//! their units, and a legend when the panel has series to tell apart.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::error::{IoError, PlotError};
use udc_core::figure::{Annotation, Mark, Panel, RING_SEGMENTS, Rgb, circle_points, palette};

/// Plot size in pixels (PNG) and user units (SVG).
const SIZE: (u32, u32) = (960, 600);

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

/// Draws `panel` as `dir/<stem>.svg` and `dir/<stem>.png` (the folder must exist); returns
/// both paths.
///
/// # Errors
/// [`IoError`] for a panel that cannot be drawn or a file that cannot be written.
pub fn write_panel(dir: &Path, stem: &str, panel: &Panel) -> Result<Vec<PathBuf>, IoError> {
    register_font();
    let svg_path = dir.join(format!("{stem}.svg"));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(&root, panel).map_err(|e| plot_error(&svg_path, e))?;
        root.present()
            .map_err(|e| plot_error(&svg_path, PlotError::Draw(e.to_string())))?;
    }
    crate::safe_file::write_atomic(&svg_path, svg.as_bytes())?;
    let png_path = dir.join(format!("{stem}.png"));
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(&root, panel).map_err(|e| plot_error(&png_path, e))?;
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

/// `[lo, hi]` widened by 5 % each side (a flat range by half its magnitude).
fn padded([lo, hi]: [f64; 2]) -> (f64, f64) {
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1e-12)
    };
    (lo - pad, hi + pad)
}

fn colour(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, panel: &Panel) -> Result<(), PlotError> {
    // plotters' error type depends on the backend, so its text is what is kept.
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| PlotError::Draw(e.to_string());
    root.fill(&WHITE).map_err(e)?;
    let (bx, by) = panel.data_bounds().unwrap_or(([0.0, 1.0], [0.0, 1.0]));
    let (x, y) = (padded(bx), padded(by));
    let mut chart = ChartBuilder::on(root)
        .caption(&panel.title, ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(e)?;
    let x_axis = panel.x.clone();
    let fmt_x = move |v: &f64| {
        x_axis
            .category_at(*v)
            .unwrap_or_else(|| format!("{}", (v * 1e4).round() / 1e4))
    };
    chart
        .configure_mesh()
        .x_desc(panel.x.title())
        .y_desc(panel.y.title())
        .x_label_formatter(&fmt_x)
        .label_style(("sans-serif", 16))
        .draw()
        .map_err(e)?;
    for s in &panel.series {
        let c = colour(s.colour);
        if let Some(band) = &s.band {
            let mut outline: Vec<(f64, f64)> = band.iter().map(|b| (b[0], b[2])).collect();
            outline.extend(band.iter().rev().map(|b| (b[0], b[1])));
            chart
                .draw_series(std::iter::once(Polygon::new(outline, c.mix(0.18))))
                .map_err(e)?;
        }
        let points = s
            .points
            .iter()
            .filter(|p| p[0].is_finite() && p[1].is_finite())
            .map(|p| (p[0], p[1]));
        let name = s.name.clone();
        match s.mark {
            Mark::Points => {
                chart
                    .draw_series(points.map(|p| Circle::new(p, 3, c.mix(0.5).filled())))
                    .map_err(e)?
                    .label(name)
                    .legend(move |(x, y)| Circle::new((x + 10, y), 3, c.filled()));
            }
            Mark::Line | Mark::LineAndPoints => {
                let line: Vec<(f64, f64)> = points.collect();
                chart
                    .draw_series(LineSeries::new(line.clone(), c.stroke_width(2)))
                    .map_err(e)?
                    .label(name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                    });
                if s.mark == Mark::LineAndPoints {
                    chart
                        .draw_series(line.iter().map(|&p| Circle::new(p, 4, c.filled())))
                        .map_err(e)?;
                }
            }
            Mark::DashedLine => {
                chart
                    .draw_series(DashedLineSeries::new(
                        points.collect::<Vec<_>>(),
                        6,
                        4,
                        c.stroke_width(1),
                    ))
                    .map_err(e)?
                    .label(name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(1))
                    });
            }
        }
    }
    annotate(&mut chart, panel, (x, y)).map_err(e)?;
    if panel.wants_legend() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

/// The panel's annotations over its data, in the annotation colour.
fn annotate<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    panel: &Panel,
    (x, y): ((f64, f64), (f64, f64)),
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let c = colour(palette::ANNOTATION);
    for a in &panel.annotations {
        match a {
            Annotation::Ring { centre, radius, .. } => {
                let ring = circle_points(*centre, *radius, RING_SEGMENTS);
                chart.draw_series(LineSeries::new(
                    ring.into_iter().map(|p| (p[0], p[1])),
                    c.stroke_width(2),
                ))?;
            }
            Annotation::Lattice { points, .. } => {
                chart.draw_series(
                    points
                        .iter()
                        .map(|p| Cross::new((p[0], p[1]), 4, c.stroke_width(1))),
                )?;
            }
            Annotation::VLine { x: at, .. } => {
                chart.draw_series(LineSeries::new([(*at, y.0), (*at, y.1)], c.stroke_width(1)))?;
            }
            Annotation::HLine { y: at, .. } => {
                chart.draw_series(LineSeries::new([(x.0, *at), (x.1, *at)], c.stroke_width(1)))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use udc_core::figure::{Axis, Series};

    fn panel() -> Panel {
        Panel {
            title: "AUC against pitch".into(),
            x: Axis::new("pitch", Some("µm")),
            y: Axis::new("AUC", None),
            series: vec![
                Series {
                    name: "repeat".into(),
                    colour: palette::series(0),
                    mark: Mark::LineAndPoints,
                    points: vec![[42.0, 0.2], [84.0, 0.3]],
                    band: Some(vec![[42.0, 0.1, 0.25], [84.0, 0.28, 0.35]]),
                },
                Series {
                    name: "random".into(),
                    colour: palette::series(1),
                    mark: Mark::Points,
                    points: vec![[42.0, 0.4], [84.0, f64::NAN]],
                    band: None,
                },
            ],
            annotations: vec![
                Annotation::VLine {
                    x: 60.0,
                    label: "600 DPI".into(),
                },
                Annotation::Ring {
                    centre: [60.0, 0.3],
                    radius: 1.0,
                    label: "ring".into(),
                },
            ],
        }
    }

    #[test]
    fn a_panel_is_written_as_svg_and_png_with_its_axes_units_and_legend() {
        let dir = tempfile::tempdir().expect("tempdir");
        let written = write_panel(dir.path(), "auc", &panel()).expect("drawn");
        assert_eq!(written.len(), 2);
        let svg = std::fs::read_to_string(dir.path().join("auc.svg")).expect("svg");
        for text in ["pitch (µm)", "AUC against pitch", "repeat", "random"] {
            assert!(svg.contains(text), "the SVG lacks {text}");
        }
        let png = image::open(dir.path().join("auc.png")).expect("png");
        assert_eq!((png.width(), png.height()), SIZE);
        // The series' colours are on the page (the band's mix is lighter; the line is exact).
        let series = palette::series(0);
        let rgb = png.to_rgb8();
        assert!(rgb.pixels().any(|p| p.0 == [series.0, series.1, series.2]));
    }

    #[test]
    fn an_empty_panel_still_draws() {
        let dir = tempfile::tempdir().expect("tempdir");
        let empty = Panel {
            title: "nothing yet".into(),
            ..Panel::default()
        };
        assert!(write_panel(dir.path(), "empty", &empty).is_ok());
    }
}
