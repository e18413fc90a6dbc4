//! The sweep spec: a base, axes over the job's parameters, the metrics to keep and the plots to
//! draw. Read from TOML or JSON by `io::sweep`; checked here so every front end refuses the same
//! specs with the same message.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::SimError;

/// Most points one sweep may hold (the point index is a `u64`; this keeps shard arithmetic and
/// the progress bar sane, and is far beyond what a cluster runs).
pub const MAX_POINTS: u64 = 1 << 40;
/// Most values one axis may list or generate.
pub const MAX_AXIS_VALUES: usize = 1_000_000;

/// Which command every point of the sweep runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SweepJob {
    /// `udc-studio analyze`: PSF, MTF, AUC, LTR, invertibility.
    Analyze,
    /// `udc-studio restore`: capture a photo through the display and restore it.
    Restore,
    /// `udc-studio phase psf`: the double microlens array's PSFs against the bare T-OLED.
    PhasePsf,
    /// `udc-studio phase invertibility`: the invertibility matrix V over λ0 and λ.
    PhaseInvertibility,
    /// `udc-studio phase optimize`: folding wavelengths allocated to lenslets (Algorithm 1).
    PhaseOptimize,
    /// `udc-studio phase restore`: a photo through the phase masks, restored.
    PhaseRestore,
    /// `udc-studio sensor`: spatially-varying gain and binning on an HDR scene.
    Sensor,
    /// `udc-studio sensor flat-patch`: a flat patch read at one gain and bin (Monte Carlo
    /// saturation and Table 5.1's variances).
    SensorFlatPatch,
}

impl SweepJob {
    /// Every job, in the order the docs list them.
    pub const ALL: [SweepJob; 8] = [
        SweepJob::Analyze,
        SweepJob::Restore,
        SweepJob::PhasePsf,
        SweepJob::PhaseInvertibility,
        SweepJob::PhaseOptimize,
        SweepJob::PhaseRestore,
        SweepJob::Sensor,
        SweepJob::SensorFlatPatch,
    ];

    /// The name in spec files (`phase-psf`).
    pub fn as_str(self) -> &'static str {
        match self {
            SweepJob::Analyze => "analyze",
            SweepJob::Restore => "restore",
            SweepJob::PhasePsf => "phase-psf",
            SweepJob::PhaseInvertibility => "phase-invertibility",
            SweepJob::PhaseOptimize => "phase-optimize",
            SweepJob::PhaseRestore => "phase-restore",
            SweepJob::Sensor => "sensor",
            SweepJob::SensorFlatPatch => "sensor-flat-patch",
        }
    }

    /// Whether the job computes PSFs on a chosen backend (its `backend` parameter, the CLI's
    /// `--backend`): the display jobs and the phase jobs whose propagations a device runs.
    pub fn takes_backend(self) -> bool {
        match self {
            SweepJob::Analyze
            | SweepJob::Restore
            | SweepJob::PhasePsf
            | SweepJob::PhaseInvertibility
            | SweepJob::PhaseOptimize
            | SweepJob::PhaseRestore => true,
            SweepJob::Sensor | SweepJob::SensorFlatPatch => false,
        }
    }

    /// The metrics kept when the spec names none: the job's headline numbers (`*` stands for
    /// every channel or strategy name).
    pub fn default_metrics(self) -> &'static [&'static str] {
        match self {
            SweepJob::Analyze => &[
                "auc_radial_min_mean",
                "channels.*.auc_radial_min",
                "ltr",
                "invertibility_loss",
                "open_fraction",
                "channels.*.energy_in_window",
            ],
            SweepJob::Restore => &["runs.0.psnr_db", "runs.0.ssim", "ltr"],
            SweepJob::PhasePsf => &[
                "channels.*.invertibility",
                "channels.*.peak",
                "channels.*.energy_vs_toled",
                "ltr_with_polariser",
                "fov_deg",
            ],
            SweepJob::PhaseInvertibility => &["v.*.*"],
            SweepJob::PhaseOptimize => &[
                "channel_invertibility.*",
                "fixed_530_invertibility.*",
                "uniform_invertibility.*",
            ],
            SweepJob::PhaseRestore => &["runs.*.psnr_db", "runs.*.ssim", "ltr"],
            SweepJob::Sensor => &[
                "strategies.*.worst_roi_ssim",
                "strategies.*.psnr_db",
                "strategies.*.saturated_fraction",
            ],
            SweepJob::SensorFlatPatch => &[
                "variance_e2",
                "table51_variance_e2",
                "variance_standard_error_e2",
                "saturated_fraction",
                "predicted",
            ],
        }
    }
}

/// One parameter value: what a command-line flag takes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ParamValue {
    /// A switch: `true` passes the flag, `false` leaves it out.
    Bool(bool),
    /// A whole number.
    Int(i64),
    /// A real number.
    Float(f64),
    /// A word or a path.
    Text(String),
}

impl ParamValue {
    /// The value as the command line spells it (`168`, `0.5`, `random-4`).
    pub fn to_arg(&self) -> String {
        match self {
            ParamValue::Bool(b) => b.to_string(),
            ParamValue::Int(i) => i.to_string(),
            // The shortest decimal that reads back exactly (`168`, `0.25`); exponent form
            // where Display would spell out hundreds of digits (`1e308`, `1e-300`).
            ParamValue::Float(f) if f.abs() >= 1e15 || (*f != 0.0 && f.abs() < 1e-6) => {
                format!("{f:e}")
            }
            ParamValue::Float(f) => f.to_string(),
            ParamValue::Text(s) => s.clone(),
        }
    }

    /// The value as a number, for plots (`None` for words).
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ParamValue::Int(i) => Some(*i as f64),
            ParamValue::Float(f) => Some(*f),
            ParamValue::Bool(_) | ParamValue::Text(_) => None,
        }
    }
}

/// Evenly spaced values from `start`, `step` apart, up to and including `stop`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangeSpec {
    /// First value.
    pub start: f64,
    /// Last value (included when the steps land on it).
    pub stop: f64,
    /// Spacing; default 1.
    #[serde(default = "one")]
    pub step: f64,
}

fn one() -> f64 {
    1.0
}

/// `count` values evenly spaced from `start` to `stop`, both included.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinspaceSpec {
    /// First value.
    pub start: f64,
    /// Last value.
    pub stop: f64,
    /// How many values (≥ 2, or 1 for `start` alone).
    pub count: usize,
}

/// One axis: a parameter (a flag of the job, without `--`) and its values, listed or generated.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    /// The job's flag, e.g. `pitch-um`, `tiling`, `seed`, `preset`.
    pub param: String,
    /// Listed values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<ParamValue>>,
    /// Generated values `start, start + step, …, ≤ stop` (whole numbers stay whole).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<RangeSpec>,
    /// Generated values, `count` of them from `start` to `stop`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linspace: Option<LinspaceSpec>,
    /// Parameters that change together with this axis, value for value (each list as long as
    /// the axis): a thesis recipe whose settings follow the light level (`with = { lambda =
    /// [0.01, 0.005] }`) is one axis, not a product of two. They enter the point's command line
    /// and hash, not the table's columns.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub with: BTreeMap<String, Vec<ParamValue>>,
    /// The values only name the points (`"T-OLED"`, `"T=5 optimized"`): the parameter is not a
    /// flag and stays off the command line; `with` holds what each value runs. Legends and the
    /// table then read as the thesis names its setups.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub label: bool,
}

/// Which plot to draw beside the results.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlotKind {
    /// A metric against one axis: the mean over `spread` with its min–max band, one line per
    /// value of `group`.
    MetricVsAxis,
    /// The points of two metrics and their Pareto front (both larger-is-better).
    Pareto,
}

/// One plot. For `metric-vs-axis`, `x` is an axis parameter and `y` a metric; for `pareto`,
/// both are metrics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSpec {
    /// What to draw.
    pub kind: PlotKind,
    /// Horizontal: an axis parameter or (Pareto) a metric.
    pub x: String,
    /// Vertical: a metric.
    pub y: String,
    /// An axis whose values become separate lines (metric-vs-axis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    /// An axis the mean and min–max band run over (metric-vs-axis), e.g. `seed`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spread: Option<String>,
    /// For Pareto: whether smaller `x` is better (e.g. a cost); default larger.
    #[serde(default)]
    pub x_smaller_is_better: bool,
}

/// A sweep: the job, the base parameters every point shares, the axes and what to keep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// A name for reports and plot titles.
    #[serde(default)]
    pub name: String,
    /// The command every point runs.
    pub job: SweepJob,
    /// Flags every point passes (without `--`), e.g. `preset = "toled-150dpi"`.
    #[serde(default)]
    pub base: BTreeMap<String, ParamValue>,
    /// The axes; the sweep is their Cartesian product, the last axis varying fastest.
    #[serde(default, rename = "axis")]
    pub axes: Vec<Axis>,
    /// Metrics to keep, as paths into the job's `--json` output (`channels.G.auc_radial_min`,
    /// `*` for every channel); default: the job's headline numbers.
    #[serde(default)]
    pub metrics: Vec<String>,
    /// Plots to draw; default: the first metric against the first axis, and for `analyze` the
    /// Pareto front of AUC and LTR.
    #[serde(default, rename = "plot")]
    pub plots: Vec<PlotSpec>,
}

/// Flags a sweep sets itself, refused in specs.
pub const RESERVED_PARAMS: [&str; 5] = ["json", "out", "help", "version", "max-memory"];

impl SweepSpec {
    /// The spec with its points' PSFs computed on `backend` (the `backend` parameter of a job
    /// that takes one, [`SweepJob::takes_backend`]). The CPU, every job's default, leaves the
    /// spec as written, and its points' hashes with it; so does a spec that already says where
    /// its points run (in its base, on an axis or with one).
    #[must_use]
    pub fn computed_on(mut self, backend: crate::psf::route::Backend) -> SweepSpec {
        let named = self.base.contains_key("backend")
            || self
                .axes
                .iter()
                .any(|a| a.param == "backend" || a.with.contains_key("backend"));
        if backend != crate::psf::route::Backend::Cpu && self.job.takes_backend() && !named {
            self.base
                .insert("backend".into(), ParamValue::Text(backend.to_string()));
        }
        self
    }

    /// The metric patterns in force: the spec's or the job's defaults.
    pub fn metric_patterns(&self) -> Vec<String> {
        if self.metrics.is_empty() {
            self.job
                .default_metrics()
                .iter()
                .map(|s| (*s).to_string())
                .collect()
        } else {
            self.metrics.clone()
        }
    }

    /// Checks the structure: parameter names, axis values, the number of points. Whether the
    /// values suit the job is checked by parsing each as the job's command line.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] naming the offending field (`axis[1].range.step`).
    pub fn validate(&self) -> Result<(), SimError> {
        let bad = |field: String, message: String| SimError::InvalidSetting {
            path: field.into(),
            message,
        };
        let name_ok = is_param_name;
        for (k, v) in &self.base {
            if !name_ok(k) {
                return Err(bad(
                    format!("base.{k}"),
                    "a parameter is a flag of the job without `--`, e.g. `pitch-um`".into(),
                ));
            }
            if RESERVED_PARAMS.contains(&k.as_str()) {
                return Err(bad(
                    format!("base.{k}"),
                    "the sweep sets this itself".into(),
                ));
            }
            check_value(v).map_err(|m| bad(format!("base.{k}"), m.to_string()))?;
        }
        let mut points: u64 = 1;
        for (i, axis) in self.axes.iter().enumerate() {
            let field = |s: &str| format!("axis[{i}]{s}");
            if !name_ok(&axis.param) {
                return Err(bad(
                    field(".param"),
                    format!(
                        "`{}`: a parameter is a flag of the job without `--`, e.g. `pitch-um`",
                        axis.param
                    ),
                ));
            }
            if RESERVED_PARAMS.contains(&axis.param.as_str()) {
                return Err(bad(field(".param"), "the sweep sets this itself".into()));
            }
            if self.axes[..i].iter().any(|a| a.param == axis.param) {
                return Err(bad(
                    field(".param"),
                    format!("`{}` has two axes; merge their values", axis.param),
                ));
            }
            if self.base.contains_key(&axis.param) {
                return Err(bad(
                    field(".param"),
                    format!("`{}` is both in `base` and an axis", axis.param),
                ));
            }
            let len = axis_len(axis).map_err(|(f, m)| bad(field(&f), m))?;
            for (j, v) in axis.values.iter().flatten().enumerate() {
                check_value(v).map_err(|m| bad(field(&format!(".values[{j}]")), m.to_string()))?;
            }
            self.validate_linked(i, len)?;
            points = points.saturating_mul(len as u64);
        }
        if points > MAX_POINTS {
            return Err(bad(
                "axis".into(),
                format!("{points} points: at most {MAX_POINTS} per sweep"),
            ));
        }
        if self.metric_patterns().iter().any(String::is_empty) {
            return Err(bad("metrics".into(), "an empty metric name".into()));
        }
        for (i, p) in self.plots.iter().enumerate() {
            let is_axis = |s: &str| self.axes.iter().any(|a| a.param == s);
            let field = |s: &str| format!("plot[{i}].{s}");
            if p.kind == PlotKind::MetricVsAxis && !is_axis(&p.x) {
                return Err(bad(field("x"), format!("`{}` is not an axis", p.x)));
            }
            for (name, v) in [("group", &p.group), ("spread", &p.spread)] {
                if let Some(a) = v
                    && !is_axis(a)
                {
                    return Err(bad(field(name), format!("`{a}` is not an axis")));
                }
            }
        }
        Ok(())
    }
}

impl SweepSpec {
    /// Checks axis `i`'s linked parameters: flag names no other part of the spec sets, each
    /// with one value per axis value.
    fn validate_linked(&self, i: usize, len: usize) -> Result<(), SimError> {
        let Some(axis) = self.axes.get(i) else {
            return Ok(());
        };
        if axis.label {
            self.validate_label(i)?;
        }
        for (name, values) in &axis.with {
            let field = format!("axis[{i}].with.{name}");
            let bad = |message: String| SimError::InvalidSetting {
                path: field.clone().into(),
                message,
            };
            if !is_param_name(name) {
                return Err(bad(
                    "a parameter is a flag of the job without `--`, e.g. `lambda`".into(),
                ));
            }
            if RESERVED_PARAMS.contains(&name.as_str()) {
                return Err(bad("the sweep sets this itself".into()));
            }
            let elsewhere = self.base.contains_key(name)
                || self.axes.iter().any(|a| &a.param == name)
                || self
                    .axes
                    .iter()
                    .enumerate()
                    .any(|(j, a)| j != i && a.with.contains_key(name));
            if elsewhere {
                return Err(bad(format!(
                    "`{name}` is set elsewhere in the spec (base, an axis or another axis's `with`)"
                )));
            }
            if values.len() != len {
                return Err(bad(format!(
                    "{} values for an axis of {len}: one per axis value",
                    values.len()
                )));
            }
            for (j, v) in values.iter().enumerate() {
                check_value(v).map_err(|m| SimError::InvalidSetting {
                    path: format!("{field}[{j}]").into(),
                    message: m.to_string(),
                })?;
            }
        }
        Ok(())
    }
}

impl SweepSpec {
    /// A label axis: listed values, each naming a different set of `with` parameters (two
    /// labels that ran the same command would be one point).
    fn validate_label(&self, i: usize) -> Result<(), SimError> {
        let Some(axis) = self.axes.get(i) else {
            return Ok(());
        };
        let bad = |f: &str, message: String| SimError::InvalidSetting {
            path: format!("axis[{i}]{f}").into(),
            message,
        };
        let Some(values) = &axis.values else {
            return Err(bad(
                ".label",
                "a label axis lists its `values` (the names of its points)".into(),
            ));
        };
        if axis.with.is_empty() {
            return Err(bad(
                ".with",
                format!(
                    "label axis `{}` runs nothing by itself: give the parameters its values stand for in `with`",
                    axis.param
                ),
            ));
        }
        let run_of = |k: usize| -> Vec<String> {
            axis.with
                .values()
                .map(|v| v.get(k).map(ParamValue::to_arg).unwrap_or_default())
                .collect()
        };
        for k in 0..values.len() {
            for j in 0..k {
                if values[j].to_arg() == values[k].to_arg() {
                    return Err(bad(
                        &format!(".values[{k}]"),
                        format!("`{}` names two points", values[k].to_arg()),
                    ));
                }
                if run_of(j) == run_of(k) {
                    return Err(bad(
                        &format!(".values[{k}]"),
                        format!(
                            "`{}` runs what `{}` runs (the same `with` values)",
                            values[k].to_arg(),
                            values[j].to_arg()
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A parameter is a job's flag without `--`: lowercase words joined by `-`.
fn is_param_name(p: &str) -> bool {
    !p.is_empty()
        && p.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
        && !p.starts_with('-')
}

/// Why a parameter value cannot be passed to a job.
#[derive(Debug, thiserror::Error)]
enum BadValue {
    #[error("{0} is not a finite number")]
    NotFinite(f64),
    #[error("an empty value")]
    Empty,
    #[error("a value with a NUL byte")]
    Nul,
}

fn check_value(v: &ParamValue) -> Result<(), BadValue> {
    match v {
        ParamValue::Float(f) if !f.is_finite() => Err(BadValue::NotFinite(*f)),
        ParamValue::Text(s) if s.is_empty() => Err(BadValue::Empty),
        ParamValue::Text(s) if s.contains('\0') => Err(BadValue::Nul),
        _ => Ok(()),
    }
}

/// How many values an axis has, checked but not generated.
///
/// # Errors
/// As [`axis_values`].
pub fn axis_len(axis: &Axis) -> Result<usize, (String, String)> {
    match (&axis.values, &axis.range, &axis.linspace) {
        (Some(v), None, None) if !v.is_empty() && v.len() <= MAX_AXIS_VALUES => Ok(v.len()),
        (None, Some(r), None) => {
            check_range(r)?;
            Ok(range_len(r))
        }
        (None, None, Some(l)) => {
            check_linspace(l)?;
            Ok(l.count)
        }
        _ => axis_values(axis).map(|v| v.len()),
    }
}

fn range_len(r: &RangeSpec) -> usize {
    (((r.stop - r.start) / r.step + 1e-9).floor() + 1.0) as usize
}

fn check_range(r: &RangeSpec) -> Result<(), (String, String)> {
    let err = |f: &str, m: String| Err((f.to_string(), m));
    if !(r.start.is_finite() && r.stop.is_finite()) {
        return err(".range", "start and stop must be finite".into());
    }
    if !(r.step.is_finite() && r.step > 0.0) {
        return err(".range.step", format!("{}: must be positive", r.step));
    }
    if r.stop < r.start {
        return err(
            ".range.stop",
            format!("{} is below start {}", r.stop, r.start),
        );
    }
    let n = ((r.stop - r.start) / r.step + 1e-9).floor() + 1.0;
    if n > MAX_AXIS_VALUES as f64 {
        return err(".range", format!("{n:e} values: at most {MAX_AXIS_VALUES}"));
    }
    Ok(())
}

fn check_linspace(l: &LinspaceSpec) -> Result<(), (String, String)> {
    if !(l.start.is_finite() && l.stop.is_finite()) {
        return Err((".linspace".into(), "start and stop must be finite".into()));
    }
    if l.count == 0 || l.count > MAX_AXIS_VALUES {
        return Err((
            ".linspace.count".into(),
            format!("{}: between 1 and {MAX_AXIS_VALUES}", l.count),
        ));
    }
    Ok(())
}

/// The values of one axis, listed or generated; errors name the sub-field and say why.
///
/// # Errors
/// `(".range.step", message)` and the like.
pub fn axis_values(axis: &Axis) -> Result<Vec<ParamValue>, (String, String)> {
    let given = [
        axis.values.is_some(),
        axis.range.is_some(),
        axis.linspace.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        return Err((
            String::new(),
            format!(
                "axis `{}` needs exactly one of `values`, `range` or `linspace`",
                axis.param
            ),
        ));
    }
    let err = |f: &str, m: String| Err((f.to_string(), m));
    if let Some(v) = &axis.values {
        if v.is_empty() {
            return err(".values", "no values".into());
        }
        if v.len() > MAX_AXIS_VALUES {
            return err(".values", format!("at most {MAX_AXIS_VALUES} values"));
        }
        return Ok(v.clone());
    }
    if let Some(r) = &axis.range {
        check_range(r)?;
        let n = range_len(r) as f64;
        let whole = [r.start, r.step].iter().all(|v| v.fract() == 0.0);
        return Ok((0..n as usize)
            .map(|k| {
                let v = r.start + k as f64 * r.step;
                if whole {
                    ParamValue::Int(v as i64)
                } else {
                    ParamValue::Float(v)
                }
            })
            .collect());
    }
    if let Some(l) = &axis.linspace {
        check_linspace(l)?;
        let span = l.stop - l.start;
        let d = if l.count > 1 {
            span / (l.count - 1) as f64
        } else {
            0.0
        };
        return Ok((0..l.count)
            .map(|k| ParamValue::Float(l.start + k as f64 * d))
            .collect());
    }
    err("", "no values".into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::psf::route::Backend;

    fn spec(job: SweepJob) -> SweepSpec {
        SweepSpec {
            name: String::new(),
            job,
            base: BTreeMap::from([("preset".into(), ParamValue::Text("toled-150dpi".into()))]),
            axes: vec![Axis {
                param: "seed".into(),
                values: Some(vec![ParamValue::Int(1), ParamValue::Int(2)]),
                ..Axis::default()
            }],
            metrics: Vec::new(),
            plots: Vec::new(),
        }
    }

    #[test]
    fn a_spec_computed_on_a_gpu_says_so_where_its_job_takes_a_backend() {
        let on = |job, backend| spec(job).computed_on(backend).base.get("backend").cloned();
        assert_eq!(
            on(SweepJob::Analyze, Backend::Gpu),
            Some(ParamValue::Text("gpu".into()))
        );
        assert_eq!(
            on(SweepJob::PhasePsf, Backend::Auto),
            Some(ParamValue::Text("auto".into()))
        );
        // The CPU is every job's default: the spec (and its points' hashes) as written.
        assert_eq!(
            spec(SweepJob::Analyze).computed_on(Backend::Cpu),
            spec(SweepJob::Analyze)
        );
        // A job without PSFs takes no backend.
        assert_eq!(on(SweepJob::Sensor, Backend::Gpu), None);
        // A spec that says where its points run keeps it.
        let mut cpu = spec(SweepJob::Analyze);
        cpu.base
            .insert("backend".into(), ParamValue::Text("cpu".into()));
        assert_eq!(cpu.clone().computed_on(Backend::Gpu), cpu);
        let mut swept = spec(SweepJob::Analyze);
        swept.axes[0].with.insert(
            "backend".into(),
            vec![
                ParamValue::Text("cpu".into()),
                ParamValue::Text("gpu".into()),
            ],
        );
        assert_eq!(swept.clone().computed_on(Backend::Gpu), swept);
    }
}
