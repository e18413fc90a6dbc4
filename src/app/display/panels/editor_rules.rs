//! The design rules on the opening editor's canvas (View > Design rules on the editor): a red
//! ring where the opening breaks a rule, and on hover the rule, the measured value and the
//! limit. The check runs in the background ([`super::rules_check`]); the canvas shows no rings
//! while it runs rather than stale ones.

use egui::{Color32, Painter, Pos2, Rect, Response, Stroke, Ui, vec2};

use super::rules_check::{RulesCheck, RulesState};
use crate::core::design::Design;
use crate::core::mask::drc::{DrcReport, Violation, ViolationKind};

/// One ring on the canvas.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleMark {
    /// The rule broken.
    pub kind: ViolationKind,
    /// Where, µm in the tile frame (on the tile's border for one across an edge).
    pub at_um: [f64; 2],
    /// What the hover says: the rule, the value found against the limit, and the place.
    pub text: String,
}

/// The overlay's state: its check and the rings of the current design.
#[derive(Default)]
pub struct RulesOverlay {
    check: RulesCheck,
    marks: Vec<RuleMark>,
    /// What the line under the toolbar says ("checking…", "3 violations", …).
    summary: String,
}

impl RulesOverlay {
    /// The rings on the canvas (none while the check runs or the overlay is off).
    pub fn marks(&self) -> &[RuleMark] {
        &self.marks
    }

    /// Whether the check of the shown design is still running.
    pub fn is_checking(&self) -> bool {
        self.check.is_checking()
    }

    /// Updates the rings for `design` (nothing while `on` is false, so no check runs).
    pub fn update(&mut self, ctx: &egui::Context, design: &Design, on: bool) {
        if !on {
            self.marks.clear();
            self.summary.clear();
            return;
        }
        self.check.update(ctx, design);
        match self.check.state(design) {
            RulesState::Checking => {
                self.marks.clear();
                self.summary = "design rules: checking…".into();
            }
            RulesState::Failed(e) => {
                self.marks.clear();
                self.summary = format!("design rules: not checked ({e})");
            }
            RulesState::Done(report) => {
                self.marks = report.violations.iter().map(|v| mark(report, v)).collect();
                self.summary = summary(report);
            }
        }
    }

    /// The summary line, when the overlay is on.
    pub fn summary_ui(&self, ui: &mut Ui) {
        if self.summary.is_empty() {
            return;
        }
        let color = if self.marks.is_empty() {
            ui.visuals().weak_text_color()
        } else {
            ui.visuals().warn_fg_color
        };
        ui.colored_label(color, &self.summary).on_hover_text(
            "The default rules: 2-µm features and gaps, no cells touching at a corner only, \
             no acute angles. udc-studio drc checks a fab's own rules file.",
        );
    }

    /// Paints the rings on the grid of `pitch_um` drawn at `grid`, and the hover text of the
    /// ring under the pointer.
    pub fn paint(&self, painter: &Painter, grid: Rect, n: usize, pitch_um: f64, hover: &Response) {
        if self.marks.is_empty() || n == 0 || !(pitch_um > 0.0) {
            return;
        }
        let radius = ring_radius(grid, n);
        let red = Stroke::new(2.0, Color32::from_rgb(255, 70, 70));
        for m in &self.marks {
            painter.circle_stroke(screen_pos(grid, pitch_um, m.at_um), radius, red);
        }
        let near = hover.hover_pos().and_then(|p| {
            self.marks
                .iter()
                .find(|m| screen_pos(grid, pitch_um, m.at_um).distance(p) <= radius + 2.0)
        });
        if let Some(m) = near {
            hover.clone().on_hover_text_at_pointer(&m.text);
        }
    }
}

/// Rings a little under a cell wide, readable on a fine grid.
fn ring_radius(grid: Rect, n: usize) -> f32 {
    (0.45 * grid.width() / n as f32).clamp(4.0, 14.0)
}

/// Where `at_um` of the tile frame is on screen, kept on the grid (a stretch that starts in
/// the next tile over is marked on the shared edge).
fn screen_pos(grid: Rect, pitch_um: f64, at_um: [f64; 2]) -> Pos2 {
    let scale = grid.width() as f64 / pitch_um;
    let x = (at_um[0] * scale).clamp(0.0, grid.width() as f64) as f32;
    let y = (at_um[1] * scale).clamp(0.0, grid.height() as f64) as f32;
    grid.min + vec2(x, y)
}

/// The ring of `v`, its hover naming the rule and the value against the limit.
fn mark(report: &DrcReport, v: &Violation) -> RuleMark {
    let r = &report.rules;
    let text = match v.kind {
        ViolationKind::MinFeature => format!(
            "Minimum feature: opening {:.2} µm, limit {:.2} µm\n{}",
            v.value, r.min_feature_um, v.place
        ),
        ViolationKind::MinGap => format!(
            "Minimum gap: chrome {:.2} µm, limit {:.2} µm\n{}",
            v.value, r.min_gap_um, v.place
        ),
        ViolationKind::CornerContact => format!(
            "Corner contact: openings touch at a corner only (0 µm neck), not allowed\n{}",
            v.place
        ),
        ViolationKind::AcuteAngle => format!(
            "Acute angle: {:.1} degrees, limit {:.1} degrees\n{}",
            v.value, r.min_angle_deg, v.place
        ),
    };
    RuleMark {
        kind: v.kind,
        at_um: v.at_um,
        text,
    }
}

/// "design rules: 8 violations (8 corner contacts)" or "design rules: clean".
fn summary(report: &DrcReport) -> String {
    if report.is_clean() {
        return "design rules: clean".into();
    }
    let names = [
        ("narrow opening", "narrow openings"),
        ("narrow gap", "narrow gaps"),
        ("corner contact", "corner contacts"),
        ("acute angle", "acute angles"),
    ];
    let parts: Vec<String> = report
        .counts
        .iter()
        .zip(names)
        .filter(|(c, _)| **c > 0)
        .map(|(c, (one, many))| format!("{c} {}", if *c == 1 { one } else { many }))
        .collect();
    let total = report.total();
    let noun = if total == 1 {
        "violation"
    } else {
        "violations"
    };
    format!("design rules: {total} {noun} ({})", parts.join(", "))
}
