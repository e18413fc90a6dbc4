//! The phase workspace's side panels: parameters (left) and numbers (right).

use egui::{RichText, Ui};

use super::{PhaseAction, PhaseCtx, Quality};
use crate::app::history::Snapshot;
use crate::app::widgets::message_ui;
use crate::core::phase::geometry::{Lenslets, lambda0_per_lenslet, lenslet_count};
use crate::core::phase::{
    GRID_LEN, HeightRounding, Lambda0, POLARISER_TRANSMISSION, PhaseDesign, SamplingConvention,
    Surface,
};

/// Microns per inch: DPI = 25 400 / pitch.
const UM_PER_INCH: f64 = 25_400.0;

/// A number field that shows (and does not clamp) values outside its range, so that a bad
/// value reaches `validate()` and its message.
fn number(
    ui: &mut Ui,
    v: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    speed: f64,
    suffix: &str,
) -> egui::Response {
    ui.add(
        crate::app::widgets::number(v)
            .range(range)
            .clamp_existing_to_range(false)
            .speed(speed)
            .max_decimals(4)
            .suffix(suffix),
    )
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum PlanKind {
    Fixed,
    Uniform,
    Counts,
    PerLenslet,
}

fn plan_kind(l: &Lambda0) -> PlanKind {
    match l {
        Lambda0::Fixed { .. } => PlanKind::Fixed,
        Lambda0::Uniform => PlanKind::Uniform,
        Lambda0::Counts { .. } => PlanKind::Counts,
        Lambda0::PerLenslet { .. } => PlanKind::PerLenslet,
    }
}

/// The plan resized to `n` lenslets: counts scaled by largest remainder, lists resampled.
pub fn fit_plan(l: &Lambda0, n: usize) -> Lambda0 {
    match l {
        Lambda0::Counts { counts } => {
            let sum = counts.iter().sum::<usize>().max(1) as f64;
            let shares: Vec<f64> = (0..GRID_LEN)
                .map(|j| counts.get(j).copied().unwrap_or(0) as f64 * n as f64 / sum)
                .collect();
            Lambda0::Counts {
                counts: crate::core::phase::geometry::round_to_total(&shares, n),
            }
        }
        Lambda0::PerLenslet { nm } if !nm.is_empty() => Lambda0::PerLenslet {
            nm: (0..n)
                .map(|i| nm[(i * nm.len() / n.max(1)).min(nm.len() - 1)])
                .collect(),
        },
        Lambda0::PerLenslet { .. } => Lambda0::PerLenslet { nm: vec![530.0; n] },
        other => other.clone(),
    }
}

/// The workspace's panels: one struct each, drawn from a [`PhaseCtx`].
#[derive(Default)]
pub struct Panels {
    /// Left.
    pub controls: ControlsPanel,
    /// Right.
    pub numbers: NumbersPanel,
    /// Centre.
    pub views: super::views::ViewsPanel,
}

/// The left panel: the design's parameters, the simulation choices and the exports.
pub struct ControlsPanel {
    /// Keep f_MLA equal to the pitch when the pitch is edited (the thesis's choice).
    link_focal: bool,
}

impl Default for ControlsPanel {
    fn default() -> Self {
        ControlsPanel { link_focal: true }
    }
}

/// The right panel: geometry, light and sharpness numbers.
#[derive(Default)]
pub struct NumbersPanel;

impl ControlsPanel {
    /// Draws the panel; every change is queued on `ctx`.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
        ui.heading("Phase masks");
        ui.label(
            "Two microlens arrays around a T-OLED (thesis chapter 4): the first focuses each \
             pixel's light into its slit, the second collimates it again. Each lenslet is folded \
             into a thin plate at its own wavelength λ0.",
        );
        ui.horizontal(|ui| {
            if ui
                .add_enabled(ctx.can_undo, egui::Button::new("Undo"))
                .on_hover_text("Ctrl+Z: the last parameter change")
                .clicked()
            {
                ctx.queue(PhaseAction::Undo);
            }
            if ui
                .add_enabled(ctx.can_redo, egui::Button::new("Redo"))
                .on_hover_text("Ctrl+Shift+Z")
                .clicked()
            {
                ctx.queue(PhaseAction::Redo);
            }
            if ui
                .button("Thesis design")
                .on_hover_text("600 DPI: pitch 42 µm, f_MLA = pitch, n 1.515, T 1, fixed 530 nm")
                .clicked()
            {
                ctx.queue(PhaseAction::Set(Box::new(PhaseDesign::thesis(42.0, 1.0))));
            }
        });
        ui.separator();
        // The controls edit a draft; a change is queued as a live edit, which the history
        // makes one undo step once the pointer is up (Workspace::apply carries it out).
        let mut draft = ctx.design.clone();
        self.geometry_controls(ui, &mut draft);
        ui.separator();
        plan_controls(ui, &mut draft, ctx);
        if !draft.same(ctx.design) {
            ctx.queue(PhaseAction::Live(Box::new(draft)));
        }
        ui.separator();
        simulation_controls(ui, ctx);
        message_ui(ui, ctx.message);
        ui.separator();
        super::export::export_ui(ui, ctx);
    }

    fn geometry_controls(&mut self, ui: &mut Ui, d: &mut PhaseDesign) {
        let link = &mut self.link_focal;
        egui::Grid::new("phase_geometry")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("Pixel pitch");
                ui.horizontal(|ui| {
                    // Compared by bits: a NaN field reports `changed` every frame.
                    let before = d.pitch_um.to_bits();
                    number(ui, &mut d.pitch_um, 1.0..=2000.0, 0.2, " µm")
                        .on_hover_text("Display pixel pitch, also the lenslet pitch");
                    let old_dpi = UM_PER_INCH / d.pitch_um;
                    let mut dpi = old_dpi;
                    ui.add(
                        crate::app::widgets::number(&mut dpi)
                            .range(12.7..=25_400.0)
                            .clamp_existing_to_range(false)
                            .max_decimals(1)
                            .suffix(" DPI"),
                    );
                    if dpi.to_bits() != old_dpi.to_bits() && dpi.is_finite() && dpi > 0.0 {
                        d.pitch_um = UM_PER_INCH / dpi;
                    }
                    if d.pitch_um.to_bits() != before && *link {
                        d.f_mla_um = d.pitch_um;
                    }
                });
                ui.end_row();
                ui.label("Lenslet focal length");
                ui.horizontal(|ui| {
                    number(ui, &mut d.f_mla_um, 1.0..=10_000.0, 0.2, " µm")
                        .on_hover_text("f_MLA, also the gap between each MLA and the display");
                    ui.checkbox(link, "= pitch");
                });
                ui.end_row();
                ui.label("Refractive index n");
                number(ui, &mut d.refractive_index, 1.01..=4.0, 0.001, "");
                ui.end_row();
                ui.label("Fold thickness T");
                number(ui, &mut d.fold, 0.05..=100.0, 0.05, "").on_hover_text(
                    "Fold height T λ0 / (n - 1): 1 suits a phase SLM, 5 a thicker plate",
                );
                ui.end_row();
                ui.label("Open ratio");
                ui.horizontal(|ui| {
                    number(ui, &mut d.open_ratio, 0.01..=1.0, 0.001, "")
                        .on_hover_text("Open fraction of each display pixel (a slit)");
                    let old_kappa = d.kappa();
                    let mut kappa = old_kappa;
                    ui.label("κ");
                    number(ui, &mut kappa, 1.0..=100.0, 0.01, "")
                        .on_hover_text("κ = f_MLA / opening (eq. 4.13); 4.2 in the thesis");
                    if kappa.to_bits() != old_kappa.to_bits() && kappa.is_finite() && kappa > 0.0 {
                        d.open_ratio = d.f_mla_um / (d.pitch_um * kappa);
                    }
                });
                ui.end_row();
                ui.label("Height step");
                ui.horizontal(|ui| {
                    let mut on = d.height_step_um.is_some();
                    if ui
                        .checkbox(&mut on, "")
                        .on_hover_text("Round the plate to a fabrication step")
                        .changed()
                    {
                        d.height_step_um = on.then_some(0.2);
                    }
                    if let Some(step) = &mut d.height_step_um {
                        number(ui, step, 0.001..=10.0, 0.005, " µm");
                    } else {
                        ui.weak("continuous");
                    }
                });
                ui.end_row();
                if d.height_step_um.is_some() {
                    ui.label("Rounding");
                    ui.horizontal(|ui| {
                        ui.selectable_value(&mut d.height_rounding, HeightRounding::Floor, "floor")
                            .on_hover_text(
                                "floor(h / step) · step, as the authors' code: every level stays \
                                 below the fold height",
                            );
                        ui.selectable_value(
                            &mut d.height_rounding,
                            HeightRounding::Nearest,
                            "nearest",
                        )
                        .on_hover_text("The nearest level of the unfolded sag");
                    });
                    ui.end_row();
                }
                ui.label("Surface");
                ui.horizontal(|ui| {
                    ui.selectable_value(&mut d.surface, Surface::Folded, "folded plate");
                    ui.selectable_value(&mut d.surface, Surface::Unfolded, "unfolded lens")
                        .on_hover_text("The thick lens the plate is folded from (the reference)");
                });
                ui.end_row();
                ui.label("Sampling");
                ui.horizontal(|ui| {
                    ui.selectable_value(&mut d.sampling, SamplingConvention::Thesis, "thesis")
                        .on_hover_text(
                            "The thesis code's sampling: 2.03 µm pixels with the axis on the left \
                             edge of pixel 512, lenslets from the display aperture's first sample. \
                             Its published numbers reproduce.",
                        );
                    ui.selectable_value(&mut d.sampling, SamplingConvention::Centred, "centred")
                        .on_hover_text(
                            "The axis at the centre of a 2 µm pixel, lenslets and slits symmetric \
                             about it",
                        );
                });
                ui.end_row();
            });
        egui::CollapsingHeader::new("Camera")
            .id_salt("phase_camera")
            .show(ui, |ui| {
                let c = &mut d.camera;
                egui::Grid::new("phase_camera_grid")
                    .num_columns(2)
                    .show(ui, |ui| {
                        ui.label("Focal length");
                        number(ui, &mut c.focal_length_mm, 0.1..=1000.0, 0.01, " mm");
                        ui.end_row();
                        ui.label("F-number");
                        number(ui, &mut c.f_number, 0.5..=64.0, 0.05, "");
                        ui.end_row();
                        ui.label("Sensor pixel");
                        number(ui, &mut c.pixel_um, 0.1..=100.0, 0.01, " µm");
                        ui.end_row();
                        ui.label("Sensor pixels");
                        ui.label(format!("{} px", c.pixels));
                        ui.end_row();
                    });
            });
    }
}

fn plan_controls(ui: &mut Ui, d: &mut PhaseDesign, ctx: &mut PhaseCtx<'_>) {
    ui.label("Folding wavelength λ0 per lenslet");
    let n = lenslet_count(d);
    let kind = plan_kind(&d.lambda0);
    ui.horizontal_wrapped(|ui| {
        if ui
            .selectable_label(kind == PlanKind::Fixed, "fixed")
            .on_hover_text("Every lenslet at one wavelength (the thesis's 530 nm)")
            .clicked()
            && kind != PlanKind::Fixed
        {
            d.lambda0 = Lambda0::Fixed { nm: 530.0 };
        }
        if ui
            .selectable_label(kind == PlanKind::Uniform, "uniform")
            .on_hover_text("The 30 grid wavelengths 401-691 nm in equal counts")
            .clicked()
        {
            d.lambda0 = Lambda0::Uniform;
        }
        let can = ctx.can_apply || kind == PlanKind::Counts;
        if ui
            .add_enabled(
                can,
                egui::Button::selectable(kind == PlanKind::Counts, "optimized"),
            )
            .on_hover_text("Counts per grid wavelength from the optimizer")
            .on_disabled_hover_text("Run the optimizer first (Optimizer view)")
            .clicked()
            && kind != PlanKind::Counts
            && let Some(o) = &ctx.optimizer.optimized
        {
            d.lambda0 = Lambda0::Counts {
                counts: o.allocation.counts.clone(),
            };
        }
        if ui
            .selectable_label(kind == PlanKind::PerLenslet, "per lenslet")
            .on_hover_text("Edit each lenslet's λ0 (click a lenslet on the strip)")
            .clicked()
            && kind != PlanKind::PerLenslet
        {
            let nm = lambda0_per_lenslet(d).unwrap_or_else(|_| vec![530.0; n]);
            d.lambda0 = Lambda0::PerLenslet { nm };
        }
    });
    let selected = ctx.selected_lenslet.min(n.saturating_sub(1));
    match &mut d.lambda0 {
        Lambda0::Fixed { nm } => {
            ui.horizontal(|ui| {
                ui.label("λ0");
                number(ui, nm, 300.0..=1100.0, 1.0, " nm");
            });
        }
        Lambda0::Uniform => {
            ui.weak(format!(
                "{} over 401-691 nm in 10-nm steps",
                crate::app::widgets::counted(n as f64, "lenslet", "lenslets")
            ));
        }
        Lambda0::Counts { counts } => {
            let used = counts.iter().filter(|c| **c > 0).count();
            let total = counts.iter().sum::<usize>() as f64;
            ui.weak(format!(
                "{} on {}",
                crate::app::widgets::counted(total, "lenslet", "lenslets"),
                crate::app::widgets::counted(used as f64, "grid wavelength", "grid wavelengths")
            ));
        }
        Lambda0::PerLenslet { nm } => {
            ui.horizontal(|ui| {
                ui.label("lenslet");
                let mut s = selected;
                ui.add(crate::app::widgets::number(&mut s).range(0..=n.saturating_sub(1)));
                if s != ctx.selected_lenslet {
                    ctx.queue(PhaseAction::SelectLenslet(s));
                }
                if let Some(v) = nm.get_mut(s) {
                    ui.label("λ0");
                    number(ui, v, 300.0..=1100.0, 1.0, " nm");
                }
            });
        }
    }
    let fits = match &d.lambda0 {
        Lambda0::Counts { counts } => counts.iter().sum::<usize>() == n,
        Lambda0::PerLenslet { nm } => nm.len() == n,
        _ => true,
    };
    if !fits
        && ui
            .button(format!(
                "Fit the λ0 plan to {}",
                crate::app::widgets::counted(n as f64, "lenslet", "lenslets")
            ))
            .on_hover_text("The lenslet count changed with the geometry")
            .clicked()
    {
        d.lambda0 = fit_plan(&d.lambda0, n);
    }
}

fn simulation_controls(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    let mut c = ctx.choices;
    egui::Grid::new("phase_simulation")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("Quality");
            ui.horizontal(|ui| {
                ui.selectable_value(&mut c.quality, Quality::Preview, "preview only")
                    .on_hover_text("60-nm display samples, 7 per sensor pixel: for dragging");
                ui.selectable_value(&mut c.quality, Quality::Full, "preview, then full")
                    .on_hover_text("Then the thesis's 15-nm samples, 14 per sensor pixel");
            });
            ui.end_row();
            ui.label("Channels");
            super::response::channel_choice_ui(ui, &mut c.channels, ctx);
            ui.end_row();
            ui.label("Optics");
            ui.checkbox(&mut c.single_mask, "single mask (Lemma 1)")
                .on_hover_text(
                    "One plate at the display and no second MLA: Lemma 1 says a single \
                         phase mask cannot beat the T-OLED's MTF",
                );
            ui.end_row();
        });
    if c != ctx.choices {
        ctx.queue(PhaseAction::Choose(c));
    }
}

impl NumbersPanel {
    /// Draws the panel.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
        ui.heading("Numbers");
        if let Some((key, j)) = ctx.psf.job.current() {
            let p = j.fraction();
            let label = match key.quality {
                Quality::Preview => "preview…",
                Quality::Full => "full quality…",
            };
            let mut cancel = false;
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label(label);
                cancel = ui.small_button("Cancel PSFs").clicked();
            });
            ui.add(egui::ProgressBar::new(p).show_percentage());
            if cancel {
                ctx.queue(PhaseAction::CancelPsfs);
            }
        } else if let Some(s) = &ctx.psf.shown {
            ui.weak(format!(
                "{} · {} · {:.0} ms",
                s.quality.label(),
                match s.optics {
                    crate::core::phase::PhaseOptics::SingleMask => "single mask",
                    _ => "double MLA",
                },
                s.elapsed_ms
            ));
        }
        let Some(d) = ctx.drawable() else {
            return;
        };
        let max_h = Lenslets::new(&d)
            .map(|l| l.max_height_um(&d))
            .unwrap_or(0.0);
        egui::Grid::new("phase_numbers_geometry")
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                let row = |ui: &mut Ui, k: &str, v: String| {
                    ui.label(k);
                    ui.monospace(v);
                    ui.end_row();
                };
                row(
                    ui,
                    "Pitch",
                    format!("{:.2} µm ({:.0} DPI)", d.pitch_um, UM_PER_INCH / d.pitch_um),
                );
                row(ui, "Lenslets per array", format!("{}", lenslet_count(&d)));
                row(ui, "κ = f_MLA / opening", format!("{:.2}", d.kappa()));
                row(
                    ui,
                    "FoV (eq. 4.13)",
                    format!("{:.1}° (±{:.1}°)", d.fov_deg(), d.fov_deg() / 2.0),
                );
                row(
                    ui,
                    "LTR_min (eq. 4.14)",
                    format!(
                        "{:.3} (with polariser {:.3})",
                        d.ltr_min(),
                        d.ltr_min() * POLARISER_TRANSMISSION
                    ),
                );
                row(ui, "Tallest plate point", format!("{max_h:.3} µm"));
            });
        let Some(s) = &ctx.psf.shown else {
            ui.label("Computing the first PSFs…");
            return;
        };
        let p = &s.psfs;
        ui.add_space(6.0);
        ui.strong(format!(
            "Light at {:.1}° (image pixel {})",
            p.angle_deg, p.image_pixel
        ));
        egui::Grid::new("phase_numbers_ltr")
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                ui.label("LTR, ours with polariser");
                ui.monospace(format!("{:.3}", p.ltr_with_polariser));
                ui.end_row();
                ui.label("LTR, bare T-OLED");
                ui.monospace(format!("{:.3}", p.toled_ltr));
                ui.end_row();
            });
        ui.add_space(4.0);
        ui.label("Light on the sensor window vs the T-OLED:");
        egui::Grid::new("phase_numbers_energy")
            .num_columns(4)
            .striped(true)
            .show(ui, |ui| {
                for h in ["channel", "λ", "with polariser", "before polariser"] {
                    ui.strong(h);
                }
                ui.end_row();
                for c in &p.channels {
                    ui.label(&c.name);
                    ui.monospace(format!("{:.0} nm", c.wavelength_nm));
                    ui.monospace(RichText::new(format!("{:.3}×", c.energy_vs_toled)).strong());
                    ui.monospace(format!("{:.3}×", c.energy_vs_toled_before_polariser));
                    ui.end_row();
                }
            });
        ui.add_space(4.0);
        ui.label("Sharpness (ours / T-OLED):");
        egui::Grid::new("phase_numbers_sharpness")
            .num_columns(3)
            .striped(true)
            .show(ui, |ui| {
                for h in ["channel", "peak share", "invertibility (Σ MTF)"] {
                    ui.strong(h);
                }
                ui.end_row();
                for c in &p.channels {
                    ui.label(&c.name);
                    ui.monospace(format!("{:.3} / {:.3}", c.peak, c.toled_peak));
                    ui.monospace(format!(
                        "{:.1} / {:.1}",
                        c.invertibility, c.toled_invertibility
                    ));
                    ui.end_row();
                }
            });
    }
}
