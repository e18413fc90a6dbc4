//! The Optimize panel (thesis §3.4.2): runs [`crate::core::optimize::optimize`] on a background
//! thread from the current design, plots the losses live, shows the opening as it evolves, and
//! applies the result as one undoable edit. Stop keeps the run so far; Cancel discards it.

use crate::app::notice::Notice;
use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, channel};

use egui::{Color32, Ui};

use super::PanelCtx;
use crate::app::error::StudioError;
use crate::app::job::{Job, JobError};
use crate::app::widgets::figure::{PlotFrame, panel_ui_in};
use crate::app::widgets::plot::visible_width;
use crate::core::Design;
use crate::core::analysis::analyze::Quality;
use crate::core::optimize::figures::losses_panel;
use crate::core::optimize::{
    DataSet, EpochReport, OptimizeSettings, Optimized, Relaxation, Scores, Start, binarise,
    optimize,
};
use udc_gpu::Route;

/// A run on its own thread, streaming one report per epoch beside its result.
struct Run {
    job: Job<Optimized>,
    epochs: Receiver<EpochReport>,
    stop: Arc<AtomicBool>,
    /// The design the run started from (the result replaces its opening only).
    start_name: String,
    /// Where its window transforms run (View ▸ Compute PSFs on, as the design on screen).
    route: Arc<Route>,
}

/// Finished run waiting to be applied.
pub struct Finished {
    /// The optimized design (binarised opening), its history, run time and the scores of the
    /// start and the result that the panel's summary shows.
    pub result: Optimized,
}

/// Panel state: the settings, the running job, the live history and the last result.
pub struct OptimizePanel {
    /// Settings of the next run (epochs, learning rate, start, quality…), edited in the panel.
    pub settings: OptimizeSettings,
    run: Option<Run>,
    history: Vec<EpochReport>,
    finished: Option<Finished>,
    message: Option<Notice>,
    show_relaxed: bool,
    /// Add the data loss on the built-in training photo (the thesis's "top-10 L2 + inv").
    pub data_loss: bool,
}

impl Default for OptimizePanel {
    fn default() -> Self {
        OptimizePanel {
            settings: OptimizeSettings {
                // Live feedback first: where the f-number allows, the preview sampling is
                // about 4× faster per epoch; elsewhere it is full quality.
                quality: Quality::Preview,
                ..OptimizeSettings::default()
            },
            run: None,
            history: Vec::new(),
            finished: None,
            message: None,
            show_relaxed: false,
            data_loss: true,
        }
    }
}

/// The built-in training photo of the data loss: another photo than the Restore view's, so the
/// view shows how the opening generalises.
const TRAINING_PHOTO: &[u8] = include_bytes!("../../../../assets/photos/coffee_256.png");

fn training_data(channels: usize) -> Result<DataSet, StudioError> {
    let img = image::load_from_memory(TRAINING_PHOTO).map_err(|e| crate::io::IoError::Image {
        path: "assets/photos/coffee_256.png".into(),
        message: e.to_string(),
    })?;
    let planes = crate::io::photo::planes_of(&img.to_rgb32f());
    if channels != planes.len() {
        return Err(StudioError::TrainingChannels {
            photo: planes.len(),
            design: channels,
        });
    }
    Ok(DataSet::new(&[planes], channels, 256)?)
}

impl OptimizePanel {
    /// Whether a run is in progress.
    pub fn is_running(&self) -> bool {
        self.run.is_some()
    }

    /// Epochs received so far from the current or last run.
    pub fn history(&self) -> &[EpochReport] {
        &self.history
    }

    /// The panel's last message (a run's outcome: its epochs, time and where it ran).
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// The finished run, if one waits to be applied.
    pub fn finished(&self) -> Option<&Finished> {
        self.finished.as_ref()
    }

    /// Starts a run from `design`, its transforms on `route` (settings are checked first; an
    /// error is shown, not run).
    pub fn start(&mut self, design: &Design, route: Arc<Route>, ctx: &egui::Context) {
        if let Err(e) = self.settings.validate() {
            self.message = Some(Notice::error(e.to_string()));
            return;
        }
        // Dropping a running job cancels it.
        self.run = None;
        let (tx, epochs) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        let data = if self.data_loss {
            match training_data(design.channels.len()) {
                Ok(d) => Some(d),
                Err(e) => {
                    self.message = Some(Notice::error(e.to_string()));
                    return;
                }
            }
        } else {
            None
        };
        let settings = self.settings.clone();
        let start_name = design.name.clone();
        let design = design.clone();
        let (wake, wake_epoch) = (ctx.clone(), ctx.clone());
        let on = route.clone();
        let job = Job::spawn(
            "optimizer",
            move || wake.request_repaint(),
            move |p| {
                optimize(&design, &settings, data.as_ref(), on.as_ref(), p, |r| {
                    let _ = tx.send(r.clone());
                    wake_epoch.request_repaint();
                    if s.load(Ordering::Relaxed) {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                })
            },
        );
        self.history.clear();
        self.finished = None;
        self.message = None;
        self.run = Some(Run {
            job,
            epochs,
            stop,
            start_name,
            route,
        });
    }

    /// Asks the run to stop after the current epoch and keep what it has.
    pub fn stop(&self) {
        if let Some(r) = &self.run {
            r.stop.store(true, Ordering::Relaxed);
        }
    }

    /// Aborts the run and discards it.
    pub fn cancel(&mut self) {
        if let Some(r) = self.run.take() {
            r.job.cancel();
            self.message = Some(Notice::info("optimization cancelled"));
        }
    }

    /// Takes the thread's messages; returns true when something changed.
    pub fn poll(&mut self) -> bool {
        let Some(run) = &self.run else {
            return false;
        };
        // The epochs first: the result is sent after the last one.
        let before = self.history.len();
        self.history.extend(run.epochs.try_iter());
        let changed = self.history.len() != before;
        let Some(result) = run.job.poll() else {
            return changed;
        };
        let name = run.start_name.clone();
        // Where it ran, when not on the CPU by choice: the device, or why `auto` left it.
        let place = match (run.route.note(), run.route.adapter()) {
            (Some(note), _) => format!(" ({note})"),
            (None, Some(adapter)) => format!(" on {adapter}"),
            (None, None) => String::new(),
        };
        self.history.extend(run.epochs.try_iter());
        self.run = None;
        match result {
            Ok(result) => {
                self.message = Some(Notice::info(format!(
                    "{}{} in {:.1} s{place}; apply to use the new opening",
                    crate::app::widgets::counted(result.history.len() as f64, "epoch", "epochs"),
                    if result.stopped_early {
                        " (stopped)"
                    } else {
                        ""
                    },
                    result.elapsed_ms / 1e3
                )));
                self.finished = Some(Finished { result });
            }
            Err(JobError::Cancelled) => {}
            Err(e) => {
                self.message = Some(Notice::error(format!("optimizing {name} failed: {e}")));
            }
        }
        true
    }

    /// Draws the settings, Run/Stop/Cancel, the live loss plot and the result to apply or discard
    /// (the workspace picks up the run's epochs and its end, [`OptimizePanel::poll`]).
    pub fn ui(&mut self, ui: &mut Ui, ctx: &mut PanelCtx) {
        ui.label(
            "Finds a pixel opening whose blur is easy to invert (thesis §3.4.2), under this \
             design's pitch, tiling (its seed stays fixed) and optics.",
        );
        ui.add_space(4.0);
        let running = self.is_running();
        ui.add_enabled_ui(!running, |ui| self.settings_ui(ui));
        ui.add_space(4.0);
        ui.horizontal(|ui| {
            if let Some(run) = &self.run {
                let done = self.history.len();
                ui.add(
                    egui::ProgressBar::new(run.job.fraction())
                        .desired_width(160.0)
                        .text(format!("epoch {done} / {}", self.settings.epochs)),
                );
                if ui
                    .button("Stop")
                    .on_hover_text("Finish after this epoch and keep the result so far")
                    .clicked()
                {
                    self.stop();
                }
                if ui
                    .button("Cancel")
                    .on_hover_text("Abort and discard this run")
                    .clicked()
                {
                    self.cancel();
                }
            } else if ui
                .button("Run optimizer")
                .on_hover_text(
                    "Start from the current design's geometry; the opening starts as chosen above",
                )
                .clicked()
            {
                self.start(ctx.design, ctx.shown_route(), ui.ctx());
            }
        });
        // Before a run: where it will go (a run's outcome line names the adapter itself).
        if !running
            && self.message.is_none()
            && let Some(adapter) = ctx.shown.and_then(|s| s.route.adapter())
        {
            ui.weak(format!("Runs on {adapter} (View ▸ Compute PSFs on)"));
        }
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        if let Some(f) = &self.finished {
            ui.separator();
            summary_ui(ui, &f.result);
            ui.weak(
                "Apply, and the views and numbers show the new opening with the full-quality \
                 L_inv above.",
            );
            let mut apply = false;
            let mut discard = false;
            ui.horizontal(|ui| {
                apply = ui
                    .button("Apply as new design")
                    .on_hover_text("Replace the opening (undo with Ctrl+Z); AUC and views update")
                    .clicked();
                discard = ui.button("Discard").clicked();
            });
            if apply {
                ctx.edit(f.result.design.clone());
                self.message = Some(Notice::info("applied the optimized opening"));
                self.finished = None;
            } else if discard {
                self.finished = None;
                self.message = None;
            }
        }
        // The run's story below its outcome: Apply stays in view without scrolling.
        if let Some(last) = self.history.last().cloned() {
            ui.separator();
            let result = self.finished.as_ref().map(|f| &f.result);
            opening_ui(ui, &mut self.show_relaxed, &last, result);
            self.loss_plot_ui(ui);
        }
    }

    fn settings_ui(&mut self, ui: &mut Ui) {
        let s = &mut self.settings;
        egui::Grid::new("optimize_settings")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("Epochs");
                ui.add(crate::app::widgets::number(&mut s.epochs).range(1..=2000));
                ui.end_row();
                ui.label("Target open fraction");
                ui.add(
                    crate::app::widgets::number(&mut s.target_open_fraction)
                        .range(0.02..=1.0)
                        .speed(0.005)
                        .fixed_decimals(3),
                )
                .on_hover_text("Fraction of the pixel left open at the end (the thesis: 0.2)");
                ui.end_row();
                ui.label("Reserve subpixels");
                ui.add(
                    crate::app::widgets::number(&mut s.reserve_subpixels_um2)
                        .range(0.0..=1.0e6)
                        .speed(10.0)
                        .suffix(" µm² per colour"),
                )
                .on_hover_text(
                    "Keep room for three equal R, G, B emitters of at least this area each in \
                     the opaque area (0 = off); the result carries their placement",
                );
                ui.end_row();
                ui.label("L_inv weight");
                ui.add(
                    crate::app::widgets::number(&mut s.weights.inv)
                        .range(0.0..=100.0)
                        .speed(0.001),
                );
                ui.end_row();
                ui.label("Area weight");
                ui.add(
                    crate::app::widgets::number(&mut s.weights.area)
                        .range(0.0..=1000.0)
                        .speed(0.1),
                );
                ui.end_row();
                ui.label("Area step / every");
                ui.horizontal(|ui| {
                    ui.add(
                        crate::app::widgets::number(&mut s.area_step)
                            .range(0.0..=1.0)
                            .speed(0.005),
                    );
                    ui.add(
                        crate::app::widgets::number(&mut s.area_every_epochs)
                            .range(1..=100)
                            .suffix(" epochs"),
                    );
                });
                ui.end_row();
                ui.label("Start from");
                ui.horizontal(|ui| {
                    ui.selectable_value(&mut s.start, Start::AllOpen, "all open")
                        .on_hover_text("The thesis's choice (its ablation's best)");
                    ui.selectable_value(&mut s.start, Start::Current, "current")
                        .on_hover_text("The current design's opening");
                });
                ui.end_row();
                ui.label("Sampling");
                ui.horizontal(|ui| {
                    ui.selectable_value(&mut s.quality, Quality::Preview, "preview")
                        .on_hover_text(
                            "Twice the fine spacing where the f-number oversamples the PSF \
                             enough to agree with full quality (about 4× faster); full quality \
                             otherwise (every preset at f/2.5)",
                        );
                    ui.selectable_value(&mut s.quality, Quality::Full, "full")
                        .on_hover_text("The design's own sampling (iccp21: ~0.2 s per epoch)");
                });
                ui.end_row();
                ui.label("Data loss");
                ui.checkbox(&mut self.data_loss, "top-10 % L2 (photo)")
                    .on_hover_text(
                        "Restore the built-in training photo (coffee, 256 px) through the \
                         Wiener filter and penalise the worst 10 % of pixels, as the thesis's \
                         published patterns were; L_inv alone raises the AUC but not always the \
                         restored photo",
                    );
                ui.end_row();
                ui.label("Loss sees");
                ui.horizontal(|ui| {
                    ui.selectable_value(
                        &mut s.relaxation,
                        Relaxation::StraightThrough,
                        "binary mask",
                    )
                    .on_hover_text(
                        "Straight-through: the loss of the thresholded opening, gradients \
                         through the sigmoid",
                    );
                    ui.selectable_value(&mut s.relaxation, Relaxation::Sigmoid, "grey mask")
                        .on_hover_text(
                            "The sigmoid relaxation itself; it drifts to a uniform grey pixel \
                             that thresholding turns into noise",
                        );
                });
                ui.end_row();
            });
    }

    /// The losses per epoch at the run's sampling, with the start design and the result
    /// scored alike as points at both ends; the legend above the plot, clear of the curves.
    fn loss_plot_ui(&self, ui: &mut Ui) {
        let scores = self.finished.as_ref().map(|f| &f.result.at_run_quality);
        let panel = losses_panel(&self.history, scores);
        let frame = PlotFrame {
            width: Some(visible_width(ui)),
            legend_above: true,
            ..PlotFrame::tall(180.0)
        };
        panel_ui_in(ui, "optimize_losses", &panel, frame);
    }
}

/// The opening of the last epoch, or the result once the run has finished (the result is
/// the mask after the last step, binarised at the final open fraction: what Apply applies).
fn opening_ui(
    ui: &mut Ui,
    show_relaxed: &mut bool,
    last: &EpochReport,
    result: Option<&Optimized>,
) {
    let n = (last.mask.len() as f64).sqrt() as usize;
    ui.horizontal_wrapped(|ui| {
        ui.label(format!(
            "Epoch {} of {}: grey-mask mean {:.3}, area target {:.3}",
            last.epoch + 1,
            last.epochs,
            last.open_fraction,
            last.area_target
        ))
        .on_hover_text(
            "The mean of the sigmoid mask g lags the area target; the opening is g's \
             brightest cells, as many as the target asks",
        );
        ui.checkbox(show_relaxed, "grey mask")
            .on_hover_text("Show the sigmoid mask g instead of the thresholded opening");
    });
    let cells: Vec<f64> = match result {
        Some(r) if *show_relaxed => r.relaxed.clone(),
        _ if *show_relaxed => last.mask.clone(),
        Some(r) => r.design.opening.cells.iter().flatten().copied().collect(),
        None => binarise(&last.mask, n, last.area_target)
            .into_iter()
            .flatten()
            .collect(),
    };
    let side = 168.0f32;
    let (rect, _) = ui.allocate_exact_size(egui::vec2(side, side), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::BLACK);
    let cell = side / n.max(1) as f32;
    for (i, v) in cells.iter().enumerate() {
        let (r, c) = (i / n.max(1), i % n.max(1));
        let g = (v.clamp(0.0, 1.0) * 255.0) as u8;
        if g == 0 {
            continue;
        }
        let min = rect.min + egui::vec2(c as f32 * cell, r as f32 * cell);
        painter.rect_filled(
            egui::Rect::from_min_size(min, egui::vec2(cell, cell)),
            0.0,
            Color32::from_gray(g),
        );
    }
}

/// The start and the result, at full quality (what the numbers show for each design) and,
/// for a preview run, at the run's sampling (the plot's scale). One wrapped line per
/// quantity, so the summary fits the narrowest panel.
fn summary_ui(ui: &mut Ui, run: &Optimized) {
    let full = &run.at_full_quality;
    let sampled = &run.at_run_quality;
    let good = Color32::from_rgb(70, 175, 90);
    let bad = ui.visuals().error_fg_color;
    let line = |ui: &mut Ui, what: &str, start: Option<f64>, result: f64, tip: &str| {
        ui.horizontal_wrapped(|ui| {
            ui.label(format!("{what}:")).on_hover_text(tip);
            ui.monospace(start.map_or_else(|| "–".to_owned(), |v| format!("{v:.4}")));
            ui.monospace("→");
            ui.monospace(format!("{result:.4}"));
            let Some(start) = start else {
                return;
            };
            // Lower losses are better; a change below the printed precision is neither.
            let d = result - start;
            if d < -5e-5 {
                ui.colored_label(good, format!("(better by {:.4})", -d));
            } else if d > 5e-5 {
                ui.colored_label(bad, format!("(worse by {d:.4})"));
            } else {
                ui.label("(unchanged)");
            }
        });
    };
    ui.strong("Start and optimized, both scored alike");
    let rows = |ui: &mut Ui, s: &Scores, what: &str, tip: &str| {
        line(
            ui,
            &format!("L_inv, {what}"),
            s.start.map(|v| v.loss_inv),
            s.result.loss_inv,
            tip,
        );
        if let Some(data) = s.result.loss_data {
            let start = s.start.and_then(|v| v.loss_data);
            line(ui, &format!("L_data, {what}"), start, data, tip);
        }
    };
    rows(
        ui,
        full,
        "full quality",
        "What the Numbers panel shows for each design (L_inv: thesis eq. 3.9); lower is better",
    );
    if sampled.quality != full.quality {
        rows(
            ui,
            sampled,
            "preview",
            "At the run's preview sampling, the scale of the plot: an estimate",
        );
    }
    ui.horizontal_wrapped(|ui| {
        ui.label("open fraction:");
        ui.monospace(
            full.start
                .map_or_else(|| "–".to_owned(), |s| percent(s.open_fraction)),
        );
        ui.monospace("→");
        ui.monospace(percent(full.result.open_fraction));
    });
}

fn percent(fraction: f64) -> String {
    format!("{:.1} %", 100.0 * fraction)
}
