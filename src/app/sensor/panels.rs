//! The sensor workspace's three panels: controls (left), pictures and plots (centre), numbers
//! (right).

use egui::{Id, Ui, vec2};

use super::{CompareMode, ExposureKind, SensorAction, SensorCtx, SensorView, TextureKey};
use crate::app::history::Snapshot;
use crate::app::widgets::figure::{
    COLORBAR_WIDTH, FigureCache, ImageFrame, Shown, colour_bar_ui, image_panel_ui,
};
use crate::core::figure::Annotation;
use crate::core::sensor::{BinMode, Exposure, SensorSpec, figures, maps};

/// Which picture of a run a figure slot holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum MapSlot {
    Scene,
    Capture,
    Gain,
    Bins,
    Saturated,
    CompareA,
    CompareB,
    Split,
}

/// A picture with its title above and its colour bar (or key) beside it, the ROI grid over it
/// when asked.
fn picture_ui(ui: &mut Ui, id: MapSlot, shown: &Shown, grid: &[Annotation], frame: ImageFrame) {
    ui.vertical(|ui| {
        ui.label(&shown.panel.title);
        ui.horizontal(|ui| {
            let with_grid;
            let panel = if grid.is_empty() {
                shown.panel.as_ref()
            } else {
                let mut p = (*shown.panel).clone();
                p.annotations.extend_from_slice(grid);
                with_grid = p;
                &with_grid
            };
            image_panel_ui(ui, ("sensor", id), panel, &shown.textures, frame);
            if let Some(img) = panel.images.first() {
                colour_bar_ui(ui, frame.size.y, img);
            }
        });
    });
}

/// The frame of a picture `width` points wide (colour bar included) of a `rows × cols` run,
/// panning and zooming with the pictures of `link`.
fn frame_of(width: f32, (rows, cols): (usize, usize), link: Id) -> ImageFrame {
    // Room for the axes' ticks and titles around the picture itself.
    const AXES: f32 = 48.0;
    let plot_w = (width - COLORBAR_WIDTH).max(120.0);
    let picture_h = (plot_w - AXES) * rows as f32 / cols.max(1) as f32;
    ImageFrame {
        size: vec2(plot_w, picture_h + AXES),
        link: Some(link),
        view_half: None,
    }
}

/// The workspace's panels: each draws from a [`SensorCtx`] and queues [`SensorAction`]s.
#[derive(Default)]
pub struct Panels {
    /// Left: the scene, the sensor and the strategy settings, the flat-patch check.
    pub controls: ControlsPanel,
    /// Right: the numbers of the shown run.
    pub numbers: super::numbers::NumbersPanel,
    /// Centre: maps, comparison, curves or the bin-size study.
    pub views: ViewsPanel,
}

/// The exposure controls and the settings beside them. Each exposure kind keeps its own value
/// while another is chosen; the settings' `exposure` is the chosen one.
pub struct ControlsPanel {
    exposure_kind: ExposureKind,
    mean_fraction: f64,
    percentile: f64,
    percentile_fill: f64,
    absolute_e_per_um2: f64,
}

impl Default for ControlsPanel {
    fn default() -> Self {
        ControlsPanel {
            exposure_kind: ExposureKind::Mean,
            mean_fraction: 0.05,
            percentile: 99.9,
            percentile_fill: 0.8,
            absolute_e_per_um2: 100.0,
        }
    }
}

/// The centre's picture and what it shows: the strategy mapped, the two compared, the split,
/// the ROI grid, the curves' light and pitch.
pub struct ViewsPanel {
    /// The picture shown.
    pub view: SensorView,
    map_strategy: usize,
    /// Captures A and B of the Compare view (strategy indices).
    pub compare: [usize; 2],
    /// Side by side or split.
    pub compare_mode: CompareMode,
    /// The split line, a share of the width.
    pub split: f32,
    roi_grid: bool,
    /// The run's pictures as figures, built (and uploaded) when the run or the choice changes.
    figures: FigureCache<MapSlot, TextureKey>,
    curve_light_e_per_um2: f64,
    curve_pitch_um: f64,
}

impl Default for ViewsPanel {
    fn default() -> Self {
        ViewsPanel {
            view: SensorView::Maps,
            map_strategy: 3,
            compare: [0, 3],
            compare_mode: CompareMode::SideBySide,
            split: 0.5,
            roi_grid: true,
            figures: FigureCache::default(),
            curve_light_e_per_um2: 20.0,
            curve_pitch_um: 1.0,
        }
    }
}

impl ControlsPanel {
    /// The exposure the controls set.
    fn exposure(&self) -> Exposure {
        match self.exposure_kind {
            ExposureKind::Mean => Exposure::MeanFraction(self.mean_fraction),
            ExposureKind::Percentile => Exposure::PercentileFill {
                percentile: self.percentile,
                fill: self.percentile_fill,
            },
            ExposureKind::Absolute => Exposure::ElectronsPerUm2(self.absolute_e_per_um2),
        }
    }

    /// The controls set to `exposure` (after an undo or redo).
    pub fn show_exposure(&mut self, exposure: Exposure) {
        match exposure {
            Exposure::MeanFraction(f) => {
                self.exposure_kind = ExposureKind::Mean;
                self.mean_fraction = f;
            }
            Exposure::PercentileFill { percentile, fill } => {
                self.exposure_kind = ExposureKind::Percentile;
                self.percentile = percentile;
                self.percentile_fill = fill;
            }
            Exposure::ElectronsPerUm2(e) => {
                self.exposure_kind = ExposureKind::Absolute;
                self.absolute_e_per_um2 = e;
            }
        }
    }

    /// Left: scene, sensor, exposure and strategy parameters.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut SensorCtx<'_>) {
        ui.heading("Sensor previewer");
        ui.label(
            "Spatially-varying gain and binning (thesis chapter 5): choose them per region from \
             the local brightness, and compare with one gain and one bin size for the frame.",
        );
        ui.separator();
        ui.horizontal_wrapped(|ui| {
            ui.label("Scene:");
            ui.strong(
                ctx.scene
                    .map(|s| s.name.as_str())
                    .unwrap_or("(none: open an HDR file)"),
            );
        });
        ui.horizontal(|ui| {
            if ui
                .add_enabled(!ctx.asking, egui::Button::new("Open HDR…"))
                .on_hover_text(
                    "Radiance .hdr or OpenEXR .exr (half or float); or drop one on the window",
                )
                .clicked()
            {
                ctx.actions.push(SensorAction::AskHdr);
            }
            if ctx.loading {
                ui.spinner();
                ui.label("reading…");
            }
        });
        ui.separator();
        // The controls edit a draft; a change is queued as a live edit, which the history
        // makes one undo step once the pointer is up (Workspace::apply carries it out).
        // Undo and redo: the Edit menu, Ctrl+Z and Ctrl+Shift+Z.
        let mut draft = ctx.settings.clone();
        let s = &mut draft;
        egui::Grid::new("sensor_settings")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("Sensor");
                let current = s.sensor.name.clone();
                egui::ComboBox::from_id_salt("sensor_preset")
                    .selected_text(&current)
                    .show_ui(ui, |ui| {
                        for p in SensorSpec::presets() {
                            let label = p.name.clone();
                            let hint = p.description.clone();
                            if ui
                                .selectable_label(current == p.name, label)
                                .on_hover_text(hint)
                                .clicked()
                            {
                                s.sensor = p;
                            }
                        }
                    });
                ui.end_row();
                ui.label("Unit pixel");
                ui.label(format!("{} µm", s.sensor.unit_pixel_um));
                ui.end_row();
                ui.label("Full well");
                ui.label(format!("{:.0} e-", s.sensor.full_well_e));
                ui.end_row();
                ui.label("Read noise pre / post");
                ui.label(format!(
                    "{:.2} / {:.2} e-",
                    s.sensor.sigma_pre_e, s.sensor.sigma_post_e
                ));
                ui.end_row();
                ui.label("Max gain, ADC");
                ui.label(format!(
                    "{}x, {} bits",
                    s.sensor.max_gain, s.sensor.adc_bits
                ));
                ui.end_row();
            });
        ui.separator();
        ui.label("Exposure");
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.exposure_kind, ExposureKind::Mean, "mean")
                .on_hover_text(
                    "The scene's mean fills this fraction of the full well (Table 5.4: 5 %)",
                );
            ui.selectable_value(
                &mut self.exposure_kind,
                ExposureKind::Percentile,
                "percentile",
            )
            .on_hover_text("A percentile of the scene fills this fraction of the full well");
            ui.selectable_value(&mut self.exposure_kind, ExposureKind::Absolute, "absolute")
                .on_hover_text("Electrons per µm² at radiance 1");
        });
        match self.exposure_kind {
            ExposureKind::Mean => {
                ui.add(
                    egui::Slider::new(&mut self.mean_fraction, 0.001..=0.5)
                        .logarithmic(true)
                        .text("mean / full well"),
                );
            }
            ExposureKind::Percentile => {
                ui.add(egui::Slider::new(&mut self.percentile, 50.0..=100.0).text("percentile"));
                ui.add(
                    egui::Slider::new(&mut self.percentile_fill, 0.01..=1.0)
                        .text("fills / full well"),
                );
            }
            ExposureKind::Absolute => {
                ui.add(
                    egui::Slider::new(&mut self.absolute_e_per_um2, 0.01..=10000.0)
                        .logarithmic(true)
                        .suffix(" e-/µm²"),
                );
            }
        }
        draft.exposure = self.exposure();
        ui.separator();
        let s = &mut draft;
        egui::Grid::new("sensor_strategy")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("ROI side");
                ui.add(
                    crate::app::widgets::number(&mut s.roi_px)
                        .range(16..=1024)
                        .suffix(" px"),
                );
                ui.end_row();
                ui.label("eta (ROI gain)");
                ui.add(
                    crate::app::widgets::number(&mut s.eta)
                        .range(0.0..=10.0)
                        .speed(0.05),
                )
                .on_hover_text("Eq. 5.3 headroom: 2 saturates about 2.2 % of a flat region");
                ui.end_row();
                ui.label("eta (per-pixel gain)");
                ui.add(
                    crate::app::widgets::number(&mut s.eta_per_pixel)
                        .range(0.0..=10.0)
                        .speed(0.05),
                );
                ui.end_row();
                ui.label("SNR threshold");
                ui.add(
                    crate::app::widgets::number(&mut s.snr_t)
                        .range(0.5..=50.0)
                        .speed(0.1),
                )
                .on_hover_text("The optimal-pitch cutoff: where contrast / noise falls to this");
                ui.end_row();
                ui.label("Binning");
                egui::ComboBox::from_id_salt("bin_mode")
                    .selected_text(s.bin_mode.label())
                    .show_ui(ui, |ui| {
                        for m in [
                            BinMode::AnalogAdditive,
                            BinMode::AnalogAverage,
                            BinMode::Digital,
                        ] {
                            ui.selectable_value(&mut s.bin_mode, m, m.label());
                        }
                    });
                ui.end_row();
                super::gain_panel::additive_gain_row(ui, s);
                super::gain_panel::roi_light_row(ui, s);
                super::colour::cfa_row_ui(ui, &mut s.cfa);
                ui.label("Display gamma");
                ui.add(
                    crate::app::widgets::number(&mut s.gamma)
                        .range(0.1..=1.0)
                        .speed(0.005),
                )
                .on_hover_text("Tone curve for display and the metrics (Table 5.4: 1/3.2)");
                ui.end_row();
                ui.label("Noise seed");
                ui.add(crate::app::widgets::number(&mut s.seed));
                ui.end_row();
            });
        if !draft.same(ctx.settings) {
            ctx.actions.push(SensorAction::Live(Box::new(draft)));
        }
        ui.separator();
        egui::CollapsingHeader::new("Flat patch check (eq. 5.3)")
            .default_open(true)
            .show(ui, |ui| ctx.flat.ui(ui));
        crate::app::widgets::message_ui(ui, ctx.message);
    }
}

impl ViewsPanel {
    /// Lets go of the pictures of the previous run (a new run is on screen).
    pub fn forget_figures(&mut self) {
        self.figures = FigureCache::default();
    }

    /// Figures built so far (a test proves a frame rebuilds none).
    pub fn figure_builds(&self) -> u64 {
        self.figures.builds()
    }

    /// Centre: maps, comparison or curves.
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut SensorCtx<'_>) {
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.view, SensorView::Maps, "Scene and maps");
            ui.selectable_value(&mut self.view, SensorView::Compare, "Compare captures");
            ui.selectable_value(
                &mut self.view,
                SensorView::Curves,
                "Optimal pitch (Fig. 5.3)",
            );
            ui.selectable_value(&mut self.view, SensorView::Study, "Bin sizes (Fig. 5.4)");
            ui.separator();
            ui.checkbox(&mut self.roi_grid, "ROI grid");
        });
        ui.separator();
        match self.view {
            SensorView::Curves => self.curves_ui(ui, ctx),
            SensorView::Maps => self.maps_ui(ui, ctx),
            SensorView::Compare => self.compare_ui(ui, ctx),
            SensorView::Study => {
                let scene = ctx.scene.cloned();
                let settings = ctx.settings;
                ctx.study.ui(ui, scene.as_deref(), settings);
            }
        }
    }

    fn strategy_picker(ui: &mut Ui, id: &str, names: &[String], index: &mut usize) {
        egui::ComboBox::from_id_salt(id)
            .selected_text(names.get(*index).map_or("", String::as_str))
            .show_ui(ui, |ui| {
                for (i, n) in names.iter().enumerate() {
                    ui.selectable_value(index, i, n);
                }
            });
    }

    fn maps_ui(&mut self, ui: &mut Ui, ctx: &SensorCtx<'_>) {
        let Some(shown) = ctx.shown else {
            ui.label("No result yet.");
            return;
        };
        let run = shown.run.clone();
        let names: Vec<String> = run.strategies.iter().map(|s| s.name.clone()).collect();
        self.map_strategy = self.map_strategy.min(names.len().saturating_sub(1));
        ui.horizontal(|ui| {
            ui.label("Maps of");
            Self::strategy_picker(ui, "map_strategy", &names, &mut self.map_strategy);
        });
        let i = self.map_strategy;
        let Some(s) = run.strategies.get(i) else {
            return;
        };
        let grid = if self.roi_grid {
            maps::roi_grid(&run)
        } else {
            Vec::new()
        };
        let frame = frame_of(
            ((ui.available_width() - 24.0) / 2.0).max(200.0),
            run.electrons.dim(),
            ui.make_persistent_id("sensor-maps"),
        );
        let (g, q) = (shown.generation, shown.quality);
        let egui_ctx = ui.ctx().clone();
        let figures = &mut self.figures;
        let mut get = |slot: MapSlot, build: &dyn Fn() -> crate::core::figure::Panel| {
            let strategy = if slot == MapSlot::Scene { 0 } else { i };
            figures.get(&egui_ctx, slot, (g, q, strategy, 0, 0), build)
        };
        let scene = get(MapSlot::Scene, &|| maps::scene_panel(&run));
        let capture = get(MapSlot::Capture, &|| maps::capture_panel(s));
        let gain = get(MapSlot::Gain, &|| maps::gain_panel(s, maps::max_gain(&run)));
        let bins = get(MapSlot::Bins, &|| maps::bin_panel(s));
        let saturated = get(MapSlot::Saturated, &|| maps::saturation_panel(s));
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.horizontal(|ui| {
                picture_ui(ui, MapSlot::Scene, &scene, &grid, frame);
                picture_ui(ui, MapSlot::Capture, &capture, &grid, frame);
            });
            ui.horizontal(|ui| {
                picture_ui(ui, MapSlot::Gain, &gain, &grid, frame);
                picture_ui(ui, MapSlot::Bins, &bins, &grid, frame);
            });
            picture_ui(ui, MapSlot::Saturated, &saturated, &grid, frame);
        });
    }

    fn compare_ui(&mut self, ui: &mut Ui, ctx: &SensorCtx<'_>) {
        let Some(shown) = ctx.shown else {
            ui.label("No result yet.");
            return;
        };
        let run = shown.run.clone();
        let names: Vec<String> = run.strategies.iter().map(|s| s.name.clone()).collect();
        for c in &mut self.compare {
            *c = (*c).min(names.len().saturating_sub(1));
        }
        ui.horizontal_wrapped(|ui| {
            ui.label("A");
            Self::strategy_picker(ui, "compare_a", &names, &mut self.compare[0]);
            ui.label("B");
            Self::strategy_picker(ui, "compare_b", &names, &mut self.compare[1]);
            ui.separator();
            ui.selectable_value(
                &mut self.compare_mode,
                CompareMode::SideBySide,
                "side by side",
            );
            ui.selectable_value(&mut self.compare_mode, CompareMode::Split, "split");
            if self.compare_mode == CompareMode::Split {
                ui.add(egui::Slider::new(&mut self.split, 0.0..=1.0).text("A | B"));
            }
        });
        let [ia, ib] = self.compare;
        let (Some(a), Some(b)) = (run.strategies.get(ia), run.strategies.get(ib)) else {
            return;
        };
        ui.label(format!(
            "A: worst ROI SSIM {:.4}, PSNR {:.2} dB    B: worst ROI SSIM {:.4}, PSNR {:.2} dB",
            a.worst_roi_ssim, a.psnr_db, b.worst_roi_ssim, b.psnr_db
        ));
        let grid = if self.roi_grid {
            maps::roi_grid(&run)
        } else {
            Vec::new()
        };
        let link = ui.make_persistent_id("sensor-compare");
        let dim = a.capture.dim();
        let (g, q) = (shown.generation, shown.quality);
        let egui_ctx = ui.ctx().clone();
        match self.compare_mode {
            CompareMode::SideBySide => {
                let frame = frame_of(((ui.available_width() - 24.0) / 2.0).max(200.0), dim, link);
                let key = |i: usize| (g, q, i, 0, 0);
                let fa = self.figures.get(&egui_ctx, MapSlot::CompareA, key(ia), || {
                    maps::capture_panel(a)
                });
                let fb = self.figures.get(&egui_ctx, MapSlot::CompareB, key(ib), || {
                    maps::capture_panel(b)
                });
                ui.horizontal(|ui| {
                    picture_ui(ui, MapSlot::CompareA, &fa, &grid, frame);
                    picture_ui(ui, MapSlot::CompareB, &fb, &grid, frame);
                });
            }
            CompareMode::Split => {
                let w = dim.1;
                let split_col = ((self.split * w as f32) as usize).min(w);
                let key = (g, q, ia, ib, split_col as u32);
                let split = self.figures.get(&egui_ctx, MapSlot::Split, key, || {
                    maps::split_panel(a, b, split_col)
                });
                let mut frame = frame_of((ui.available_width() - 12.0).max(240.0), dim, link);
                frame.size.y = frame.size.y.min(ui.available_height() - 24.0).max(120.0);
                picture_ui(ui, MapSlot::Split, &split, &grid, frame);
            }
        }
    }

    fn curves_ui(&mut self, ui: &mut Ui, ctx: &SensorCtx<'_>) {
        let sensor = ctx.settings.sensor.clone();
        let snr_t = ctx.settings.snr_t;
        ui.horizontal_wrapped(|ui| {
            ui.add(
                egui::Slider::new(&mut self.curve_light_e_per_um2, 0.1..=1000.0)
                    .logarithmic(true)
                    .suffix(" e-/µm²")
                    .text("light"),
            );
            ui.add(
                egui::Slider::new(&mut self.curve_pitch_um, 0.25..=8.0)
                    .logarithmic(true)
                    .suffix(" µm")
                    .text("pitch"),
            );
        });
        let h = (ui.available_height() / 2.0 - 30.0).max(160.0);
        for (id, panel) in [
            (
                "sensor-contrast",
                figures::contrast_panel(
                    self.curve_light_e_per_um2,
                    self.curve_pitch_um,
                    &sensor,
                    snr_t,
                ),
            ),
            ("sensor-pitch", figures::optimal_pitch_panel(&sensor, snr_t)),
        ] {
            ui.label(&panel.title);
            crate::app::widgets::figure::panel_ui(ui, id, &panel, h);
        }
    }
}
