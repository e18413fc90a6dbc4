//! The phase workspace's centre: PSFs and MTFs, the plate's geometry, and the V matrix with the
//! λ0 optimizer.

use egui::{Align2, Color32, FontId, Sense, Stroke, Ui, pos2, vec2};

use super::swatches::{lambda0_strip, wavelength_legend};
use super::{PhaseAction, PhaseCtx, PhaseView};
use crate::app::widgets::figure::{PlotFrame, panel_ui_in};
use crate::core::phase::figures;
use crate::core::phase::geometry::Lenslets;

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

/// The centre: PSFs, geometry, the optimizer or the captures, and how they are drawn.
pub struct ViewsPanel {
    /// The picture the centre shows.
    pub view: PhaseView,
    /// Plot the PSFs on a log10 scale instead of a linear one.
    log_psf: bool,
    /// Half width of the PSF plots, in sensor pixels either side of the image point.
    psf_half_width_px: usize,
}

impl Default for ViewsPanel {
    fn default() -> Self {
        ViewsPanel {
            view: PhaseView::Psf,
            log_psf: false,
            psf_half_width_px: figures::PSF_HALF_WIDTH_PX,
        }
    }
}

impl ViewsPanel {
    /// Draws the panel; every change is queued on `ctx`.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
        // Wrapped: at laptop widths the four tabs do not fit on one line.
        ui.horizontal_wrapped(|ui| {
            let view = &mut self.view;
            ui.selectable_value(view, PhaseView::Psf, "PSF and MTF");
            ui.selectable_value(view, PhaseView::Geometry, "Plate and λ0");
            ui.selectable_value(view, PhaseView::Optimizer, "V matrix and optimizer");
            ui.selectable_value(view, PhaseView::Capture, "Capture & restore");
        });
        ui.separator();
        egui::ScrollArea::vertical().show(ui, |ui| match self.view {
            PhaseView::Psf => {
                self.psf_ui(ui, ctx);
                super::kernels::kernels_ui(ui, ctx);
            }
            PhaseView::Geometry => geometry_ui(ui, ctx),
            PhaseView::Optimizer => super::optimizer_view::optimizer_ui(ui, ctx),
            PhaseView::Capture => super::capture_view::capture_ui(ui, ctx),
        });
    }

    fn psf_ui(&mut self, ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
        let fov = ctx.drawable().map_or(0.0, |d| d.fov_deg());
        let range = (fov * 0.75).clamp(20.0, 80.0);
        let mut choices = ctx.choices;
        ui.horizontal_wrapped(|ui| {
            ui.add(
                egui::Slider::new(&mut choices.angle_deg, -range..=range)
                    .suffix("°")
                    .text("incidence angle"),
            );
            if ui.small_button("on axis").clicked() {
                choices.angle_deg = 0.0;
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
        if choices != ctx.choices {
            ctx.queue(PhaseAction::Choose(choices));
        }
        fov_ruler(ui, choices.angle_deg, fov, range);
        if choices.angle_deg.abs() > fov / 2.0 {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                "This direction is outside the field of view.",
            );
        }
        let Some(s) = &ctx.psf.shown else {
            ui.label("Computing the first PSFs…");
            return;
        };
        let p = s.psfs.clone();
        let ours = figures::optics_label(s.optics);
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
                        legend_above: false,
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
}

fn geometry_ui(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    let Some(d) = ctx.drawable() else {
        ui.label("No valid design yet.");
        return;
    };
    let Ok(lenslets) = Lenslets::new(&d) else {
        return;
    };
    let n = lenslets.count();
    let mut sel = ctx.selected_lenslet.min(n.saturating_sub(1));
    ui.horizontal(|ui| {
        ui.label("Height profile around lenslet");
        ui.add(crate::app::widgets::number(&mut sel).range(0..=n.saturating_sub(1)));
        ui.label(format!(
            "of {n} (λ0 {:.0} nm, fold height {:.3} µm)",
            lenslets.lambda0_nm[sel], lenslets.fold_height_um[sel]
        ));
    });
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
        sel = i;
    }
    if sel != ctx.selected_lenslet {
        ctx.queue(PhaseAction::SelectLenslet(sel));
    }
    wavelength_legend(ui);
}
