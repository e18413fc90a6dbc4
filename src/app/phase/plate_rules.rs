//! The phase plate's design-rule check for the export panel, on a background job: the panel
//! shows the narrowest ring or step and how many break the default rule before the user
//! exports (the same check `udc-studio drc` and `phase export --strict` run).

use crate::app::job::{Job, JobError, Keyed};
use crate::core::mask::drc::{DrcReport, Rules};
use crate::core::phase::PhaseDesign;
use crate::core::phase::drc::check_plate;

/// The newest check and the one in flight, each with the design it is of.
#[derive(Default)]
pub(super) struct PlateRules {
    running: Keyed<PhaseDesign, DrcReport>,
    done: Option<(PhaseDesign, Result<DrcReport, JobError>)>,
}

impl PlateRules {
    /// Collects a finished check and starts one when `design` changed.
    pub(super) fn update(&mut self, ctx: &egui::Context, design: &PhaseDesign) {
        if let Some((d, result)) = self.running.poll() {
            self.done = Some((d, result));
        }
        let known = |d: &PhaseDesign| d == design;
        if self.done.as_ref().is_some_and(|(d, _)| known(d))
            || self.running.is_running_for(known)
            || design.validate().is_err()
        {
            return;
        }
        let wake = {
            let ctx = ctx.clone();
            move || ctx.request_repaint()
        };
        let d = design.clone();
        let job = Job::spawn("phase-plate rules", wake, move |_| {
            check_plate(&d, &Rules::default())
        });
        self.running.start(design.clone(), job);
    }

    /// One line for the panel, and the hover text listing the first violations.
    pub(super) fn ui(&self, ui: &mut egui::Ui, design: &PhaseDesign) {
        match &self.done {
            Some((d, Ok(r))) if d == design => {
                let rule = r.rules.phase_min_feature_um;
                let narrowest = r
                    .min_feature_um
                    .map_or("none".to_string(), |w| format!("{w:.3} µm"));
                let text = if r.is_clean() {
                    format!("Design rules: clean (narrowest feature {narrowest}, rule {rule} µm)")
                } else {
                    format!(
                        "Design rules: {} features narrower than {rule} µm (narrowest {narrowest})",
                        r.total()
                    )
                };
                let colour = if r.is_clean() {
                    ui.visuals().text_color()
                } else {
                    ui.visuals().warn_fg_color
                };
                let hover: Vec<String> = r
                    .violations
                    .iter()
                    .take(8)
                    .map(|v| format!("{:.3} µm: {}", v.value, v.place))
                    .collect();
                let label = ui.label(egui::RichText::new(text).color(colour));
                if !hover.is_empty() {
                    label.on_hover_text(format!(
                        "{}\n`udc-studio drc` lists them all; `phase export --strict` refuses \
                         to write the plate",
                        hover.join("\n")
                    ));
                }
            }
            Some((d, Err(e))) if d == design => {
                ui.label(format!("Design rules: not checked ({e})"));
            }
            _ => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("Design rules: checking…");
                });
            }
        }
    }
}
