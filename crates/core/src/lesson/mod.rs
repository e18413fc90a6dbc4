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
    /// The phase-mask design to look at (thesis chapter 4): the studio shows the Phase
    /// workspace with this change made to its design.
    #[serde(default)]
    pub phase: Option<PhaseChange>,
    /// The view to look at (in the Display workspace).
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
    /// A mystery aperture from a design file the teacher wrote (JSON, as File ▸ Save writes
    /// it), its path relative to the lesson file: as `mystery`, for an opening no preset has.
    #[serde(default)]
    pub mystery_file: Option<std::path::PathBuf>,
    /// The explanation shown with the answer. `{answer}` is replaced by the measured answer
    /// and `{closed}` by the closed form's value, both with their units.
    pub explain: String,
}

/// Where a step's mystery aperture comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MysterySource<'a> {
    /// A built-in preset, by name.
    Preset(&'a str),
    /// A design file (made absolute when the lesson file is read).
    File(&'a std::path::Path),
}

impl Step {
    /// The step's mystery aperture, if it sets one.
    pub fn mystery_source(&self) -> Option<MysterySource<'_>> {
        match (&self.mystery, &self.mystery_file) {
            (Some(name), _) => Some(MysterySource::Preset(name)),
            (None, Some(path)) => Some(MysterySource::File(path)),
            (None, None) => None,
        }
    }
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

/// A change a step makes to the phase-mask design (one undoable edit in the Phase workspace).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhaseChange {
    /// Start from the thesis's design (pitch 42 µm, f_MLA = pitch, T = 1, a slit of 1/4.2 of
    /// the pixel, λ0 = 530 nm) before the changes below; the first step that sets a phase
    /// design must, as the lesson cannot know what is on screen.
    #[serde(default)]
    pub from_thesis: bool,
    /// The display pixel's (and lenslet's) pitch, µm; the lenslet focal length follows it.
    #[serde(default)]
    pub pitch_um: Option<f64>,
    /// The fold thickness T (the plate's height is T λ0 / (n − 1)).
    #[serde(default)]
    pub fold: Option<f64>,
    /// One folding wavelength for every lenslet, nm.
    #[serde(default)]
    pub lambda0_nm: Option<f64>,
}

/// The folding wavelengths a lesson may set, nm (the spectral grid's span).
pub const LAMBDA0_NM_RANGE: std::ops::RangeInclusive<f64> = 400.0..=700.0;
/// The fold thicknesses a lesson may set.
pub const FOLD_RANGE: std::ops::RangeInclusive<f64> = 1.0..=20.0;

impl PhaseChange {
    /// `design` with the change made.
    pub fn apply(&self, design: &crate::phase::PhaseDesign) -> crate::phase::PhaseDesign {
        let mut d = if self.from_thesis {
            crate::phase::PhaseDesign::thesis(42.0, 1.0)
        } else {
            design.clone()
        };
        if let Some(p) = self.pitch_um {
            d.pitch_um = p;
            d.f_mla_um = p;
        }
        if let Some(t) = self.fold {
            d.fold = t;
        }
        if let Some(nm) = self.lambda0_nm {
            d.lambda0 = crate::phase::Lambda0::Fixed { nm };
        }
        d
    }
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
    /// How many times more light reaches the sensor window through the double microlens array
    /// than through the bare T-OLED, before the folded plate's polariser (closed form `P / a`:
    /// the first array focuses a whole pixel's light through its slit of width `a`, where the
    /// bare display passes the open share `a / P`). Measured on the Phase workspace's PSFs.
    MlaLightGain,
}

impl Quantity {
    /// The unit the answer is given in ("" for a share).
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::FirstDarkUm | Quantity::FringeSpacingUm | Quantity::OrderSpacingUm => "µm",
            Quantity::ZeroOrderShare | Quantity::MlaLightGain => "",
            Quantity::NyquistCycPerMm => "cycles/mm",
        }
    }

    /// Whether it is measured on the phase-mask design (the Phase workspace) rather than
    /// the display layout.
    pub fn is_phase(self) -> bool {
        matches!(self, Quantity::MlaLightGain)
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
    /// Which channel the double microlens array brings the most light to (the largest gain
    /// over the bare T-OLED, [`Quantity::MlaLightGain`]): the options are the channels' names.
    /// The closed form picks the channel nearest the folding wavelength, where the folded
    /// plate is the lens it was cut from. Measured on the Phase workspace's PSFs.
    MostLightChannel,
}

impl ChoiceRule {
    /// The options offered, given the design's channel names.
    pub fn options(self, channels: &[String]) -> Vec<String> {
        match self {
            ChoiceRule::WidestChannel | ChoiceRule::MostLightChannel => channels.to_vec(),
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
            if i == 0 && s.preset.is_none() && s.phase.is_none() {
                return Err(err(
                    at,
                    "preset",
                    "the first step must load a preset or set a phase design (the lesson \
                     cannot know what is on screen)"
                        .into(),
                ));
            }
            if let Some(c) = &s.phase {
                let first = !self.steps[..i].iter().any(|e| e.phase.is_some());
                if first && !c.from_thesis {
                    return Err(err(
                        at,
                        "phase.from_thesis",
                        "the first step with a phase design must start from the thesis's \
                         (from_thesis = true): the lesson cannot know what is on screen"
                            .into(),
                    ));
                }
                if s.preset.is_some() || s.change.is_some() || s.mystery_source().is_some() {
                    return Err(err(
                        at,
                        "phase",
                        "a step sets up the Phase workspace or the Display workspace, not both"
                            .into(),
                    ));
                }
                let ranges = [
                    ("phase.pitch_um", c.pitch_um, &PITCH_UM_RANGE, "µm"),
                    ("phase.fold", c.fold, &FOLD_RANGE, ""),
                    ("phase.lambda0_nm", c.lambda0_nm, &LAMBDA0_NM_RANGE, "nm"),
                ];
                for (field, v, range, unit) in ranges {
                    if let Some(v) = v
                        && !range.contains(&v)
                    {
                        return Err(err(
                            at,
                            field,
                            format!("{v}: give {} to {} {unit}", range.start(), range.end())
                                .trim_end()
                                .to_owned(),
                        ));
                    }
                }
            }
            let phase_on_screen = self.steps[..=i].iter().any(|e| e.phase.is_some());
            let wants_phase = match &s.question {
                Some(Question::Number { quantity, .. }) => quantity.is_phase(),
                Some(Question::Choice { rule, .. }) => *rule == ChoiceRule::MostLightChannel,
                _ => false,
            };
            if wants_phase && !phase_on_screen {
                return Err(err(
                    at,
                    "question",
                    "measures a phase-mask design, but no step so far sets one (phase)".into(),
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
            if s.mystery.is_some() && s.mystery_file.is_some() {
                return Err(err(
                    at,
                    "mystery_file",
                    "a step's mystery is a preset (mystery) or a design file (mystery_file), \
                     not both"
                        .into(),
                ));
            }
            if s.mystery_file.is_some() && s.question.is_some() {
                return Err(err(
                    at,
                    "mystery_file",
                    "a step asks a question or sets a mystery, not both".into(),
                ));
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
                        (ChoiceRule::WidestChannel | ChoiceRule::MostLightChannel, Some(_)) => {
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
