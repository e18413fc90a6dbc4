//! Lessons: a sequence of steps that set the studio up (a preset, the view to look at), say
//! what to look for, ask a predict-then-reveal question and explain the answer with its
//! closed form. A question's right answer is never stored: it is measured on the design on
//! screen ([`measure`]), so changing a parameter changes it; the closed form it is explained by
//! is computed beside it, and the lesson tests check that the two agree.
//!
//! The file format (TOML, `format = "udc-studio-lesson"`, `version = 1`) is these types as
//! serde reads them; the book's chapter for teachers documents it with a complete example.

pub mod measure;

use serde::{Deserialize, Serialize};

use crate::views::saved::DisplayView;

/// The format tag of a lesson file.
pub const FORMAT: &str = "udc-studio-lesson";
/// The lesson format version this build reads.
pub const VERSION: u32 = 1;

/// A lesson: its title, a line on what it teaches, and its steps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lesson {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`].
    pub version: u32,
    /// The lesson's title.
    pub title: String,
    /// What it teaches, in a sentence.
    pub summary: String,
    /// The steps, in order.
    #[serde(rename = "step")]
    pub steps: Vec<Step>,
}

/// One step: the studio's setup, what to look for, a question and its explanation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// The step's title.
    pub title: String,
    /// The built-in preset to load (none: the design on screen stays).
    #[serde(default)]
    pub preset: Option<String>,
    /// A change to the design on screen, after the preset (if any) is loaded.
    #[serde(default)]
    pub change: Option<Change>,
    /// The view to look at.
    #[serde(default)]
    pub view: Option<DisplayView>,
    /// What to look for.
    pub look: String,
    /// The question, if the step asks one.
    #[serde(default)]
    pub question: Option<Question>,
    /// A mystery aperture: the built-in preset whose PSF is shown without its opening; the
    /// student draws a guess on the design on screen, the studio scores the match
    /// ([`measure::psf_match`]) and reveals the opening. A step asks a question or sets a
    /// mystery, not both.
    #[serde(default)]
    pub mystery: Option<String>,
    /// The explanation shown with the answer. `{answer}` is replaced by the measured answer
    /// and `{closed}` by the closed form's value, both with their units.
    pub explain: String,
}

/// A change a step makes to the design on screen (one undoable edit in the studio).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Change {
    /// The display pixel's pitch, µm (the opening's cells scale with it).
    #[serde(default)]
    pub pitch_um: Option<f64>,
    /// The tiling.
    #[serde(default)]
    pub tiling: Option<crate::design::TilingMode>,
}

/// The pitches a lesson may set, µm.
pub const PITCH_UM_RANGE: std::ops::RangeInclusive<f64> = 1.0..=10_000.0;

impl Change {
    /// `design` with the change made.
    pub fn apply(&self, design: &crate::design::Design) -> crate::design::Design {
        let mut d = design.clone();
        if let Some(p) = self.pitch_um {
            d.opening.pitch_um = p;
        }
        if let Some(t) = self.tiling {
            d.tiling.mode = t;
        }
        d
    }
}

/// A predict-then-reveal question.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Question {
    /// A number, right within `tolerance` (a fraction of the answer).
    Number {
        /// The question.
        prompt: String,
        /// What is measured on the design on screen.
        quantity: Quantity,
        /// The channel it is measured in (`R`, `G`, `B`); the first by default.
        #[serde(default)]
        channel: Option<String>,
        /// The relative tolerance of a right answer (0.1: within 10 %).
        tolerance: f64,
    },
    /// A drawing: the student changes the design on screen until the simulation shows
    /// `goal`.
    Drawing {
        /// The task.
        prompt: String,
        /// What the simulated PSF must show.
        goal: DrawingGoal,
    },
    /// One of several options; the right one follows from a measurement.
    Choice {
        /// The question.
        prompt: String,
        /// How the right option is found.
        rule: ChoiceRule,
        /// The preset compared with ([`ChoiceRule::AucAgainst`]).
        #[serde(default)]
        than: Option<String>,
    },
}

impl Question {
    /// The question's text.
    pub fn prompt(&self) -> &str {
        match self {
            Question::Number { prompt, .. }
            | Question::Drawing { prompt, .. }
            | Question::Choice { prompt, .. } => prompt,
        }
    }
}

/// What a number question measures on the design on screen.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Quantity {
    /// The first dark fringe's distance from the axis, µm: the light per column for a slit or
    /// rectangle (closed form `λf / a`), the axis row for a circle (`1.22 λf / D`).
    FirstDarkUm,
    /// The spacing of a double slit's fringes, µm (closed form `λf / d`).
    FringeSpacingUm,
    /// The distance of the first diffraction order from the axis, µm (closed form `λf / P`).
    OrderSpacingUm,
    /// The share of the light in the zero order of a periodic display (closed form `|c(0,0)|²`,
    /// the open fraction squared).
    ZeroOrderShare,
    /// The highest frequency the sensor samples, cycles/mm (closed form `1 / (2 p)`).
    NyquistCycPerMm,
}

impl Quantity {
    /// The unit the answer is given in ("" for a share).
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::FirstDarkUm | Quantity::FringeSpacingUm | Quantity::OrderSpacingUm => "µm",
            Quantity::ZeroOrderShare => "",
            Quantity::NyquistCycPerMm => "cycles/mm",
        }
    }
}

/// What a drawn design's simulated PSF must show.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DrawingGoal {
    /// No diffraction orders along x besides the zero order: the light in the orders (m, 0),
    /// m ≠ 0, under [`NO_ORDERS_SHARE`] of the zero order's (closed form: the opening's
    /// column means are all equal, so `c(m, 0) = 0` for m ≠ 0).
    NoHorizontalOrders,
}

/// The most light the orders a drawing must remove may keep, as a share of the zero order's.
pub const NO_ORDERS_SHARE: f64 = 0.01;

/// How a choice question's right option is found.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ChoiceRule {
    /// Which channel's PSF spreads widest (its first dark ring furthest out): the options are
    /// the channels' names.
    WidestChannel,
    /// Whether the design on screen has a higher or lower radially-minimum AUC (green) than
    /// the preset the question's `than` names: the options are "higher" and "lower".
    AucAgainst,
}

impl ChoiceRule {
    /// The options offered, given the design's channel names.
    pub fn options(self, channels: &[String]) -> Vec<String> {
        match self {
            ChoiceRule::WidestChannel => channels.to_vec(),
            ChoiceRule::AucAgainst => vec!["higher".into(), "lower".into()],
        }
    }
}

/// A lesson file that breaks a rule: where (the step, 1-based, and the field) and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{field}: {message}", step.map(|s| format!("step {s}, ")).unwrap_or_default())]
pub struct LessonError {
    /// The step, counted from 1; `None` for the lesson's own fields.
    pub step: Option<usize>,
    /// The field.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl Lesson {
    /// Checks what serde cannot: the format and version, text that is not empty, tolerances in
    /// (0, 1), at least one step, placeholders the explanation may use, and presets that
    /// `known_preset` knows.
    ///
    /// # Errors
    /// The first broken rule, naming its step and field.
    pub fn check(&self, known_preset: impl Fn(&str) -> bool) -> Result<(), LessonError> {
        let err = |step: Option<usize>, field: &str, message: String| LessonError {
            step,
            field: field.into(),
            message,
        };
        if self.format != FORMAT {
            return Err(err(
                None,
                "format",
                format!("is {:?}, a lesson says {FORMAT:?}", self.format),
            ));
        }
        if self.version != VERSION {
            return Err(err(
                None,
                "version",
                format!(
                    "{} is not a version this studio reads ({VERSION})",
                    self.version
                ),
            ));
        }
        for (field, text) in [("title", &self.title), ("summary", &self.summary)] {
            if text.trim().is_empty() {
                return Err(err(None, field, "is empty".into()));
            }
        }
        if self.steps.is_empty() {
            return Err(err(None, "step", "a lesson needs at least one step".into()));
        }
        for (i, s) in self.steps.iter().enumerate() {
            let at = Some(i + 1);
            for (field, text) in [
                ("title", &s.title),
                ("look", &s.look),
                ("explain", &s.explain),
            ] {
                if text.trim().is_empty() {
                    return Err(err(at, field, "is empty".into()));
                }
            }
            if let Some(p) = &s.preset
                && !known_preset(p)
            {
                return Err(err(at, "preset", format!("{p:?} is not a built-in preset")));
            }
            if i == 0 && s.preset.is_none() {
                return Err(err(
                    at,
                    "preset",
                    "the first step must load a preset (the lesson cannot know what is on \
                     screen)"
                        .into(),
                ));
            }
            if let Some(rest) = s.explain.split('{').nth(1)
                && !s
                    .explain
                    .split('{')
                    .skip(1)
                    .all(|p| p.starts_with("answer}") || p.starts_with("closed}"))
            {
                let name = rest.split('}').next().unwrap_or(rest);
                return Err(err(
                    at,
                    "explain",
                    format!("{{{name}}} is not a placeholder ({{answer}}, {{closed}})"),
                ));
            }
            if let Some(c) = &s.change {
                if let Some(p) = c.pitch_um
                    && !PITCH_UM_RANGE.contains(&p)
                {
                    return Err(err(
                        at,
                        "change.pitch_um",
                        format!(
                            "{p}: give {} to {} µm",
                            PITCH_UM_RANGE.start(),
                            PITCH_UM_RANGE.end()
                        ),
                    ));
                }
                if c.pitch_um.is_none() && c.tiling.is_none() {
                    return Err(err(
                        at,
                        "change",
                        "changes nothing (pitch_um, tiling)".into(),
                    ));
                }
            }
            if let Some(m) = &s.mystery {
                if !known_preset(m) {
                    return Err(err(
                        at,
                        "mystery",
                        format!("{m:?} is not a built-in preset"),
                    ));
                }
                if s.question.is_some() {
                    return Err(err(
                        at,
                        "mystery",
                        "a step asks a question or sets a mystery, not both".into(),
                    ));
                }
            }
            match &s.question {
                Some(Question::Number {
                    prompt, tolerance, ..
                }) => {
                    if prompt.trim().is_empty() {
                        return Err(err(at, "question.prompt", "is empty".into()));
                    }
                    if !(*tolerance > 0.0 && *tolerance < 1.0) {
                        return Err(err(
                            at,
                            "question.tolerance",
                            format!("{tolerance}: give a fraction between 0 and 1 (0.1: 10 %)"),
                        ));
                    }
                }
                Some(Question::Drawing { prompt, .. }) if prompt.trim().is_empty() => {
                    return Err(err(at, "question.prompt", "is empty".into()));
                }
                Some(Question::Choice { prompt, rule, than }) => {
                    if prompt.trim().is_empty() {
                        return Err(err(at, "question.prompt", "is empty".into()));
                    }
                    match (rule, than) {
                        (ChoiceRule::AucAgainst, None) => {
                            return Err(err(
                                at,
                                "question.than",
                                "auc-against needs the preset to compare with".into(),
                            ));
                        }
                        (ChoiceRule::AucAgainst, Some(than)) if !known_preset(than) => {
                            return Err(err(
                                at,
                                "question.than",
                                format!("{than:?} is not a built-in preset"),
                            ));
                        }
                        (ChoiceRule::WidestChannel, Some(_)) => {
                            return Err(err(
                                at,
                                "question.than",
                                "only auc-against compares with a preset".into(),
                            ));
                        }
                        _ => {}
                    }
                }
                Some(Question::Drawing { .. }) | None => {}
            }
        }
        Ok(())
    }
}
