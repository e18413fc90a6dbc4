//! New study…: a window that builds a study of the design it was opened with (the Display
//! workspace's current design): axes picked from the design's own parameters, each a list or
//! a range, the metrics to record and the quality. Before anything runs it shows the number
//! of points, the time the engine's cost model expects and the memory a point needs, and it
//! refuses bad values with the reason, as `udc-studio sweep` would.

use egui::{RichText, Ui};

use crate::app::notice::Notice;
use crate::core::Design;
use crate::core::analysis::analyze::Quality;
use crate::core::budget::format_bytes;
use crate::core::design::TilingMode;
use crate::core::sweep::one_axis::{SweepMetric, SweepParameter};
use crate::core::sweep::study::{Study, StudyAxis, StudyEstimate, parse_values};

/// Which kind of axis a row edits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// Display pixel densities.
    Dpi,
    /// Tilings.
    Tiling,
    /// Seeds of the random tiling.
    Seeds,
    /// One of the design's numbers.
    Number(SweepParameter),
}

impl AxisKind {
    /// Every kind offered, in menu order.
    pub fn all() -> Vec<AxisKind> {
        let mut v = vec![AxisKind::Dpi, AxisKind::Tiling, AxisKind::Seeds];
        v.extend(
            SweepParameter::ALL
                .into_iter()
                .filter(|p| !matches!(p, SweepParameter::PitchUm | SweepParameter::Seed))
                .map(AxisKind::Number),
        );
        v
    }

    /// Its name in the menu, with the unit.
    pub fn label(self) -> String {
        match self {
            AxisKind::Dpi => "display density (DPI)".into(),
            AxisKind::Tiling => "tiling".into(),
            AxisKind::Seeds => "seeds of the random tiling".into(),
            AxisKind::Number(p) => p.label_with_unit(),
        }
    }
}

/// One axis as the window edits it.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisRow {
    /// Which axis.
    pub kind: AxisKind,
    /// The values as typed (DPI and numbers): a list or `from:to:count`.
    pub text: String,
    /// The tilings ticked (tiling).
    pub tilings: [bool; 3],
    /// How many seeds (seeds).
    pub seeds: u64,
}

impl AxisRow {
    /// A new row of `kind` with values around the design's own.
    pub fn new(kind: AxisKind, design: &Design) -> AxisRow {
        let text = match kind {
            AxisKind::Dpi => {
                let d = design.opening.dpi().round();
                format!("{}, {}, {}", (d / 2.0).round(), d, 2.0 * d)
            }
            AxisKind::Number(p) => {
                let (from, to, n) = p.default_range(p.get(design));
                format!("{from}:{to}:{n}")
            }
            AxisKind::Tiling | AxisKind::Seeds => String::new(),
        };
        AxisRow {
            kind,
            text,
            tilings: [true, true, false],
            seeds: 3,
        }
    }

    /// The axis, or why its values are refused.
    fn axis(&self) -> Result<StudyAxis, String> {
        let label = self.kind.label();
        let values = || parse_values(&self.text).map_err(|e| format!("{label}: {e}"));
        Ok(match self.kind {
            AxisKind::Dpi => StudyAxis::Dpi(values()?),
            AxisKind::Number(p) => StudyAxis::Number(p, values()?),
            AxisKind::Tiling => StudyAxis::Tiling(
                TilingMode::ALL
                    .into_iter()
                    .zip(self.tilings)
                    .filter_map(|(m, on)| on.then_some(m))
                    .collect(),
            ),
            AxisKind::Seeds => StudyAxis::Seeds(self.seeds),
        })
    }
}

/// The New study window's state.
pub struct StudyDialog {
    open: bool,
    design: Design,
    /// How long the design's analysis took on screen, and at which quality.
    reference: Option<(f64, Quality)>,
    /// The axes, the last varying fastest.
    pub axes: Vec<AxisRow>,
    /// The metrics offered, each ticked or not.
    pub metrics: Vec<(SweepMetric, bool)>,
    /// Full quality instead of the preview.
    pub full: bool,
    message: Option<Notice>,
}

impl Default for StudyDialog {
    fn default() -> Self {
        StudyDialog {
            open: false,
            design: Design::default_toled(),
            reference: None,
            axes: Vec::new(),
            metrics: Vec::new(),
            full: false,
            message: None,
        }
    }
}

/// What the window asks for when its Run (or Run on a cluster…) button is pressed.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRequest {
    /// The design the study varies.
    pub design: Design,
    /// The study.
    pub study: Study,
    /// Write the Slurm scripts for it instead of running it here.
    pub cluster: bool,
}

impl StudyDialog {
    /// Opens the window for `design`; `reference` is its analysis time on screen and the
    /// quality it ran at. It starts with DPI × tiling × seeds, the thesis's question.
    pub fn open(&mut self, design: Design, reference: Option<(f64, Quality)>) {
        self.axes = [AxisKind::Dpi, AxisKind::Tiling, AxisKind::Seeds]
            .into_iter()
            .map(|k| AxisRow::new(k, &design))
            .collect();
        self.metrics = SweepMetric::all_for(&design)
            .into_iter()
            .map(|m| (m, matches!(m, SweepMetric::AucMean | SweepMetric::Ltr)))
            .collect();
        self.design = design;
        self.reference = reference;
        self.message = None;
        self.open = true;
    }

    /// Keeps one axis: `field` (the pitch as DPI), as "Study this parameter…" asks.
    pub fn only(&mut self, field: SweepParameter) {
        let kind = match field {
            SweepParameter::PitchUm => AxisKind::Dpi,
            SweepParameter::Seed => AxisKind::Seeds,
            f => AxisKind::Number(f),
        };
        self.axes = vec![AxisRow::new(kind, &self.design)];
    }

    /// Whether the window is open.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// Closes it.
    pub fn close(&mut self) {
        self.open = false;
    }

    /// The design it studies.
    pub fn design(&self) -> &Design {
        &self.design
    }

    /// The study as the controls stand, checked against the design, or the reason it is
    /// refused.
    pub fn study(&self) -> Result<Study, String> {
        let axes = self
            .axes
            .iter()
            .map(AxisRow::axis)
            .collect::<Result<Vec<_>, _>>()?;
        let study = Study {
            axes,
            metrics: self
                .metrics
                .iter()
                .filter_map(|(m, on)| on.then_some(*m))
                .collect(),
            full: self.full,
        };
        study.check(&self.design).map_err(|e| e.to_string())?;
        Ok(study)
    }

    /// The study's expected cost, when its values are good and the design has a time on
    /// screen to scale.
    pub fn estimate(&self) -> Result<Option<StudyEstimate>, String> {
        let study = self.study()?;
        match self.reference {
            Some((ms, q)) => study
                .estimate(&self.design, ms, q)
                .map(Some)
                .map_err(|e| e.to_string()),
            None => Ok(None),
        }
    }

    /// Draws the window; returns the run asked for when Run is pressed.
    pub fn ui(&mut self, ctx: &egui::Context) -> Option<RunRequest> {
        if !self.open {
            return None;
        }
        let mut open = true;
        let mut run = None;
        egui::Window::new("New study")
            .open(&mut open)
            .default_width(440.0)
            .show(ctx, |ui| run = self.body_ui(ui));
        if !open {
            self.open = false;
        }
        run
    }

    fn body_ui(&mut self, ui: &mut Ui) -> Option<RunRequest> {
        let name = if self.design.name.is_empty() {
            "the current design"
        } else {
            self.design.name.as_str()
        };
        ui.label(format!(
            "Varies {name} over every combination of the axes below (the last varies fastest)."
        ));
        ui.separator();
        let mut remove = None;
        egui::Grid::new("study_axes")
            .num_columns(3)
            .striped(true)
            .show(ui, |ui| {
                for (i, row) in self.axes.iter_mut().enumerate() {
                    ui.label(row.kind.label());
                    match row.kind {
                        AxisKind::Dpi | AxisKind::Number(_) => {
                            ui.add(
                                egui::TextEdit::singleline(&mut row.text)
                                    .desired_width(180.0)
                                    .hint_text("80, 150, 300  or  80:600:5"),
                            )
                            .on_hover_text(
                                "A list of values, or from:to:count (both ends included)",
                            );
                        }
                        AxisKind::Tiling => {
                            ui.horizontal(|ui| {
                                for (m, on) in TilingMode::ALL.iter().zip(&mut row.tilings) {
                                    ui.checkbox(on, m.as_str());
                                }
                            });
                        }
                        AxisKind::Seeds => {
                            ui.horizontal(|ui| {
                                ui.add(
                                    egui::DragValue::new(&mut row.seeds)
                                        .range(1..=10_000)
                                        .speed(0.2),
                                );
                                ui.label(format!("from seed {}", self.design.tiling.seed));
                            });
                        }
                    }
                    if ui
                        .small_button("Remove")
                        .on_hover_text("Remove this axis")
                        .clicked()
                    {
                        remove = Some(i);
                    }
                    ui.end_row();
                }
            });
        if let Some(i) = remove {
            self.axes.remove(i);
        }
        let taken: Vec<AxisKind> = self.axes.iter().map(|a| a.kind).collect();
        ui.menu_button("Add axis", |ui| {
            for k in AxisKind::all() {
                if ui
                    .add_enabled(!taken.contains(&k), egui::Button::new(k.label()))
                    .clicked()
                {
                    self.axes.push(AxisRow::new(k, &self.design));
                    ui.close();
                }
            }
        });
        ui.separator();
        ui.label("Record");
        ui.horizontal_wrapped(|ui| {
            for (m, on) in &mut self.metrics {
                ui.checkbox(on, m.label(&self.design));
            }
        });
        ui.checkbox(
            &mut self.full,
            "Full quality (the thesis's sampling; slower)",
        )
        .on_hover_text("Off: the interactive preview sampling, AUC within 3 %");
        ui.separator();
        let ready = match self.estimate() {
            Ok(e) => {
                let points = self.study().map(|s| s.points()).unwrap_or(0);
                let line = match e {
                    Some(e) => format!(
                        "{points} points, about {} on this machine, about {} of memory per \
                         point",
                        duration_text(e.seconds),
                        format_bytes(e.bytes_per_point)
                    ),
                    None => format!(
                        "{points} points (the time is estimated once the design's own result \
                         is on screen)"
                    ),
                };
                ui.label(RichText::new(line).strong());
                true
            }
            Err(why) => {
                ui.colored_label(ui.visuals().error_fg_color, why);
                false
            }
        };
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        let mut run = None;
        ui.horizontal(|ui| {
            if ui
                .add_enabled(ready, egui::Button::new("Run"))
                .on_hover_text(
                    "Runs in a results folder that resumes: the table and plots fill as the \
                     points finish",
                )
                .clicked()
                && let Ok(study) = self.study()
            {
                run = Some(RunRequest {
                    design: self.design.clone(),
                    study,
                    cluster: false,
                });
                self.open = false;
            }
            if ui
                .add_enabled(ready, egui::Button::new("Run on a cluster…"))
                .on_hover_text(
                    "Writes the study's folder with a Slurm job array and a merge job for the \
                     same spec (udc-studio sweep slurm); submit it on the cluster",
                )
                .clicked()
                && let Ok(study) = self.study()
            {
                run = Some(RunRequest {
                    design: self.design.clone(),
                    study,
                    cluster: true,
                });
                self.open = false;
            }
            if ui.button("Close").clicked() {
                self.open = false;
            }
        });
        run
    }
}

/// Seconds for people: "40 s", "3.2 min", "1.5 h".
pub fn duration_text(s: f64) -> String {
    if s < 90.0 {
        format!("{:.0} s", s.max(1.0))
    } else if s < 5400.0 {
        format!("{:.1} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dialog_starts_with_dpi_tiling_and_seeds_and_refuses_bad_values() {
        let mut d = StudyDialog::default();
        d.open(Design::default_toled(), Some((100.0, Quality::Preview)));
        let s = d.study().expect("the starting study is valid");
        assert_eq!(s.points(), 3 * 2 * 3);
        assert!(d.estimate().expect("costed").is_some());
        d.axes[0].text = "150, zero".into();
        let why = d.study().unwrap_err();
        assert!(why.contains("DPI") && why.contains("zero"), "{why}");
        d.axes[0].text = "150, -1".into();
        assert!(d.study().unwrap_err().contains("dpi"));
        for m in &mut d.metrics {
            m.1 = false;
        }
        d.axes[0].text = "150".into();
        assert!(d.study().unwrap_err().contains("metric"));
    }

    #[test]
    fn durations_read_in_their_unit() {
        assert_eq!(duration_text(12.0), "12 s");
        assert_eq!(duration_text(600.0), "10.0 min");
        assert_eq!(duration_text(7200.0), "2.0 h");
    }
}
