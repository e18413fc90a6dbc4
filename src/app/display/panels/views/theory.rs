//! The Theory view: the simulated PSF profile (or diffraction orders) and MTF drawn over the
//! closed-form pattern of the design's aperture, with the formula and how far they differ.
//! A lecturer loads a Fourier-optics preset, shows the two agree, then edits the opening and
//! watches them part.

use egui::{Color32, Ui};
use egui_plot::{Corner, Legend, Line, LineStyle, MarkerShape, Plot, Points};

use super::images::channel_color;
use crate::app::display::panels::Shown;
use crate::app::widgets::plot::with_nice_ticks;
use crate::core::theory::{ProfileKind, Theory, TheoryComparison, compare};
use crate::core::{Quality, SimError};

/// Deviation under which theory and simulation are said to agree (2 % of the peak).
const AGREE: f64 = 0.02;
/// Values below this fraction of the peak sit on the floor of the log scale.
const LOG_FLOOR: f64 = 1e-6;

/// What a comparison was computed for: a new result or channel recomputes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Key {
    generation: u64,
    quality: Quality,
    channel: usize,
}

/// The Theory view's state (view state: never undone).
#[derive(Default)]
pub struct TheoryView {
    cached: Option<(Key, Result<TheoryComparison, SimError>)>,
    /// Profile on a log scale (the side lobes and the halo show).
    pub log: bool,
}

impl TheoryView {
    /// Draws the comparison of channel `channel` of `shown`.
    pub fn ui(&mut self, ui: &mut Ui, shown: &Shown, channel: usize) {
        let theory = shown.design.theory.unwrap_or(Theory::Grating);
        let key = Key {
            generation: shown.generation,
            quality: shown.quality,
            channel,
        };
        if self.cached.as_ref().map(|c| c.0) != Some(key) {
            // A few thousand closed-form values: cheap enough for the UI thread, once per result.
            let result = compare(&shown.design, theory, &shown.analysis, channel);
            self.cached = Some((key, result));
        }
        let Some((_, result)) = &self.cached else {
            return;
        };
        let Some(ch) = shown.analysis.channels.get(channel) else {
            return;
        };
        let d = &shown.design;
        let period_um = d.opening.pitch_um + d.tiling.wiring_gap_um;
        let formula = theory.formula(ch.wavelength_nm, d.optics.focal_length_mm, period_um);
        ui.horizontal_wrapped(|ui| {
            ui.strong(format!("Theory: {}", theory.name()));
            if d.theory.is_none() {
                ui.weak("(this design names no aperture: its own diffraction orders)");
            }
        });
        ui.label(&formula);
        let c = match result {
            Ok(c) => c,
            Err(e) => {
                let message = crate::app::display::labels::in_ui_words(&e.to_string());
                ui.colored_label(
                    ui.visuals().warn_fg_color,
                    format!("No comparison: {message}."),
                );
                return;
            }
        };
        agreement_ui(ui, c, theory);
        if let Some(note) = &c.note {
            ui.label(note);
        }
        if c.kind != ProfileKind::Orders {
            ui.checkbox(&mut self.log, "log scale")
                .on_hover_text("Show the profile in decades, so the side lobes show");
        }
        let color = channel_color(&ch.name);
        let lf_um2 = ch.wavelength_nm * d.optics.focal_length_mm;
        let plots = if c.mtf.is_some() { 2.0 } else { 1.0 };
        let height = ((ui.available_height() - 8.0) / plots).max(160.0);
        profile_plot_ui(
            ui,
            c,
            &ch.name,
            color,
            self.log,
            extent_um(theory, lf_um2),
            height,
        );
        if let Some(m) = &c.mtf {
            // Up to a little past the aperture's cutoff: a slit's MTF ends at 0.07 cycles/pixel.
            let last = m
                .predicted
                .iter()
                .rposition(|v| *v > 1e-3)
                .and_then(|i| m.freqs_cyc_per_px.get(i + 1))
                .map_or(0.5, |f| (1.3 * f).min(0.5));
            with_nice_ticks(Plot::new("views_theory_mtf"))
                .height(height)
                .legend(Legend::default().position(Corner::RightTop))
                .default_x_bounds(0.0, last)
                .default_y_bounds(0.0, 1.05)
                .x_axis_label("spatial frequency along x (cycles/pixel)")
                .y_axis_label("MTF")
                .show(ui, |p| {
                    let pts = |v: &[f64]| -> Vec<[f64; 2]> {
                        m.freqs_cyc_per_px
                            .iter()
                            .zip(v)
                            .map(|(f, y)| [*f, *y])
                            .collect()
                    };
                    p.line(
                        Line::new(format!("{} simulated", ch.name), pts(&m.simulated))
                            .color(color)
                            .width(2.0),
                    );
                    p.line(
                        Line::new("theory", pts(&m.predicted))
                            .color(Color32::WHITE)
                            .style(LineStyle::Dashed { length: 6.0 }),
                    );
                });
        }
    }
}

/// One line saying how well they agree, in the colour of the verdict.
fn agreement_ui(ui: &mut Ui, c: &TheoryComparison, theory: Theory) {
    let what = match c.kind {
        ProfileKind::Orders => "of the zero order's light",
        _ => "of the peak",
    };
    let mtf = c
        .mtf
        .as_ref()
        .map(|m| format!("; MTF within {:.3}", m.deviation))
        .unwrap_or_default();
    let text = format!(
        "Simulation and theory differ by at most {:.2} % {what}{mtf}.",
        100.0 * c.deviation
    );
    if c.note.is_some() {
        ui.label(text);
    } else if c.deviation < AGREE {
        ui.colored_label(Color32::from_rgb(120, 200, 120), text);
    } else {
        ui.colored_label(ui.visuals().warn_fg_color, text)
            .on_hover_text(format!(
                "The opening no longer is the {} the formula describes: the difference is the \
             diffraction of what you changed.",
                theory.name()
            ));
    }
}

/// How far from the axis the profile is shown at first, µm: a few lobes of the pattern.
fn extent_um(theory: Theory, lf_um2: f64) -> Option<f64> {
    match theory {
        Theory::Slit { width_um } | Theory::Rectangle { width_um, .. } => {
            Some(6.0 * lf_um2 / width_um)
        }
        Theory::DoubleSlit { width_um, .. } => Some(3.0 * lf_um2 / width_um),
        Theory::Circle { diameter_um } => Some(5.0 * 1.22 * lf_um2 / diameter_um),
        Theory::Grating => None,
    }
}

/// The profile (or the orders) against position on the sensor.
fn profile_plot_ui(
    ui: &mut Ui,
    c: &TheoryComparison,
    name: &str,
    color: Color32,
    log: bool,
    extent_um: Option<f64>,
    height: f32,
) {
    let value = |v: f64| {
        if log { v.max(LOG_FLOOR).log10() } else { v }
    };
    let pts = |v: &[f64]| -> Vec<[f64; 2]> {
        c.x_um.iter().zip(v).map(|(x, y)| [*x, value(*y)]).collect()
    };
    let mut plot = with_nice_ticks(Plot::new("views_theory_profile"))
        .height(height)
        .legend(Legend::default().position(Corner::RightTop))
        .x_axis_label("position on the sensor, x (µm)")
        .y_axis_label(if log {
            format!("{} (log10)", c.kind.label())
        } else {
            c.kind.label().to_string()
        });
    if let Some(e) = extent_um {
        plot = plot.default_x_bounds(-e, e);
    }
    if log {
        plot = plot
            .default_y_bounds(LOG_FLOOR.log10(), 0.1)
            .y_axis_formatter(|mark, _| format!("1e{:.0}", mark.value));
    }
    plot.show(ui, |p| match c.kind {
        ProfileKind::Orders => {
            p.points(
                Points::new(format!("{name} simulated"), pts(&c.simulated))
                    .color(color)
                    .shape(MarkerShape::Circle)
                    .filled(true)
                    .radius(4.0),
            );
            p.points(
                Points::new("theory", pts(&c.predicted))
                    .color(Color32::WHITE)
                    .shape(MarkerShape::Diamond)
                    .filled(false)
                    .radius(6.0),
            );
        }
        ProfileKind::ColumnSums | ProfileKind::AxisRow => {
            p.line(
                Line::new(format!("{name} simulated"), pts(&c.simulated))
                    .color(color)
                    .width(2.0),
            );
            p.line(
                Line::new("theory", pts(&c.predicted))
                    .color(Color32::WHITE)
                    .style(LineStyle::Dashed { length: 6.0 }),
            );
        }
    });
}
