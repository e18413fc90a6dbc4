//! Plot widgets of the result views: a zoomable image with a hover readout and optional
//! teaching overlays, its colour bar, and the MTF line plot.

use egui::{Align2, Color32, Id, Mesh, Rect, Sense, Stroke, TextureId, Ui, pos2, vec2};
use egui_plot::{
    HoverPosition, Line, LineStyle, MarkerShape, Plot, PlotImage, PlotPoint, PlotPoints, Points,
    VLine,
};
use ndarray::Array2;

use super::images::{Grid, format_value, light_half_extent};
use crate::app::widgets::colormap::Colormap;
use crate::app::widgets::plot::{
    LegendEntry, Swatch, hidden_names, legend_ui, visible_width, with_nice_ticks,
};
use crate::core::Analysis;
use crate::core::analysis::analyze::Quality;
use crate::core::figure::{RING_SEGMENTS, circle_points};

/// Width reserved beside an image plot for its colour bar and tick labels.
pub const COLORBAR_WIDTH: f32 = 78.0;

/// How values map to colours, for the colour bar and the hover readout.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scale {
    /// 0 … `max`, linear.
    Linear { max: f64 },
    /// `reference · 10^−floor_decades` … `reference`, logarithmic.
    Log { reference: f64, floor_decades: f64 },
}

/// Diffraction-order lattice and Airy ring drawn over a PSF, in µm.
#[derive(Debug, Clone, PartialEq)]
pub struct PsfOverlay {
    /// Spacing of the orders on the sensor, `λ f / T`, in µm.
    pub order_spacing_um: f64,
    /// The orders to mark (empty when they are switched off).
    pub lattice_um: Vec<[f64; 2]>,
    /// The Airy ring's radius `1.22 λ F#` in µm, when it is switched on.
    pub airy_radius_um: Option<f64>,
}

/// One zoomable image: a texture placed on `grid`, with `values` read out under the pointer.
pub struct ImagePlot<'a> {
    pub id: &'a str,
    pub texture: TextureId,
    pub grid: Grid,
    pub values: &'a Array2<f64>,
    pub scale: Scale,
    /// Unit of the axes, e.g. "µm" or "cyc/px".
    pub unit: &'a str,
    /// Name of the value in the readout, e.g. "PSF" or "MTF".
    pub value_name: &'a str,
    pub overlay: Option<&'a PsfOverlay>,
    /// Plots sharing this id pan, zoom and hover together.
    pub link: Option<Id>,
    pub size: egui::Vec2,
    /// Half-width of the view the plot opens on (and returns to on a double-click), centred on
    /// the axis: where the light is, not the whole window.
    pub view_half: f64,
}

impl Scale {
    /// The smallest value the colour map tells apart from no light: the floor of a log scale,
    /// 1 % of the maximum of a linear one (darker than that reads as black).
    pub fn visible_threshold(self) -> f64 {
        match self {
            Scale::Linear { max } => 0.01 * max,
            Scale::Log {
                reference,
                floor_decades,
            } => reference * 10f64.powf(-floor_decades),
        }
    }
}

/// Shows an image plot (data aspect 1, zoom and pan) with a hover readout of the value at the
/// pointer.
pub fn image_plot_ui(ui: &mut Ui, p: &ImagePlot<'_>) {
    let ImagePlot {
        grid,
        values,
        scale,
        unit,
        value_name,
        ..
    } = *p;
    let readout = move |pos: &HoverPosition<'_>| {
        let at = match pos {
            HoverPosition::NearDataPoint { position, .. }
            | HoverPosition::Elsewhere { position } => *position,
        };
        let [row, col] = grid.index_at(at.x, at.y)?;
        let v = *values.get([row, col])?;
        let [x, y] = grid.position(row, col);
        // The readout shows the true value, not the floored one the colour stands for.
        let log = match scale {
            Scale::Log { reference, .. } if v > 0.0 && reference > 0.0 => {
                format!(
                    "\nlog10({value_name} / peak) = {:.2}",
                    (v / reference).log10()
                )
            }
            Scale::Log { .. } => "\n(no light: drawn at the floor)".to_owned(),
            Scale::Linear { .. } if v > 0.0 => format!("\nlog10 = {:.2}", v.log10()),
            Scale::Linear { .. } => String::new(),
        };
        Some(format!(
            "x = {x:.3} {unit}, y = {y:.3} {unit}\n{value_name} = {}{log}",
            format_value(v)
        ))
    };
    let half = p.view_half;
    let mut plot = with_nice_ticks(Plot::new(p.id))
        .default_x_bounds(-half, half)
        .default_y_bounds(-half, half)
        .data_aspect(1.0)
        .width(p.size.x)
        .height(p.size.y)
        .show_crosshair(false)
        .x_axis_label(format!("x ({unit})"))
        .y_axis_label(format!("y ({unit})"))
        .label_formatter(readout);
    if let Some(link) = p.link {
        plot = plot.link_axis(link, true).link_cursor(link, true);
    }
    let [cx, cy] = grid.image_centre();
    let [w, h] = grid.image_size();
    plot.show(ui, |plot_ui| {
        // No name: the image needs no legend entry.
        plot_ui.image(PlotImage::new(
            "",
            p.texture,
            PlotPoint::new(cx, cy),
            vec2(w as f32, h as f32),
        ));
        // No legend over the data: the checkboxes above the plot name the overlays.
        if let Some(o) = p.overlay {
            if !o.lattice_um.is_empty() {
                plot_ui.points(
                    Points::new("diffraction orders", o.lattice_um.clone())
                        .shape(MarkerShape::Plus)
                        .radius(3.0)
                        .color(Color32::from_rgb(90, 220, 255))
                        // Hovering must keep reading the image under the pointer.
                        .allow_hover(false),
                );
            }
            if let Some(r) = o.airy_radius_um {
                plot_ui.line(
                    Line::new("Airy radius", circle_points([0.0, 0.0], r, RING_SEGMENTS))
                        .color(Color32::WHITE)
                        .width(1.0)
                        .allow_hover(false),
                );
            }
        }
    });
}

/// A vertical colour bar of `height` with tick labels: linear 0…max, or log decades below the
/// peak. Drawn as a mesh each frame (a few dozen quads: cheaper than keeping a texture).
pub fn colorbar_ui(ui: &mut Ui, height: f32, scale: Scale, map: Colormap) {
    let (rect, _) = ui.allocate_exact_size(vec2(COLORBAR_WIDTH, height), Sense::hover());
    let painter = ui.painter_at(rect);
    let bar = Rect::from_min_max(
        pos2(rect.left() + 4.0, rect.top() + 8.0),
        pos2(rect.left() + 18.0, rect.bottom() - 8.0),
    );
    const BANDS: usize = 64;
    let mut mesh = Mesh::default();
    for k in 0..BANDS {
        let t0 = k as f32 / BANDS as f32;
        let t1 = (k + 1) as f32 / BANDS as f32;
        let band = Rect::from_min_max(
            pos2(bar.left(), bar.bottom() - t1 * bar.height()),
            pos2(bar.right(), bar.bottom() - t0 * bar.height()),
        );
        mesh.add_colored_rect(band, map.color((t0 + t1) / 2.0));
    }
    painter.add(mesh);
    let text = ui.visuals().text_color();
    painter.rect_stroke(
        bar,
        0.0,
        Stroke::new(1.0, ui.visuals().weak_text_color()),
        egui::StrokeKind::Outside,
    );
    let ticks: Vec<(f32, String)> = match scale {
        Scale::Linear { max } => (0..=4)
            .map(|k| (k as f32 / 4.0, format_value(max * k as f64 / 4.0)))
            .collect(),
        Scale::Log { floor_decades, .. } => {
            let decades = floor_decades.round().max(1.0) as i32;
            // Label every decade, or every other one when they would crowd.
            let every = if decades > 6 { 2 } else { 1 };
            (0..=decades)
                .filter(|d| d % every == 0 || *d == decades)
                .map(|d| {
                    let t = 1.0 - d as f32 / floor_decades as f32;
                    let label = if d == 0 {
                        "peak".into()
                    } else {
                        format!("1e-{d}")
                    };
                    (t.clamp(0.0, 1.0), label)
                })
                .collect()
        }
    };
    let font = egui::TextStyle::Body.resolve(ui.style());
    for (t, label) in ticks {
        let y = bar.bottom() - t * bar.height();
        painter.line_segment(
            [pos2(bar.right(), y), pos2(bar.right() + 4.0, y)],
            Stroke::new(1.0, text),
        );
        painter.text(
            pos2(bar.right() + 6.0, y),
            Align2::LEFT_CENTER,
            label,
            font.clone(),
            text,
        );
    }
}

/// Which curve families the MTF plot shows (view state).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MtfFamilies {
    pub horizontal: bool,
    pub vertical: bool,
    pub radial_min: bool,
    pub radial_mean: bool,
}

impl Default for MtfFamilies {
    fn default() -> Self {
        MtfFamilies {
            horizontal: false,
            vertical: false,
            radial_min: true,
            radial_mean: true,
        }
    }
}

impl MtfFamilies {
    /// Only the radial minimum (the Compare tab).
    pub const RADIAL_MIN: MtfFamilies = MtfFamilies {
        horizontal: false,
        vertical: false,
        radial_min: true,
        radial_mean: false,
    };
}

fn curve(freqs: &[f64], values: &[f64]) -> Vec<[f64; 2]> {
    freqs.iter().zip(values).map(|(f, v)| [*f, *v]).collect()
}

/// A family of vertical marker lines on the MTF plot (one legend entry for all of them).
#[derive(Debug, Clone, PartialEq)]
pub struct Markers {
    pub label: String,
    pub freqs_cyc_per_px: Vec<f64>,
    pub color: Color32,
}

/// The AUC as a legend shows it: a preview's is marked as an estimate.
fn auc_label(analysis: &Analysis, auc: f64) -> String {
    match analysis.quality {
        Quality::Full => format!("AUC {auc:.3}"),
        Quality::Preview => format!("AUC ≈ {auc:.3}, preview"),
    }
}

/// The MTF plot's items, one legend entry each (a marker family is one entry for all its lines).
enum MtfItem<'a> {
    Curve {
        values: &'a [f64],
        freqs: Vec<f64>,
        width: f32,
        style: LineStyle,
    },
    Marks(&'a [f64]),
}

/// MTF curves of `b` (solid) and the radial minima of the pinned design `a` (dashed, "A:"),
/// over 0…0.5 cycles/pixel, with optional vertical marker lines. The legend sits above the
/// plot, a row per channel, so no curve hides behind it; clicking an entry hides its curves.
pub fn mtf_plot_ui(
    ui: &mut Ui,
    id: &str,
    b: &Analysis,
    a: Option<&Analysis>,
    families: MtfFamilies,
    markers: &[Markers],
    channel_color: impl Fn(&str) -> Color32,
) {
    let mut groups: Vec<Vec<(LegendEntry, MtfItem<'_>)>> = Vec::new();
    let curve_item = |values,
                      ch: &crate::core::analysis::analyze::ChannelAnalysis,
                      width,
                      style| MtfItem::Curve {
        values,
        freqs: ch.mtf.freqs_cyc_per_px(),
        width,
        style,
    };
    for ch in &b.channels {
        let color = channel_color(&ch.name);
        let (m, name) = (&ch.mtf, &ch.name);
        let mut g = Vec::new();
        if families.radial_min {
            let label = format!("{name} radial min ({})", auc_label(b, m.auc_radial_min));
            g.push((
                LegendEntry::new(label, color, Swatch::Solid(2)),
                curve_item(&m.radial_min, ch, 2.0, LineStyle::Solid),
            ));
        }
        if families.radial_mean {
            let faint = color.gamma_multiply(0.55);
            g.push((
                LegendEntry::new(format!("{name} radial mean"), faint, Swatch::Solid(1)),
                curve_item(&m.radial_mean, ch, 1.0, LineStyle::Solid),
            ));
        }
        if families.horizontal {
            g.push((
                LegendEntry::new(format!("{name} horizontal"), color, Swatch::Dotted),
                curve_item(&m.horizontal, ch, 1.5, LineStyle::Dotted { spacing: 4.0 }),
            ));
        }
        if families.vertical {
            g.push((
                LegendEntry::new(format!("{name} vertical"), color, Swatch::Dashed),
                curve_item(&m.vertical, ch, 1.5, LineStyle::Dashed { length: 4.0 }),
            ));
        }
        groups.push(g);
    }
    groups.push(
        markers
            .iter()
            .map(|m| {
                let faint = m.color.gamma_multiply(0.6);
                (
                    LegendEntry::new(m.label.clone(), faint, Swatch::Dotted),
                    MtfItem::Marks(&m.freqs_cyc_per_px),
                )
            })
            .collect(),
    );
    // A's curve of a channel sits in that channel's row; channels only A has, in a last row.
    let mut a_only = Vec::new();
    if let Some(a) = a {
        for ch in &a.channels {
            let m = &ch.mtf;
            let label = format!(
                "A: {} radial min ({})",
                ch.name,
                auc_label(a, m.auc_radial_min)
            );
            let entry = (
                LegendEntry::new(label, channel_color(&ch.name), Swatch::Dashed),
                curve_item(&m.radial_min, ch, 1.5, LineStyle::dashed_loose()),
            );
            // The first groups are B's channels, one each, in order.
            match b.channels.iter().position(|c| c.name == ch.name) {
                Some(row) => groups[row].push(entry),
                None => a_only.push(entry),
            }
        }
    }
    groups.push(a_only);
    let legend_id = ui.make_persistent_id((id, "legend"));
    let entries: Vec<Vec<LegendEntry>> = groups
        .iter()
        .map(|g| g.iter().map(|(e, _)| e.clone()).collect())
        .collect();
    legend_ui(ui, legend_id, &entries);
    let hidden = hidden_names(ui.ctx(), legend_id);
    with_nice_ticks(Plot::new(id))
        .width(visible_width(ui))
        // Room for the curves even under a long table (the Compare tab scrolls).
        .height(ui.available_height().max(220.0))
        .default_x_bounds(0.0, 0.5)
        .default_y_bounds(0.0, 1.0)
        .x_axis_label("spatial frequency (cycles/pixel)")
        .y_axis_label("MTF (fraction of DC)")
        .label_formatter(|pos| match pos {
            HoverPosition::NearDataPoint {
                plot_name,
                position,
                ..
            } => Some(format!(
                "{plot_name}\nν = {:.3} cyc/px, MTF = {:.3}",
                position.x, position.y
            )),
            HoverPosition::Elsewhere { position } => Some(format!("ν = {:.3} cyc/px", position.x)),
        })
        .show(ui, |plot_ui| {
            // Marker lines first, under the curves.
            let items = groups
                .iter()
                .flatten()
                .filter(|(e, _)| !hidden.contains(&e.name));
            let (marks, curves): (Vec<_>, Vec<_>) =
                items.partition(|(_, item)| matches!(item, MtfItem::Marks(_)));
            for (e, item) in marks.into_iter().chain(curves) {
                match item {
                    MtfItem::Marks(freqs) => {
                        for nu in *freqs {
                            plot_ui.vline(
                                VLine::new(e.name.clone(), *nu)
                                    .color(e.color)
                                    .style(LineStyle::dotted_dense())
                                    .allow_hover(false),
                            );
                        }
                    }
                    MtfItem::Curve {
                        values,
                        freqs,
                        width,
                        style,
                    } => {
                        plot_ui.line(
                            Line::new(e.name.clone(), PlotPoints::new(curve(freqs, values)))
                                .color(e.color)
                                .width(*width)
                                .style(*style),
                        );
                    }
                }
            }
        });
}

/// Room the axes take beside a plot's data: tick labels and the axis title on the left, the
/// same below.
const AXES: egui::Vec2 = vec2(56.0, 40.0);

/// How image plots share the space: the size of each plot widget, and whether they are stacked
/// (one above the other) rather than side by side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ImageLayout {
    pub size: egui::Vec2,
    pub stacked: bool,
}

/// Lays out `count` image plots and one colour bar so that each plot's data area is the largest
/// square that fits: side by side in a wide area, stacked in a tall one. Data of aspect 1 in a
/// square frame uses the whole frame, none of it blank axis range.
pub(super) fn image_layout(ui: &Ui, count: usize) -> ImageLayout {
    // Never past the panel's visible edge, even when a row above ran over it.
    let avail = vec2(visible_width(ui), ui.available_height());
    let gap = ui.spacing().item_spacing;
    let k = count.max(1) as f32;
    // Side-by-side plots carry a caption line each.
    let caption = if count > 1 {
        ui.text_style_height(&egui::TextStyle::Body) + gap.y
    } else {
        0.0
    };
    let width = avail.x - COLORBAR_WIDTH - gap.x * k;
    let beside = (width / k - AXES.x).min(avail.y - caption - AXES.y);
    let above = (width - AXES.x).min((avail.y - gap.y * (k - 1.0)) / k - caption - AXES.y);
    let stacked = count > 1 && above > beside;
    let side = beside.max(above).max(120.0);
    ImageLayout {
        size: vec2(side + AXES.x, side + AXES.y),
        stacked,
    }
}

/// The view an image plot opens on: where `values` are brighter than the colour scale's floor.
pub(super) fn view_half(values: &ndarray::Array2<f64>, grid: Grid, scale: Scale) -> f64 {
    light_half_extent(values, grid, scale.visible_threshold())
}

pub(super) fn image_with_colorbar_ui(
    ui: &mut Ui,
    id: &str,
    texture: TextureId,
    grid: Grid,
    values: &ndarray::Array2<f64>,
    scale: Scale,
    overlay: Option<&PsfOverlay>,
) {
    let size = image_layout(ui, 1).size;
    ui.horizontal(|ui| {
        image_plot_ui(
            ui,
            &ImagePlot {
                id,
                texture,
                grid,
                values,
                scale,
                unit: "µm",
                value_name: "PSF",
                overlay,
                link: None,
                size,
                view_half: view_half(values, grid, scale),
            },
        );
        colorbar_ui(ui, size.y, scale, Colormap::Inferno);
    });
}
