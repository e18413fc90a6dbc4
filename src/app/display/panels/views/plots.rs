//! Plot widgets of the result views: an image figure beside its colour bar, how image plots
//! share the space, and the MTF line plot.

use egui::{Color32, TextureId, Ui, vec2};
use egui_plot::{HoverPosition, Line, LineStyle, Plot, PlotPoints, VLine};

use crate::app::widgets::figure::{
    COLORBAR_WIDTH, ImageFrame, colour_bar_ui, image_panel_ui, lit_view_half,
};
use crate::app::widgets::plot::{
    LegendEntry, Swatch, hidden_names, legend_ui, visible_width, with_nice_ticks,
};
use crate::core::Analysis;
use crate::core::analysis::analyze::Quality;
use crate::core::figure::Panel;

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

/// An image panel beside its colour bar, laid out as the largest square that fits, opening on
/// where the light is.
pub(super) fn image_with_colour_bar_ui(
    ui: &mut Ui,
    id: &str,
    panel: &Panel,
    textures: &[TextureId],
) {
    let size = image_layout(ui, 1).size;
    ui.horizontal(|ui| {
        let frame = ImageFrame {
            size,
            link: None,
            view_half: lit_view_half(panel),
        };
        image_panel_ui(ui, id, panel, textures, frame);
        if let Some(img) = panel.images.first() {
            colour_bar_ui(ui, size.y, img);
        }
    });
}
