//! The Compare tab: design A (pinned) and B (current) side by side, named apart even when
//! both carry the same design name, with their numbers and radial-minimum MTFs.

use egui::{Color32, RichText, Ui};

use super::ViewsPanel;
use super::plots::{MtfFamilies, mtf_plot_ui};
use crate::app::display::action::DisplayAction;
use crate::app::display::panels::{PanelCtx, Pinned, Shown};
use crate::core::analysis::analyze::ChannelAnalysis;
use crate::core::{Analysis, Design};

fn display_name(name: &str) -> &str {
    if name.trim().is_empty() {
        "(untitled)"
    } else {
        name
    }
}

/// The parts of the design in which `b` differs from `a`, as the studio's tabs name them.
pub fn edited_parts(a: &Design, b: &Design) -> Vec<&'static str> {
    [
        ("opening", a.opening != b.opening),
        ("tiling", a.tiling != b.tiling),
        ("optics", a.optics != b.optics),
        ("channels", a.channels != b.channels),
    ]
    .into_iter()
    .filter_map(|(part, differs)| differs.then_some(part))
    .collect()
}

/// How A and B are named on screen: the pinned design with the time of the pin, the current
/// one with what was edited since, so the two never read alike, even under one design name.
pub fn captions(pinned: &Pinned, b: &Design) -> (String, String) {
    let a = format!(
        "A: {} (pinned {})",
        display_name(&pinned.design.name),
        pinned.pinned_at
    );
    let parts = edited_parts(&pinned.design, b);
    let state = if !parts.is_empty() {
        format!("current, edited: {}", parts.join(", "))
    } else if pinned.design.name == b.name && *pinned.design == *b {
        "current, same as A".to_owned()
    } else {
        "current".to_owned()
    };
    (a, format!("B: {} ({state})", display_name(&b.name)))
}

impl ViewsPanel {
    pub(super) fn compare_ui(&mut self, ui: &mut Ui, shown: &Shown, ctx: &mut PanelCtx) {
        ui.horizontal(|ui| {
            if ui
                .button("Pin as A")
                .on_hover_text("Ctrl+P: keep the current design's full-quality result as A")
                .clicked()
            {
                ctx.actions.push(DisplayAction::PinCompare);
            }
            if ctx.pinned.is_some() && ui.button("Clear A").clicked() {
                ctx.actions.push(DisplayAction::ClearCompare);
            }
        });
        let Some(pinned) = ctx.pinned else {
            ui.label(
                "Nothing is pinned yet. Press Ctrl+P or \"Pin as A\" to keep the current design \
                 as A; then edit the design (B) and compare the numbers and MTFs here.",
            );
            return;
        };
        let (a, b) = captions(pinned, &shown.design);
        ui.label(a);
        ui.label(b);
        crate::app::display::panels::quality::badge_ui(ui, shown);
        // The table and the plot scroll together in a short window.
        egui::ScrollArea::vertical()
            .id_salt("views_compare_scroll")
            .show(ui, |ui| {
                compare_table_ui(ui, &compare_rows(&pinned.analysis, &shown.analysis));
                ui.separator();
                mtf_plot_ui(
                    ui,
                    "views_compare_mtf",
                    &shown.analysis,
                    Some(&pinned.analysis),
                    MtfFamilies::RADIAL_MIN,
                    None,
                );
            });
    }
}

/// One line of the comparison table.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The quantity, with its channel.
    pub label: String,
    /// A's value, if A has this quantity.
    pub a: Option<f64>,
    /// B's value, if B has this quantity.
    pub b: Option<f64>,
    /// Whether a larger value is the better design (colours the difference).
    pub higher_is_better: bool,
}

impl Row {
    /// `B − A` when both exist.
    pub fn difference(&self) -> Option<f64> {
        Some(self.b? - self.a?)
    }
}

fn row(label: impl Into<String>, a: Option<f64>, b: Option<f64>, higher_is_better: bool) -> Row {
    Row {
        label: label.into(),
        a,
        b,
        higher_is_better,
    }
}

/// The rows of the table. Channels are matched by name; a channel only one design has keeps a
/// blank on the other side.
pub fn compare_rows(a: &Analysis, b: &Analysis) -> Vec<Row> {
    let mut names: Vec<&str> = b.channels.iter().map(|c| c.name.as_str()).collect();
    for c in &a.channels {
        if !names.contains(&c.name.as_str()) {
            names.push(&c.name);
        }
    }
    let mut rows = Vec::new();
    let per_channel = |rows: &mut Vec<Row>, what: &str, f: fn(&ChannelAnalysis) -> f64| {
        for name in &names {
            let va = a.channels.iter().find(|c| c.name == *name).map(f);
            let vb = b.channels.iter().find(|c| c.name == *name).map(f);
            rows.push(row(format!("{name} {what}"), va, vb, true));
        }
    };
    per_channel(&mut rows, "AUC", |c| c.mtf.auc_radial_min);
    per_channel(&mut rows, "AUC normalised", |c| c.mtf.auc_normalised());
    rows.push(row("LTR", Some(a.ltr), Some(b.ltr), true));
    rows.push(row(
        "open fraction",
        Some(a.open_fraction),
        Some(b.open_fraction),
        true,
    ));
    rows.push(row(
        "invertibility loss",
        Some(a.invertibility_loss),
        Some(b.invertibility_loss),
        false,
    ));
    per_channel(&mut rows, "energy in window", |c| c.energy_in_window);
    rows
}

fn cell(v: Option<f64>) -> String {
    v.map_or_else(|| "–".into(), |v| format!("{v:.4}"))
}

/// The table: quantity | A | B | B − A, the difference coloured by which side is better.
pub fn compare_table_ui(ui: &mut Ui, rows: &[Row]) {
    let good = Color32::from_rgb(70, 175, 90);
    let bad = ui.visuals().error_fg_color;
    egui::Grid::new("views_compare_table")
        .striped(true)
        .num_columns(4)
        .spacing([24.0, 4.0])
        .show(ui, |ui| {
            ui.strong("");
            ui.strong("A (pinned)");
            ui.strong("B (current)");
            ui.strong("B − A");
            ui.end_row();
            for r in rows {
                ui.label(&r.label);
                ui.monospace(cell(r.a));
                ui.monospace(cell(r.b));
                match r.difference() {
                    Some(d) => {
                        let text = RichText::new(format!("{d:+.4}")).monospace();
                        // Differences below the printed precision are neither better nor worse.
                        let better = if r.higher_is_better { d } else { -d };
                        if better > 5e-5 {
                            ui.label(text.color(good));
                        } else if better < -5e-5 {
                            ui.label(text.color(bad));
                        } else {
                            ui.label(text);
                        }
                    }
                    None => {
                        ui.monospace("–");
                    }
                }
                ui.end_row();
            }
        });
}

#[cfg(test)]
mod tests {
    use ndarray::Array2;

    use super::*;
    use crate::core::analysis::analyze::Quality;
    use crate::core::analysis::mtf::mtf_of;

    fn channel(name: &str, energy_in_window: f64) -> ChannelAnalysis {
        let mut psf = Array2::zeros((8, 8));
        psf[[4, 4]] = 1.0;
        ChannelAnalysis {
            name: name.into(),
            wavelength_nm: 500.0,
            wavelengths_nm: vec![500.0],
            fft_sizes: vec![16],
            fine_um: 1.0,
            mtf: mtf_of(&psf),
            psf,
            expected_psf: None,
            energy_in_window,
            invertibility: 0.0,
        }
    }

    fn analysis(channels: Vec<ChannelAnalysis>, ltr: f64, loss: f64) -> Analysis {
        Analysis {
            channels,
            open_fraction: 0.5,
            ltr,
            invertibility_loss: loss,
            warnings: Vec::new(),
            elapsed_ms: 0.0,
            quality: Quality::Full,
            window_px: 8,
            sensor_pixel_um: 2.0,
            pupil_diameter_um: 1000.0,
            tiles_in_pupil: 10.0,
        }
    }

    #[test]
    fn a_and_b_are_named_apart_under_one_design_name() {
        let design = Design::default_toled();
        let pinned = Pinned {
            design: std::sync::Arc::new(design.clone()),
            analysis: std::sync::Arc::new(analysis(Vec::new(), 0.2, -0.3)),
            pinned_at: "12:03".into(),
        };
        let name = &design.name;
        let (a, b) = captions(&pinned, &design);
        assert_eq!(a, format!("A: {name} (pinned 12:03)"));
        assert_eq!(b, format!("B: {name} (current, same as A)"));
        let mut edited = design.clone();
        edited.opening.cells[0][0] = 1.0 - edited.opening.cells[0][0];
        edited.tiling.seed += 1;
        let (a2, b2) = captions(&pinned, &edited);
        assert_eq!(a2, a);
        assert_eq!(b2, format!("B: {name} (current, edited: opening, tiling)"));
        let mut renamed = design.clone();
        renamed.name = "mine".into();
        assert_eq!(captions(&pinned, &renamed).1, "B: mine (current)");
        renamed.name = " ".into();
        assert_eq!(captions(&pinned, &renamed).1, "B: (untitled) (current)");
    }

    #[test]
    fn rows_match_channels_by_name_and_difference_is_b_minus_a() {
        let a = analysis(vec![channel("R", 0.9), channel("G", 0.8)], 0.2, -0.3);
        let b = analysis(vec![channel("G", 0.95), channel("B", 0.7)], 0.25, -0.2);
        let rows = compare_rows(&a, &b);
        let get = |label: &str| rows.iter().find(|r| r.label == label).cloned();
        let g = get("G energy in window").expect("G row");
        assert!((g.difference().unwrap_or(0.0) - 0.15).abs() < 1e-12);
        let r = get("R energy in window").expect("R row");
        assert_eq!((r.a, r.b), (Some(0.9), None));
        assert_eq!(r.difference(), None);
        assert_eq!(get("B AUC").and_then(|r| r.a), None);
        let ltr = get("LTR").expect("LTR row");
        assert!((ltr.difference().unwrap_or(0.0) - 0.05).abs() < 1e-12);
        // A lower (more negative) invertibility loss is the better design.
        assert!(
            !get("invertibility loss")
                .expect("loss row")
                .higher_is_better
        );
        // B's channels come first, then those only A has.
        assert_eq!(rows[0].label, "G AUC");
    }
}
