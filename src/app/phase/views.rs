//! The phase workspace's centre: PSFs and MTFs, the plate's geometry, and the V matrix with the
//! λ0 optimizer.

use egui::{Align2, Color32, FontId, Sense, Stroke, Ui, pos2, vec2};

use super::{PhaseView, PhaseWorkspace, wavelength_color};
use crate::app::widgets::figure::{PlotFrame, panel_ui_in};
use crate::core::phase::PhaseDesign;
use crate::core::phase::figures;
use crate::core::phase::geometry::Lenslets;

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

/// The angle range with the field of view shaded and the current angle marked.
fn fov_ruler(ui: &mut Ui, angle: f64, fov_deg: f64, range: f64) {
    let (rect, _) =
        ui.allocate_exact_size(vec2(ui.available_width().min(420.0), 26.0), Sense::hover());
    let p = ui.painter_at(rect);
    let bar = egui::Rect::from_min_max(
        pos2(rect.left() + 20.0, rect.top() + 2.0),
        pos2(rect.right() - 20.0, rect.top() + 10.0),
    );
    let x =
        |a: f64| bar.left() + bar.width() * ((a + range) / (2.0 * range)).clamp(0.0, 1.0) as f32;
    p.rect_filled(bar, 2.0, ui.visuals().faint_bg_color);
    let half = fov_deg / 2.0;
    let fov = egui::Rect::from_min_max(pos2(x(-half), bar.top()), pos2(x(half), bar.bottom()));
    p.rect_filled(fov, 2.0, Color32::from_rgba_unmultiplied(80, 200, 120, 120));
    p.line_segment(
        [
            pos2(x(angle), rect.top()),
            pos2(x(angle), bar.bottom() + 2.0),
        ],
        Stroke::new(2.0, Color32::from_rgb(255, 170, 0)),
    );
    let font = FontId::proportional(11.0);
    let c = ui.visuals().weak_text_color();
    p.text(
        pos2(bar.left(), rect.bottom()),
        Align2::CENTER_BOTTOM,
        format!("{:.0}°", -range),
        font.clone(),
        c,
    );
    p.text(
        pos2(bar.right(), rect.bottom()),
        Align2::CENTER_BOTTOM,
        format!("{range:.0}°"),
        font.clone(),
        c,
    );
    p.text(
        pos2(x(0.0), rect.bottom()),
        Align2::CENTER_BOTTOM,
        format!("FoV ±{half:.1}°"),
        font,
        c,
    );
}

impl PhaseWorkspace {
    /// Centre: PSFs, geometry or the optimizer.
    pub fn views_ui(&mut self, ui: &mut Ui) {
        // Wrapped: at laptop widths the four tabs do not fit on one line.
        ui.horizontal_wrapped(|ui| {
            ui.selectable_value(&mut self.view, PhaseView::Psf, "PSF and MTF");
            ui.selectable_value(&mut self.view, PhaseView::Geometry, "Plate and λ0");
            ui.selectable_value(
                &mut self.view,
                PhaseView::Optimizer,
                "V matrix and optimizer",
            );
            ui.selectable_value(&mut self.view, PhaseView::Capture, "Capture & restore");
        });
        ui.separator();
        egui::ScrollArea::vertical().show(ui, |ui| match self.view {
            PhaseView::Psf => {
                self.psf_ui(ui);
                self.kernels_ui(ui);
            }
            PhaseView::Geometry => self.geometry_ui(ui),
            PhaseView::Optimizer => self.optimizer_ui(ui),
            PhaseView::Capture => self.capture_ui(ui),
        });
    }

    /// The design to draw geometry from: the current one if valid, else the shown result's.
    fn drawable(&self) -> Option<PhaseDesign> {
        if self.history.current().validate().is_ok() {
            Some(self.history.current().clone())
        } else {
            self.psf.shown.as_ref().map(|s| s.design.clone())
        }
    }

    fn psf_ui(&mut self, ui: &mut Ui) {
        let fov = self.drawable().map_or(0.0, |d| d.fov_deg());
        let range = (fov * 0.75).clamp(20.0, 80.0);
        ui.horizontal_wrapped(|ui| {
            ui.add(
                egui::Slider::new(&mut self.angle_deg, -range..=range)
                    .suffix("°")
                    .text("incidence angle"),
            );
            if ui.small_button("on axis").clicked() {
                self.angle_deg = 0.0;
            }
            ui.separator();
            ui.selectable_value(&mut self.log_psf, false, "linear");
            ui.selectable_value(&mut self.log_psf, true, "log10");
            ui.separator();
            ui.label("half width");
            ui.add(
                crate::app::widgets::number(&mut self.psf_half_width_px)
                    .range(4..=512)
                    .suffix(" px"),
            );
        });
        fov_ruler(ui, self.angle_deg, fov, range);
        if self.angle_deg.abs() > fov / 2.0 {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                "This direction is outside the field of view.",
            );
        }
        let Some(s) = &self.psf.shown else {
            ui.label("Computing the first PSFs…");
            return;
        };
        let p = s.psfs.clone();
        let ours = match s.optics {
            crate::core::phase::PhaseOptics::SingleMask => "single mask",
            _ => "double MLA",
        };
        let mut caption = format!(
            "{} PSFs at {:.1}° ({}); the bare T-OLED dashed, imaged at pixel {} from the axis.",
            s.quality.label(),
            p.angle_deg,
            ours,
            p.image_pixel
        );
        if p.image_pixel != 0 && s.optics == crate::core::phase::PhaseOptics::DoubleMla {
            caption.push_str(&format!(
                " The double MLA inverts the angle (a 1:1 telescope per lenslet): its light lands \
                 near pixel {}.",
                -p.image_pixel
            ));
        }
        ui.label(caption);
        let half = self.psf_half_width_px as i64 + p.image_pixel.abs();
        let log = self.log_psf;
        let n = p.channels.len().max(1) as f32;
        let w = ((ui.available_width() - 12.0 * n) / n).max(160.0);
        let h = 230.0;
        let link = ui.make_persistent_id("phase-psf-link");
        ui.horizontal(|ui| {
            for (i, c) in p.channels.iter().enumerate() {
                ui.vertical(|ui| {
                    let panel = figures::psf_panel(c, i, ours, half, log);
                    ui.label(&panel.title);
                    let frame = PlotFrame {
                        width: Some(w),
                        height: h,
                        link_x: Some(link),
                    };
                    panel_ui_in(ui, ("phase-psf", i), &panel, frame);
                });
            }
        });
        ui.add_space(6.0);
        let mtf = figures::mtf_panel(&p, ours);
        ui.label(&mtf.title);
        panel_ui_in(ui, "phase-mtf", &mtf, PlotFrame::tall(260.0));
    }

    fn geometry_ui(&mut self, ui: &mut Ui) {
        let Some(d) = self.drawable() else {
            ui.label("No valid design yet.");
            return;
        };
        let Ok(lenslets) = Lenslets::new(&d) else {
            return;
        };
        let n = lenslets.count();
        self.selected_lenslet = self.selected_lenslet.min(n.saturating_sub(1));
        ui.horizontal(|ui| {
            ui.label("Height profile around lenslet");
            ui.add(
                crate::app::widgets::number(&mut self.selected_lenslet)
                    .range(0..=n.saturating_sub(1)),
            );
            ui.label(format!(
                "of {n} (λ0 {:.0} nm, fold height {:.3} µm)",
                lenslets.lambda0_nm[self.selected_lenslet],
                lenslets.fold_height_um[self.selected_lenslet]
            ));
        });
        let sel = self.selected_lenslet;
        match figures::profile_panel(&d, &lenslets, sel) {
            Ok(panel) => panel_ui_in(ui, "phase-profile", &panel, PlotFrame::tall(280.0)),
            Err(e) => {
                ui.colored_label(ui.visuals().error_fg_color, e.to_string());
            }
        }
        ui.add_space(6.0);
        ui.label(format!(
            "λ0 of each of the {n} lenslets, left to right (click one to select it):"
        ));
        if let Some(i) = lambda0_strip(ui, &lenslets.lambda0_nm, Some(sel), 36.0) {
            self.selected_lenslet = i;
        }
        wavelength_legend(ui);
    }
}
