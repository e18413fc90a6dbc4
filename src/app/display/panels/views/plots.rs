//! Plot widgets of the result views: a zoomable image with a hover readout and optional
//! teaching overlays, its colour bar, and the MTF line plot.

use egui::{Align2, Color32, FontId, Id, Mesh, Rect, Sense, Stroke, TextureId, Ui, pos2, vec2};
use egui_plot::{
    HoverPosition, Legend, Line, LineStyle, MarkerShape, Plot, PlotImage, PlotPoint, PlotPoints,
    Points, VLine,
};
use ndarray::Array2;

use super::images::{Grid, circle_points, format_value};
use crate::app::widgets::colormap::Colormap;
use crate::core::Analysis;

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
    let mut plot = Plot::new(p.id)
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
                    Line::new("Airy radius", circle_points(r, 96))
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
    let font = FontId::proportional(11.0);
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

/// MTF curves of `b` (solid) and the radial minima of the pinned design `a` (dashed, "A:"),
/// over 0…0.5 cycles/pixel, with optional vertical marker lines.
pub fn mtf_plot_ui(
    ui: &mut Ui,
    id: &str,
    b: &Analysis,
    a: Option<&Analysis>,
    families: MtfFamilies,
    markers: &[Markers],
    channel_color: impl Fn(&str) -> Color32,
) {
    Plot::new(id)
        .legend(Legend::default())
        .default_x_bounds(0.0, 0.5)
        .default_y_bounds(0.0, 1.0)
        .x_axis_label("spatial frequency (cycles/pixel)")
        .y_axis_label("MTF")
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
            // Lines of one family share a name, so the legend groups (and toggles) them together.
            for m in markers {
                for nu in &m.freqs_cyc_per_px {
                    plot_ui.vline(
                        VLine::new(m.label.clone(), *nu)
                            .color(m.color.gamma_multiply(0.6))
                            .style(LineStyle::dotted_dense())
                            .allow_hover(false),
                    );
                }
            }
            for ch in &b.channels {
                let color = channel_color(&ch.name);
                let freqs = ch.mtf.freqs_cyc_per_px();
                let m = &ch.mtf;
                if families.horizontal {
                    plot_ui.line(
                        Line::new(
                            format!("{} horizontal", ch.name),
                            curve(&freqs, &m.horizontal),
                        )
                        .color(color)
                        .style(LineStyle::Dotted { spacing: 4.0 }),
                    );
                }
                if families.vertical {
                    plot_ui.line(
                        Line::new(format!("{} vertical", ch.name), curve(&freqs, &m.vertical))
                            .color(color)
                            .style(LineStyle::Dashed { length: 4.0 }),
                    );
                }
                if families.radial_mean {
                    plot_ui.line(
                        Line::new(
                            format!("{} radial mean", ch.name),
                            curve(&freqs, &m.radial_mean),
                        )
                        .color(color.gamma_multiply(0.55))
                        .width(1.0),
                    );
                }
                if families.radial_min {
                    plot_ui.line(
                        Line::new(
                            format!("{} radial min (AUC {:.3})", ch.name, m.auc_radial_min),
                            curve(&freqs, &m.radial_min),
                        )
                        .color(color)
                        .width(2.0),
                    );
                }
            }
            for ch in a.map(|a| a.channels.as_slice()).unwrap_or_default() {
                let freqs = ch.mtf.freqs_cyc_per_px();
                plot_ui.line(
                    Line::new(
                        format!(
                            "A: {} radial min (AUC {:.3})",
                            ch.name, ch.mtf.auc_radial_min
                        ),
                        PlotPoints::new(curve(&freqs, &ch.mtf.radial_min)),
                    )
                    .color(channel_color(&ch.name))
                    .width(1.5)
                    .style(LineStyle::dashed_loose()),
                );
            }
        });
}

/// Size of each of `count` image plots side by side, leaving room for one colour bar.
pub(super) fn plot_size(ui: &Ui, count: usize) -> egui::Vec2 {
    let avail = ui.available_size();
    let gaps = ui.spacing().item_spacing.x * count as f32;
    let w = ((avail.x - COLORBAR_WIDTH - gaps) / count.max(1) as f32).max(120.0);
    // Leave a line for the captions above side-by-side plots.
    let h = (avail.y - if count > 1 { 24.0 } else { 0.0 }).max(160.0);
    egui::vec2(w, h)
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
    let size = plot_size(ui, 1);
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
            },
        );
        colorbar_ui(ui, size.y, scale, Colormap::Inferno);
    });
}
