//! New study…: a window that builds a study of the design it was opened with (the Display
//! workspace's current design, or the Phase workspace's): axes picked from the design's own
//! parameters, each a list or a range, the metrics to record and the quality. Before anything
//! runs it shows the number of points, the time the engine's cost model expects and the memory
//! a point needs, and it refuses bad values with the reason, as `udc-studio sweep` would. The
//! check and the estimate are redone only when a control changes.

use std::sync::Arc;

use egui::{RichText, Ui};

use crate::app::notice::Notice;
pub use crate::app::study_start::StudyStart;
use crate::app::widgets::photo::Photo;
use crate::core::Design;
use crate::core::budget::format_bytes;
use crate::core::design::TilingMode;
use crate::core::restore::RestoreMethod;
use crate::core::sweep::one_axis::SweepParameter;
use crate::core::sweep::study::{
    RestoreSetup, Study, StudyAxis, StudyEstimate, StudyMetric, StudySubject, parse_plans,
    parse_steps, parse_values,
};

/// Most cells an opening axis grows or shrinks the opening by (the editor's grids are at most a
/// few hundred cells).
const MAX_GROW_CELLS: i32 = 64;

/// Which kind of axis a row edits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// Display pixel densities.
    Dpi,
    /// Tilings.
    Tiling,
    /// Seeds of the random tiling.
    Seeds,
    /// One of the design's numbers (a phase-mask design's pitch).
    Number(SweepParameter),
    /// Light levels of the restored capture (SNR, dB).
    SnrDb,
    /// Restoration methods.
    Method,
    /// The drawn opening grown or shrunk by whole cells.
    Opening,
    /// Open ratios of a phase-mask design's display pixel.
    OpenRatio,
    /// Fold thicknesses of a phase-mask plate.
    Fold,
    /// λ0 plans of a phase-mask plate.
    Lambda0,
}

impl AxisKind {
    /// Every kind offered for `subject`, in menu order.
    pub fn all(subject: &StudySubject) -> Vec<AxisKind> {
        match subject {
            StudySubject::Phase(_) => vec![
                AxisKind::Number(SweepParameter::PitchUm),
                AxisKind::Fold,
                AxisKind::Lambda0,
                AxisKind::OpenRatio,
            ],
            StudySubject::Display(_) => {
                let mut v = vec![
                    AxisKind::Dpi,
                    AxisKind::Tiling,
                    AxisKind::Seeds,
                    AxisKind::Opening,
                ];
                // The pitch is the DPI axis (which also keeps the pupil samples on the cells);
                // the seed is the seeds axis.
                v.extend(
                    SweepParameter::ALL
                        .into_iter()
                        .filter(|p| !matches!(p, SweepParameter::PitchUm | SweepParameter::Seed))
                        .map(AxisKind::Number),
                );
                v.extend([AxisKind::SnrDb, AxisKind::Method]);
                v
            }
        }
    }

    /// Its name in the menu, with the unit.
    pub fn label(self) -> String {
        match self {
            AxisKind::Dpi => "display density (DPI)".into(),
            AxisKind::Tiling => "tiling".into(),
            AxisKind::Seeds => "seeds of the random tiling".into(),
            AxisKind::Number(p) => p.label_with_unit(),
            AxisKind::SnrDb => "light level, SNR (dB): restores the photo".into(),
            AxisKind::Method => "restoration method: restores the photo".into(),
            AxisKind::Opening => "opening grown (+) or shrunk (−), cells".into(),
            AxisKind::OpenRatio => "open ratio of the display pixel".into(),
            AxisKind::Fold => "fold thickness T".into(),
            AxisKind::Lambda0 => "λ0 plan".into(),
        }
    }
}

/// One axis as the window edits it.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisRow {
    /// Which axis.
    pub kind: AxisKind,
    /// The values as typed (numbers: a list or `from:to:count`; λ0 plans: a list).
    pub text: String,
    /// The tilings ticked (tiling).
    pub tilings: [bool; 3],
    /// The methods ticked (method).
    pub methods: [bool; 2],
    /// How many seeds (seeds).
    pub seeds: u64,
}

/// A value as a list entry: at most 2 decimals, trailing zeros dropped (`151.19`, `75.6`).
fn short(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

impl AxisRow {
    /// A new row of `kind` with values around the design's own.
    pub fn new(kind: AxisKind, subject: &StudySubject, restore: &RestoreSetup) -> AxisRow {
        let text = match (kind, subject) {
            (AxisKind::Dpi, StudySubject::Display(d)) => {
                let dpi = d.opening.dpi();
                format!("{}, {}, {}", short(dpi / 2.0), short(dpi), short(2.0 * dpi))
            }
            (AxisKind::Number(SweepParameter::PitchUm), StudySubject::Phase(d)) => {
                format!(
                    "{}, {}, {}",
                    short(d.pitch_um),
                    short(2.0 * d.pitch_um),
                    short(4.0 * d.pitch_um)
                )
            }
            (AxisKind::Number(p), StudySubject::Display(d)) => {
                let (from, to, n) = p.default_range(p.get(d));
                format!("{from}:{to}:{n}")
            }
            (AxisKind::SnrDb, _) => {
                let s = restore.snr_db;
                format!("{}, {}, {}", short(s - 8.0), short(s), short(s + 8.0))
            }
            (AxisKind::Fold, StudySubject::Phase(d)) => {
                let mut v = vec![1.0, 2.0, 5.0, 10.0];
                if !v.contains(&d.fold) {
                    v.insert(0, d.fold);
                }
                v.iter().map(|x| short(*x)).collect::<Vec<_>>().join(", ")
            }
            (AxisKind::Lambda0, _) => "fixed:530, uniform, optimized".into(),
            (AxisKind::Opening, _) => "-1, 0, 1".into(),
            (AxisKind::OpenRatio, StudySubject::Phase(d)) => format!(
                "{}, {}, {}",
                short(0.5 * d.open_ratio),
                short(d.open_ratio),
                short((1.5 * d.open_ratio).min(1.0))
            ),
            _ => String::new(),
        };
        AxisRow {
            kind,
            text,
            tilings: [true, true, false],
            methods: [true, true],
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
            AxisKind::SnrDb => StudyAxis::SnrDb(values()?),
            AxisKind::Fold => StudyAxis::Fold(values()?),
            AxisKind::OpenRatio => StudyAxis::OpenRatio(values()?),
            AxisKind::Opening => StudyAxis::Opening(
                parse_steps(&self.text, MAX_GROW_CELLS).map_err(|e| format!("{label}: {e}"))?,
            ),
            AxisKind::Lambda0 => {
                StudyAxis::Lambda0(parse_plans(&self.text).map_err(|e| format!("{label}: {e}"))?)
            }
            AxisKind::Tiling => StudyAxis::Tiling(
                TilingMode::ALL
                    .into_iter()
                    .zip(self.tilings)
                    .filter_map(|(m, on)| on.then_some(m))
                    .collect(),
            ),
            AxisKind::Method => StudyAxis::Method(
                RestoreMethod::ALL
                    .into_iter()
                    .zip(self.methods)
                    .filter_map(|(m, on)| on.then_some(m))
                    .collect(),
            ),
            AxisKind::Seeds => StudyAxis::Seeds(self.seeds),
        })
    }
}

/// The controls a study is made from, compared to know when to check and cost it again.
#[derive(Debug, Clone, PartialEq)]
struct Controls {
    axes: Vec<AxisRow>,
    metrics: Vec<(StudyMetric, bool)>,
    full: bool,
}

/// The study the controls make and its estimate, or why they are refused.
type Checked = (Result<Study, String>, Result<Option<StudyEstimate>, String>);

/// The New study window's state.
pub struct StudyDialog {
    open: bool,
    start: StudyStart,
    /// The axes, the last varying fastest.
    pub axes: Vec<AxisRow>,
    /// The metrics offered, each ticked or not.
    pub metrics: Vec<(StudyMetric, bool)>,
    /// Full quality instead of the preview.
    pub full: bool,
    message: Option<Notice>,
    /// The controls last checked and what they gave.
    checked: Option<(Controls, Checked)>,
}

impl Default for StudyDialog {
    fn default() -> Self {
        StudyDialog {
            open: false,
            start: StudyStart::display(Design::default_toled()),
            axes: Vec::new(),
            metrics: Vec::new(),
            full: false,
            message: None,
            checked: None,
        }
    }
}

/// What the window asks for when its Run (or Run on a cluster…) button is pressed.
#[derive(Debug, Clone)]
pub struct RunRequest {
    /// The study.
    pub study: Study,
    /// The photo a restoring study captures (`None`: the built-in one).
    pub photo: Option<Arc<Photo>>,
    /// Write the Slurm scripts for it instead of running it here.
    pub cluster: bool,
}

impl StudyDialog {
    /// Opens the window for `start`. A display design starts with DPI × tiling × seeds, the
    /// thesis's question; a phase-mask design with its fold × λ0 plan (§4.5's).
    pub fn open(&mut self, start: StudyStart) {
        let kinds: &[AxisKind] = match &start.subject {
            StudySubject::Display(_) => &[AxisKind::Dpi, AxisKind::Tiling, AxisKind::Seeds],
            StudySubject::Phase(_) => &[AxisKind::Fold, AxisKind::Lambda0],
        };
        self.axes = kinds
            .iter()
            .map(|k| AxisRow::new(*k, &start.subject, &start.restore))
            .collect();
        self.metrics = match &start.subject {
            StudySubject::Display(d) => StudyMetric::display(d)
                .into_iter()
                .map(|m| {
                    let on = matches!(
                        m,
                        StudyMetric::Analysis(
                            crate::core::sweep::one_axis::SweepMetric::AucMean
                                | crate::core::sweep::one_axis::SweepMetric::Ltr
                        )
                    );
                    (m, on)
                })
                .collect(),
            StudySubject::Phase(_) => StudyMetric::PHASE
                .into_iter()
                .map(|m| (m, m != StudyMetric::PhasePeak))
                .collect(),
        };
        self.start = start;
        self.message = None;
        self.checked = None;
        self.open = true;
    }

    /// Keeps one axis: `field` (the pitch as DPI), as "Study this parameter…" asks.
    pub fn only(&mut self, field: SweepParameter) {
        let kind = match field {
            SweepParameter::PitchUm => AxisKind::Dpi,
            SweepParameter::Seed => AxisKind::Seeds,
            f => AxisKind::Number(f),
        };
        self.axes = vec![AxisRow::new(kind, &self.start.subject, &self.start.restore)];
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
    pub fn subject(&self) -> &StudySubject {
        &self.start.subject
    }

    fn controls(&self) -> Controls {
        Controls {
            axes: self.axes.clone(),
            metrics: self.metrics.clone(),
            full: self.full,
        }
    }

    /// The study and its estimate as the controls stand, checked and costed again only when
    /// a control changed.
    fn checked(&mut self) -> &Checked {
        let controls = self.controls();
        if self.checked.as_ref().is_none_or(|(c, _)| *c != controls) {
            let study = self.build();
            let estimate = match &study {
                Ok(s) => s.estimate(&self.start.times).map_err(|e| e.to_string()),
                Err(e) => Err(e.clone()),
            };
            self.checked = Some((controls, (study, estimate)));
        }
        match &self.checked {
            Some((_, c)) => c,
            None => unreachable!("set just above"),
        }
    }

    fn build(&self) -> Result<Study, String> {
        let axes = self
            .axes
            .iter()
            .map(AxisRow::axis)
            .collect::<Result<Vec<_>, _>>()?;
        let study = Study {
            subject: self.start.subject.clone(),
            axes,
            metrics: self
                .metrics
                .iter()
                .filter_map(|(m, on)| on.then_some(*m))
                .collect(),
            full: self.full,
            restore: self.start.restore,
        };
        study.check().map_err(|e| e.to_string())?;
        Ok(study)
    }

    /// The study as the controls stand, checked, or the reason it is refused.
    pub fn study(&mut self) -> Result<Study, String> {
        self.checked().0.clone()
    }

    /// The study's expected cost, when its values are good and the times it scales by are
    /// known.
    pub fn estimate(&mut self) -> Result<Option<StudyEstimate>, String> {
        self.checked().1.clone()
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

    fn names(&self) -> Design {
        match &self.start.subject {
            StudySubject::Display(d) => (**d).clone(),
            StudySubject::Phase(_) => Design::default_toled(),
        }
    }

    fn body_ui(&mut self, ui: &mut Ui) -> Option<RunRequest> {
        let what = match &self.start.subject {
            StudySubject::Display(d) if d.name.is_empty() => "the current design".to_string(),
            StudySubject::Display(d) => d.name.clone(),
            StudySubject::Phase(d) => format!(
                "the {} µm phase masks (on axis, channels R 610, G 530, B 470 nm)",
                d.pitch_um
            ),
        };
        ui.label(format!(
            "Varies {what} over every combination of the axes below (the last varies fastest)."
        ));
        ui.separator();
        self.axes_ui(ui);
        ui.separator();
        ui.label("Record");
        let names = self.names();
        ui.horizontal_wrapped(|ui| {
            for (m, on) in &mut self.metrics {
                ui.checkbox(on, m.label(&names));
            }
        });
        if matches!(self.start.subject, StudySubject::Display(_)) {
            ui.label(
                RichText::new(format!(
                    "A light-level or method axis, PSNR or SSIM restores {} at each point with \
                     the Restore view's settings.",
                    self.start
                        .photo
                        .as_ref()
                        .map_or(crate::io::photo::BUILT_IN_PHOTO_NAME, |p| p.name.as_str())
                ))
                .weak(),
            );
        }
        ui.checkbox(
            &mut self.full,
            "Full quality (the thesis's sampling; slower)",
        )
        .on_hover_text("Off: the interactive preview sampling, AUC within 3 %");
        ui.separator();
        let (study, estimate) = self.checked().clone();
        let ready = match (&study, &estimate) {
            (Ok(s), Ok(e)) => {
                let points = s.points();
                let line = match e {
                    Some(e) => format!(
                        "{points} points, {} {} on this machine, about {} of memory per point",
                        if e.at_least { "at least" } else { "about" },
                        duration_text(e.seconds),
                        format_bytes(e.bytes_per_point)
                    ),
                    None => format!(
                        "{points} points (the time is estimated once the design's own result \
                         is on screen{})",
                        if s.needs_photo() {
                            " and the Restore view has run"
                        } else {
                            ""
                        }
                    ),
                };
                ui.label(RichText::new(line).strong());
                true
            }
            (Err(why), _) | (Ok(_), Err(why)) => {
                ui.colored_label(ui.visuals().error_fg_color, why);
                false
            }
        };
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        let mut run = None;
        ui.horizontal(|ui| {
            let run_button = ui
                .add_enabled(ready, egui::Button::new("Run"))
                .on_hover_text(
                    "Runs in a results folder that resumes: the table and plots fill as the \
                     points finish",
                );
            let cluster_button = ui
                .add_enabled(ready, egui::Button::new("Run on a cluster…"))
                .on_hover_text(
                    "Writes the study's folder with a Slurm job array and a merge job for the \
                     same spec (udc-studio sweep slurm); submit it on the cluster",
                );
            let cluster = cluster_button.clicked();
            if (run_button.clicked() || cluster)
                && let Ok(study) = study
            {
                run = Some(RunRequest {
                    study,
                    photo: self.start.photo.clone(),
                    cluster,
                });
                self.open = false;
            }
            if ui.button("Close").clicked() {
                self.open = false;
            }
        });
        run
    }

    fn axes_ui(&mut self, ui: &mut Ui) {
        let mut remove = None;
        let first_seed = match &self.start.subject {
            StudySubject::Display(d) => d.tiling.seed,
            StudySubject::Phase(_) => 0,
        };
        egui::Grid::new("study_axes")
            .num_columns(3)
            .striped(true)
            .show(ui, |ui| {
                for (i, row) in self.axes.iter_mut().enumerate() {
                    ui.label(row.kind.label());
                    match row.kind {
                        AxisKind::Tiling => {
                            ui.horizontal(|ui| {
                                for (m, on) in TilingMode::ALL.iter().zip(&mut row.tilings) {
                                    ui.checkbox(on, m.as_str());
                                }
                            });
                        }
                        AxisKind::Method => {
                            ui.horizontal(|ui| {
                                for (m, on) in RestoreMethod::ALL.iter().zip(&mut row.methods) {
                                    ui.checkbox(on, m.label());
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
                                ui.label(format!("from seed {first_seed}"));
                            });
                        }
                        AxisKind::Lambda0 => {
                            ui.add_sized(
                                field_size(ui),
                                egui::TextEdit::singleline(&mut row.text)
                                    .hint_text("fixed:530, uniform, optimized"),
                            )
                            .on_hover_text(
                                "fixed:NM (every lenslet at one λ0), uniform (400-700 nm \
                                 evenly) or optimized (Algorithm 1 runs first)",
                            );
                        }
                        AxisKind::Opening => {
                            ui.add_sized(
                                field_size(ui),
                                egui::TextEdit::singleline(&mut row.text).hint_text("-1, 0, 1, 2"),
                            )
                            .on_hover_text(
                                "Whole cells: each grows (+) or shrinks (−) the drawn opening by \
                                 one cell on every side; the points are named by their open \
                                 fraction",
                            );
                        }
                        AxisKind::Dpi
                        | AxisKind::Number(_)
                        | AxisKind::SnrDb
                        | AxisKind::OpenRatio
                        | AxisKind::Fold => {
                            ui.add_sized(
                                field_size(ui),
                                egui::TextEdit::singleline(&mut row.text)
                                    .hint_text("80, 150, 300  or  80:600:5"),
                            )
                            .on_hover_text(
                                "A list of values, or from:to:count (both ends included)",
                            );
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
            for k in AxisKind::all(&self.start.subject) {
                if ui
                    .add_enabled(!taken.contains(&k), egui::Button::new(k.label()))
                    .clicked()
                {
                    self.axes
                        .push(AxisRow::new(k, &self.start.subject, &self.start.restore));
                    // A restoring axis is asked for to see the restoration: record it.
                    if matches!(k, AxisKind::SnrDb | AxisKind::Method) {
                        for (m, on) in &mut self.metrics {
                            *on |= matches!(m, StudyMetric::PsnrDb | StudyMetric::Ssim);
                        }
                    }
                    ui.close();
                }
            }
        });
    }
}

/// An axis's text field: wide enough for a few values whatever else the grid holds (a grid
/// sizes its columns from their widgets, and a text field alone would shrink to nothing).
fn field_size(ui: &Ui) -> egui::Vec2 {
    egui::vec2(200.0, ui.spacing().interact_size.y)
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
    use crate::core::Quality;
    use crate::core::phase::PhaseDesign;

    fn timed(mut start: StudyStart) -> StudyStart {
        start.times.on_screen = Some((100.0, Quality::Preview));
        start
    }

    #[test]
    fn the_dialog_starts_with_dpi_tiling_and_seeds_and_refuses_bad_values() {
        let mut d = StudyDialog::default();
        d.open(timed(StudyStart::display(Design::default_toled())));
        let s = d.study().expect("the starting study is valid");
        assert_eq!(s.points(), 3 * 2 * 3);
        assert!(d.estimate().expect("costed").is_some());
        // The design's own DPI to two decimals: its pitch within 0.01 µm of 168.
        let StudyAxis::Dpi(dpis) = &s.axes[0] else {
            panic!("a DPI axis first")
        };
        assert!((25_400.0 / dpis[1] - 168.0).abs() < 0.01, "{dpis:?}");
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
    fn a_light_axis_makes_a_restoring_study_that_waits_for_the_restore_views_time() {
        let mut d = StudyDialog::default();
        d.open(timed(StudyStart::display(Design::default_toled())));
        d.axes = vec![
            AxisRow::new(AxisKind::SnrDb, d.subject(), &RestoreSetup::default()),
            AxisRow::new(AxisKind::Method, d.subject(), &RestoreSetup::default()),
        ];
        let s = d.study().expect("valid");
        assert!(s.needs_photo());
        assert_eq!(s.points(), 3 * 2);
        assert_eq!(d.estimate().expect("costed"), None);
        d.axes[0].text = "24, inf".into();
        assert!(d.study().unwrap_err().contains("SNR"));
    }

    #[test]
    fn a_phase_design_starts_with_fold_and_plans_and_offers_only_its_own_axes() {
        let mut d = StudyDialog::default();
        d.open(timed(StudyStart::phase(PhaseDesign::thesis(42.0, 1.0))));
        let s = d.study().expect("valid");
        assert_eq!(s.points(), 4 * 3);
        let e = d.estimate().expect("costed").expect("timed");
        assert!(e.at_least, "the optimizer's plan is not modelled");
        assert!(!AxisKind::all(d.subject()).contains(&AxisKind::Dpi));
        d.axes[1].text = "fixed:530, best".into();
        assert!(d.study().unwrap_err().contains("best"));
    }

    #[test]
    fn durations_read_in_their_unit() {
        assert_eq!(duration_text(12.0), "12 s");
        assert_eq!(duration_text(600.0), "10.0 min");
        assert_eq!(duration_text(7200.0), "2.0 h");
    }
}
