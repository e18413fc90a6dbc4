//! Help ▸ Lessons: a side panel that stays open while the student works. It lists the shipped
//! lessons (and opens a teacher's file), walks a lesson's steps, sets the studio up for each
//! (the app loads the preset and shows the view: [`Setup`]), asks the step's question and
//! checks the student's prediction against the simulation on screen, then reveals the answer
//! with its explanation. The lesson text lives in the lesson files and the measurements in
//! [`crate::core::lesson`]; this panel only draws and routes.

use std::path::{Path, PathBuf};

use std::sync::{Arc, Mutex};

use egui::{ColorImage, RichText, TextureHandle, TextureOptions, Ui};

use crate::app::dialogs::{self, FileSpec};
use crate::app::display::panels::Shown;
use crate::app::job::{Job, JobError};
use crate::app::notice::Notice;
use crate::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use crate::core::figure::Panel;
use crate::core::lesson::measure::{Answer, Guess, answer, phase_answer, psf_match};
use crate::core::lesson::{ChoiceRule, Lesson, MysterySource, Question};
use crate::core::views::saved::DisplayView;
use crate::core::{Analysis, Design};
use udc_gpu::Route;

/// What a step asks of the studio: the app loads the preset and shows the view, or shows the
/// Phase workspace with its design changed.
#[derive(Debug, Clone, PartialEq)]
pub struct Setup {
    /// The preset to load, if the step loads one.
    pub preset: Option<String>,
    /// The change to the phase-mask design, if the step sets one.
    pub phase: Option<crate::core::lesson::PhaseChange>,
    /// The change to make to the design then, if any.
    pub change: Option<crate::core::lesson::Change>,
    /// The view to show, if the step names one.
    pub view: Option<DisplayView>,
}

/// What a lesson measures: the workspaces' results, each only when it is its design's
/// current one (the Display workspace's at full quality).
#[derive(Default)]
pub struct OnScreen {
    /// The Display workspace's result.
    pub display: Option<Shown>,
    /// The Phase workspace's PSFs and the design they were computed for.
    pub phase: Option<PhaseShown>,
}

/// The Phase workspace's PSFs as a lesson measures them.
pub struct PhaseShown {
    /// The design they were computed for.
    pub design: crate::core::phase::PhaseDesign,
    /// The PSFs.
    pub psfs: Arc<crate::core::phase::psf::PhasePsfs>,
}

impl OnScreen {
    /// The channels a choice offers: the phase PSFs' or the display analysis's.
    fn channel_names(&self, phase: bool) -> Vec<String> {
        if phase {
            self.phase
                .as_ref()
                .map(|p| p.psfs.channels.iter().map(|c| c.name.clone()).collect())
                .unwrap_or_default()
        } else {
            self.display
                .as_ref()
                .map(|s| s.analysis.channels.iter().map(|c| c.name.clone()).collect())
                .unwrap_or_default()
        }
    }
}

/// Whether `q` is measured on the phase-mask design.
fn is_phase(q: &Question) -> bool {
    match q {
        Question::Number { quantity, .. } => quantity.is_phase(),
        Question::Choice { rule, .. } => *rule == ChoiceRule::MostLightChannel,
        Question::Drawing { .. } => false,
    }
}

/// How the student's last check went.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Right.
    Right,
    /// Wrong: try again or reveal.
    Wrong,
}

/// The panel's state.
#[derive(Default)]
pub struct LessonsPanel {
    open: bool,
    lesson: Option<(String, Lesson)>,
    step: usize,
    /// The number typed as the prediction.
    pub guess: String,
    /// The option chosen as the prediction.
    pub choice: Option<usize>,
    verdict: Option<Verdict>,
    revealed: Option<Answer>,
    /// The analysis of the preset a comparison question names, computed when its step opens.
    other: Option<(String, Job<Analysis>)>,
    other_done: Option<(String, Analysis)>,
    dialog: Option<Job<Option<PathBuf>>>,
    setup: Option<Setup>,
    message: Option<Notice>,
    /// The mystery aperture being computed, and once computed.
    mystery_job: Option<(String, Job<(Design, Analysis)>)>,
    mystery: Option<Mystery>,
    /// The last score of the drawing against the mystery, 0 … 1.
    score: Option<f64>,
    /// Whether the mystery's opening is shown.
    unveiled: bool,
    /// The PSFs' backend (View ▸ Compute PSFs on) the lessons' analyses run on; the CPU when
    /// `None`.
    route: Option<Arc<Mutex<Arc<Route>>>>,
}

/// A mystery aperture: the hidden design, its analysis and the pictures shown.
struct Mystery {
    name: String,
    design: Design,
    analysis: Analysis,
    psf: Option<(Arc<Panel>, Vec<TextureHandle>)>,
    opening: Option<TextureHandle>,
}

impl LessonsPanel {
    /// Shows or hides the panel.
    pub fn toggle(&mut self) {
        self.open = !self.open;
    }

    /// Whether the panel is shown.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// The lesson being walked and the step (from 0).
    pub fn current(&self) -> Option<(&Lesson, usize)> {
        self.lesson.as_ref().map(|(_, l)| (l, self.step))
    }

    /// The verdict of the last check.
    pub fn verdict(&self) -> Option<&Verdict> {
        self.verdict.as_ref()
    }

    /// The answer revealed, if it is.
    pub fn revealed(&self) -> Option<&Answer> {
        self.revealed.as_ref()
    }

    /// The last score of the drawing against the step's mystery aperture, 0 … 1.
    pub fn score(&self) -> Option<f64> {
        self.score
    }

    /// Whether the mystery aperture's opening is revealed.
    pub fn unveiled(&self) -> bool {
        self.unveiled
    }

    /// Whether the step's mystery aperture is computed.
    pub fn mystery_ready(&self) -> bool {
        self.mystery.is_some()
    }

    /// The last message.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// The setup the current step asks for, once (the app carries it out).
    pub fn take_setup(&mut self) -> Option<Setup> {
        self.setup.take()
    }

    /// The panel with its analyses on the PSFs' backend, read when each starts.
    #[must_use]
    pub fn with_route(self, route: Arc<Mutex<Arc<Route>>>) -> Self {
        LessonsPanel {
            route: Some(route),
            ..self
        }
    }

    /// The route an analysis starting now runs on.
    fn route(&self) -> Arc<Route> {
        self.route
            .as_ref()
            .and_then(|r| r.lock().ok().map(|r| r.clone()))
            .unwrap_or_else(|| Arc::new(Route::cpu()))
    }

    /// Starts `lesson` (named `name`) at its first step.
    pub fn start(&mut self, name: String, lesson: Lesson, ctx: &egui::Context) {
        self.open = true;
        self.lesson = Some((name, lesson));
        self.go_to(0, ctx);
    }

    /// Opens the lesson file at `path`.
    pub fn open_file(&mut self, path: &Path, ctx: &egui::Context) {
        match crate::io::lesson::read_lesson(path) {
            Ok(l) => {
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into(),
                );
                self.start(name, l, ctx);
                self.message = None;
            }
            Err(e) => {
                self.open = true;
                self.message = Some(Notice::error(e.to_string()));
            }
        }
    }

    /// Goes to step `k` (from 0): asks for its setup and clears the last prediction.
    pub fn go_to(&mut self, k: usize, ctx: &egui::Context) {
        let Some((_, lesson)) = &self.lesson else {
            return;
        };
        let Some(step) = lesson.steps.get(k) else {
            return;
        };
        self.step = k;
        self.guess.clear();
        self.choice = None;
        self.verdict = None;
        self.revealed = None;
        self.setup = Some(Setup {
            preset: step.preset.clone(),
            phase: step.phase.clone(),
            change: step.change.clone(),
            view: step.view,
        });
        self.score = None;
        self.unveiled = false;
        let source = step.mystery_source().map(|m| match m {
            MysterySource::Preset(name) => (name.to_owned(), None),
            MysterySource::File(path) => (path.display().to_string(), Some(path.to_path_buf())),
        });
        if let Some((name, file)) = source
            && self.mystery.as_ref().is_none_or(|m| m.name != name)
        {
            self.mystery = None;
            let (hidden, wake, route) = (name.clone(), ctx.clone(), self.route());
            self.mystery_job = Some((
                name,
                Job::spawn(
                    "mystery aperture",
                    move || wake.request_repaint(),
                    move |p| -> Result<(Design, Analysis), JobError> {
                        let design = match &file {
                            Some(path) => crate::io::design::file::load_design(path)?,
                            None => crate::io::design::presets::load_preset(&hidden)?,
                        };
                        let options = AnalyzeOptions {
                            quality: Quality::Full,
                            expected_psf: false,
                        };
                        let analysis = analyze_with_route(&design, &options, route.as_ref(), p)?;
                        Ok((design, analysis))
                    },
                ),
            ));
        }
        if let Some(Question::Choice {
            than: Some(than), ..
        }) = &step.question
            && self.other_done.as_ref().is_none_or(|(n, _)| n != than)
        {
            let (name, wake, route) = (than.clone(), ctx.clone(), self.route());
            self.other = Some((
                than.clone(),
                Job::spawn(
                    "lesson comparison",
                    move || wake.request_repaint(),
                    move |p| -> Result<Analysis, JobError> {
                        let design = crate::io::design::presets::load_preset(&name)?;
                        let options = AnalyzeOptions {
                            quality: Quality::Full,
                            expected_psf: false,
                        };
                        Ok(analyze_with_route(&design, &options, route.as_ref(), p)?)
                    },
                ),
            ));
        }
    }

    /// Checks `guess` against the simulation on screen (`on`: the results that are their
    /// design's, at full quality); returns the verdict, `None` while the answer cannot be
    /// computed yet (the message says why).
    pub fn check(&mut self, on: &OnScreen, guess: Guess) -> Option<Verdict> {
        let (a, tolerance) = self.answer_now(on)?;
        let v = if a.grade(guess, tolerance) {
            Verdict::Right
        } else {
            Verdict::Wrong
        };
        self.verdict = Some(v.clone());
        Some(v)
    }

    /// Reveals the answer measured on the simulation on screen, with the explanation.
    pub fn reveal(&mut self, on: &OnScreen) {
        if let Some((a, _)) = self.answer_now(on) {
            self.revealed = Some(a);
        }
    }

    fn answer_now(&mut self, on: &OnScreen) -> Option<(Answer, f64)> {
        let (_, lesson) = self.lesson.as_ref()?;
        let q = lesson.steps.get(self.step)?.question.as_ref()?;
        let tolerance = match q {
            Question::Number { tolerance, .. } => *tolerance,
            Question::Choice { .. } | Question::Drawing { .. } => 0.0,
        };
        if is_phase(q) {
            let Some(p) = &on.phase else {
                self.message = Some(Notice::info(
                    "the phase-mask PSFs are still being computed: check again in a moment",
                ));
                return None;
            };
            let measured = phase_answer(q, &p.design, &p.psfs);
            return self.settle(measured, tolerance);
        }
        let Some(shown) = on.display.as_ref() else {
            self.message = Some(Notice::info(
                "the simulation is still running: check again in a moment",
            ));
            return None;
        };
        let other = match q {
            Question::Choice {
                than: Some(than), ..
            } => match &self.other_done {
                Some((n, a)) if n == than => Some(a),
                _ => {
                    self.message = Some(Notice::info("computing the comparison…"));
                    return None;
                }
            },
            _ => None,
        };
        let measured = answer(q, &shown.design, &shown.analysis, other);
        self.settle(measured, tolerance)
    }

    /// A measured answer with its tolerance, or its error shown as the panel's message.
    fn settle(
        &mut self,
        measured: Result<Answer, crate::core::SimError>,
        tolerance: f64,
    ) -> Option<(Answer, f64)> {
        match measured {
            Ok(a) => {
                self.message = None;
                Some((a, tolerance))
            }
            Err(e) => {
                self.message = Some(Notice::error(e.to_string()));
                None
            }
        }
    }

    /// Scores the design on screen against the step's mystery aperture (green channel).
    pub fn score_drawing(&mut self, on: &OnScreen) {
        let Some(m) = &self.mystery else {
            self.message = Some(Notice::info("the mystery is still being computed"));
            return;
        };
        let Some(shown) = on.display.as_ref() else {
            self.message = Some(Notice::info(
                "the simulation is still running: score again in a moment",
            ));
            return;
        };
        match psf_match(&shown.analysis, &m.analysis, "G") {
            Ok(s) => {
                self.score = Some(s);
                self.message = None;
            }
            Err(e) => self.message = Some(Notice::error(e.to_string())),
        }
    }

    /// Shows the mystery's opening.
    pub fn unveil(&mut self) {
        self.unveiled = self.mystery.is_some();
    }

    /// Takes finished jobs.
    fn poll(&mut self, ctx: &egui::Context) {
        if let Some((name, j)) = &self.mystery_job
            && let Some(r) = j.poll()
        {
            match r {
                Ok((design, analysis)) => {
                    self.mystery = Some(Mystery {
                        name: name.clone(),
                        design,
                        analysis,
                        psf: None,
                        opening: None,
                    });
                }
                Err(e) => self.message = Some(Notice::error(format!("{name}: {e}"))),
            }
            self.mystery_job = None;
        }
        if let Some((name, j)) = &self.other
            && let Some(r) = j.poll()
        {
            match r {
                Ok(a) => self.other_done = Some((name.clone(), a)),
                Err(e) => self.message = Some(Notice::error(format!("{name}: {e}"))),
            }
            self.other = None;
        }
        if let Some(j) = &self.dialog
            && let Some(answer) = j.poll()
        {
            self.dialog = None;
            match answer {
                Ok(Some(path)) => self.open_file(&path, ctx),
                Ok(None) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
    }

    /// Draws the panel (when open) at the window's right edge.
    pub fn ui(&mut self, ui: &mut Ui, on: &OnScreen, native_dialogs: bool) {
        self.poll(ui.ctx());
        if !self.open {
            return;
        }
        egui::Panel::right("lessons")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.horizontal(|ui| {
                        ui.heading("Lessons");
                        if ui.small_button("Close").clicked() {
                            self.open = false;
                        }
                    });
                    if self.lesson.is_some() {
                        self.step_ui(ui, on);
                    } else {
                        self.list_ui(ui, native_dialogs);
                    }
                    crate::app::widgets::message_ui(ui, self.message.as_ref());
                });
            });
    }

    fn mystery_ui(&mut self, ui: &mut Ui, on: &OnScreen, explain: &str) {
        use crate::core::views::{Landmarks, PsfScale, psf_panel};
        let Some(m) = &mut self.mystery else {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("computing the mystery's PSF…");
            });
            return;
        };
        let ctx = ui.ctx().clone();
        if m.psf.is_none() {
            let i = m
                .analysis
                .channels
                .iter()
                .position(|c| c.name.eq_ignore_ascii_case("g"))
                .unwrap_or(0);
            if let Some(ch) = m.analysis.channels.get(i) {
                let mut panel = psf_panel(
                    &m.design,
                    &m.analysis,
                    ch,
                    PsfScale::Log { floor_decades: 5.0 },
                    Landmarks {
                        airy: false,
                        orders: false,
                    },
                );
                panel.title = "The mystery's log-PSF (green)".into();
                let textures =
                    crate::app::widgets::figure::panel_textures(&ctx, "lesson mystery", &panel);
                m.psf = Some((Arc::new(panel), textures));
            }
        }
        if let Some((panel, textures)) = &m.psf {
            let ids: Vec<egui::TextureId> = textures.iter().map(TextureHandle::id).collect();
            let side = ui.available_width().min(260.0);
            crate::app::widgets::figure::image_panel_ui(
                ui,
                "lesson mystery psf",
                panel,
                &ids,
                crate::app::widgets::figure::ImageFrame {
                    size: egui::vec2(side, side),
                    link: None,
                    view_half: crate::app::widgets::figure::lit_view_half(panel),
                },
            );
        }
        ui.horizontal(|ui| {
            if ui
                .button("Score my drawing")
                .on_hover_text(
                    "How well your design's PSF matches the mystery's: the correlation of the \
                     two log-PSFs, 0 to 100 %",
                )
                .clicked()
            {
                self.score_drawing(on);
            }
            if ui.button("Reveal the opening").clicked() {
                self.unveil();
            }
        });
        if let Some(s) = self.score {
            ui.label(RichText::new(format!("Match: {:.0} %", 100.0 * s)).strong());
        }
        let Some(m) = &mut self.mystery else { return };
        if self.unveiled {
            ui.separator();
            let texture = m.opening.get_or_insert_with(|| {
                ctx.load_texture(
                    "lesson mystery opening",
                    opening_image(&m.design),
                    TextureOptions::NEAREST,
                )
            });
            ui.label(format!("The hidden opening: {}", m.design.name));
            let side = ui.available_width().min(200.0);
            ui.add(
                egui::Image::new((texture.id(), egui::vec2(side, side)))
                    .alt_text("the mystery's opening"),
            );
            ui.label(explain);
        }
    }

    fn list_ui(&mut self, ui: &mut Ui, native_dialogs: bool) {
        ui.label("Each lesson sets the studio up, asks you to predict, then checks your answer against the simulation.");
        for (name, parsed) in crate::io::lesson::shipped() {
            let Ok(lesson) = parsed else { continue };
            if ui
                .button(&lesson.title)
                .on_hover_text(&lesson.summary)
                .clicked()
            {
                self.start(name.display().to_string(), lesson.clone(), ui.ctx());
            }
        }
        ui.separator();
        if ui
            .add_enabled(
                self.dialog.is_none(),
                egui::Button::new("Open lesson file…"),
            )
            .on_hover_text("A teacher's lesson (TOML); dropping it on the window opens it too")
            .clicked()
        {
            self.ask_file(ui.ctx(), native_dialogs);
        }
    }

    /// Opens the panel and asks for a lesson file (File ▸ Open lesson…).
    pub fn ask_file(&mut self, ctx: &egui::Context, native_dialogs: bool) {
        self.open = true;
        if self.dialog.is_some() {
            return;
        }
        if native_dialogs {
            let wake = ctx.clone();
            self.dialog = Some(dialogs::ask(
                FileSpec::open("Open a lesson", ("lesson", &["toml"])),
                move || wake.request_repaint(),
            ));
        } else {
            self.message = Some(Notice::error("file dialogs are disabled in this session"));
        }
    }

    fn step_ui(&mut self, ui: &mut Ui, on: &OnScreen) {
        let Some((_, lesson)) = &self.lesson else {
            return;
        };
        let n = lesson.steps.len();
        let Some(step) = lesson.steps.get(self.step).cloned() else {
            return;
        };
        ui.label(RichText::new(&lesson.title).strong());
        ui.label(format!("Step {} of {n}: {}", self.step + 1, step.title));
        ui.separator();
        ui.label(&step.look);
        if step.mystery_source().is_some() {
            self.mystery_ui(ui, on, &step.explain);
        } else if let Some(q) = &step.question {
            ui.separator();
            ui.label(RichText::new(q.prompt()).strong());
            let guess = match q {
                Question::Number { quantity, .. } => {
                    ui.horizontal(|ui| {
                        ui.add(egui::TextEdit::singleline(&mut self.guess).desired_width(90.0))
                            .on_hover_text("Your prediction");
                        ui.label(quantity.unit());
                    });
                    guessed_number(&self.guess).map(Guess::Number)
                }
                Question::Drawing { .. } => {
                    ui.label(
                        "Draw on the Opening tab, then check: the simulation on screen decides.",
                    );
                    Some(Guess::Drawn)
                }
                Question::Choice { rule, .. } => {
                    let names = on.channel_names(is_phase(q));
                    let options = rule.options(&names);
                    ui.horizontal_wrapped(|ui| {
                        for (i, o) in options.iter().enumerate() {
                            ui.radio_value(&mut self.choice, Some(i), o);
                        }
                    });
                    self.choice.map(Guess::Choice)
                }
            };
            ui.horizontal(|ui| {
                if ui
                    .add_enabled(guess.is_some(), egui::Button::new("Check"))
                    .on_hover_text("Compared with the simulation on screen")
                    .clicked()
                    && let Some(g) = guess
                {
                    self.check(on, g);
                }
                if ui.button("Reveal").clicked() {
                    self.reveal(on);
                }
            });
            match &self.verdict {
                Some(Verdict::Right) => {
                    ui.colored_label(egui::Color32::from_rgb(40, 160, 60), "Right.");
                }
                Some(Verdict::Wrong) => {
                    ui.colored_label(
                        ui.visuals().warn_fg_color,
                        "Not quite: try again, or reveal.",
                    );
                }
                None => {}
            }
            if let Some(a) = &self.revealed {
                ui.separator();
                ui.label(RichText::new(format!("Answer: {}", a.text())).strong());
                ui.label(a.explain(&step.explain));
            }
        } else {
            ui.separator();
            ui.label(&step.explain);
        }
        ui.separator();
        let ctx = ui.ctx().clone();
        ui.horizontal(|ui| {
            if ui
                .add_enabled(self.step > 0, egui::Button::new("◀ Back"))
                .clicked()
            {
                self.go_to(self.step - 1, &ctx);
            }
            if ui
                .add_enabled(self.step + 1 < n, egui::Button::new("Next ▶"))
                .clicked()
            {
                self.go_to(self.step + 1, &ctx);
            }
            if ui.button("All lessons").clicked() {
                self.lesson = None;
            }
        });
    }
}

/// A design's opening as a picture: white where light passes, one pixel a cell.
fn opening_image(design: &Design) -> ColorImage {
    let cells = &design.opening.cells;
    let (h, w) = (cells.len(), cells.first().map_or(0, Vec::len));
    let pixels = cells
        .iter()
        .flat_map(|row| {
            row.iter().map(|t| {
                let v = (t.clamp(0.0, 1.0) * 255.0).round() as u8;
                egui::Color32::from_gray(v)
            })
        })
        .collect();
    ColorImage::new(
        [w.max(1), h.max(1)],
        if w * h == 0 {
            vec![egui::Color32::BLACK]
        } else {
            pixels
        },
    )
}

/// A typed prediction as a number: a unit after it is ignored ("24 µm"), a comma reads as a
/// decimal point; `None` for anything that is not a finite number.
fn guessed_number(text: &str) -> Option<f64> {
    let number = text
        .trim()
        .trim_end_matches(|c: char| c.is_alphabetic() || c.is_whitespace() || c == '/' || c == 'µ')
        .replace(',', ".")
        .replace('−', "-");
    number.parse::<f64>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::guessed_number;

    #[test]
    fn a_prediction_reads_with_or_without_its_unit() {
        assert_eq!(guessed_number("24.5"), Some(24.5));
        assert_eq!(guessed_number(" 24,5 µm"), Some(24.5));
        assert_eq!(guessed_number("250 cycles/mm"), Some(250.0));
        assert_eq!(guessed_number("nan"), None);
        assert_eq!(guessed_number("abc"), None);
    }
}
