//! The numbers of the shown result, with units, and the sampling warnings.

use super::PanelCtx;
use crate::app::display::action::DisplayAction;

/// The Numbers panel: progress, open fraction, LTR, invertibility loss, per-channel MTF areas
/// and the sampling warnings of the shown result.
#[derive(Default)]
pub struct NumbersPanel;

impl NumbersPanel {
    /// Draws the panel; `progress` is the running job's fraction done (`None`: up to date).
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelCtx, progress: Option<f32>) {
        ui.horizontal(|ui| {
            match progress {
                Some(p) => {
                    ui.add(
                        egui::ProgressBar::new(p)
                            .desired_width(140.0)
                            .show_percentage()
                            .text("computing"),
                    );
                }
                None => {
                    ui.label("Up to date");
                }
            }
            if ui
                .button("Pin as A")
                .on_hover_text(
                    "Keep this design and its result as A to compare with your edits (Ctrl+P)",
                )
                .clicked()
            {
                ctx.actions.push(DisplayAction::PinCompare);
            }
        });
        let Some(shown) = ctx.shown else {
            ui.spinner();
            return;
        };
        let a = &shown.analysis;
        let d = &shown.design;
        super::quality::badge_ui(ui, shown);
        // Values that depend on the PSF sampling carry "≈" in a preview.
        let est = |v: String| super::quality::estimate(shown.quality, v);
        egui::Grid::new("numbers-grid").num_columns(2).striped(true).show(ui, |ui| {
            let row = |ui: &mut egui::Ui, k: &str, v: String, tip: &str| {
                ui.label(k).on_hover_text(tip);
                ui.monospace(v);
                ui.end_row();
            };
            row(ui, "Open fraction", format!("{:.2} %", 100.0 * a.open_fraction), "Open area of one pixel (intensity transmittance of the tile)");
            row(ui, "LTR", format!("{:.2} %", 100.0 * a.ltr), "Light transmittance ratio: fraction of the pupil's light that passes the display");
            // −0.00001 would print as "−0.0000": a sign that means nothing at four decimals.
            let l_inv = if a.invertibility_loss.abs() < 5e-5 { 0.0 } else { a.invertibility_loss };
            row(ui, "Invertibility loss", est(format!("{l_inv:.4}")), "L_inv = −mean of the lowest 30 % of H = |K|²/(|K|²+0.015), pooled over channels (thesis eq. 3.9); lower is better");
            row(ui, "Pixel pitch", format!("{:.1} µm ({:.0} DPI)", d.opening.pitch_um, d.opening.dpi()), "Display pixel pitch");
            row(ui, "Tiles in pupil", format!("{:.0}", a.tiles_in_pupil), "Display pixels inside the lens pupil");
        });
        ui.separator();
        // Four columns fit the panel at 1024 px; the normalised AUC is in the AUC's tooltip.
        egui::Grid::new("channel-grid").num_columns(4).striped(true).show(ui, |ui| {
            ui.strong("ch");
            ui.strong("λ (nm)").on_hover_text("Peak or mean wavelength");
            // The headers carry the preview's "≈", so the columns keep their width.
            ui.strong(est("AUC".into())).on_hover_text("Area under the radially-minimum MTF over 0…0.5 cycles/pixel; bigger is more invertible");
            ui.strong(est("in window".into())).on_hover_text("Fraction of the light inside the PSF window");
            ui.end_row();
            for c in &a.channels {
                ui.label(&c.name);
                ui.monospace(format!("{:.0}", c.wavelength_nm));
                ui.monospace(format!("{:.4}", c.mtf.auc_radial_min)).on_hover_text(format!(
                    "AUC {} = {:.5}; {:.1} % of the ideal 0.5",
                    c.name,
                    c.mtf.auc_radial_min,
                    100.0 * c.mtf.auc_normalised()
                ));
                ui.monospace(format!("{:.2} %", 100.0 * c.energy_in_window));
                ui.end_row();
            }
        });
        super::advice::warnings_ui(ui, ctx, shown);
    }
}
