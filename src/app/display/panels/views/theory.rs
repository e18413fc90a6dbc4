//! The Theory view: the simulated PSF profile (or diffraction orders) and MTF drawn over the
//! closed-form pattern of the design's aperture, with the formula and how far they differ.
//! A lecturer loads a Fourier-optics preset, shows the two agree, then edits the opening and
//! watches them part.

use egui::{Color32, Ui};

use crate::app::display::panels::Shown;
use crate::app::widgets::figure::panel_ui;
use crate::core::figure::{Rgb, palette};
use crate::core::theory::{ProfileKind, Theory, TheoryComparison, compare, figures};
use crate::core::{Quality, SimError};

/// Deviation under which theory and simulation are said to agree (2 % of the peak).
const AGREE: f64 = 0.02;

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
        let colour = channel_colour(&ch.name);
        let lf_um2 = ch.wavelength_nm * d.optics.focal_length_mm;
        let mtf = figures::mtf_panel(c, &ch.name, colour);
        let plots = if mtf.is_some() { 2.0 } else { 1.0 };
        let height = ((ui.available_height() - 8.0) / plots).max(160.0);
        let profile = figures::profile_panel(c, &ch.name, colour, lf_um2, self.log);
        panel_ui(ui, "views_theory_profile", &profile, height);
        if let Some(m) = &mtf {
            panel_ui(ui, "views_theory_mtf", m, height);
        }
    }
}

/// The figure colour of a channel: red, green or blue by name, the first series colour
/// otherwise.
fn channel_colour(name: &str) -> Rgb {
    palette::channel(name).unwrap_or(palette::series(0))
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
