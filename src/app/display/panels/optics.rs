//! Camera optics, sampling and colour channels.

use super::PanelCtx;
use crate::app::display::action::DisplayAction;
// The advice's limits are these fields' ranges: a fix the fields would clamp is no fix.
use crate::core::analysis::advice::{
    MAX_FIX_WINDOW_PX, MIN_FIX_FINE_SAMPLE_UM, MIN_FIX_PUPIL_SAMPLE_UM,
};
use crate::core::design::{Channel, Design, OpticsRecipe};
use crate::core::sweep::one_axis::SweepParameter;

/// The Optics panel: recipe, focal length, f-number, sampling, sampling phase and colour
/// channels.
#[derive(Default)]
pub struct OpticsPanel {
    draft: Option<Design>,
    /// Wavelength step for the spectral channels, nm.
    pub spectral_step_nm: f64,
}

fn num(
    ui: &mut egui::Ui,
    label: &str,
    v: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    speed: f64,
    suffix: &str,
    tip: &str,
) -> egui::Response {
    ui.label(label);
    let r = ui
        .add(
            crate::app::widgets::number(v)
                .range(range)
                .speed(speed)
                .suffix(suffix)
                .max_decimals(4),
        )
        .on_hover_text(tip);
    ui.end_row();
    r
}

impl OpticsPanel {
    /// Draws the panel; values being dragged are held in a draft and committed on release.
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelCtx) {
        let mut d = self.draft.clone().unwrap_or_else(|| ctx.design.clone());
        let mut dragging = false;
        ui.horizontal(|ui| {
            ui.label("Recipe:");
            for recipe in OpticsRecipe::NAMED {
                if ui
                    .selectable_label(d.optics.recipe == recipe, recipe.as_str())
                    .on_hover_text(recipe.describe())
                    .clicked()
                    && let Some(o) = recipe.optics()
                {
                    d.optics = o;
                }
            }
        });
        let before = d.optics.clone();
        egui::Grid::new("optics-grid").num_columns(2).show(ui, |ui| {
            let o = &mut d.optics;
            let r = num(ui, "Focal length", &mut o.focal_length_mm, 0.5..=100.0, 0.05, " mm", "Lens focal length f (mm); right-click: sweep it");
            dragging |= r.dragged();
            super::one_axis_sweep::sweep_menu(&r, SweepParameter::FocalLengthMm, ctx.actions);
            let r = num(ui, "f-number", &mut o.f_number, 0.5..=32.0, 0.01, "", "F# = f / D; right-click: sweep it");
            dragging |= r.dragged();
            super::one_axis_sweep::sweep_menu(&r, SweepParameter::FNumber, ctx.actions);
            ui.label("Pupil diameter");
            ui.label(format!("{:.3} mm", o.pupil_diameter_um() / 1000.0));
            ui.end_row();
            dragging |= num(ui, "Pupil sampling δ1", &mut o.pupil_sample_um, MIN_FIX_PUPIL_SAMPLE_UM..=64.0, 0.05, " µm", "Pupil/display sample spacing (µm); must resolve the display cells").dragged();
            dragging |= num(ui, "Fine PSF spacing δ2", &mut o.fine_sample_um, MIN_FIX_FINE_SAMPLE_UM..=8.0, 0.01, " µm", "Target fine PSF spacing on the sensor (µm); FFT size M = 2·floor(λf/(2 δ1 δ2))").dragged();
            let r = num(ui, "Sensor pixel", &mut o.sensor_pixel_um, 0.2..=20.0, 0.01, " µm", "Sensor pixel pitch (µm); right-click: sweep it");
            dragging |= r.dragged();
            super::one_axis_sweep::sweep_menu(&r, SweepParameter::SensorPixelUm, ctx.actions);
            ui.label("Window");
            let r = ui
                .add(crate::app::widgets::number(&mut o.window_px).range(8..=MAX_FIX_WINDOW_PX).suffix(" px"))
                .on_hover_text("Side of the square PSF window, in sensor pixels");
            dragging |= r.dragged();
            ui.end_row();
            let px = o.sensor_pixel_um;
            dragging |= num(ui, "Axis in pixel x", &mut o.axis_in_pixel_um[0], 0.0..=px * 0.999, 0.01, " µm", "Sampling phase: where the optical axis lies inside its pixel, from the pixel's left edge (µm)").dragged();
            dragging |= num(ui, "Axis in pixel y", &mut o.axis_in_pixel_um[1], 0.0..=px * 0.999, 0.01, " µm", "Sampling phase along y, from the pixel's lower edge (µm)").dragged();
        });
        if d.optics != before {
            d.optics.recipe = OpticsRecipe::Custom;
        }
        ui.separator();
        ui.label("Channels");
        egui::Grid::new("channels-grid")
            .num_columns(3)
            .show(ui, |ui| {
                for ch in &mut d.channels {
                    ui.label(&ch.name);
                    if ch.wavelengths_nm.len() == 1 {
                        let r = ui
                            .add(
                                crate::app::widgets::number(&mut ch.wavelengths_nm[0])
                                    .range(350.0..=1100.0)
                                    .speed(1.0)
                                    .suffix(" nm"),
                            )
                            .on_hover_text("Peak wavelength of the channel (nm)");
                        dragging |= r.dragged();
                        ui.label("peak");
                    } else {
                        ui.label(format!(
                            "{} wavelengths, {:.0}–{:.0} nm",
                            ch.wavelengths_nm.len(),
                            ch.wavelengths_nm.first().copied().unwrap_or(0.0),
                            ch.wavelengths_nm.last().copied().unwrap_or(0.0)
                        ));
                        ui.label(format!("mean {:.0} nm", ch.mean_wavelength_nm()));
                    }
                    ui.end_row();
                }
            });
        ui.horizontal(|ui| {
            if ui
                .button("Peak RGB")
                .on_hover_text("One wavelength per channel: R 610, G 530, B 470 nm (the thesis)")
                .clicked()
            {
                d.channels = Channel::rgb_peaks();
            }
            if self.spectral_step_nm <= 0.0 {
                self.spectral_step_nm = 30.0;
            }
            ui.add(crate::app::widgets::number(&mut self.spectral_step_nm).range(5.0..=100.0).suffix(" nm step"))
                .on_hover_text("Wavelength step when sampling a spectral response (smaller = slower)");
            if ui
                .button("Spectral CSV…")
                .on_hover_text("Weight each channel by a sensor spectral response (CSV: wavelength_nm, r, g, b)")
                .clicked()
            {
                ctx.actions.push(DisplayAction::LoadSpectral(self.spectral_step_nm));
            }
        });
        if dragging {
            self.draft = Some(d);
        } else {
            self.draft = None;
            ctx.edit(d);
        }
    }
}
