//! Which numbers are on screen: where the design's f-number allows it, an edit shows a quick
//! preview first (twice the fine PSF spacing δ2, within 3 % of full quality's AUC) and the
//! full-quality result after it; every place that shows a result's numbers says which of the
//! two it is.

use super::Shown;
use crate::core::analysis::analyze::Quality;

/// A length in µm with up to two decimals (`1`, `0.5`, `2.25`).
fn um(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// The badge's text and its tooltip for `shown`.
pub fn badge_text(shown: &Shown) -> (String, String) {
    let a = &shown.analysis;
    // Every channel of one result shares the quality; the first one's spacing stands for all.
    let fine = a.channels.first().map(|c| c.fine_um);
    let spacing = fine.map_or_else(String::new, |f| format!(" (δ2 = {} µm)", um(f)));
    let full_um = Quality::Full.fine_sample_um(&shown.design);
    match shown.quality {
        Quality::Preview => (
            format!("Preview estimate{spacing}: full quality follows"),
            format!(
                "A quick first result at twice the fine PSF spacing δ2, taken only where this \
                 f-number oversamples the PSF enough for the AUC to stay within 3 % of full \
                 quality's. The numbers marked ≈ (AUC, L_inv, light in the window) can still move \
                 a little when the full-quality result (δ2 = {} µm) arrives.",
                um(full_um)
            ),
        ),
        Quality::Full => (
            format!("Full quality{spacing} · {:.0} ms", a.elapsed_ms),
            "The design's own sampling (Optics > Fine PSF spacing δ2): these are the numbers \
             that are saved, exported and compared."
                .to_owned(),
        ),
    }
}

/// A value as shown for `quality`: a preview's sampling-dependent values carry "≈".
pub fn estimate(quality: Quality, value: String) -> String {
    match quality {
        Quality::Preview => format!("≈ {value}"),
        Quality::Full => value,
    }
}

/// The badge: amber for a preview estimate, green for full quality.
pub fn badge_ui(ui: &mut egui::Ui, shown: &Shown) {
    let (text, tip) = badge_text(shown);
    let color = match shown.quality {
        Quality::Preview => ui.visuals().warn_fg_color,
        Quality::Full => egui::Color32::from_rgb(70, 175, 90),
    };
    egui::Frame::new()
        .fill(color.gamma_multiply(0.15))
        .stroke(egui::Stroke::new(1.0, color.gamma_multiply(0.6)))
        .corner_radius(4.0)
        .inner_margin(egui::Margin::symmetric(6, 2))
        .show(ui, |ui| ui.colored_label(color, text))
        .inner
        .on_hover_text(tip);
}
