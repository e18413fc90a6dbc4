//! Exports of the plate's height profile (CSV, 16-bit PNG, GDSII, STL): a save dialog on a helper
//! thread, then the write on another, so the UI never waits for either.

use crate::app::notice::Notice;
use std::path::PathBuf;

use egui::Ui;

use super::{PhaseAction, PhaseCtx, PhaseWorkspace};
use crate::app::dialogs::{FileSpec, ask};
use crate::app::job::{Job, Writes};
use crate::core::phase::PhaseDesign;
use crate::io::IoError;
use crate::io::phase::export as phase_export;

pub use crate::io::phase::export::HeightFormat;

/// The exports' parameters (the controls' defaults suit a 42 µm pitch plate).
pub type ExportParams = phase_export::HeightParams;

/// The controls' starting values.
const DEFAULT_PARAMS: ExportParams = ExportParams {
    sample_um: 0.1,
    rows: 16,
    length_um: 100.0,
    base_um: 20.0,
    deterministic: false,
    // The rule the plate check above the buttons applies.
    phase_min_feature_um: crate::core::mask::drc::DEFAULT_PHASE_MIN_FEATURE_UM,
};

pub(super) struct ExportState {
    native_dialogs: bool,
    pub params: ExportParams,
    dialog: Option<(HeightFormat, PhaseDesign, Job<Option<PathBuf>>)>,
    writes: Writes,
    message: Option<Notice>,
    /// The plate's design-rule check, shown above the export buttons.
    pub rules: super::plate_rules::PlateRules,
}

/// Writes one export; the message names the file and what was written.
///
/// # Errors
/// The writer's error, naming the file.
pub fn write_height(
    format: HeightFormat,
    design: &PhaseDesign,
    path: &std::path::Path,
    p: &ExportParams,
) -> Result<String, IoError> {
    let summary = phase_export::write_height(format, design, path, p)?;
    Ok(format!(
        "exported {}: {}",
        path.display(),
        describe(&summary, p.phase_min_feature_um)
    ))
}

/// The numbers of a finished export, for the message line.
/// The numbers of a finished export, for the message line; `rule_um` is the writer's rule the
/// part-level rings were joined under.
fn describe(s: &phase_export::ExportSummary, rule_um: f64) -> String {
    let what = match s.kind {
        HeightFormat::Csv => format!(
            "{} samples every {} µm",
            s.samples.unwrap_or(0),
            s.sample_um.unwrap_or(0.0)
        ),
        HeightFormat::Png => format!(
            "{}×{} px of {} µm, {} levels",
            s.samples.unwrap_or(0),
            s.rows.unwrap_or(0),
            s.pixel_um.unwrap_or(0.0),
            s.levels.unwrap_or(0)
        ),
        HeightFormat::Gds => format!(
            "{}, {}",
            crate::app::widgets::counted(s.layers.len() as f64, "layer", "layers"),
            crate::app::widgets::counted(
                s.rectangles.unwrap_or(0) as f64,
                "rectangle",
                "rectangles"
            )
        ),
        HeightFormat::Stl => format!("{} triangles", s.triangles.unwrap_or(0)),
    };
    let merged = s.ring_merge.map_or(String::new(), |m| {
        format!(
            "; {} joined to the next fold (under the {} µm rule), RMS phase error at λ0 {:.3} → \
             {:.3} rad",
            crate::app::widgets::counted(
                m.merged_rings as f64,
                "part-level ring",
                "part-level rings"
            ),
            rule_um,
            m.model_rms_phase_error_rad,
            m.fabricated_rms_phase_error_rad
        )
    });
    format!(
        "{what}; {:.1} µm wide, up to {:.3} µm high{merged}",
        s.width_um, s.max_height_um
    )
}

impl ExportState {
    pub fn new(native_dialogs: bool) -> Self {
        ExportState {
            native_dialogs,
            params: DEFAULT_PARAMS,
            dialog: None,
            writes: Writes::default(),
            message: None,
            rules: Default::default(),
        }
    }

    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    pub fn is_running(&self) -> bool {
        self.dialog.is_some() || !self.writes.is_empty()
    }

    fn start_write(
        &mut self,
        format: HeightFormat,
        design: PhaseDesign,
        path: PathBuf,
        ctx: &egui::Context,
    ) {
        let params = self.params;
        let wake = ctx.clone();
        self.message = Some(Notice::info(format!("writing {}…", path.display())));
        self.writes.spawn(
            move || wake.request_repaint(),
            move || {
                write_height(format, &design, &path, &params)
                    .map_err(|e| format!("export failed: {e}"))
            },
        );
    }

    pub(super) fn ask(&mut self, format: HeightFormat, design: PhaseDesign, ctx: &egui::Context) {
        if !self.native_dialogs {
            self.message = Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        if self.dialog.is_some() {
            return;
        }
        let wake = ctx.clone();
        let spec = FileSpec::save(
            "Export the phase plate",
            (format.label().trim_end_matches('…'), &[format.extension()]),
            format!("phase-plate.{}", format.extension()),
        );
        let task = ask(spec, move || wake.request_repaint());
        self.dialog = Some((format, design, task));
    }

    /// Takes answered dialogs and finished writes.
    pub fn poll(&mut self, ctx: &egui::Context) {
        if let Some(answer) = self.dialog.as_ref().and_then(|d| d.2.poll())
            && let Some((format, design, _)) = self.dialog.take()
        {
            match answer {
                Ok(Some(path)) => self.start_write(format, design, path, ctx),
                Ok(None) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(report) = self.writes.poll() {
            self.message = Some(report);
        }
    }
}

impl PhaseWorkspace {
    /// Writes the current design's plate to `path` on a background thread (no dialog).
    pub fn export_to(&mut self, format: HeightFormat, path: PathBuf, ctx: &egui::Context) {
        match self.history.current().validate() {
            Ok(()) => self
                .export
                .start_write(format, self.history.current().clone(), path, ctx),
            Err(e) => self.export.message = Some(Notice::error(format!("cannot export: {e}"))),
        }
    }

    /// Asks where to write the plate in `format` (a file dialog), if the design is valid.
    pub(super) fn ask_export(&mut self, format: HeightFormat, ctx: &egui::Context) {
        match self.history.current().validate() {
            Ok(()) => self.export.ask(format, self.history.current().clone(), ctx),
            Err(e) => self.export.message = Some(Notice::error(format!("cannot export: {e}"))),
        }
    }
}

/// The export section of the controls.
pub(super) fn export_ui(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    let egui_ctx = ui.ctx().clone();
    egui::CollapsingHeader::new("Export the plate")
        .id_salt("phase_export")
        .default_open(true)
        .show(ui, |ui| {
            let p = &mut ctx.export.params;
            egui::Grid::new("phase_export_params")
                .num_columns(2)
                .show(ui, |ui| {
                    ui.label("Sample along x");
                    ui.add(
                        crate::app::widgets::number(&mut p.sample_um)
                            .range(0.005..=10.0)
                            .speed(0.005)
                            .suffix(" µm"),
                    );
                    ui.end_row();
                    ui.label("PNG rows");
                    ui.add(
                        crate::app::widgets::number(&mut p.rows)
                            .range(1..=4096)
                            .suffix(" px"),
                    );
                    ui.end_row();
                    ui.label("Length along y");
                    ui.add(
                        crate::app::widgets::number(&mut p.length_um)
                            .range(1.0..=100_000.0)
                            .suffix(" µm"),
                    );
                    ui.end_row();
                    ui.label("STL base");
                    ui.add(
                        crate::app::widgets::number(&mut p.base_um)
                            .range(0.0..=10_000.0)
                            .suffix(" µm"),
                    );
                    ui.end_row();
                });
            let valid = ctx.design.validate().is_ok();
            ctx.export.rules.update(&egui_ctx, ctx.design);
            ctx.export.rules.ui(ui, ctx.design);
            ui.horizontal_wrapped(|ui| {
                for format in HeightFormat::ALL {
                    // GDSII writes one layer per height level: it needs a height step.
                    let stepped =
                        format != HeightFormat::Gds || ctx.design.height_step_um.is_some();
                    if ui
                        .add_enabled(
                            valid && stepped && ctx.export.dialog.is_none(),
                            egui::Button::new(format.label()),
                        )
                        .on_disabled_hover_text(if stepped {
                            "Fix the design first"
                        } else {
                            "Turn on the height step: GDSII has one layer per level"
                        })
                        .clicked()
                    {
                        ctx.queue(PhaseAction::Export(format));
                    }
                }
            });
            if ctx.export.is_running() {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("exporting…");
                });
            }
            crate::app::widgets::message_ui(ui, ctx.export.message.as_ref());
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_message_says_which_rings_were_joined_and_what_it_cost() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("plate.gds");
        let mut design = PhaseDesign::thesis(42.0, 5.0);
        design.lambda0 = crate::core::phase::Lambda0::Fixed { nm: 600.0 };
        design.height_step_um = Some(0.2);
        let p = ExportParams {
            phase_min_feature_um: 0.1,
            ..DEFAULT_PARAMS
        };
        let message = write_height(HeightFormat::Gds, &design, &path, &p).expect("written");
        // T = 5 at 600 nm, 0.2 µm steps: one sliver each side of each of the 58 lenslets.
        assert!(
            message
                .contains("116 part-level rings joined to the next fold (under the 0.1 µm rule)"),
            "{message}"
        );
        assert!(message.contains("RMS phase error at λ0"), "{message}");
        // Without a step there is nothing to join, and the message does not mention it.
        design.height_step_um = None;
        let csv = dir.path().join("plate.csv");
        let message = write_height(HeightFormat::Csv, &design, &csv, &p).expect("written");
        assert!(!message.contains("joined"), "{message}");
    }
}
