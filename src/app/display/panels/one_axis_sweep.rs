//! "Sweep this parameter…": a window that analyses a copy of the design at a range of one
//! field's values and plots a metric as each value finishes. It works on the copy taken when
//! it opened, so editing the design meanwhile does not disturb it; invalid values leave gaps.
//! The run is the one sweep runner's case of one axis ([`crate::core::sweep::one_axis::spec`],
//! [`crate::jobs::sweep::run_sweep`]): the copy is written to a scratch folder as a design
//! file and each row the runner writes comes back as a point.

use std::sync::mpsc::{Receiver, channel};

use crate::app::display::action::DisplayAction;
use crate::app::job::{Job, JobError};
use crate::app::notice::Notice;
use crate::core::Design;
use crate::core::sweep::Shard;
use crate::core::sweep::one_axis::{
    OneAxisPoint, SweepMetric, SweepParameter, panel, point_of, spec, values,
};
use crate::jobs::sweep::{RunOptions, run_sweep};

/// A run in flight: the job and the points it sends as they finish.
struct Run {
    job: Job<()>,
    points: Receiver<(usize, OneAxisPoint)>,
}

/// The 1-D sweep window.
pub struct OneAxisSweepWindow {
    open: bool,
    field: SweepParameter,
    /// The design as it was when the window opened.
    design: Design,
    current: f64,
    /// First value, in the field's unit.
    pub from: f64,
    /// Last value, in the field's unit.
    pub to: f64,
    /// How many values, both ends included.
    pub steps: usize,
    /// The number plotted.
    pub metric: SweepMetric,
    /// Full quality instead of the fast preview.
    pub full: bool,
    run: Option<Run>,
    /// The values of the last run and what each gave (`None`: not yet).
    points: Vec<(f64, Option<OneAxisPoint>)>,
    /// The metric and field the points are of (the controls may have changed since).
    points_of: (SweepParameter, SweepMetric),
    message: Option<Notice>,
}

impl Default for OneAxisSweepWindow {
    fn default() -> Self {
        OneAxisSweepWindow {
            open: false,
            field: SweepParameter::PitchUm,
            design: Design::default_toled(),
            current: 0.0,
            from: 0.0,
            to: 0.0,
            steps: 9,
            metric: SweepMetric::AucMean,
            full: false,
            run: None,
            points: Vec::new(),
            points_of: (SweepParameter::PitchUm, SweepMetric::AucMean),
            message: None,
        }
    }
}

impl OneAxisSweepWindow {
    /// Opens the window for `field` of a copy of `design`, with the default range around its
    /// value. A run of the previous field is cancelled.
    pub fn open(&mut self, field: SweepParameter, design: Design) {
        let current = field.get(&design);
        let (from, to, steps) = field.default_range(current);
        *self = OneAxisSweepWindow {
            open: true,
            field,
            design,
            current,
            from,
            to,
            steps,
            metric: self.metric,
            full: self.full,
            run: None,
            points: Vec::new(),
            points_of: (field, self.metric),
            message: None,
        };
        let metrics = SweepMetric::all_for(&self.design);
        if !metrics.contains(&self.metric) {
            self.metric = SweepMetric::AucMean;
        }
    }

    /// Whether it is shown.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// The field it sweeps.
    pub fn field(&self) -> SweepParameter {
        self.field
    }

    /// The field's value in the design it works on.
    pub fn current(&self) -> f64 {
        self.current
    }

    /// Whether a run is in flight.
    pub fn is_running(&self) -> bool {
        self.run.is_some()
    }

    /// The values the controls ask for.
    pub fn values(&self) -> Vec<f64> {
        values(self.from, self.to, self.steps, self.field.is_integer())
    }

    /// The last run's values and what each gave (`None`: not computed yet).
    pub fn points(&self) -> &[(f64, Option<OneAxisPoint>)] {
        &self.points
    }

    /// The window's message line.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Starts a run of the values on a job; each finished value wakes the UI to grow the plot.
    pub fn run(&mut self, ctx: &egui::Context) {
        let vals = self.values();
        self.points = vals.iter().map(|v| (*v, None)).collect();
        self.points_of = (self.field, self.metric);
        self.message = None;
        let (tx, rx) = channel();
        let (design, field, metric, full) =
            (self.design.clone(), self.field, self.metric, self.full);
        let wake = ctx.clone();
        let done = ctx.clone();
        let job = Job::spawn(
            "parameter sweep",
            move || done.request_repaint(),
            move |progress| -> Result<(), JobError> {
                let failed = |e: &dyn std::fmt::Display| JobError::Failed(format!("{e:#}"));
                let scratch = tempfile::tempdir().map_err(|e| failed(&e))?;
                let file = scratch.path().join("design.json");
                crate::io::design::file::save_design(&file, &design).map_err(|e| failed(&e))?;
                let spec = spec(&design, &file.to_string_lossy(), field, &vals, metric, full);
                let options = RunOptions {
                    shard: Shard::WHOLE,
                    threads: None,
                    plots: false,
                    check_values: false,
                    hold_after_points: None,
                };
                let out = scratch.path().join("sweep");
                let ran = run_sweep(&spec, &out, &options, progress, &mut |row| {
                    let metric = row.metrics.first().copied().unwrap_or(f64::NAN);
                    // The window may be gone; the run then ends at its next check.
                    let _ = tx.send((row.point as usize, point_of(&row.error, metric)));
                    wake.request_repaint();
                });
                match ran {
                    Ok(_) => Ok(()),
                    Err(_) if progress.is_cancelled() => Err(JobError::Cancelled),
                    Err(e) => Err(failed(&e)),
                }
            },
        );
        self.run = Some(Run { job, points: rx });
    }

    /// Stops the run; the points so far stay.
    pub fn cancel(&mut self) {
        if let Some(r) = &self.run {
            r.job.cancel();
        }
    }

    /// Closes the window (a run is cancelled with it).
    pub fn close(&mut self) {
        self.open = false;
        self.run = None;
    }

    /// Takes the points that finished, and the run's end.
    pub fn poll(&mut self) {
        let Some(run) = &self.run else {
            return;
        };
        while let Ok((i, p)) = run.points.try_recv() {
            if let Some(slot) = self.points.get_mut(i) {
                slot.1 = Some(p);
            }
        }
        if let Some(done) = run.job.poll() {
            // Points sent just before the end are already in the channel.
            while let Ok((i, p)) = run.points.try_recv() {
                if let Some(slot) = self.points.get_mut(i) {
                    slot.1 = Some(p);
                }
            }
            self.run = None;
            self.message = match done {
                Ok(()) => {
                    let bad = self
                        .points
                        .iter()
                        .filter(|(_, p)| matches!(p, Some(OneAxisPoint::Invalid(_))))
                        .count();
                    Some(Notice::info(format!(
                        "{} values done{}",
                        self.points.len(),
                        if bad > 0 {
                            format!(", {bad} invalid (gaps in the curve)")
                        } else {
                            String::new()
                        }
                    )))
                }
                Err(JobError::Cancelled) => Some(Notice::info("cancelled; the points so far stay")),
                Err(e) => Some(Notice::error(e.to_string())),
            };
        }
    }

    /// Draws the window when open; Escape closes it.
    pub fn ui(&mut self, ctx: &egui::Context) {
        if !self.open {
            return;
        }
        if ctx.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::Escape)) {
            self.close();
            return;
        }
        let mut open = self.open;
        egui::Window::new(format!("Sweep {}", self.field.label()))
            .id(egui::Id::unique("field_sweep_window"))
            .open(&mut open)
            .collapsible(false)
            .default_width(520.0)
            .show(ctx, |ui| {
                self.controls_ui(ui, ctx);
                ui.separator();
                self.plot_ui(ui);
            });
        if !open {
            self.close();
        }
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        let unit = self.field.unit();
        let int = self.field.is_integer();
        ui.label(format!(
            "On a copy of the design as it was when this opened: {} = {}{}{unit}",
            self.field.label(),
            crate::app::sweep::table::format_number(self.current),
            if unit.is_empty() { "" } else { " " },
        ));
        let idle = self.run.is_none();
        ui.add_enabled_ui(idle, |ui| {
            egui::Grid::new("field_sweep_grid")
                .num_columns(2)
                .show(ui, |ui| {
                    let suffix = if unit.is_empty() {
                        String::new()
                    } else {
                        format!(" {unit}")
                    };
                    for (label, v) in [("from", &mut self.from), ("to", &mut self.to)] {
                        ui.label(label);
                        let speed = if int { 1.0 } else { (v.abs() * 0.01).max(0.01) };
                        let mut field = crate::app::widgets::number(v)
                            .speed(speed)
                            .suffix(suffix.clone());
                        if int {
                            field = field.max_decimals(0);
                        }
                        ui.add(field);
                        ui.end_row();
                    }
                    ui.label("steps");
                    ui.add(crate::app::widgets::number(&mut self.steps).range(1..=200));
                    ui.end_row();
                    ui.label("metric");
                    let d = &self.design;
                    egui::ComboBox::from_id_salt("field_sweep_metric")
                        .selected_text(self.metric.label(d))
                        .show_ui(ui, |ui| {
                            for m in SweepMetric::all_for(d) {
                                ui.selectable_value(&mut self.metric, m, m.label(d));
                            }
                        });
                    ui.end_row();
                });
            ui.checkbox(&mut self.full, "Full quality (slower; preview otherwise)")
                .on_hover_text(
                    "The preview doubles the fine spacing only where the f-number oversamples \
                     the PSF enough to stay within 3 % of full quality's AUC; elsewhere (every \
                     preset at f/2.5) it is full quality",
                );
        });
        ui.horizontal(|ui| {
            if ui
                .add_enabled(idle && self.steps > 0, egui::Button::new("Run"))
                .clicked()
            {
                self.run(ctx);
            }
            if ui.add_enabled(!idle, egui::Button::new("Cancel")).clicked() {
                self.cancel();
            }
            if let Some(run) = &self.run {
                ui.spinner();
                let done = self.points.iter().filter(|(_, p)| p.is_some()).count();
                ui.label(format!(
                    "{done} / {} values · {:.0} s",
                    self.points.len(),
                    run.job.elapsed().as_secs_f64()
                ));
            }
        });
        crate::app::widgets::message_ui(ui, self.message.as_ref());
    }

    fn plot_ui(&mut self, ui: &mut egui::Ui) {
        let (field, metric) = self.points_of;
        let invalid: Vec<(f64, &str)> = self
            .points
            .iter()
            .filter_map(|(x, p)| match p {
                Some(OneAxisPoint::Invalid(why)) => Some((*x, why.as_str())),
                _ => None,
            })
            .collect();
        if let Some((x, why)) = invalid.first() {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                format!(
                    "{} invalid value(s), shown as gaps; at {}: {why}",
                    invalid.len(),
                    crate::app::sweep::table::format_number(*x)
                ),
            );
        }
        let figure = panel(
            field,
            &metric.label(&self.design),
            &self.points,
            self.current,
        );
        // Fixed height: a window's available height is the screen's.
        crate::app::widgets::figure::panel_ui(ui, "one_axis_sweep_plot", &figure, 260.0);
    }
}

/// The number field's right-click menu: "Sweep this parameter…" opens the window for `field`.
pub fn sweep_menu(
    response: &egui::Response,
    field: SweepParameter,
    actions: &mut Vec<DisplayAction>,
) {
    response.context_menu(|ui| {
        if ui
            .button("Sweep this parameter…")
            .on_hover_text(format!(
                "Analyse the design at a range of {} values and plot a metric",
                field.label()
            ))
            .clicked()
        {
            actions.push(DisplayAction::SweepParameter(field));
            ui.close();
        }
        if ui
            .button("Study this parameter…")
            .on_hover_text(format!(
                "New study of the {} values in the Sweep workspace: a results folder that \
                 resumes, more axes and metrics",
                field.label()
            ))
            .clicked()
        {
            actions.push(DisplayAction::NewStudy(Some(field)));
            ui.close();
        }
    });
}
