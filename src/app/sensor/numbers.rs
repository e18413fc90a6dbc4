//! The sensor workspace's right panel: the Table 5.4-style numbers of the shown run.

use egui::{RichText, Ui};

use super::{Quality, SensorCtx};

/// Right: the Table 5.4-style numbers of the shown run.
#[derive(Default)]
pub struct NumbersPanel;

impl NumbersPanel {
    /// Draws the panel.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut SensorCtx<'_>) {
        ui.heading("Numbers");
        match (ctx.running, ctx.shown) {
            (Some((quality, fraction)), _) => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label(match quality {
                        Quality::Preview => "preview…",
                        Quality::Full => "full scene…",
                    });
                });
                ui.add(egui::ProgressBar::new(fraction));
            }
            (None, Some(s)) => {
                ui.weak(format!(
                    "{} · {}×{} px · {:.0} ms",
                    match s.quality {
                        Quality::Preview => "preview",
                        Quality::Full => "full scene",
                    },
                    s.run.electrons.ncols(),
                    s.run.electrons.nrows(),
                    s.run.elapsed_ms
                ));
            }
            (None, None) => {}
        }
        let Some(shown) = ctx.shown else {
            ui.label("Open an HDR scene to start.");
            return;
        };
        let run = &shown.run;
        ui.label(format!(
            "ROI {} px; metrics after the tone curve",
            run.roi_px
        ));
        egui::Grid::new("sensor_numbers")
            .striped(true)
            .num_columns(6)
            .show(ui, |ui| {
                for h in [
                    "strategy",
                    "worst ROI SSIM",
                    "mean SSIM",
                    "PSNR (dB)",
                    "saturated",
                    "saturated ROIs",
                ] {
                    ui.strong(h);
                }
                ui.end_row();
                let best = run
                    .strategies
                    .iter()
                    .map(|s| s.worst_roi_ssim)
                    .fold(f64::NEG_INFINITY, f64::max);
                for s in &run.strategies {
                    let name = RichText::new(&s.name);
                    ui.label(if s.worst_roi_ssim == best {
                        name.strong()
                    } else {
                        name
                    });
                    ui.monospace(format!("{:.4}", s.worst_roi_ssim));
                    ui.monospace(format!("{:.4}", s.mean_ssim));
                    ui.monospace(format!("{:.2}", s.psnr_db));
                    ui.monospace(format!("{:.2} %", 100.0 * s.saturated_fraction))
                        .on_hover_text("Pixels whose readout (or bin) hit the ADC's top code");
                    ui.monospace(format!("{:.1} %", 100.0 * s.saturated_roi_fraction))
                        .on_hover_text("ROIs holding at least one saturated pixel");
                    ui.end_row();
                }
            });
        ui.add_space(6.0);
        egui::Grid::new("sensor_dr").num_columns(2).show(ui, |ui| {
            ui.strong("strategy");
            ui.strong("dynamic range");
            ui.end_row();
            for s in &run.strategies {
                ui.label(&s.name);
                ui.monospace(format!("{:.1} dB", s.dynamic_range_db));
                ui.end_row();
            }
        });
        super::colour::channels_ui(ui, run);
    }
}
