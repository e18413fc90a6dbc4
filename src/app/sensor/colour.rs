//! The colour sensor in the sensor workspace: the colour-filter choice, which planes a picture
//! shows (RGB on a Bayer sensor, grey otherwise) and the per-channel scores.

use egui::Ui;

use crate::core::sensor::colour::CHANNEL_NAMES;
use crate::core::sensor::{Cfa, SensorRun};

/// A row of the settings grid: the colour filter array.
pub fn cfa_row_ui(ui: &mut Ui, cfa: &mut Cfa) {
    ui.label("Colour filter");
    egui::ComboBox::from_id_salt("sensor_cfa")
        .selected_text(match cfa {
            Cfa::None => "none (mono)",
            Cfa::Rggb => "RGGB Bayer",
        })
        .show_ui(ui, |ui| {
            ui.selectable_value(cfa, Cfa::None, "none (mono)")
                .on_hover_text("A monochrome sensor on the scene's luminance");
            ui.selectable_value(cfa, Cfa::Rggb, "RGGB Bayer")
                .on_hover_text(
                    "A Bayer mosaic of the RGB scene; bins combine sites of one colour; \
                 Malvar-He-Cutler demosaic; scores on the demosaiced luminance",
                );
        });
    ui.end_row();
}

/// Under the numbers: worst-ROI SSIM and PSNR of each channel, on a colour sensor.
pub fn channels_ui(ui: &mut Ui, run: &SensorRun) {
    if run.colour_truth.is_none() {
        return;
    }
    ui.add_space(6.0);
    ui.label("Per channel (worst ROI SSIM, PSNR dB); the table above is the luminance");
    egui::Grid::new("sensor_channels")
        .striped(true)
        .num_columns(4)
        .show(ui, |ui| {
            ui.strong("strategy");
            for c in CHANNEL_NAMES {
                ui.strong(c);
            }
            ui.end_row();
            for s in &run.strategies {
                let Some(colour) = &s.colour else {
                    continue;
                };
                ui.label(&s.name);
                for ch in &colour.channels {
                    ui.monospace(format!("{:.4}, {:.1}", ch.worst_roi_ssim, ch.psnr_db));
                }
                ui.end_row();
            }
        });
}
