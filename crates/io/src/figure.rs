//! Figures ([`udc_core::figure::Figure`]: panels side by side and a caption) drawn to files
//! with plotters: SVG or PNG at a chosen size (a lone panel at 960×600 by default), on white, with egui's own Ubuntu font (no system fonts), the axes' titles with
//! their units, and a legend when the panel has series to tell apart.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::error::{IoError, PlotError};
use udc_core::figure::{
    Annotation, ColorScale, Corner, FIGURE_SIDE_PX, Figure, FigureFormat, Image, Mark, Paint,
    Panel, RING_SEGMENTS, Rgb, circle_points, palette,
};

/// The most cells an image is drawn with per side: a 1024² PSF as 1 M rectangles would make a
/// 100 MB SVG; nearest samples on a 256² lattice read the same at figure size.
const MAX_CELLS: usize = 256;

/// Width of the colour bar's strip beside an image panel.
const COLORBAR_PX: u32 = 120;

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

/// Draws `panel` as `dir/<stem>.svg` and `dir/<stem>.png` at 960×600 (the folder must exist);
/// returns both paths.
///
/// # Errors
/// [`IoError`] for a panel that cannot be drawn or a file that cannot be written.
pub fn write_panel(dir: &Path, stem: &str, panel: &Panel) -> Result<Vec<PathBuf>, IoError> {
    let figure = Figure {
        panels: vec![panel.clone()],
        caption: None,
    };
    let svg_path = dir.join(format!("{stem}.svg"));
    write_figure(&svg_path, &figure, FigureFormat::Svg, SIZE)?;
    let png_path = dir.join(format!("{stem}.png"));
    write_figure(&png_path, &figure, FigureFormat::Png, SIZE)?;
    Ok(vec![svg_path, png_path])
}

/// Draws `figure` (its panels side by side, its caption under them) into `path` as `format`
/// at `size_px` (width, height: pixels for PNG, user units for SVG; checked against
/// [`FIGURE_SIDE_PX`]).
///
/// # Errors
/// A size outside [`FIGURE_SIDE_PX`], a figure that cannot be drawn, a file that cannot be
/// written.
pub fn write_figure(
    path: &Path,
    figure: &Figure,
    format: FigureFormat,
    size_px: (u32, u32),
) -> Result<(), IoError> {
    register_font();
    for side in [size_px.0, size_px.1] {
        if !FIGURE_SIDE_PX.contains(&side) {
            return Err(plot_error(
                path,
                PlotError::Draw(format!(
                    "a figure of {}×{} px: each side must be {} to {} px",
                    size_px.0,
                    size_px.1,
                    FIGURE_SIDE_PX.start(),
                    FIGURE_SIDE_PX.end()
                )),
            ));
        }
    }
    let bytes = match format {
        FigureFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size_px).into_drawing_area();
                draw_figure(&root, figure).map_err(|e| plot_error(path, e))?;
                root.present()
                    .map_err(|e| plot_error(path, PlotError::Draw(e.to_string())))?;
            }
            svg.into_bytes()
        }
        FigureFormat::Png => {
            let mut rgb = vec![0u8; size_px.0 as usize * size_px.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut rgb, size_px).into_drawing_area();
                draw_figure(&root, figure).map_err(|e| plot_error(path, e))?;
                root.present()
                    .map_err(|e| plot_error(path, PlotError::Draw(e.to_string())))?;
            }
            let img = image::RgbImage::from_raw(size_px.0, size_px.1, rgb)
                .ok_or_else(|| plot_error(path, PlotError::BufferSize))?;
            let mut bytes = Vec::new();
            img.write_to(
                &mut std::io::Cursor::new(&mut bytes),
                image::ImageFormat::Png,
            )
            .map_err(|e| plot_error(path, PlotError::Encode(e)))?;
            bytes
        }
    };
    crate::safe_file::write_atomic(path, &bytes)
}

/// Height of one caption line under a figure, and the caption's font size.
const CAPTION_LINE_PX: u32 = 22;
const CAPTION_FONT_PX: u32 = 16;

/// `caption` broken at spaces into lines of at most `width_px` (the font's characters are
/// taken as 0.5 em wide on average, a little more than Ubuntu Light's).
fn caption_lines(caption: &str, width_px: u32) -> Vec<String> {
    let max_chars = ((width_px.saturating_sub(32)) / (CAPTION_FONT_PX / 2)).max(20) as usize;
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in caption.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > max_chars {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// The figure's panels side by side over its caption.
fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
) -> Result<(), PlotError> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| PlotError::Draw(e.to_string());
    root.fill(&WHITE).map_err(e)?;
    let (w, h) = root.dim_in_pixel();
    let panels_area = match &figure.caption {
        Some(caption) => {
            let lines = caption_lines(caption, w);
            let strip = CAPTION_LINE_PX * lines.len() as u32 + 10;
            let (top, bottom) = root.split_vertically(h.saturating_sub(strip));
            let style = ("sans-serif", CAPTION_FONT_PX).into_font().color(&BLACK);
            for (k, line) in lines.into_iter().enumerate() {
                let y = 6 + (CAPTION_LINE_PX * k as u32) as i32;
                bottom
                    .draw(&Text::new(line, (16, y), style.clone()))
                    .map_err(e)?;
            }
            top
        }
        None => root.clone(),
    };
    let n = figure.panels.len().max(1);
    let areas = panels_area.split_evenly((1, n));
    for (area, panel) in areas.iter().zip(&figure.panels) {
        draw(area, panel)?;
    }
    Ok(())
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
    let plot_area = match panel.images.first() {
        Some(img) => {
            let (w, _) = root.dim_in_pixel();
            let (plot_area, bar_area) = root.split_horizontally(w.saturating_sub(COLORBAR_PX));
            colour_bar(&bar_area, img).map_err(e)?;
            plot_area
        }
        None => root.clone(),
    };
    let root = &plot_area;
    let (bx, by) = panel.data_bounds().unwrap_or(([0.0, 1.0], [0.0, 1.0]));
    let (x, y) = if panel.images.is_empty() {
        (padded(bx), padded(by))
    } else {
        // An image fills its axes edge to edge.
        ((bx[0], bx[1]), (by[0], by[1]))
    };
    // The range the studio opens on is the figure's range too.
    let x = panel.x.view.map_or(x, |[lo, hi]| (lo, hi));
    let y = panel.y.view.map_or(y, |[lo, hi]| (lo, hi));
    let (x, y) = if panel.equal_aspect {
        let (w, h) = root.dim_in_pixel();
        // The plotting area is about the drawing area less the label areas and margins.
        equal_aspect(
            x,
            y,
            f64::from(w.saturating_sub(112)),
            f64::from(h.saturating_sub(112)),
        )
    } else {
        (x, y)
    };
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
            .or_else(|| x_axis.tick_label(*v))
            .unwrap_or_else(|| format!("{}", (v * 1e4).round() / 1e4))
    };
    let y_axis = panel.y.clone();
    let fmt_y = move |v: &f64| {
        y_axis
            .tick_label(*v)
            .unwrap_or_else(|| format!("{}", (v * 1e4).round() / 1e4))
    };
    chart
        .configure_mesh()
        .x_desc(panel.x.title())
        .y_desc(panel.y.title())
        .x_label_formatter(&fmt_x)
        .y_label_formatter(&fmt_y)
        .label_style(("sans-serif", 16))
        .draw()
        .map_err(e)?;
    for img in &panel.images {
        chart.draw_series(cells(img)).map_err(e)?;
    }
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
            Mark::FaintLine | Mark::DottedLine => {
                let (style, width) = if s.mark == Mark::FaintLine {
                    (c.mix(0.55), 1)
                } else {
                    (c.mix(1.0), 2)
                };
                let line: Vec<(f64, f64)> = points.collect();
                let series = if s.mark == Mark::DottedLine {
                    chart.draw_series(DashedLineSeries::new(line, 2, 3, style.stroke_width(width)))
                } else {
                    chart.draw_series(LineSeries::new(line, style.stroke_width(width)))
                };
                series.map_err(e)?.label(name).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], style.stroke_width(width))
                });
            }
            Mark::Rules => {
                let faint = c.mix(0.5);
                chart
                    .draw_series(points.flat_map(|(x, _)| {
                        DashedLineSeries::new([(x, y.0), (x, y.1)], 2, 3, faint.stroke_width(1))
                    }))
                    .map_err(e)?
                    .label(name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], faint));
            }
            Mark::Hollow => {
                chart
                    .draw_series(points.map(|p| Circle::new(p, 6, c.stroke_width(2))))
                    .map_err(e)?
                    .label(name)
                    .legend(move |(x, y)| Circle::new((x + 10, y), 6, c.stroke_width(2)));
            }
            Mark::Bars => {
                let half = panel.bar_width() / 2.0;
                chart
                    .draw_series(
                        points.map(|(x, y)| {
                            Rectangle::new([(x - half, 0.0), (x + half, y)], c.filled())
                        }),
                    )
                    .map_err(e)?
                    .label(name)
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 10, y + 5)], c.filled())
                    });
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
        let corner = match panel.quietest_corner() {
            Corner::LeftTop => SeriesLabelPosition::UpperLeft,
            Corner::LeftBottom => SeriesLabelPosition::LowerLeft,
            Corner::RightTop => SeriesLabelPosition::UpperRight,
            Corner::RightBottom => SeriesLabelPosition::LowerRight,
        };
        chart
            .configure_series_labels()
            .position(corner)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

/// `x` and `y` widened about their centres so that one unit is as long across as up on a
/// plotting area of `w × h` pixels.
fn equal_aspect(x: (f64, f64), y: (f64, f64), w: f64, h: f64) -> ((f64, f64), (f64, f64)) {
    let (dx, dy) = (x.1 - x.0, y.1 - y.0);
    if !(dx > 0.0 && dy > 0.0 && w > 0.0 && h > 0.0) {
        return (x, y);
    }
    let per_px = (dx / w).max(dy / h);
    let (cx, cy) = ((x.0 + x.1) / 2.0, (y.0 + y.1) / 2.0);
    let (hx, hy) = (per_px * w / 2.0, per_px * h / 2.0);
    ((cx - hx, cx + hx), (cy - hy, cy + hy))
}

/// The image as filled cells, at most [`MAX_CELLS`] a side (nearest samples beyond).
fn cells(img: &Image) -> Vec<Rectangle<(f64, f64)>> {
    let (rows, cols) = img.values.dim();
    let (nr, nc) = (rows.min(MAX_CELLS), cols.min(MAX_CELLS));
    let (x0, y1) = (
        img.centre[0] - img.size[0] / 2.0,
        img.centre[1] + img.size[1] / 2.0,
    );
    let (w, h) = (
        img.size[0] / nc.max(1) as f64,
        img.size[1] / nr.max(1) as f64,
    );
    let colours = img.colours();
    let mut out = Vec::with_capacity(nr * nc);
    for i in 0..nr {
        for j in 0..nc {
            let (r, c) = (i * rows / nr, j * cols / nc);
            let rgb = colour(colours.get(r * cols + c).copied().unwrap_or(Rgb(0, 0, 0)));
            let (xl, yt) = (x0 + j as f64 * w, y1 - i as f64 * h);
            out.push(Rectangle::new([(xl, yt), (xl + w, yt - h)], rgb.filled()));
        }
    }
    out
}

/// The image's colour bar (the map bottom to top, its ticks, and the value's name and unit),
/// or its categories' key; nothing for a picture drawn as it is seen.
fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    img: &Image,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let style = ("sans-serif", 14).into_font().color(&BLACK);
    if let Paint::Categories(cats) = &img.paint {
        area.draw(&Text::new(img.name.clone(), (4, 20), style.clone()))?;
        for (k, cat) in cats.iter().enumerate() {
            let y = 48 + 24 * k as i32;
            area.draw(&Rectangle::new(
                [(8, y), (24, y + 16)],
                colour(cat.colour).filled(),
            ))?;
            area.draw(&Rectangle::new(
                [(8, y), (24, y + 16)],
                BLACK.stroke_width(1),
            ))?;
            area.draw(&Text::new(cat.label.clone(), (30, y), style.clone()))?;
        }
        return Ok(());
    }
    if !img.paint.has_colour_bar() {
        return Ok(());
    }
    let (_, h) = area.dim_in_pixel();
    let (top, bottom) = (48i32, h as i32 - 64);
    let span = f64::from((bottom - top).max(1));
    const BANDS: i32 = 64;
    for k in 0..BANDS {
        let t = (f64::from(k) + 0.5) / f64::from(BANDS);
        let y0 = bottom - (f64::from(k) / f64::from(BANDS) * span) as i32;
        let y1 = bottom - (f64::from(k + 1) / f64::from(BANDS) * span) as i32;
        let c = colour(img.colormap.at(t as f32));
        area.draw(&Rectangle::new([(8, y1), (28, y0)], c.filled()))?;
    }
    area.draw(&Rectangle::new(
        [(8, top), (28, bottom)],
        BLACK.stroke_width(1),
    ))?;
    for (t, label) in img.scale.tick_labels() {
        let y = bottom - (f64::from(t) * span) as i32;
        area.draw(&PathElement::new(
            vec![(28, y), (33, y)],
            BLACK.stroke_width(1),
        ))?;
        area.draw(&Text::new(label, (38, y - 7), style.clone()))?;
    }
    let log = matches!(
        img.scale,
        ColorScale::Log { .. } | ColorScale::LogRange { .. }
    );
    let title = match (&img.unit, log) {
        (Some(u), true) => format!("{} ({u}, log)", img.name),
        (Some(u), false) => format!("{} ({u})", img.name),
        (None, true) => format!("{} (log)", img.name),
        (None, false) => img.name.clone(),
    };
    area.draw(&Text::new(title, (4, top - 28), style))?;
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
            ..Panel::default()
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
    fn a_long_caption_wraps_at_spaces_within_the_width() {
        let caption = "word ".repeat(60);
        let lines = caption_lines(&caption, 400);
        assert!(lines.len() > 1);
        let max_chars = ((400 - 32) / (CAPTION_FONT_PX / 2)) as usize;
        assert!(
            lines.iter().all(|l| l.chars().count() <= max_chars),
            "{lines:?}"
        );
        assert_eq!(lines.join(" "), caption.trim());
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

    fn image_panel(n: usize) -> Panel {
        // A centred bright spot on a dark field, 1 µm a sample.
        let values = ndarray::Array2::from_shape_fn((n, n), |(r, c)| {
            let (dr, dc) = (r as f64 - n as f64 / 2.0, c as f64 - n as f64 / 2.0);
            (-(dr * dr + dc * dc) / 8.0).exp()
        });
        Panel {
            title: "PSF".into(),
            x: Axis::new("x", Some("µm")),
            y: Axis::new("y", Some("µm")),
            images: vec![Image {
                name: "PSF".into(),
                unit: None,
                values: std::sync::Arc::new(values),
                centre: [0.0, 0.0],
                size: [n as f64, n as f64],
                scale: ColorScale::Log {
                    reference: 1.0,
                    floor_decades: 4.0,
                },
                colormap: udc_core::figure::Colormap::Inferno,
                paint: udc_core::figure::Paint::Mapped,
            }],
            equal_aspect: true,
            ..Panel::default()
        }
    }

    #[test]
    fn an_image_is_drawn_through_its_map_with_a_colour_bar() {
        let dir = tempfile::tempdir().expect("tempdir");
        write_panel(dir.path(), "psf", &image_panel(32)).expect("drawn");
        let svg = std::fs::read_to_string(dir.path().join("psf.svg")).expect("svg");
        assert!(
            svg.contains("PSF (log)"),
            "the colour bar names the value and its scale"
        );
        assert!(
            svg.contains("1e-4") || svg.contains("0.0001"),
            "the bar's floor tick"
        );
        let rgb = image::open(dir.path().join("psf.png"))
            .expect("png")
            .to_rgb8();
        let (top, bottom) = (
            udc_core::figure::Colormap::Inferno.at(1.0),
            udc_core::figure::Colormap::Inferno.at(0.0),
        );
        let count = |c: Rgb| rgb.pixels().filter(|p| p.0 == [c.0, c.1, c.2]).count();
        // The spot's peak and the dark field are both on the page, the field far larger.
        assert!(count(top) > 0, "the peak's colour is drawn");
        assert!(
            count(bottom) > 20 * count(top).max(1),
            "the floor's colour fills the field"
        );
    }

    #[test]
    fn a_large_image_is_drawn_on_a_bounded_lattice() {
        let dir = tempfile::tempdir().expect("tempdir");
        write_panel(dir.path(), "big", &image_panel(1024)).expect("drawn");
        let bytes = std::fs::metadata(dir.path().join("big.svg"))
            .expect("svg")
            .len();
        // 256² cells at ~100 bytes each, not 1024² of them.
        assert!(bytes < 12_000_000, "the SVG is {bytes} bytes");
    }
}
