//! A quick one-dimensional sweep of one number of a design ("sweep this parameter" in the
//! studio): the values to try, a copy of the design with one field changed, the metric each
//! copy scores, and the sweep spec of one axis that runs it ([`spec`]) on the one sweep runner,
//! as `udc-studio sweep` would.

use std::collections::BTreeMap;

use crate::Setting;
use crate::SimError;
use crate::analysis::analyze::Analysis;
use crate::design::{Design, OpticsRecipe};
use crate::figure::{Annotation, Axis, Mark, Panel, Series, palette};
use crate::sweep::{Axis as SweepAxis, ParamValue, SweepJob, SweepSpec};

/// The design numbers a 1-D sweep can change: a closed set, so each one knows its unit, its
/// range and how to write itself into a design.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SweepParameter {
    /// Display pixel pitch, µm (`opening.pitch_um`).
    PitchUm,
    /// Seed of the random tiling (`tiling.seed`), a whole number.
    Seed,
    /// Opaque wiring gap around every pixel, µm (`tiling.wiring_gap_um`).
    WiringGapUm,
    /// Lens f-number (`optics.f_number`).
    FNumber,
    /// Lens focal length, mm (`optics.focal_length_mm`).
    FocalLengthMm,
    /// Sensor pixel pitch, µm (`optics.sensor_pixel_um`).
    SensorPixelUm,
}

impl SweepParameter {
    /// Every sweepable field.
    pub const ALL: [SweepParameter; 6] = [
        SweepParameter::PitchUm,
        SweepParameter::Seed,
        SweepParameter::WiringGapUm,
        SweepParameter::FNumber,
        SweepParameter::FocalLengthMm,
        SweepParameter::SensorPixelUm,
    ];

    /// Its name for titles and axis labels, without the unit.
    pub fn label(self) -> &'static str {
        match self {
            SweepParameter::PitchUm => "pitch",
            SweepParameter::Seed => "tiling seed",
            SweepParameter::WiringGapUm => "wiring gap",
            SweepParameter::FNumber => "f-number",
            SweepParameter::FocalLengthMm => "focal length",
            SweepParameter::SensorPixelUm => "sensor pixel",
        }
    }

    /// Its unit as labels show it ("" for pure numbers).
    pub fn unit(self) -> &'static str {
        match self {
            SweepParameter::PitchUm
            | SweepParameter::WiringGapUm
            | SweepParameter::SensorPixelUm => "µm",
            SweepParameter::FocalLengthMm => "mm",
            SweepParameter::Seed | SweepParameter::FNumber => "",
        }
    }

    /// The label with its unit: "pitch (µm)".
    pub fn label_with_unit(self) -> String {
        match self.unit() {
            "" => self.label().to_string(),
            u => format!("{} ({u})", self.label()),
        }
    }

    /// The job parameter that sets it (the `analyze` flag without `--`).
    pub fn param(self) -> &'static str {
        match self {
            SweepParameter::PitchUm => "pitch-um",
            SweepParameter::Seed => "seed",
            SweepParameter::WiringGapUm => "wiring-gap-um",
            SweepParameter::FNumber => "f-number",
            SweepParameter::FocalLengthMm => "focal-length-mm",
            SweepParameter::SensorPixelUm => "sensor-pixel-um",
        }
    }

    /// A value of it as a sweep parameter: a whole number for the seed.
    pub fn param_value(self, value: f64) -> ParamValue {
        if self.is_integer() && value.fract() == 0.0 && value.abs() < 2f64.powi(53) {
            ParamValue::Int(value as i64)
        } else {
            ParamValue::Float(value)
        }
    }

    /// The design setting it sweeps.
    pub fn setting(self) -> Setting {
        match self {
            SweepParameter::PitchUm => Setting::OpeningPitchUm,
            SweepParameter::Seed => Setting::TilingSeed,
            SweepParameter::WiringGapUm => Setting::TilingWiringGapUm,
            SweepParameter::FNumber => Setting::OpticsFNumber,
            SweepParameter::FocalLengthMm => Setting::OpticsFocalLengthMm,
            SweepParameter::SensorPixelUm => Setting::OpticsSensorPixelUm,
        }
    }

    /// Its path in the design file, as validation errors name it.
    pub fn path(self) -> &'static str {
        self.setting().path()
    }

    /// Whether only whole numbers make sense (the seed).
    pub fn is_integer(self) -> bool {
        self == SweepParameter::Seed
    }

    /// The field's value in `design`.
    pub fn get(self, design: &Design) -> f64 {
        match self {
            SweepParameter::PitchUm => design.opening.pitch_um,
            SweepParameter::Seed => design.tiling.seed as f64,
            SweepParameter::WiringGapUm => design.tiling.wiring_gap_um,
            SweepParameter::FNumber => design.optics.f_number,
            SweepParameter::FocalLengthMm => design.optics.focal_length_mm,
            SweepParameter::SensorPixelUm => design.optics.sensor_pixel_um,
        }
    }

    /// A copy of `design` with this field set to `value`. A changed lens number makes the
    /// optics a custom recipe (as editing it by hand does). A seed that is not a whole
    /// non-negative number is refused here, since the design stores it unsigned; every other
    /// value is left to [`Design::validate`].
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for a negative or fractional seed.
    pub fn apply(self, design: &Design, value: f64) -> Result<Design, SimError> {
        let mut d = design.clone();
        match self {
            SweepParameter::PitchUm => d.opening.pitch_um = value,
            SweepParameter::Seed => {
                if !(value.is_finite() && value >= 0.0 && value.fract() == 0.0) {
                    return Err(SimError::InvalidSetting {
                        path: self.setting().into(),
                        message: format!("{value} is not a whole number of at least 0"),
                    });
                }
                d.tiling.seed = value as u64;
            }
            SweepParameter::WiringGapUm => d.tiling.wiring_gap_um = value,
            SweepParameter::FNumber => d.optics.f_number = value,
            SweepParameter::FocalLengthMm => d.optics.focal_length_mm = value,
            SweepParameter::SensorPixelUm => d.optics.sensor_pixel_um = value,
        }
        if d.optics != design.optics {
            d.optics.recipe = OpticsRecipe::Custom;
        }
        Ok(d)
    }

    /// The range a sweep of this field starts with, around the `current` value: ±50 % with 9
    /// steps; the seed takes the 9 seeds from the current one; a field at 0 (no wiring gap)
    /// sweeps up to a span that means something for it.
    pub fn default_range(self, current: f64) -> (f64, f64, usize) {
        if self.is_integer() {
            return (current, current + 8.0, 9);
        }
        if current == 0.0 {
            let span = match self {
                SweepParameter::WiringGapUm => 10.0,
                _ => 1.0,
            };
            return (0.0, span, 9);
        }
        (0.5 * current, 1.5 * current, 9)
    }
}

/// The number a 1-D sweep plots for each value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SweepMetric {
    /// AUC of the radially-minimum MTF, mean over the channels (`auc_radial_min_mean`).
    AucMean,
    /// AUC of the radially-minimum MTF of one channel, by its index in the design.
    AucChannel(usize),
    /// Light transmittance ratio over the pupil.
    Ltr,
    /// Invertibility loss `L_inv`, pooled over the channels.
    InvertibilityLoss,
}

impl SweepMetric {
    /// The metrics a design offers: the mean AUC, each channel's AUC, LTR and `L_inv`.
    pub fn all_for(design: &Design) -> Vec<SweepMetric> {
        let mut out = vec![SweepMetric::AucMean];
        out.extend((0..design.channels.len()).map(SweepMetric::AucChannel));
        out.extend([SweepMetric::Ltr, SweepMetric::InvertibilityLoss]);
        out
    }

    /// Its name for the combo box and the plot's axis, with the channel's name from `design`.
    pub fn label(self, design: &Design) -> String {
        match self {
            SweepMetric::AucMean => "AUC min, mean of channels".into(),
            SweepMetric::AucChannel(k) => format!(
                "AUC min, {}",
                design.channels.get(k).map_or("?", |c| c.name.as_str())
            ),
            SweepMetric::Ltr => "LTR".into(),
            SweepMetric::InvertibilityLoss => "L_inv".into(),
        }
    }

    /// Its name among an `analyze` job's metrics (the path into its JSON object).
    pub fn column(self, design: &Design) -> String {
        match self {
            SweepMetric::AucMean => "auc_radial_min_mean".into(),
            SweepMetric::AucChannel(k) => format!(
                "channels.{}.auc_radial_min",
                design.channels.get(k).map_or("?", |c| c.name.as_str())
            ),
            SweepMetric::Ltr => "ltr".into(),
            SweepMetric::InvertibilityLoss => "invertibility_loss".into(),
        }
    }

    /// Its value in an analysis (NaN for a channel the analysis lacks).
    pub fn of(self, a: &Analysis) -> f64 {
        match self {
            SweepMetric::AucMean => {
                a.channels.iter().map(|c| c.mtf.auc_radial_min).sum::<f64>()
                    / a.channels.len().max(1) as f64
            }
            SweepMetric::AucChannel(k) => {
                a.channels.get(k).map_or(f64::NAN, |c| c.mtf.auc_radial_min)
            }
            SweepMetric::Ltr => a.ltr,
            SweepMetric::InvertibilityLoss => a.invertibility_loss,
        }
    }
}

/// `steps` values from `from` to `to`, both included (one value: `from`). For a whole-number
/// field the values are rounded and repeats dropped, so a narrow seed range gives fewer
/// points rather than the same seed twice.
pub fn values(from: f64, to: f64, steps: usize, integer: bool) -> Vec<f64> {
    let mut out: Vec<f64> = match steps {
        0 => Vec::new(),
        1 => vec![from],
        n => (0..n)
            .map(|i| from + (to - from) * i as f64 / (n - 1) as f64)
            .collect(),
    };
    if integer {
        for v in &mut out {
            *v = v.round();
        }
        out.dedup();
    }
    out
}

/// What one value of a 1-D sweep gave.
#[derive(Debug, Clone, PartialEq)]
pub enum OneAxisPoint {
    /// The metric's value.
    Value(f64),
    /// The design with this value is invalid or cannot be simulated: the reason, for the note
    /// under the plot (the plot leaves a gap).
    Invalid(String),
}

/// The sweep of one axis behind "sweep this parameter": `analyze` of the design in
/// `design_file` with `field` at each of `values`, keeping `metric`, at preview quality unless
/// `full`. Every value is a point, an invalid one a failed point (a gap in the curve).
pub fn spec(
    design: &Design,
    design_file: &str,
    field: SweepParameter,
    values: &[f64],
    metric: SweepMetric,
    full: bool,
) -> SweepSpec {
    let mut base = BTreeMap::from([("design".to_string(), ParamValue::Text(design_file.into()))]);
    if !full {
        base.insert("preview".into(), ParamValue::Bool(true));
    }
    SweepSpec {
        name: format!("{} against {}", metric.label(design), field.label()),
        job: SweepJob::Analyze,
        base,
        axes: vec![SweepAxis {
            param: field.param().into(),
            values: Some(values.iter().map(|v| field.param_value(*v)).collect()),
            ..SweepAxis::default()
        }],
        metrics: vec![metric.column(design)],
        plots: Vec::new(),
    }
}

/// What a sweep row of [`spec`] says about its value: the metric, or why the value failed.
pub fn point_of(error: &str, metric: f64) -> OneAxisPoint {
    if !error.is_empty() {
        OneAxisPoint::Invalid(error.to_string())
    } else if metric.is_finite() {
        OneAxisPoint::Value(metric)
    } else {
        OneAxisPoint::Invalid("the metric is not a finite number".into())
    }
}

/// The figure of a 1-D sweep: the metric against the parameter, one line per run of valid
/// values (an invalid value is a gap, not a jump), and the design's current value marked.
pub fn panel(
    parameter: SweepParameter,
    metric_label: &str,
    points: &[(f64, Option<OneAxisPoint>)],
    current: f64,
) -> Panel {
    let mut runs: Vec<Vec<[f64; 2]>> = vec![Vec::new()];
    for (x, p) in points {
        match p {
            Some(OneAxisPoint::Value(y)) => {
                if let Some(run) = runs.last_mut() {
                    run.push([*x, *y]);
                }
            }
            Some(OneAxisPoint::Invalid(_)) => runs.push(Vec::new()),
            None => {}
        }
    }
    let unit = match parameter.unit() {
        "" => None,
        u => Some(u),
    };
    Panel {
        title: format!("{metric_label} against {}", parameter.label()),
        x: Axis::new(parameter.label(), unit),
        y: Axis::new(metric_label, None),
        series: runs
            .into_iter()
            .filter(|r| !r.is_empty())
            .map(|points| Series {
                name: metric_label.to_string(),
                colour: palette::series(0),
                mark: Mark::LineAndPoints,
                points,
                band: None,
            })
            .collect(),
        annotations: vec![Annotation::VLine {
            x: current,
            label: "current value".into(),
        }],
        ..Panel::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_include_both_ends_and_round_for_whole_numbers() {
        assert_eq!(values(1.0, 3.0, 5, false), vec![1.0, 1.5, 2.0, 2.5, 3.0]);
        assert_eq!(values(2.0, 9.0, 1, false), vec![2.0]);
        assert!(values(2.0, 9.0, 0, false).is_empty());
        assert_eq!(values(0.0, 2.0, 5, true), vec![0.0, 1.0, 2.0]);
    }

    #[test]
    fn apply_changes_one_field_and_refuses_bad_seeds() {
        let d = Design::default_toled();
        for f in SweepParameter::ALL {
            let v = f.get(&d) + 1.0;
            let changed = f.apply(&d, v).expect("a whole seed");
            assert_eq!(f.get(&changed), v, "{f:?}");
        }
        assert!(SweepParameter::Seed.apply(&d, -1.0).is_err());
        assert!(SweepParameter::Seed.apply(&d, 0.5).is_err());
        let lens = SweepParameter::FNumber.apply(&d, 3.0).expect("any number");
        assert_eq!(lens.optics.recipe, OpticsRecipe::Custom);
    }

    #[test]
    fn default_ranges() {
        assert_eq!(
            SweepParameter::PitchUm.default_range(100.0),
            (50.0, 150.0, 9)
        );
        assert_eq!(SweepParameter::Seed.default_range(3.0), (3.0, 11.0, 9));
        assert_eq!(
            SweepParameter::WiringGapUm.default_range(0.0),
            (0.0, 10.0, 9)
        );
    }

    #[test]
    fn an_invalid_value_splits_the_line_and_the_current_value_is_marked() {
        let points = vec![
            (1.0, Some(OneAxisPoint::Value(0.1))),
            (2.0, Some(OneAxisPoint::Value(0.2))),
            (3.0, Some(OneAxisPoint::Invalid("too small".into()))),
            (4.0, Some(OneAxisPoint::Value(0.4))),
            (5.0, None),
        ];
        let p = panel(SweepParameter::PitchUm, "AUC", &points, 2.0);
        assert_eq!(p.series.len(), 2);
        assert_eq!(p.series[0].points, vec![[1.0, 0.1], [2.0, 0.2]]);
        assert_eq!(p.series[1].points, vec![[4.0, 0.4]]);
        assert_eq!(p.x.unit.as_deref(), Some("µm"));
        assert!(matches!(p.annotations[..], [Annotation::VLine { x, .. }] if x == 2.0));
    }
}
