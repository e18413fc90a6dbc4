//! The numbers of the Compare tab: design A (pinned) and B (current) side by side.

use egui::{Color32, RichText, Ui};

use crate::core::Analysis;
use crate::core::analyze::ChannelAnalysis;

/// One line of the comparison table.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub label: String,
    pub a: Option<f64>,
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
    use crate::core::analyze::Quality;
    use crate::core::mtf::mtf_of;

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
