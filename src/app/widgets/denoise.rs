//! The Denoise control of the restoration views: BM3D or none, and BM3D's σ² matched to the
//! capture's noise (the default), from the authors' table (conventions.md §5), or typed in.

use egui::Ui;

use crate::core::restore::{Denoise, Recipe, Sigma2};

/// The override's range: below it BM3D barely changes a capture, above it every capture is flat.
const SIGMA2_RANGE: std::ops::RangeInclusive<f64> = 1e-6..=1.0;

/// Draws the control on one wrapped line and edits `denoise`. `thesis_sigma2` is the σ² the
/// authors' table of `recipe` gives at the current light level, on the capture's scale (shown on
/// the "authors' table" choice and taken as the override's starting value); `matched_sigma2`
/// the capture's own variance at white, when the view knows it.
pub fn denoise_ui(
    ui: &mut Ui,
    denoise: &mut Denoise,
    recipe: Recipe,
    thesis_sigma2: f64,
    matched_sigma2: Option<f64>,
) {
    ui.label("Denoise:");
    let on = matches!(denoise, Denoise::Bm3d { .. });
    if ui
        .selectable_label(on, "BM3D")
        .on_hover_text(
            "BM3D before deblurring (CBM3D on colour photos), as every simulated number of the \
             thesis: denoise, then deblur",
        )
        .clicked()
        && !on
    {
        *denoise = Denoise::default();
    }
    if ui
        .selectable_label(!on, "none")
        .on_hover_text("Deblur the raw capture (the restoration step alone)")
        .clicked()
    {
        *denoise = Denoise::None;
    }
    let Denoise::Bm3d { sigma2 } = denoise else {
        return;
    };
    let matched = matches!(sigma2, Sigma2::Matched);
    let matched_text = match matched_sigma2.filter(|s| s.is_finite()) {
        Some(s) => format!("σ² {s:.2e} (matched)"),
        None => "σ² matched".to_string(),
    };
    if ui
        .selectable_label(matched, matched_text)
        .on_hover_text(
            "The default: the capture's own noise variance at a white pixel, 1/e + σ_read²/e² + \
             q²/12 for the e electrons white collects through this display and the ADC step q",
        )
        .clicked()
    {
        *sigma2 = Sigma2::Matched;
    }
    let thesis = matches!(sigma2, Sigma2::Thesis(_));
    if ui
        .selectable_label(thesis, format!("σ² {thesis_sigma2:.2e} (authors' table)"))
        .on_hover_text(format!(
            "The authors' σ² for this light level ({} table, nearest of 24/28/32/36/40 dB), on \
             the capture's scale where white reads 1: the variance with no display in front, so \
             it understates a dim display's noise. For comparisons with their code",
            recipe.name()
        ))
        .clicked()
    {
        *sigma2 = Sigma2::Thesis(recipe);
    }
    let fixed = matches!(sigma2, Sigma2::Fixed(_));
    if ui
        .selectable_label(fixed, "override")
        .on_hover_text("Give BM3D your own noise variance σ² (on the capture's scale)")
        .clicked()
        && !fixed
    {
        *sigma2 = Sigma2::Fixed(thesis_sigma2);
    }
    if let Sigma2::Fixed(value) = sigma2 {
        ui.add(
            crate::app::widgets::number(value)
                .range(SIGMA2_RANGE)
                .speed(1e-5)
                .max_decimals(6)
                .prefix("σ² "),
        )
        .on_hover_text("BM3D's noise variance σ², > 0, on the capture's scale (white = 1)");
    }
}
