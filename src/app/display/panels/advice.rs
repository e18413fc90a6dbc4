//! The sampling warnings and notes of the shown result, in the studio's words, each with the
//! Apply button of its advice.

use super::{PanelCtx, Shown};
use crate::app::display::action::DisplayAction;
use crate::app::display::labels::in_ui_words;
use crate::core::psf::warning::Severity;

/// Draws the shown result's warnings (yellow) and notes (grey); a fix's Apply button sets the
/// advised optics as one undo step.
pub fn warnings_ui(ui: &mut egui::Ui, ctx: &mut PanelCtx, shown: &Shown) {
    // A fix belongs to the optics it was computed for: while the document's optics differ
    // (a newer result is on its way), applying it would undo the user's newer edit.
    let current = shown.design.optics == ctx.design.optics;
    for w in &shown.analysis.warnings {
        let text = in_ui_words(&w.message);
        match w.severity {
            Severity::Warning => {
                ui.colored_label(ui.visuals().warn_fg_color, format!("Warning: {text}"));
            }
            Severity::Note => {
                ui.label(egui::RichText::new(text).weak());
            }
        }
        if let Some(fix) = &w.fix {
            ui.horizontal_wrapped(|ui| {
                let apply = ui
                    .add_enabled(current, egui::Button::new("Apply"))
                    .on_hover_text(format!(
                        "Sets {} (one step: Ctrl+Z undoes it)",
                        in_ui_words(&fix.field_changes())
                    ))
                    .on_disabled_hover_text("The optics changed: wait for their result");
                if apply.clicked() {
                    ctx.actions
                        .push(DisplayAction::SetOptics(fix.optics.clone()));
                }
                ui.weak(in_ui_words(&fix.summary()));
            });
        }
    }
    // The panel scrolls sideways, and its floating scroll bar covers the bottom of the content
    // when the pointer comes near: the last Apply button must not sit under it.
    let bar = &ui.spacing().scroll;
    ui.add_space(bar.bar_width.max(bar.floating_width) + bar.bar_outer_margin + 4.0);
}
