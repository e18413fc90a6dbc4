//! Plot widgets of the result views: an image figure beside its colour bar, how image plots
//! share the space, and the MTF line plot.

use egui::{Ui, vec2};

use crate::app::widgets::figure::{
    COLORBAR_WIDTH, ImageFrame, PlotFrame, Shown, colour_bar_ui, image_panel_ui, panel_ui_in,
};
use crate::app::widgets::plot::visible_width;
use crate::core::Analysis;
use crate::core::figure::Panel;
use crate::core::views::mtf_curves_panel;

pub use crate::core::views::MtfFamilies;

/// MTF curves of `b` (solid) and the radial minima of the pinned design `a` (dashed, "A:"),
/// over 0…0.5 cycles/pixel, with the frequencies where `repeats`' MTF repeats. The legend sits
/// above the plot, a row per channel, so no curve hides behind it; clicking an entry hides its
/// curves. Returns the panel drawn (for Save figure).
pub fn mtf_plot_ui(
    ui: &mut Ui,
    id: &str,
    b: &Analysis,
    a: Option<&Analysis>,
    families: MtfFamilies,
    repeats: Option<&crate::core::Design>,
) -> Panel {
    let panel = mtf_curves_panel(b, a, families, repeats);
    let frame = PlotFrame {
        width: Some(visible_width(ui)),
        legend_above: true,
        // Room for the curves even under a long table (the Compare tab scrolls).
        ..PlotFrame::tall(ui.available_height().max(220.0))
    };
    panel_ui_in(ui, id, &panel, frame);
    panel
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
pub(super) fn image_with_colour_bar_ui(ui: &mut Ui, id: &str, shown: &Shown) {
    let (panel, textures) = (&shown.panel, &shown.textures);
    let size = image_layout(ui, 1).size;
    ui.horizontal(|ui| {
        let frame = ImageFrame {
            size,
            link: None,
            view_half: shown.view_half,
        };
        image_panel_ui(ui, id, panel, textures, frame);
        if let Some(img) = panel.images.first() {
            colour_bar_ui(ui, size.y, img);
        }
    });
}
