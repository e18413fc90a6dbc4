//! The phase workspace's optimizer view: the V matrix as a figure with its colour bar, the
//! optimizer's progress and Cancel, and its allocation beside the fixed and uniform plans.

use egui::{TextureHandle, Ui, vec2};

use super::optimizer::without_plan;
use super::swatches::{lambda0_strip, wavelength_legend};
use super::{ChannelSet, PhaseAction, PhaseCtx};
use crate::app::widgets::figure::{
    COLORBAR_WIDTH, ImageFrame, colour_bar_ui, image_panel_ui, panel_ui,
};
use crate::app::widgets::message_ui;
use crate::core::phase::allocate::plan_invertibility;
use crate::core::phase::figures::allocation_panel;
use crate::core::phase::geometry::{lambda0_per_lenslet, lenslet_count};

/// The V matrix and optimizer view.
pub(super) fn optimizer_ui(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    ui.label(
        "V[λ0][λ]: the invertibility (sum of the MTF) with every lenslet folded at λ0, seen at \
             λ. The optimizer (Algorithm 1, eqs. 4.9-4.11) chooses how many lenslets to fold at \
             each grid wavelength so that every channel stays invertible.",
    );
    ui.horizontal_wrapped(|ui| {
        let idle = !ctx.optimizer.v_job.is_running() && !ctx.optimizer.opt_job.is_running();
        if ui
            .add_enabled(idle, egui::Button::new("Compute V"))
            .on_hover_text(
                "900 propagations, each of one lenslet's samples (every lenslet of a V row is \
                 folded alike): on the CPU whichever View ▸ Compute PSFs on is chosen",
            )
            .clicked()
        {
            ctx.queue(PhaseAction::ComputeV);
        }
        if ui
            .add_enabled(idle, egui::Button::new("Run optimizer"))
            .clicked()
        {
            ctx.queue(PhaseAction::Optimize);
        }
        ui.weak(format!(
            "at {} sampling, {} channels, on the CPU",
            ctx.choices.quality.label(),
            match ctx.choices.channels {
                ChannelSet::Peaks => "peak",
                ChannelSet::Spectral => "spectral",
                ChannelSet::Custom(_) => "custom",
            }
        ));
    });
    let running = ctx
        .optimizer
        .opt_job
        .job()
        .map(|j| {
            (
                j.fraction(),
                "optimizer (V, then Algorithm 1)…",
                j.elapsed(),
            )
        })
        .or_else(|| {
            ctx.optimizer
                .v_job
                .job()
                .map(|j| (j.fraction(), "V matrix…", j.elapsed()))
        });
    if let Some((f, what, elapsed)) = running {
        let mut cancel = false;
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!("{what} {:.0} s", elapsed.as_secs_f64()));
            cancel = ui.button("Cancel").clicked();
        });
        ui.add(egui::ProgressBar::new(f).show_percentage());
        if cancel {
            ctx.queue(PhaseAction::CancelOptimizer);
        }
    }
    message_ui(ui, ctx.optimizer.message.as_ref());
    ui.separator();
    ui.columns(2, |cols| {
        v_ui(&mut cols[0], ctx);
        allocation_ui(&mut cols[1], ctx);
    });
}

fn v_ui(ui: &mut Ui, ctx: &PhaseCtx<'_>) {
    let Some(v) = &ctx.optimizer.v else {
        ui.label("V: not computed yet (Compute V, or Run optimizer).");
        return;
    };
    ui.strong(format!("V ({} sampling)", v.quality.label()));
    if without_plan(&v.design) != without_plan(ctx.design) {
        ui.colored_label(
            ui.visuals().warn_fg_color,
            "computed for other parameters: compute again",
        );
    }
    let side = (ui.available_width() - COLORBAR_WIDTH - 8.0).clamp(160.0, 420.0);
    let textures: Vec<egui::TextureId> = v.textures.iter().map(TextureHandle::id).collect();
    ui.horizontal(|ui| {
        let frame = ImageFrame {
            size: vec2(side, side),
            link: None,
            view_half: None,
        };
        image_panel_ui(ui, "phase-v", &v.panel, &textures, frame);
        if let Some(img) = v.panel.images.first() {
            colour_bar_ui(ui, side, img);
        }
    });
}

fn allocation_ui(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    let optimizer = ctx.optimizer;
    let Some(o) = &optimizer.optimized else {
        ui.label("No allocation yet: Run optimizer.");
        return;
    };
    let a = &o.allocation;
    let total: usize = a.counts.iter().sum();
    ui.strong(format!(
        "Allocation: {} on {} ({} sampling, {:.1} s)",
        crate::app::widgets::counted(total as f64, "lenslet", "lenslets"),
        crate::app::widgets::counted(
            a.counts.iter().filter(|c| **c > 0).count() as f64,
            "wavelength",
            "wavelengths"
        ),
        o.quality.label(),
        o.elapsed_s
    ));
    panel_ui(ui, "phase-counts", &allocation_panel(&a.counts), 180.0);
    ui.label("Per lenslet, left to right:");
    lambda0_strip(ui, &a.lambda0_nm, None, 24.0);
    wavelength_legend(ui);
    let current = if lenslet_count(ctx.design) == total && ctx.design.validate().is_ok() {
        lambda0_per_lenslet(ctx.design)
            .ok()
            .map(|l| plan_invertibility(&a.a, &l))
    } else {
        None
    };
    ui.label("Invertibility per channel (normalised, 1 = the best single λ0 for any channel):");
    egui::Grid::new("phase_invertibility")
        .num_columns(5)
        .striped(true)
        .show(ui, |ui| {
            for h in [
                "channel",
                "optimized",
                "fixed 530 nm (V row 531 nm)",
                "uniform",
                "current plan",
            ] {
                ui.strong(h);
            }
            ui.end_row();
            for (c, name) in ["R", "G", "B"].iter().enumerate() {
                ui.label(*name);
                ui.monospace(format!("{:.3}", a.channel_invertibility[c]));
                ui.monospace(format!("{:.3}", o.fixed_530[c]));
                ui.monospace(format!("{:.3}", o.uniform[c]));
                ui.monospace(current.map_or_else(|| "-".to_string(), |v| format!("{:.3}", v[c])));
                ui.end_row();
            }
            let min = |v: [f64; 3]| v.iter().copied().fold(f64::INFINITY, f64::min);
            ui.label("worst");
            ui.monospace(format!("{:.3}", min(a.channel_invertibility)));
            ui.monospace(format!("{:.3}", min(o.fixed_530)));
            ui.monospace(format!("{:.3}", min(o.uniform)));
            ui.monospace(current.map_or_else(|| "-".to_string(), |v| format!("{:.3}", min(v))));
            ui.end_row();
        });
    if ui
        .add_enabled(ctx.can_apply, egui::Button::new("Apply"))
        .on_hover_text("Use these counts as the λ0 plan (undoable)")
        .on_disabled_hover_text("The lenslet count changed since the run")
        .clicked()
    {
        ctx.queue(PhaseAction::ApplyOptimized);
    }
}
