//! What every plot of the studio shares: tick marks on a 1-2-5 ladder, so an axis is labelled
//! at any width (egui_plot's default powers of ten leave a narrow plot with only "0"), and a
//! legend drawn outside the plot, so no curve hides behind the legend box.

use std::collections::BTreeSet;

use egui::{Color32, Id, Sense, Shape, Stroke, Ui, pos2, vec2};
use egui_plot::{AxisHints, GridInput, GridMark};

/// Which axis a grid is for: the x axis's labels are wide, so they need more room apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TickAxis {
    /// Horizontal axis: labels at least 50 points apart (room for "−1000" or "0.25").
    X,
    /// Vertical axis: labels at least 30 points apart (one line of text and a gap).
    Y,
}

impl TickAxis {
    /// The spacing from which egui_plot draws a label at full strength; it fades labels in
    /// from 10 points closer.
    fn label_spacing_points(self) -> f32 {
        match self {
            TickAxis::X => 50.0,
            TickAxis::Y => 30.0,
        }
    }
}

/// The smallest of 1, 2, 5 × 10ᵏ that is at least `v` (0 for a non-positive or non-finite `v`).
pub fn next_nice(v: f64) -> f64 {
    if !(v > 0.0) || !v.is_finite() {
        return 0.0;
    }
    let decade = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|s| *s >= v * (1.0 - 1e-12))
        .unwrap_or(10.0 * decade)
}

/// Grid marks for `input`: thin lines at the finest 1-2-5 step egui_plot allows and labelled
/// lines at the 1-2-5 step that keeps the labels of `axis` apart.
pub fn nice_marks(input: &GridInput, axis: TickAxis) -> Vec<GridMark> {
    // `base_step_size` is the value spanned by egui_plot's minimum grid spacing, 8 points.
    let base = input.base_step_size;
    let fine = next_nice(base);
    let labelled = next_nice(base * f64::from(axis.label_spacing_points()) / 8.0);
    if !(fine > 0.0 && labelled > 0.0) {
        return Vec::new();
    }
    let (lo, hi) = input.bounds;
    let mut marks = Vec::new();
    for step in [fine, labelled] {
        let first = (lo / step).ceil() as i64;
        let last = (hi / step).floor() as i64;
        // Bounds so wide that the steps would not fit are not worth a grid.
        if last.saturating_sub(first) > 10_000 {
            continue;
        }
        marks.extend((first..=last).map(|i| GridMark {
            value: i as f64 * step,
            step_size: step,
        }));
    }
    marks.sort_by(|a, b| a.value.total_cmp(&b.value));
    // A labelled mark and a fine one at the same value (3 × 0.1 and 30 × 0.01 differ in the
    // last bit, in either order): keep the labelled one.
    let mut out: Vec<GridMark> = Vec::with_capacity(marks.len());
    for m in marks {
        match out.last_mut() {
            Some(last) if (m.value - last.value).abs() < 0.1 * fine => {
                if m.step_size > last.step_size {
                    *last = m;
                }
            }
            _ => out.push(m),
        }
    }
    out
}

/// The width left in `ui` up to the edge of what is visible: a row above that ran past a
/// panel's edge widens the `Ui` for everything below it, and a plot sized to that would hide
/// its right-hand side.
pub fn visible_width(ui: &Ui) -> f32 {
    ui.available_width()
        .min(ui.clip_rect().right() - ui.cursor().left())
        .max(0.0)
}

/// A tick label with as many decimals as the step needs: 0.5, 0.25, 200 (egui_plot's own
/// rounds the decimals of a step of 0.5 to none and labels 0.5 "0").
fn tick_label(mark: GridMark, _range: &std::ops::RangeInclusive<f64>) -> String {
    let step = mark.step_size.abs();
    let decimals = if step > 0.0 && step.is_finite() {
        (-step.log10() - 1e-9).ceil().clamp(0.0, 12.0) as usize
    } else {
        0
    };
    egui::emath::format_with_decimals_in_range(mark.value, decimals..=decimals)
}

/// The plot with 1-2-5 ticks on both axes, each labelled at full strength (set the axis
/// titles after this call: it replaces the axes).
pub fn with_nice_ticks(plot: egui_plot::Plot<'_>) -> egui_plot::Plot<'_> {
    let axis = |hints: AxisHints<'static>, a: TickAxis| {
        let full = a.label_spacing_points();
        hints
            .label_spacing(full - 10.0..=full)
            .formatter(tick_label)
    };
    plot.custom_x_axes(vec![axis(AxisHints::new_x(), TickAxis::X)])
        .custom_y_axes(vec![axis(AxisHints::new_y(), TickAxis::Y)])
        .x_grid_spacer(|input| nice_marks(&input, TickAxis::X))
        .y_grid_spacer(|input| nice_marks(&input, TickAxis::Y))
}

/// How an entry's curves are drawn, for the sample beside its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Swatch {
    /// A solid line of the given width in points.
    Solid(u8),
    /// A dashed line.
    Dashed,
    /// A dotted line.
    Dotted,
    /// A single marker.
    Marker,
}

/// One legend entry: the name its plot items carry, their colour and line style.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendEntry {
    /// The plot items' name; clicking the entry hides or shows every item of this name.
    pub name: String,
    /// The items' colour.
    pub color: Color32,
    /// The items' line style.
    pub swatch: Swatch,
}

impl LegendEntry {
    /// An entry named `name`.
    pub fn new(name: impl Into<String>, color: Color32, swatch: Swatch) -> Self {
        LegendEntry {
            name: name.into(),
            color,
            swatch,
        }
    }
}

/// The names clicked off in the legend `id` (kept in egui's memory, so the plot drawn before
/// the legend in a frame knows what to leave out).
pub fn hidden_names(ctx: &egui::Context, id: Id) -> BTreeSet<String> {
    ctx.data(|d| d.get_temp::<BTreeSet<String>>(id))
        .unwrap_or_default()
}

/// The legend outside the plot: one wrapped row per group (a channel, a design), each entry a
/// line sample and its name; a click hides or shows the entry's curves.
pub fn legend_ui(ui: &mut Ui, id: Id, groups: &[Vec<LegendEntry>]) {
    let mut hidden = hidden_names(ui.ctx(), id);
    let before = hidden.clone();
    let row_h = ui.text_style_height(&egui::TextStyle::Body);
    let font = egui::TextStyle::Body.resolve(ui.style());
    for group in groups.iter().filter(|g| !g.is_empty()) {
        ui.horizontal_wrapped(|ui| {
            let mut row_start = true;
            for e in group {
                // An entry is never split between rows: it moves to the next row whole.
                let text_w = ui
                    .painter()
                    .layout_no_wrap(e.name.clone(), font.clone(), Color32::WHITE)
                    .size()
                    .x;
                let need = 22.0 + ui.spacing().item_spacing.x + text_w;
                if !row_start && visible_width(ui) < need {
                    ui.end_row();
                }
                row_start = false;
                let off = hidden.contains(&e.name);
                let color = if off {
                    e.color.gamma_multiply(0.25)
                } else {
                    e.color
                };
                let (rect, _) = ui.allocate_exact_size(vec2(22.0, row_h), Sense::hover());
                let (a, b) = (
                    pos2(rect.left() + 1.0, rect.center().y),
                    pos2(rect.right() - 1.0, rect.center().y),
                );
                let painter = ui.painter();
                match e.swatch {
                    Swatch::Solid(w) => {
                        painter.line_segment([a, b], Stroke::new(f32::from(w.max(1)), color));
                    }
                    Swatch::Dashed => {
                        painter.extend(Shape::dashed_line(
                            &[a, b],
                            Stroke::new(1.5, color),
                            4.0,
                            3.0,
                        ));
                    }
                    Swatch::Dotted => {
                        painter.extend(Shape::dotted_line(&[a, b], color, 4.0, 1.0));
                    }
                    Swatch::Marker => {
                        painter.circle_filled(rect.center(), 3.5, color);
                    }
                }
                let text = if off {
                    egui::RichText::new(&e.name).weak().strikethrough()
                } else {
                    egui::RichText::new(&e.name)
                };
                let tip = if off {
                    "Click to show these curves again"
                } else {
                    "Click to hide these curves"
                };
                if ui
                    .add(
                        egui::Label::new(text)
                            .wrap_mode(egui::TextWrapMode::Extend)
                            .sense(Sense::click()),
                    )
                    .on_hover_text(tip)
                    .clicked()
                    && !hidden.remove(&e.name)
                {
                    hidden.insert(e.name.clone());
                }
                ui.add_space(6.0);
            }
        });
    }
    if hidden != before {
        ui.ctx().data_mut(|d| d.insert_temp(id, hidden));
        ui.ctx().request_repaint();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_keep_the_decimals_of_their_step() {
        let label =
            |value: f64, step_size: f64| tick_label(GridMark { value, step_size }, &(0.0..=1.0));
        assert_eq!(label(0.5, 0.5), "0.5");
        assert_eq!(label(0.25, 0.05), "0.25");
        assert_eq!(label(0.2, 0.1), "0.2");
        assert_eq!(label(200.0, 200.0), "200");
        assert_eq!(label(0.30000000000000004, 0.1), "0.3");
    }

    #[test]
    fn nice_steps_follow_one_two_five() {
        assert_eq!(next_nice(0.7), 1.0);
        assert_eq!(next_nice(1.0), 1.0);
        assert_eq!(next_nice(1.3), 2.0);
        assert_eq!(next_nice(3.0), 5.0);
        assert_eq!(next_nice(6.0), 10.0);
        assert!((next_nice(0.013) - 0.02).abs() < 1e-15);
        assert_eq!(next_nice(0.0), 0.0);
        assert_eq!(next_nice(f64::NAN), 0.0);
    }

    /// The expected PSF's plot at 1024×700: 190 points for ±300 µm. egui_plot's powers of ten
    /// label only 0 there (100 µm is 32 points, 1000 µm is off the plot); the 1-2-5 ladder
    /// labels every 200 µm, 63 points apart.
    #[test]
    fn a_narrow_plot_still_gets_labelled_ticks() {
        let points_per_um = 190.0 / 600.0;
        let input = GridInput {
            bounds: (-300.0, 300.0),
            base_step_size: 8.0 / points_per_um,
        };
        let marks = nice_marks(&input, TickAxis::X);
        let labelled: Vec<f64> = marks
            .iter()
            .filter(|m| m.step_size * points_per_um >= 50.0)
            .map(|m| m.value)
            .collect();
        assert_eq!(labelled, vec![-200.0, 0.0, 200.0]);
        // Every labelled mark is kept once, with its larger step, even where the two steps'
        // multiples differ in the last bit (3 × 0.1 ≠ 15 × 0.02).
        let mtf = GridInput {
            bounds: (0.0, 0.5),
            base_step_size: 0.012,
        };
        let marks = nice_marks(&mtf, TickAxis::X);
        let labelled: Vec<f64> = marks
            .iter()
            .filter(|m| m.step_size > 0.05)
            .map(|m| (m.value * 10.0).round())
            .collect();
        assert_eq!(labelled, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(marks.len(), 26);
        assert!(
            nice_marks(
                &GridInput {
                    bounds: (0.0, 1.0),
                    base_step_size: 0.0
                },
                TickAxis::Y
            )
            .is_empty()
        );
    }
}
