//! Tiling controls and a zoomable preview of the tiled display over the lens pupil.

use std::sync::Arc;

use super::one_axis_sweep::sweep_menu;
use super::{DisplayPreview, PanelCtx};
use crate::app::display::action::DisplayAction;
use crate::app::widgets::figure::{FigureCache, ImageFrame, image_panel_ui};
use crate::core::design::{Design, TilingMode};
use crate::core::display::figures::tiling_panel;
use crate::core::sweep::one_axis::SweepParameter;

/// The Tiling panel: tiling mode, seed, wiring gap, axis cell and the preview of the tiled
/// display over the pupil.
#[derive(Default)]
pub struct TilingPanel {
    /// Edits in progress while a value is being dragged (committed on release).
    draft: Option<Design>,
    /// The preview's figure, rebuilt once per result.
    figure: FigureCache<(), u64>,
}

fn mode_label(m: TilingMode) -> &'static str {
    match m {
        TilingMode::Repeat => "Repeat",
        TilingMode::RandomD4 => "Random D4",
        TilingMode::Random4 => "Random 4",
    }
}

fn mode_hint(m: TilingMode) -> &'static str {
    match m {
        TilingMode::Repeat => {
            "Every pixel identical: a periodic display (sharp diffraction orders)."
        }
        TilingMode::RandomD4 => {
            "Each pixel takes one of the 8 rotations/flips (three coins: rotate 90° CCW, flip left-right, flip up-down)."
        }
        TilingMode::Random4 => {
            "Each pixel takes one of P, Pᵀ, fliplr P, flipud Pᵀ (the thesis's optimization set)."
        }
    }
}

impl TilingPanel {
    /// Draws the controls and the preview; values being dragged are committed on release.
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelCtx) {
        let mut d = self.draft.clone().unwrap_or_else(|| ctx.design.clone());
        let mut dragging = false;
        ui.horizontal(|ui| {
            for m in TilingMode::ALL {
                if ui
                    .selectable_label(d.tiling.mode == m, mode_label(m))
                    .on_hover_text(mode_hint(m))
                    .clicked()
                {
                    d.tiling.mode = m;
                }
            }
        });
        ui.horizontal(|ui| {
            let label = ui.label("Pitch");
            let r = ui
                .add(crate::app::widgets::number(&mut d.opening.pitch_um).range(1.0..=2000.0).speed(0.5).suffix(" µm"))
                .labelled_by(label.id)
                .on_hover_text("Display pixel pitch (µm): the opening's cells scale with it (right-click: sweep it)");
            dragging |= r.dragged();
            sweep_menu(&r, SweepParameter::PitchUm, ctx.actions);
        });
        ui.horizontal(|ui| {
            ui.label("Seed");
            let r = ui
                .add(crate::app::widgets::number(&mut d.tiling.seed).speed(1.0))
                .on_hover_text("Seed of the random orientations (the same seed gives the same display everywhere)");
            dragging |= r.dragged();
            sweep_menu(&r, SweepParameter::Seed, ctx.actions);
            if ui
                .add_enabled(d.tiling.mode.is_random(), egui::Button::new("Reroll"))
                .on_hover_text("A new random realisation (F5)")
                .clicked()
            {
                ctx.actions.push(DisplayAction::Reroll);
            }
        });
        ui.horizontal(|ui| {
            let label = ui.label("Wiring gap");
            let r = ui
                .add(crate::app::widgets::number(&mut d.tiling.wiring_gap_um).range(0.0..=100.0).speed(0.5).suffix(" µm"))
                .labelled_by(label.id)
                .on_hover_text("Opaque gap added around every pixel (µm); the display period becomes pitch + gap");
            dragging |= r.dragged();
            sweep_menu(&r, SweepParameter::WiringGapUm, ctx.actions);
        });
        ui.horizontal(|ui| {
            ui.label("Axis on cell");
            for k in 0..2 {
                let r = ui
                    .add(
                        crate::app::widgets::number(&mut d.tiling.origin_offset_cells[k])
                            .range(0.0..=d.opening.n() as f64)
                            .speed(0.05)
                            .prefix(if k == 0 { "x " } else { "y " })
                            .custom_formatter(|v, _| {
                                crate::app::widgets::counted(v, "cell", "cells")
                            }),
                    )
                    .on_hover_text("Tile-origin offset: the optical axis sits on the centre of this cell of its tile (thesis: 6, 6)");
                dragging |= r.dragged();
            }
        });
        let period = d.opening.pitch_um + d.tiling.wiring_gap_um;
        let tiles = std::f64::consts::PI * (0.5 * d.optics.pupil_diameter_um() / period).powi(2);
        ui.label(format!(
            "period {period:.1} µm · {:.0} DPI · {} in the pupil",
            25400.0 / period,
            crate::app::widgets::counted(tiles.round(), "tile", "tiles")
        ));
        if dragging {
            self.draft = Some(d);
        } else {
            self.draft = None;
            ctx.edit(d);
        }
        ui.separator();
        self.preview_ui(ui, ctx.display);
    }

    fn preview_ui(&mut self, ui: &mut egui::Ui, display: Option<&DisplayPreview>) {
        let Some(p) = display else {
            ui.spinner();
            return;
        };
        let figure = self.figure.get(ui.ctx(), (), p.generation, || {
            let values = ndarray::Array2::from_shape_fn((p.side, p.side), |(r, c)| {
                f64::from(p.values.get(r * p.side + c).copied().unwrap_or(0.0))
            });
            tiling_panel(Arc::new(values), p.sample_um, p.pupil_diameter_um)
        });
        let side = ui
            .available_height()
            .clamp(160.0, 420.0)
            .min(ui.available_width());
        let frame = ImageFrame {
            size: egui::vec2(ui.available_width(), side),
            link: None,
            view_half: None,
        };
        ui.scope(|ui| {
            image_panel_ui(
                ui,
                "display-preview",
                &figure.panel,
                &figure.textures,
                frame,
            )
        })
        .response
        .on_hover_text(
            "The tiled display over the lens pupil (orange); Ctrl + scroll to zoom, drag or \
                 scroll to pan, double-click to reset",
        );
    }
}
