//! The result views: PSF (linear and log), RGB composite, 2-D MTF, MTF plots, expected PSF of a
//! random tiling, and the A/B comparison, with optional teaching overlays.
//!
//! Image figures are built by the core's pure functions (`core::views`) and
//! uploaded once per result and setting (a figure cache keyed by generation, quality, channel,
//! floor and marks); the frame loop only places them in plots.

pub mod appearance;
mod compare;
mod expected;
pub mod field_depth;
mod hints;
pub mod images;
mod plots;
pub mod restore;
mod textures;
mod theory;

use std::sync::Arc;

use egui::{RichText, Ui};

use self::images::{DEFAULT_FLOOR_DECADES, FLOOR_DECADES_RANGE, channel_color};
use self::plots::{MtfFamilies, image_with_colour_bar_ui, mtf_plot_ui};
use self::textures::{Slot, TexKey, Textures};
use super::{PanelCtx, Shown};
use crate::core::analysis::analyze::ChannelAnalysis;
use crate::core::figure::Panel;
use crate::core::theory::landmarks::{airy_radius_um, order_spacing_um};
use crate::core::views::{Landmarks, PsfScale, mtf2d_panel, psf_panel, rgb_panel, rgb_slots};

/// The tabs of the result views.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ViewTab {
    /// The sensor PSF of one channel on a linear scale (teaching overlays: orders, Airy disc).
    #[default]
    Psf,
    /// The PSF in decades below its peak, so the faint orders and halo show.
    LogPsf,
    /// The colour channels' log-PSFs together as one RGB image.
    Rgb,
    /// The 2-D MTF of one channel, DC in the centre, in decades below MTF(0) = 1.
    Mtf2d,
    /// MTF curves: horizontal and vertical slices, radial mean and radial minimum.
    MtfPlots,
    /// This random tiling's PSF beside the expected PSF averaged over all tilings.
    Expected,
    /// The PSF profile and MTF over the closed-form pattern of the aperture (Fourier optics).
    Theory,
    /// The pinned design A against the current design B, with their differences.
    Compare,
    /// A photo blurred by the PSFs, exposed with noise and restored, with PSNR and SSIM.
    Restore,
    /// PSFs over the field and with depth, with their residuals (thesis §3.7).
    FieldDepth,
    /// A photo on the layout as the eye sees it, periodic and random, with display quality.
    Appearance,
}

impl ViewTab {
    /// Every tab, in the order of the tab bar.
    pub const ALL: [ViewTab; 11] = [
        ViewTab::Psf,
        ViewTab::LogPsf,
        ViewTab::Rgb,
        ViewTab::Mtf2d,
        ViewTab::MtfPlots,
        ViewTab::Expected,
        ViewTab::Theory,
        ViewTab::Compare,
        ViewTab::Restore,
        ViewTab::FieldDepth,
        ViewTab::Appearance,
    ];

    /// Text on the tab.
    pub fn label(self) -> &'static str {
        match self {
            ViewTab::Psf => "PSF",
            ViewTab::LogPsf => "log-PSF",
            ViewTab::Rgb => "RGB",
            ViewTab::Mtf2d => "MTF 2-D",
            ViewTab::MtfPlots => "MTF plots",
            ViewTab::Expected => "Expected PSF",
            ViewTab::Theory => "Theory",
            ViewTab::Compare => "Compare",
            ViewTab::Restore => "Restore",
            ViewTab::FieldDepth => "Field & depth",
            ViewTab::Appearance => "Appearance",
        }
    }

    fn hint(self) -> &'static str {
        match self {
            ViewTab::Psf => hints::PSF,
            ViewTab::LogPsf => hints::LOG_PSF,
            ViewTab::Rgb => hints::RGB,
            ViewTab::Mtf2d => hints::MTF_2D,
            ViewTab::MtfPlots => hints::MTF_PLOTS,
            ViewTab::Expected => hints::EXPECTED,
            ViewTab::Theory => hints::THEORY,
            ViewTab::Compare => hints::COMPARE,
            ViewTab::Restore => hints::RESTORE,
            ViewTab::FieldDepth => hints::FIELD_DEPTH,
            ViewTab::Appearance => hints::APPEARANCE,
        }
    }
}

/// The result views panel. All of its state is view state (never undone).
pub struct ViewsPanel {
    tab: ViewTab,
    channel: usize,
    /// Depth of the log views, in decades below the peak.
    floor_decades: f64,
    /// Depth of the 2-D MTF view, in decades below MTF(0) = 1.
    mtf_floor_decades: f64,
    families: MtfFamilies,
    textures: Textures,
    /// The Restore view (its own photo, settings and background job).
    pub restore: restore::RestoreView,
    /// The Field & depth view (its own settings and background job).
    pub field_depth: field_depth::FieldDepthView,
    /// The Appearance view (its settings, renderings and scatter).
    pub appearance: appearance::AppearanceView,
    /// The reference marks drawn over the PSFs (with the teaching overlays on).
    overlay_choice: Landmarks,
    /// The Theory view's cached comparison and scale.
    theory: theory::TheoryView,
    /// The figure the view drew last frame, for its Save figure button.
    saveable: Option<(ViewTab, Arc<Panel>)>,
}

impl Default for ViewsPanel {
    fn default() -> Self {
        ViewsPanel {
            tab: ViewTab::LogPsf,
            channel: 0,
            floor_decades: DEFAULT_FLOOR_DECADES,
            mtf_floor_decades: 3.0,
            families: MtfFamilies::default(),
            textures: Textures::default(),
            restore: restore::RestoreView::default(),
            field_depth: field_depth::FieldDepthView::default(),
            appearance: appearance::AppearanceView::default(),
            overlay_choice: Landmarks::default(),
            theory: theory::TheoryView::default(),
            saveable: None,
        }
    }
}

impl ViewsPanel {
    /// The selected tab.
    pub fn tab(&self) -> ViewTab {
        self.tab
    }

    /// Selects a tab (menus and shortcuts of the shell may call this).
    pub fn set_tab(&mut self, tab: ViewTab) {
        self.tab = tab;
    }

    /// Images built and uploaded so far: a diagnostic that must not grow while neither the
    /// result nor a view setting changes.
    pub fn texture_builds(&self) -> u64 {
        self.textures.builds()
    }

    /// Takes the views' finished jobs, shown or not (the workspace calls it once per frame:
    /// a tab that is not drawn must not hold its result back).
    pub fn poll(&mut self, ctx: &egui::Context) {
        self.restore.poll(ctx);
        self.field_depth.poll(ctx);
        self.appearance.poll(ctx);
    }

    /// Draws the tabs and the selected view of `ctx.shown`; pushes `PinCompare`/`ClearCompare`.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut PanelCtx) {
        ui.horizontal_wrapped(|ui| {
            for tab in ViewTab::ALL {
                ui.selectable_value(&mut self.tab, tab, tab.label());
            }
        });
        ui.separator();
        let Some(shown) = ctx.shown else {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("computing…");
            });
            return;
        };
        let n_channels = shown.analysis.channels.len();
        self.channel = self.channel.min(n_channels.saturating_sub(1));
        self.controls_ui(ui, shown, ctx.overlays);
        if ctx.overlays {
            egui::CollapsingHeader::new("What am I seeing?")
                .id_salt(("views_hint", self.tab))
                .show(ui, |ui| ui.label(self.tab.hint()));
        }
        let Some(ch) = shown.analysis.channels.get(self.channel) else {
            ui.label("This result has no colour channels.");
            return;
        };
        match self.tab {
            ViewTab::Psf | ViewTab::LogPsf => self.psf_ui(ui, shown, ch, ctx.overlays),
            ViewTab::Rgb => self.rgb_ui(ui, shown),
            ViewTab::Mtf2d => self.mtf2d_ui(ui, shown, ch),
            ViewTab::MtfPlots => self.mtf_plots_ui(ui, shown, ctx),
            ViewTab::Expected => self.expected_ui(ui, shown, ch, ctx.overlays),
            ViewTab::Theory => self.theory.ui(ui, shown, self.channel),
            ViewTab::Compare => self.compare_ui(ui, shown, ctx),
            ViewTab::Restore => self.restore.ui(ui, shown, ctx),
            ViewTab::FieldDepth => self.field_depth.ui(ui, shown),
            ViewTab::Appearance => self.appearance.ui(ui, shown),
        }
    }

    /// The settings row of the current tab: channel, floor, curve families.
    fn controls_ui(&mut self, ui: &mut Ui, shown: &Shown, overlays: bool) {
        let tab = self.tab;
        ui.horizontal_wrapped(|ui| {
            if let Some((drawn, panel)) = &self.saveable
                && *drawn == tab
                && ui
                    .button("Save figure…")
                    .on_hover_text(
                        "This view as an SVG or PNG with its axes, units, colour bar and a caption \
                         naming the design (also: right-click the plot)",
                    )
                    .clicked()
            {
                crate::app::widgets::figure::request_save(ui.ctx(), panel);
            }
            if matches!(
                tab,
                ViewTab::Psf
                    | ViewTab::LogPsf
                    | ViewTab::Mtf2d
                    | ViewTab::Expected
                    | ViewTab::Theory
            ) {
                ui.label("Channel:");
                for (i, c) in shown.analysis.channels.iter().enumerate() {
                    let text = RichText::new(&c.name).color(channel_color(&c.name));
                    ui.selectable_value(&mut self.channel, i, text)
                        .on_hover_text(format!("{:.0} nm", c.wavelength_nm));
                }
            }
            if overlays && matches!(tab, ViewTab::Psf | ViewTab::LogPsf | ViewTab::Expected) {
                let (f_mm, f_number, period_um) = (
                    shown.design.optics.focal_length_mm,
                    shown.design.optics.f_number,
                    shown.design.opening.pitch_um + shown.design.tiling.wiring_gap_um,
                );
                let nm = shown
                    .analysis
                    .channels
                    .get(self.channel)
                    .map_or(530.0, |c| c.wavelength_nm);
                let o = &mut self.overlay_choice;
                ui.separator();
                ui.checkbox(&mut o.airy, "Airy ring").on_hover_text(format!(
                    "The lens alone: first dark ring at 1.22 λ F# = {:.2} µm",
                    airy_radius_um(nm, f_number)
                ));
                ui.checkbox(&mut o.orders, "diffraction orders")
                    .on_hover_text(format!(
                        "Where a periodic display throws light: every λ f / T = {:.1} µm",
                        order_spacing_um(nm, f_mm, period_um)
                    ));
            }
            // A slider is a row of its own inside a wrapped row: it cannot wrap, so it starts a
            // line rather than run past the panel's edge (and widen everything below).
            if matches!(tab, ViewTab::LogPsf | ViewTab::Expected | ViewTab::Mtf2d) {
                ui.end_row();
            }
            if matches!(tab, ViewTab::LogPsf | ViewTab::Rgb | ViewTab::Expected) {
                ui.add(
                    egui::Slider::new(&mut self.floor_decades, FLOOR_DECADES_RANGE)
                        .step_by(0.5)
                        .text("floor (decades below peak)"),
                )
                .on_hover_text(
                    "The log scale stops this many decades below the peak: values under \
                     peak × 10^−floor (including exact zeros, whose log is −∞) take the floor \
                     colour. Deeper floors reveal fainter orders and, eventually, round-off noise.",
                );
            }
            if tab == ViewTab::Mtf2d {
                ui.add(
                    egui::Slider::new(&mut self.mtf_floor_decades, 1.0..=9.0)
                        .step_by(0.5)
                        .text("floor (decades below 1)"),
                )
                .on_hover_text(
                    "log10 of the MTF is shown down to 10^−floor; lower values, and the exact \
                     zeros whose log is −∞, take the floor colour.",
                );
            }
            if matches!(
                tab,
                ViewTab::Psf | ViewTab::LogPsf | ViewTab::Rgb | ViewTab::Mtf2d | ViewTab::Expected
            ) {
                ui.weak("Ctrl + scroll: zoom · drag: pan · double-click: reset");
            }
            if tab == ViewTab::MtfPlots {
                let f = &mut self.families;
                ui.checkbox(&mut f.horizontal, "horizontal");
                ui.checkbox(&mut f.vertical, "vertical");
                ui.checkbox(&mut f.radial_min, "radial min");
                ui.checkbox(&mut f.radial_mean, "radial mean");
            }
        });
    }

    fn key(&self, shown: &Shown, channel: usize, floor_decades: f64, marks: Landmarks) -> TexKey {
        TexKey {
            generation: shown.generation,
            quality: shown.quality,
            channel,
            floor_decades,
            landmarks: marks,
        }
    }

    /// The marks drawn over a PSF: the chosen ones with the teaching overlays on, else none.
    fn landmarks(&self, overlays: bool) -> Landmarks {
        if overlays {
            self.overlay_choice
        } else {
            Landmarks {
                airy: false,
                orders: false,
            }
        }
    }

    fn psf_ui(&mut self, ui: &mut Ui, shown: &Shown, ch: &ChannelAnalysis, overlays: bool) {
        let log = self.tab == ViewTab::LogPsf;
        let marks = self.landmarks(overlays);
        let (slot, scale, floor) = if log {
            let floor_decades = self.floor_decades;
            (Slot::LogPsf, PsfScale::Log { floor_decades }, floor_decades)
        } else {
            (Slot::Psf, PsfScale::Linear, 0.0)
        };
        let key = self.key(shown, self.channel, floor, marks);
        let figure = self.textures.get(ui.ctx(), slot, key, || {
            psf_panel(&shown.design, &shown.analysis, ch, scale, marks)
        });
        let id = if log { "views_log_psf" } else { "views_psf" };
        image_with_colour_bar_ui(ui, id, &figure);
        self.saveable = Some((self.tab, figure.panel));
    }

    fn rgb_ui(&mut self, ui: &mut Ui, shown: &Shown) {
        let channels = &shown.analysis.channels;
        let names: Vec<&str> = channels.iter().map(|c| c.name.as_str()).collect();
        let slots = rgb_slots(&names);
        let floor = self.floor_decades;
        let used: Vec<String> = ["red", "green", "blue"]
            .iter()
            .zip(slots)
            .map(|(plane, s)| match s.and_then(|i| channels.get(i)) {
                Some(c) => format!("{plane} = {}", c.name),
                None => format!("{plane} empty"),
            })
            .collect();
        ui.label(format!(
            "Each channel normalised to its own peak, on a log scale from the peak down to \
             1e-{floor} (the floor); {}.",
            used.join(", ")
        ));
        let none = self.landmarks(false);
        let key = self.key(shown, 0, floor, none);
        let figure = self.textures.get(ui.ctx(), Slot::Rgb, key, || {
            rgb_panel(&shown.analysis, floor).unwrap_or_default()
        });
        if figure.panel.images.is_empty() {
            return;
        }
        image_with_colour_bar_ui(ui, "views_rgb", &figure);
        self.saveable = Some((ViewTab::Rgb, figure.panel));
    }

    fn mtf2d_ui(&mut self, ui: &mut Ui, shown: &Shown, ch: &ChannelAnalysis) {
        let floor = self.mtf_floor_decades;
        let key = self.key(shown, self.channel, floor, self.landmarks(false));
        let figure = self
            .textures
            .get(ui.ctx(), Slot::Mtf2d, key, || mtf2d_panel(ch, floor));
        image_with_colour_bar_ui(ui, "views_mtf2d", &figure);
        self.saveable = Some((ViewTab::Mtf2d, figure.panel));
    }

    fn mtf_plots_ui(&mut self, ui: &mut Ui, shown: &Shown, ctx: &PanelCtx) {
        let pinned = ctx.pinned.map(|p| p.analysis.as_ref());
        let repeats = ctx.overlays.then_some(shown.design.as_ref());
        let panel = mtf_plot_ui(
            ui,
            "views_mtf_plots",
            &shown.analysis,
            pinned,
            self.families,
            repeats,
        );
        self.saveable = Some((ViewTab::MtfPlots, Arc::new(panel)));
    }
}
