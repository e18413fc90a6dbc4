//! The Expected PSF tab: this random tiling's PSF beside the expectation over all tilings, on
//! one colour scale, with linked axes that open on where the light is.

use egui::Ui;

use super::images::{log_image, peak};
use super::overlay::psf_overlay;
use super::plots::{ImagePlot, Scale, colorbar_ui, image_layout, image_plot_ui, view_half};
use super::textures::Slot;
use super::{ViewsPanel, psf_grid};
use crate::app::display::panels::Shown;
use crate::app::widgets::colormap::Colormap;
use crate::core::analysis::analyze::ChannelAnalysis;

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
        let Some(expected) = &ch.expected_psf else {
            ui.label(
                "The expected PSF was not computed for this result (previews skip it); it \
                 appears with the full-quality result.",
            );
            return;
        };
        // One colour scale for both: the larger of the two peaks.
        let reference = peak(&ch.psf).max(peak(expected));
        let floor = self.floor_decades;
        let key = self.key(shown, self.channel, floor);
        let ctx = ui.ctx().clone();
        let real = self.textures.get(&ctx, Slot::ExpectedRealisation, key, || {
            log_image(&ch.psf, reference, floor, Colormap::Inferno)
        });
        let mean = self.textures.get(&ctx, Slot::ExpectedMean, key, || {
            log_image(expected, reference, floor, Colormap::Inferno)
        });
        let grid = psf_grid(shown, ch);
        let overlay = overlays.then(|| psf_overlay(shown, ch, grid, self.overlay_choice));
        let scale = Scale::Log {
            reference,
            floor_decades: floor,
        };
        let layout = image_layout(ui, 2);
        let size = layout.size;
        // The axes are linked, so both open on the larger of the two lit areas.
        let half = view_half(&ch.psf, grid, scale).max(view_half(expected, grid, scale));
        let link = Some(ui.make_persistent_id("views_expected_link"));
        let seed = shown.design.tiling.seed;
        let plots = [
            (
                format!("this realisation ({}, seed {seed})", mode.as_str()),
                "views_expected_realisation",
                real,
                &ch.psf,
                "PSF",
            ),
            (
                "expected over all random tilings".to_owned(),
                "views_expected_mean",
                mean,
                expected,
                "expected PSF",
            ),
        ];
        let plots_ui = |ui: &mut Ui| {
            for (caption, id, texture, values, value_name) in &plots {
                ui.vertical(|ui| {
                    ui.label(caption);
                    image_plot_ui(
                        ui,
                        &ImagePlot {
                            id,
                            texture: *texture,
                            grid,
                            values,
                            scale,
                            unit: "µm",
                            value_name,
                            overlay: overlay.as_ref(),
                            link,
                            size,
                            view_half: half,
                        },
                    );
                });
            }
        };
        ui.horizontal(|ui| {
            let height = if layout.stacked {
                ui.vertical(plots_ui).response.rect.height()
            } else {
                ui.horizontal(plots_ui).response.rect.height()
            };
            colorbar_ui(ui, height, scale, Colormap::Inferno);
        });
    }
}
