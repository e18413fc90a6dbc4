//! A figure panel ([`crate::core::figure::Panel`]) drawn with egui_plot: the same description
//! the files are drawn from (`crate::io::figure`), so a plot on screen and its exported PNG
//! agree, with the studio's tick ladder, hover and zoom.

use egui::Color32;
use egui_plot::{FilledArea, HLine, Legend, Line, LineStyle, Plot, PlotPoints, Points, VLine};

use crate::core::figure::{Annotation, Mark, Panel, RING_SEGMENTS, Rgb, circle_points, palette};

/// The most points a point cloud draws each frame: beyond a few thousand an even sample shows
/// the cloud as well and keeps scrolling smooth (lines are always drawn whole).
const MAX_POINTS_DRAWN: usize = 5000;

/// The egui colour of a palette colour.
pub fn color32(c: Rgb) -> Color32 {
    Color32::from_rgb(c.0, c.1, c.2)
}

/// Draws `panel` (without its title: the caller places it) `height` points tall.
pub fn panel_ui(ui: &mut egui::Ui, id: impl egui::AsIdSalt, panel: &Panel, height: f32) {
    panel_ui_in(ui, id, panel, PlotFrame::tall(height));
}

/// Where a panel's plot sits: its size, and the plots its x axis pans and zooms with.
#[derive(Debug, Clone, Copy)]
pub struct PlotFrame {
    /// Width in points; `None`: the available width.
    pub width: Option<f32>,
    /// Height in points.
    pub height: f32,
    /// Plots sharing this id share their x axis (side-by-side channels).
    pub link_x: Option<egui::Id>,
}

impl PlotFrame {
    /// The available width, `height` points tall, on its own.
    pub fn tall(height: f32) -> Self {
        PlotFrame {
            width: None,
            height,
            link_x: None,
        }
    }
}

/// Draws `panel` (without its title) in `frame`.
pub fn panel_ui_in(ui: &mut egui::Ui, id: impl egui::AsIdSalt, panel: &Panel, frame: PlotFrame) {
    let height = frame.height;
    let mut plot = Plot::new(id);
    if let Some(w) = frame.width {
        plot = plot.width(w);
    }
    if let Some(link) = frame.link_x {
        plot = plot.link_axis(link, [true, false]);
    }
    if panel.wants_legend() {
        plot = plot.legend(Legend::default().position(egui_plot::Corner::RightBottom));
    }
    // The axis titles after the ticks, which replace the axes.
    let mut plot = crate::app::widgets::plot::with_nice_ticks(plot.height(height))
        .x_axis_label(panel.x.title())
        .y_axis_label(panel.y.title());
    if panel.x.categories.is_some() {
        // A word axis (a tiling): its values sit at 0, 1, 2… and are named there.
        let axis = panel.x.clone();
        plot =
            plot.x_axis_formatter(move |mark, _| axis.category_at(mark.value).unwrap_or_default());
    }
    plot.show(ui, |pl| {
        for s in &panel.series {
            let c = color32(s.colour);
            if let Some(band) = &s.band {
                let xs: Vec<f64> = band.iter().map(|b| b[0]).collect();
                let lo: Vec<f64> = band.iter().map(|b| b[1]).collect();
                let hi: Vec<f64> = band.iter().map(|b| b[2]).collect();
                pl.add(
                    FilledArea::new(format!("{} min–max", s.name), &xs, &lo, &hi)
                        .fill_color(c.gamma_multiply(0.25)),
                );
            }
            let finite = |p: &&[f64; 2]| p[0].is_finite() && p[1].is_finite();
            match s.mark {
                Mark::Points => {
                    let step = s.points.len().div_ceil(MAX_POINTS_DRAWN).max(1);
                    let name = if step > 1 {
                        format!("{} (1 in {step})", s.name)
                    } else {
                        s.name.clone()
                    };
                    let cloud: PlotPoints = s
                        .points
                        .iter()
                        .step_by(step)
                        .filter(finite)
                        .copied()
                        .collect();
                    pl.points(Points::new(name, cloud).color(c).radius(3.0));
                }
                Mark::DashedLine => {
                    let line: Vec<[f64; 2]> = s.points.iter().filter(finite).copied().collect();
                    // A reference is read against the data, not over it: dimmer.
                    pl.line(
                        Line::new(s.name.clone(), PlotPoints::from(line))
                            .color(c.gamma_multiply(0.6))
                            .style(LineStyle::dashed_dense()),
                    );
                }
                Mark::Line | Mark::LineAndPoints => {
                    let line: Vec<[f64; 2]> = s.points.iter().filter(finite).copied().collect();
                    let dots = (s.mark == Mark::LineAndPoints).then(|| line.clone());
                    pl.line(
                        Line::new(s.name.clone(), PlotPoints::from(line))
                            .color(c)
                            .width(2.0),
                    );
                    if let Some(dots) = dots {
                        pl.points(
                            Points::new(s.name.clone(), PlotPoints::from(dots))
                                .color(c)
                                .radius(3.0),
                        );
                    }
                }
            }
        }
        let c = color32(palette::ANNOTATION);
        for a in &panel.annotations {
            match a {
                Annotation::Ring {
                    centre,
                    radius,
                    label,
                } => {
                    let ring: PlotPoints = circle_points(*centre, *radius, RING_SEGMENTS).into();
                    pl.line(Line::new(label.clone(), ring).color(c).width(1.5));
                }
                Annotation::Lattice { points, label } => {
                    let lattice: PlotPoints = points.iter().copied().collect();
                    pl.points(Points::new(label.clone(), lattice).color(c).radius(2.0));
                }
                Annotation::VLine { x, label } => {
                    pl.vline(VLine::new(label.clone(), *x).color(c));
                }
                Annotation::HLine { y, label } => {
                    pl.hline(HLine::new(label.clone(), *y).color(c));
                }
            }
        }
    });
}
