//! The Expected PSF tab: this random tiling's PSF beside the expectation over all tilings, on
//! one colour scale, with linked axes that open on where the light is.

use egui::Ui;

use super::ViewsPanel;
use super::plots::image_layout;
use super::textures::Slot;
use crate::app::display::panels::Shown;
use crate::app::widgets::figure::{ImageFrame, colour_bar_ui, image_panel_ui};
use crate::core::analysis::analyze::ChannelAnalysis;
use crate::core::views::expected_panels;

impl ViewsPanel {
    pub(super) fn expected_ui(
        &mut self,
        ui: &mut Ui,
        shown: &Shown,
        ch: &ChannelAnalysis,
        overlays: bool,
    ) {
        let mode = shown.design.tiling.mode;
        if !mode.is_random() {
            ui.label(
                "This design uses a periodic tiling (repeat): every pixel is identical, so there \
                 is no randomness to average and the expected PSF is the PSF itself. Choose a \
                 random tiling to compare one realisation with the expectation.",
            );
            return;
        }
        if ch.expected_psf.is_none() {
            ui.label(
                "The expected PSF was not computed for this result (previews skip it); it \
                 appears with the full-quality result.",
            );
            return;
        }
        let floor = self.floor_decades;
        let marks = self.landmarks(overlays);
        let key = self.key(shown, self.channel, floor, marks);
        let ctx = ui.ctx().clone();
        let build = |i: usize| {
            move || {
                expected_panels(&shown.design, &shown.analysis, ch, floor, marks)
                    .map(|[a, b]| if i == 0 { a } else { b })
                    .unwrap_or_default()
            }
        };
        let real = self
            .textures
            .get(&ctx, Slot::ExpectedRealisation, key, build(0));
        let mean = self.textures.get(&ctx, Slot::ExpectedMean, key, build(1));
        let layout = image_layout(ui, 2);
        let size = layout.size;
        // The axes are linked, so both open on the larger of the two lit areas.
        let half = match (real.view_half, mean.view_half) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        let link = Some(ui.make_persistent_id("views_expected_link"));
        let plots = [
            ("views_expected_realisation", &real),
            ("views_expected_mean", &mean),
        ];
        let plots_ui = |ui: &mut Ui| {
            for (id, figure) in &plots {
                let (panel, textures) = (&figure.panel, &figure.textures);
                ui.vertical(|ui| {
                    ui.label(&panel.title);
                    let frame = ImageFrame {
                        size,
                        link,
                        view_half: half,
                    };
                    image_panel_ui(ui, *id, panel, textures, frame);
                });
            }
        };
        ui.horizontal(|ui| {
            let height = if layout.stacked {
                ui.vertical(plots_ui).response.rect.height()
            } else {
                ui.horizontal(plots_ui).response.rect.height()
            };
            if let Some(img) = real.panel.images.first() {
                colour_bar_ui(ui, height, img);
            }
        });
    }
}
