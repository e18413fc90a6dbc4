//! Colour swatches the phase views share: λ0 per lenslet as a strip of coloured cells, the
//! wavelength legend, and a colormap's gradient bar.

use egui::{Color32, Sense, Stroke, Ui, pos2, vec2};

use super::wavelength_color;

/// λ0 of every lenslet as a strip of coloured cells (Fig. 4.4). Returns the clicked lenslet.
pub fn lambda0_strip(
    ui: &mut Ui,
    lambda0_nm: &[f64],
    selected: Option<usize>,
    height: f32,
) -> Option<usize> {
    let width = ui.available_width().max(60.0);
    let (rect, resp) = ui.allocate_exact_size(vec2(width, height), Sense::click());
    let n = lambda0_nm.len().max(1);
    let cell = rect.width() / n as f32;
    let painter = ui.painter_at(rect);
    for (i, &l) in lambda0_nm.iter().enumerate() {
        let r = egui::Rect::from_min_size(
            pos2(rect.left() + i as f32 * cell, rect.top()),
            vec2(cell, height),
        );
        painter.rect_filled(
            r.shrink2(vec2(0.5 * (cell > 4.0) as u8 as f32, 0.0)),
            0.0,
            wavelength_color(l),
        );
    }
    if let Some(s) = selected.filter(|s| *s < lambda0_nm.len()) {
        let r = egui::Rect::from_min_size(
            pos2(rect.left() + s as f32 * cell, rect.top()),
            vec2(cell, height),
        );
        painter.rect_stroke(
            r,
            0.0,
            Stroke::new(2.0, ui.visuals().strong_text_color()),
            egui::StrokeKind::Inside,
        );
    }
    let at = |p: egui::Pos2| (((p.x - rect.left()) / cell).floor().max(0.0) as usize).min(n - 1);
    let hovered = resp.hover_pos().map(at);
    let clicked = resp
        .interact_pointer_pos()
        .filter(|_| resp.clicked())
        .map(at);
    if let Some(i) = hovered
        && let Some(l) = lambda0_nm.get(i)
    {
        resp.on_hover_text(format!("lenslet {i}: λ0 = {l:.0} nm"));
    }
    clicked
}

/// A colour key: a `width`-point bar painted with `color_at(t)` for t from 0 (left) to 1 (right).
pub(super) fn gradient_bar(ui: &mut Ui, width: f32, color_at: impl Fn(f32) -> Color32) {
    let (rect, _) = ui.allocate_exact_size(vec2(width, 12.0), Sense::hover());
    let steps = 60;
    for k in 0..steps {
        let x0 = rect.left() + rect.width() * k as f32 / steps as f32;
        let r = egui::Rect::from_min_max(
            pos2(x0, rect.top()),
            pos2(x0 + rect.width() / steps as f32 + 0.5, rect.bottom()),
        );
        ui.painter()
            .rect_filled(r, 0.0, color_at(k as f32 / (steps - 1) as f32));
    }
}

/// The colour key of [`lambda0_strip`]: 400 to 700 nm.
pub fn wavelength_legend(ui: &mut Ui) {
    ui.horizontal(|ui| {
        ui.label("λ0:");
        gradient_bar(ui, 180.0, |t| {
            wavelength_color(400.0 + 300.0 * f64::from(t))
        });
        ui.label("400 to 700 nm");
    });
}
