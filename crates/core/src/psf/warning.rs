//! Sampling warnings as data: what is wrong ([`WarningKind`]), how much it matters
//! ([`Severity`]), the message in the design file's field words (the studio maps them to its
//! labels) and, once `advice::advise` has found one, a [`Fix`]: the optics to
//! apply, checked to resolve the warning without raising a new one.
//!
//! **Severity.** The thesis recipe (`iccp21`) crops every PSF to its 294-pixel window
//! (588 µm at f = 10 mm) and normalises it there; its δ1 = 8 µm grid is as wide as that window at
//! 470 nm. The thesis's published numbers, which the presets reproduce, are computed that way, so
//! under that camera and window some light falls outside the window and some reaches the edge of
//! the grid. That is a documented property of the recipe, not a mistake of the user: for optics
//! that keep the thesis recipe's camera, sampling and window (δ1 may only be finer, as the 300-
//! and 600-DPI T-OLED presets need for their smaller cells) the window and grid-edge kinds are
//! [`Severity::Note`]s, shown in grey with the same fix. With any other optics they are
//! [`Severity::Warning`]s, and the other kinds always are.

use crate::Setting;
use std::fmt;

use crate::design::{Optics, OpticsRecipe};

/// How much a warning matters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// A documented property of the thesis recipe (see the module docs): shown, not alarming.
    Note,
    /// The sampling misrepresents the design: the numbers are off until it is fixed.
    Warning,
}

impl Severity {
    /// The word the CLI and JSON reports use ("note", "warning").
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Note => "note",
            Severity::Warning => "warning",
        }
    }
}

/// What a sampling warning is about; one warning per kind and analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum WarningKind {
    /// The FFT grid pads the pupil less than 2×: the PSF is under-sampled.
    UnderPadded,
    /// The sensor pixel is not a whole number of fine samples.
    PixelNotWhole,
    /// The sensor window is larger than the FFT grid of some wavelength: its edges are empty.
    WindowBeyondGrid,
    /// The display cells are finer than the pupil sampling δ1.
    CellsFinerThanSampling,
    /// More than 2 % of a channel's light falls outside the sensor window.
    LightOutsideWindow,
    /// More than 2 % of a channel's light reaches the edge of the fine grid and wraps around.
    Aliasing,
}

impl WarningKind {
    /// Every kind, in the order the analysis reports them.
    pub const ALL: [WarningKind; 6] = [
        WarningKind::UnderPadded,
        WarningKind::PixelNotWhole,
        WarningKind::WindowBeyondGrid,
        WarningKind::CellsFinerThanSampling,
        WarningKind::LightOutsideWindow,
        WarningKind::Aliasing,
    ];

    /// The name JSON reports use (kebab-case).
    pub fn as_str(self) -> &'static str {
        match self {
            WarningKind::UnderPadded => "under-padded",
            WarningKind::PixelNotWhole => "pixel-not-whole",
            WarningKind::WindowBeyondGrid => "window-beyond-grid",
            WarningKind::CellsFinerThanSampling => "cells-finer-than-sampling",
            WarningKind::LightOutsideWindow => "light-outside-window",
            WarningKind::Aliasing => "aliasing",
        }
    }

    /// A short noun phrase for sentences such as "would leave …".
    pub fn describe(self) -> &'static str {
        match self {
            WarningKind::UnderPadded => "pupil zero-padding below 2×",
            WarningKind::PixelNotWhole => {
                "a sensor pixel that is not a whole number of fine samples"
            }
            WarningKind::WindowBeyondGrid => "a window larger than the FFT grid",
            WarningKind::CellsFinerThanSampling => "display cells finer than δ1",
            WarningKind::LightOutsideWindow => "more than 2 % of the light outside the window",
            WarningKind::Aliasing => "PSF aliasing at the edge of the fine grid",
        }
    }

    /// Whether the sampling plan raises this kind (before any FFT); the others come from the
    /// PSFs and the display cells.
    pub fn is_planned(self) -> bool {
        matches!(
            self,
            WarningKind::UnderPadded | WarningKind::PixelNotWhole | WarningKind::WindowBeyondGrid
        )
    }

    /// Whether the thesis recipe's crop explains this kind (see the module docs).
    fn is_a_crop_property(self) -> bool {
        matches!(
            self,
            WarningKind::WindowBeyondGrid | WarningKind::LightOutsideWindow | WarningKind::Aliasing
        )
    }
}

/// The optics values a fix may change: a closed set, each with its design-file path, the
/// studio's short name and its unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpticsField {
    /// `optics.pupil_sample_um`, δ1.
    PupilSample,
    /// `optics.fine_sample_um`, δ2.
    FineSample,
    /// `optics.window_px`.
    Window,
}

impl OpticsField {
    /// The design setting it is.
    pub fn setting(self) -> Setting {
        match self {
            OpticsField::PupilSample => Setting::OpticsPupilSampleUm,
            OpticsField::FineSample => Setting::OpticsFineSampleUm,
            OpticsField::Window => Setting::OpticsWindowPx,
        }
    }

    /// The field's path in the design file (`optics.window_px`).
    pub fn path(self) -> &'static str {
        self.setting().path()
    }

    /// Its short name in summaries ("δ1", "window").
    pub fn short(self) -> &'static str {
        match self {
            OpticsField::PupilSample => "δ1",
            OpticsField::FineSample => "δ2",
            OpticsField::Window => "window",
        }
    }

    /// Its unit.
    pub fn unit(self) -> &'static str {
        match self {
            OpticsField::Window => "px",
            OpticsField::PupilSample | OpticsField::FineSample => "µm",
        }
    }

    fn get(self, o: &Optics) -> f64 {
        match self {
            OpticsField::PupilSample => o.pupil_sample_um,
            OpticsField::FineSample => o.fine_sample_um,
            OpticsField::Window => o.window_px as f64,
        }
    }
}

/// One value a fix changes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Change {
    /// Which value.
    pub field: OpticsField,
    /// Its value before the fix (in the field's unit).
    pub from: f64,
    /// Its value after the fix.
    pub to: f64,
}

/// Concrete advice: the optics to apply (recipe `custom`) and what they change.
#[derive(Debug, Clone, PartialEq)]
pub struct Fix {
    /// The design's optics with the fix applied.
    pub optics: Optics,
    /// The values that differ from the design's optics, in [`OpticsField`] order.
    pub changes: Vec<Change>,
}

/// `v` with at most 4 decimals and no trailing zeros ("8", "0.5", "0.6667").
pub fn short_number(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

impl Fix {
    /// The fix that turns `from` into `to` (whose recipe becomes `custom`).
    pub fn between(from: &Optics, mut to: Optics) -> Fix {
        to.recipe = OpticsRecipe::Custom;
        let changes = [
            OpticsField::PupilSample,
            OpticsField::FineSample,
            OpticsField::Window,
        ]
        .into_iter()
        .filter(|f| f.get(from) != f.get(&to))
        .map(|field| Change {
            field,
            from: field.get(from),
            to: field.get(&to),
        })
        .collect();
        Fix {
            optics: to,
            changes,
        }
    }

    fn join(&self, each: impl Fn(&Change) -> String) -> String {
        self.changes.iter().map(each).collect::<Vec<_>>().join(", ")
    }

    /// "δ1 8 → 4 µm, window 294 → 588 px".
    pub fn summary(&self) -> String {
        self.join(|c| {
            format!(
                "{} {} → {} {}",
                c.field.short(),
                short_number(c.from),
                short_number(c.to),
                c.field.unit()
            )
        })
    }

    /// "optics.pupil_sample_um: 8 → 4 µm, optics.window_px: 294 → 588 px" (the studio maps the
    /// paths to its labels).
    pub fn field_changes(&self) -> String {
        self.join(|c| {
            format!(
                "{}: {} → {} {}",
                c.field.path(),
                short_number(c.from),
                short_number(c.to),
                c.field.unit()
            )
        })
    }

    /// "optics.pupil_sample_um = 4, optics.window_px = 588", as the CLI prints it.
    pub fn assignments(&self) -> String {
        self.join(|c| format!("{} = {}", c.field.path(), short_number(c.to)))
    }
}

/// One sampling warning or note of an analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplingWarning {
    /// What it is about.
    pub kind: WarningKind,
    /// Note or warning (see the module docs).
    pub severity: Severity,
    /// The message, naming design fields by their paths (`optics.window_px`); when no fix
    /// exists it also says why.
    pub message: String,
    /// The optics that resolve it, once `advice::advise` found them.
    pub fix: Option<Fix>,
}

/// Whether `op` crops PSFs as the thesis recipe does: its camera, sampling and window, with δ1
/// at most the recipe's (see the module docs).
pub fn crops_like_the_thesis(op: &Optics) -> bool {
    let thesis = Optics::iccp21();
    let same_but_delta1 = Optics {
        recipe: thesis.recipe,
        pupil_sample_um: thesis.pupil_sample_um,
        ..op.clone()
    } == thesis;
    op.recipe == OpticsRecipe::Iccp21 || (same_but_delta1 && op.pupil_sample_um <= 8.0)
}

impl SamplingWarning {
    /// A warning of a kind the thesis recipe does not explain.
    pub fn warning(kind: WarningKind, message: String) -> Self {
        SamplingWarning {
            kind,
            severity: Severity::Warning,
            message,
            fix: None,
        }
    }

    /// A warning of a crop kind: under optics that crop like the thesis (see
    /// [`crops_like_the_thesis`]) the note "Thesis recipe: `what`, as in the thesis's numbers";
    /// otherwise the warning "`what`: `why`".
    pub fn about_the_crop(kind: WarningKind, optics: &Optics, what: &str, why: &str) -> Self {
        if kind.is_a_crop_property() && crops_like_the_thesis(optics) {
            let source = if optics.recipe == OpticsRecipe::Iccp21 {
                "Thesis recipe"
            } else {
                "Thesis window"
            };
            SamplingWarning {
                kind,
                severity: Severity::Note,
                message: format!("{source}: {what}, as in the thesis's numbers"),
                fix: None,
            }
        } else {
            SamplingWarning::warning(kind, format!("{what}: {why}"))
        }
    }
}

impl fmt::Display for SamplingWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fix_lists_what_it_changes_in_three_wordings() {
        let from = Optics::iccp21();
        let to = Optics {
            pupil_sample_um: 4.0,
            window_px: 588,
            ..from.clone()
        };
        let fix = Fix::between(&from, to);
        assert_eq!(fix.optics.recipe, OpticsRecipe::Custom);
        assert_eq!(fix.summary(), "δ1 8 → 4 µm, window 294 → 588 px");
        assert_eq!(
            fix.assignments(),
            "optics.pupil_sample_um = 4, optics.window_px = 588"
        );
        assert_eq!(
            fix.field_changes(),
            "optics.pupil_sample_um: 8 → 4 µm, optics.window_px: 294 → 588 px"
        );
        assert_eq!(short_number(2.0 / 3.0), "0.6667");
        assert_eq!(short_number(0.5), "0.5");
    }

    #[test]
    fn only_the_thesis_crop_turns_crop_warnings_into_notes() {
        let thesis = Optics::iccp21();
        let finer = Optics {
            recipe: OpticsRecipe::Custom,
            pupil_sample_um: 4.0,
            ..thesis.clone()
        };
        let wider = Optics {
            window_px: 588,
            ..finer.clone()
        };
        assert!(crops_like_the_thesis(&thesis));
        assert!(crops_like_the_thesis(&finer));
        assert!(!crops_like_the_thesis(&wider));
        assert!(!crops_like_the_thesis(&Optics::phone()));
        let k = WarningKind::LightOutsideWindow;
        let note = SamplingWarning::about_the_crop(k, &thesis, "2 % out", "why");
        assert_eq!(note.severity, Severity::Note);
        assert_eq!(
            note.message,
            "Thesis recipe: 2 % out, as in the thesis's numbers"
        );
        let w = SamplingWarning::about_the_crop(k, &wider, "2 % out", "why");
        assert_eq!(
            (w.severity, w.message.as_str()),
            (Severity::Warning, "2 % out: why")
        );
        let padding = SamplingWarning::about_the_crop(WarningKind::UnderPadded, &thesis, "a", "b");
        assert_eq!(padding.severity, Severity::Warning);
    }
}
