//! The gain controls of the sensor workspace's left panel: the additive-bin gain, the ROI light
//! statistic, and the flat-patch check of eq. 5.3's η (`core::sensor::flat`), which runs on a
//! background thread whenever its inputs or the sensor change.

use egui::Ui;

use crate::app::job::Job;
use crate::core::sensor::binning::read_sigma_e;
use crate::core::sensor::{
    AdditiveGain, BIN_SIZES, BinMode, FlatPatch, FlatPatchSpec, RoiLight, SensorSettings,
    SensorSpec, flat_patch,
};

/// The bin the additive-gain hint quotes numbers for: 2×2 pixels at base gain.
const HINT_BIN_PIXELS: usize = 4;

/// A grid row: the amplifier gain of additive bins, enabled only for additive binning, with the
/// read noise and the light at which a 2×2 sum fills the ADC.
pub(super) fn additive_gain_row(ui: &mut Ui, s: &mut SensorSettings) {
    let additive = s.bin_mode == BinMode::AnalogAdditive;
    ui.label("Additive gain");
    let text = |g: AdditiveGain| match g {
        AdditiveGain::Scaled => "g/N (scaled)",
        AdditiveGain::Same => "g (same)",
    };
    ui.vertical(|ui| {
        ui.add_enabled_ui(additive, |ui| {
            egui::ComboBox::from_id_salt("additive_gain")
                .selected_text(text(s.additive_gain))
                .show_ui(ui, |ui| {
                    ui.selectable_value(
                        &mut s.additive_gain,
                        AdditiveGain::Scaled,
                        text(AdditiveGain::Scaled),
                    )
                    .on_hover_text(
                        "The N-pixel sum is read at g/N: it fills the ADC no sooner than one \
                         pixel at g, and its read noise is sigma_post/g per pixel, as average \
                         binning's (sqrt(N) x digital binning's)",
                    );
                    ui.selectable_value(
                        &mut s.additive_gain,
                        AdditiveGain::Same,
                        text(AdditiveGain::Same),
                    )
                    .on_hover_text(
                        "The sum is read at g like the other modes: the least read noise, \
                         sigma_post/(N g) per pixel (sqrt(N) x below digital's), but the sum \
                         saturates N x sooner, at l_wc/(N g) e- per pixel",
                    );
                });
        })
        .response
        .on_disabled_hover_text("Only additive binning has a choice of gain");
        if additive {
            let sensor = &s.sensor;
            let sigma = read_sigma_e(s.bin_mode, s.additive_gain, sensor, 1.0, HINT_BIN_PIXELS);
            let amp = s
                .bin_mode
                .amplifier_gain(1.0, HINT_BIN_PIXELS, s.additive_gain);
            let full = sensor.full_well_e / (amp * HINT_BIN_PIXELS as f64);
            ui.weak(format!(
                "2x2 at gain 1: read noise {sigma:.2} e-, full at {full:.0} e-/px"
            ));
        }
    });
    ui.end_row();
}

/// A grid row: which snapshot statistic of an ROI sets its gain.
pub(super) fn roi_light_row(ui: &mut Ui, s: &mut SensorSettings) {
    let text = |l: RoiLight| match l {
        RoiLight::Brightest => "brightest 2x2 block",
        RoiLight::P99 => "99th percentile",
        RoiLight::Mean => "mean",
    };
    let hint = |l: RoiLight| match l {
        RoiLight::Brightest => {
            "The ROI's brightest pixels saturate with eq. 5.3's small probability (default)"
        }
        RoiLight::P99 => "A higher gain; the ROI's brightest 1 % may saturate",
        RoiLight::Mean => "The gain for the ROI's typical pixel; brighter parts saturate",
    };
    ui.label("ROI light");
    egui::ComboBox::from_id_salt("roi_light")
        .selected_text(text(s.roi_light))
        .show_ui(ui, |ui| {
            for l in [RoiLight::Brightest, RoiLight::P99, RoiLight::Mean] {
                ui.selectable_value(&mut s.roi_light, l, text(l))
                    .on_hover_text(hint(l));
            }
        })
        .response
        .on_hover_text("The light level that eq. 5.3 sets each ROI's gain for (vary-gain)");
    ui.end_row();
}

/// The flat-patch check: a flat patch at `light_e`, read at eq. 5.3's gain for it with `eta`,
/// in `bin_px` bins of the workspace's binning mode; measured against predicted saturation.
pub struct FlatPatchCheck {
    /// The patch's light level, electrons per unit pixel (the `l̂` of eq. 5.3).
    pub light_e: f64,
    /// η of eq. 5.3.
    pub eta: f64,
    /// Bin side, unit pixels (1, 2, 4 or 8).
    pub bin_px: usize,
    submitted: Option<(FlatPatchSpec, SensorSpec)>,
    job: Option<Job<FlatPatch>>,
    result: Option<(FlatPatchSpec, FlatPatch)>,
    error: Option<String>,
}

impl Default for FlatPatchCheck {
    fn default() -> Self {
        let spec = FlatPatchSpec::default();
        FlatPatchCheck {
            light_e: spec.light_e,
            eta: spec.eta,
            bin_px: spec.bin_px,
            submitted: None,
            job: None,
            result: None,
            error: None,
        }
    }
}

impl FlatPatchCheck {
    fn spec(&self, settings: &SensorSettings) -> FlatPatchSpec {
        FlatPatchSpec {
            light_e: self.light_e,
            eta: self.eta,
            bin_px: self.bin_px,
            bin_mode: settings.bin_mode,
            additive_gain: settings.additive_gain,
            seed: settings.seed,
            ..FlatPatchSpec::default()
        }
    }

    /// The last finished check and what it was run with.
    pub fn result(&self) -> Option<&(FlatPatchSpec, FlatPatch)> {
        self.result.as_ref()
    }

    /// True when no check is running and the shown one (or its error) is for the current inputs.
    pub fn is_up_to_date(&self, settings: &SensorSettings) -> bool {
        self.job.is_none()
            && self.submitted.as_ref().is_some_and(|(spec, sensor)| {
                *spec == self.spec(settings) && *sensor == settings.sensor
            })
    }

    /// Takes a finished check; starts one when the inputs or the sensor changed (dropping a
    /// running one cancels it).
    pub fn poll(&mut self, settings: &SensorSettings, ctx: &egui::Context) {
        if let Some(done) = self.job.as_ref().and_then(Job::poll) {
            self.job = None;
            match done {
                Ok(r) => {
                    if let Some((spec, _)) = &self.submitted {
                        self.result = Some((spec.clone(), r));
                    }
                    self.error = None;
                }
                Err(crate::app::job::JobError::Cancelled) => {}
                Err(e) => self.error = Some(e.to_string()),
            }
        }
        let spec = self.spec(settings);
        let unchanged = self
            .submitted
            .as_ref()
            .is_some_and(|(s, sensor)| *s == spec && *sensor == settings.sensor);
        if unchanged {
            return;
        }
        self.submitted = Some((spec.clone(), settings.sensor.clone()));
        self.job = None;
        if let Err(e) = spec.validate() {
            self.error = Some(e.to_string());
            return;
        }
        let sensor = settings.sensor.clone();
        let wake = ctx.clone();
        self.job = Some(Job::spawn(
            "flat-patch check",
            move || wake.request_repaint(),
            move |p| flat_patch(&spec, &sensor, p),
        ));
    }

    /// The check's inputs and its measured and predicted saturation.
    pub fn ui(&mut self, ui: &mut Ui) {
        ui.label(
            "A flat 512x512 px patch at one light level, read at the gain eq. 5.3 gives for that \
             level: the fraction of readouts that saturate. The thesis's 2.2 % at eta 2 is this \
             per-pixel probability.",
        );
        egui::Grid::new("flat_patch").num_columns(2).show(ui, |ui| {
            ui.label("Light");
            ui.add(
                crate::app::widgets::number(&mut self.light_e)
                    .range(0.0..=1e6)
                    .speed(1.0)
                    .suffix(" e-/px"),
            )
            .on_hover_text("The patch's light level, electrons per unit pixel");
            ui.end_row();
            ui.label("eta");
            ui.add(
                crate::app::widgets::number(&mut self.eta)
                    .range(0.0..=10.0)
                    .speed(0.05),
            )
            .on_hover_text("Eq. 5.3: l_wc = g l + eta g sqrt(l)");
            ui.end_row();
            ui.label("Bin");
            egui::ComboBox::from_id_salt("flat_patch_bin")
                .selected_text(format!("{0}x{0}", self.bin_px))
                .show_ui(ui, |ui| {
                    for b in BIN_SIZES {
                        ui.selectable_value(&mut self.bin_px, b, format!("{b}x{b}"));
                    }
                })
                .response
                .on_hover_text("Bins combine as the Binning mode above says");
            ui.end_row();
        });
        if self.job.is_some() {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("exposing…");
            });
        }
        if let Some(e) = &self.error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        let Some((spec, r)) = &self.result else {
            return;
        };
        egui::Grid::new("flat_patch_result")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("Gain (eq. 5.3)");
                ui.monospace(format!("{:.3}x", r.gain));
                ui.end_row();
                ui.label("Saturated, measured");
                ui.monospace(format!(
                    "{:.2} % ± {:.2}",
                    100.0 * r.saturated_fraction,
                    100.0 * r.standard_error
                ))
                .on_hover_text(format!("{} readouts; ± one standard error", r.readouts));
                ui.end_row();
                ui.label("Saturated, predicted");
                ui.monospace(format!("{:.2} %", 100.0 * r.predicted))
                    .on_hover_text(
                        "The model's own probability: Poisson photons, Gaussian read noise, the \
                         ADC's top code",
                    );
                ui.end_row();
                ui.label("Eq. 5.3's Gaussian");
                ui.monospace(format!("{:.2} %", 100.0 * r.gaussian_tail))
                    .on_hover_text(
                        "1 - Phi(eta): the thesis's approximation, for one pixel at an unclamped \
                         gain; the Poisson tail is a little heavier",
                    );
                ui.end_row();
            });
        if spec.light_e != self.light_e || spec.eta != self.eta || spec.bin_px != self.bin_px {
            ui.weak("(for the previous inputs)");
        }
    }
}
