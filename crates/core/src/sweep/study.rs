//! A study of the design on screen (the studio's New study…): axes picked from the design's own
//! parameters, the metrics to record, and the sweep spec they make ([`Study::spec`]), which the
//! one sweep runner runs and `udc-studio sweep` runs the same. Before anything runs, a study is
//! checked value by value as the command line would check it ([`Study::check`]) and costed by
//! the engine's model ([`Study::estimate`]): the FFT sizes each point's sampling plan needs.

use std::collections::BTreeMap;

use crate::SimError;
use crate::analysis::analyze::Quality;
use crate::design::{Design, TilingMode};
use crate::sweep::one_axis::{SweepMetric, SweepParameter};
use crate::sweep::{Axis as SweepAxis, ParamValue, PlotKind, PlotSpec, SweepJob, SweepSpec};

/// Micrometres in an inch: a display of `d` DPI has a pitch of `25 400 / d` µm.
pub const UM_PER_INCH: f64 = 25_400.0;

/// One axis of a study.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyAxis {
    /// Display pixel densities, DPI (each point's pitch is `25 400 µm / DPI`).
    Dpi(Vec<f64>),
    /// Tilings.
    Tiling(Vec<TilingMode>),
    /// This many seeds of the random tiling, from the design's own.
    Seeds(u64),
    /// One of the design's numbers (the one-axis sweep's fields), at these values.
    Number(SweepParameter, Vec<f64>),
}

impl StudyAxis {
    /// The job parameter the axis sets (its column in the results).
    pub fn param(&self) -> &'static str {
        match self {
            StudyAxis::Dpi(_) => "dpi",
            StudyAxis::Tiling(_) => "tiling",
            StudyAxis::Seeds(_) => "seed",
            StudyAxis::Number(p, _) => p.param(),
        }
    }

    /// How many values it takes.
    pub fn len(&self) -> usize {
        match self {
            StudyAxis::Dpi(v) | StudyAxis::Number(_, v) => v.len(),
            StudyAxis::Tiling(t) => t.len(),
            StudyAxis::Seeds(n) => usize::try_from(*n).unwrap_or(usize::MAX),
        }
    }

    /// Whether it takes no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Its values as sweep parameters, `design`'s seed the first seed.
    fn values(&self, design: &Design) -> Vec<ParamValue> {
        match self {
            StudyAxis::Dpi(v) => v.iter().map(|d| ParamValue::Float(*d)).collect(),
            StudyAxis::Tiling(t) => t
                .iter()
                .map(|m| ParamValue::Text(m.as_str().into()))
                .collect(),
            StudyAxis::Seeds(n) => (0..*n)
                .map(|k| ParamValue::Int(design.tiling.seed.saturating_add(k) as i64))
                .collect(),
            StudyAxis::Number(p, v) => v.iter().map(|x| p.param_value(*x)).collect(),
        }
    }

    /// `design` at each of the axis's values that changes how much work a point is (the
    /// DPI and the lens numbers; a tiling or a seed costs the same).
    fn variants(&self, design: &Design) -> Vec<Result<Design, SimError>> {
        match self {
            StudyAxis::Dpi(v) => v
                .iter()
                .map(|dpi| {
                    let mut d = design.clone();
                    d.opening.pitch_um = UM_PER_INCH / dpi;
                    Ok(d)
                })
                .collect(),
            StudyAxis::Number(p, v) => v.iter().map(|x| p.apply(design, *x)).collect(),
            StudyAxis::Tiling(_) | StudyAxis::Seeds(_) => Vec::new(),
        }
    }
}

/// A study: its axes (their Cartesian product are the points), the metrics recorded and the
/// sampling quality.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// The axes, the last varying fastest.
    pub axes: Vec<StudyAxis>,
    /// The metrics recorded for every point.
    pub metrics: Vec<SweepMetric>,
    /// Full quality (the thesis's numbers) instead of the interactive preview.
    pub full: bool,
}

/// What a study is expected to cost before it runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudyEstimate {
    /// The points.
    pub points: u64,
    /// Seconds to run them all on this machine, one after another (the runner shares them
    /// among the cores).
    pub seconds: f64,
    /// Working memory of the largest point, bytes.
    pub bytes_per_point: u64,
}

/// Modelled work of one analysis: the column transforms of every sampled wavelength, the
/// dominant term of the PSF route's cost (`psf::route`), in complex multiply-adds.
fn work(design: &Design, quality: Quality) -> Result<(f64, u64), SimError> {
    let mut warnings = Vec::new();
    let plan = quality.plan(design, &mut warnings)?;
    let mut ops = 0.0;
    let mut largest = 0usize;
    for s in plan.iter().flatten() {
        let m = s.fft_size;
        let mf = m as f64;
        ops += (m / 2 + 1) as f64 * (crate::psf::zoom::fft_ops(m) + 3.0 * mf) + 8.0 * mf * mf;
        largest = largest.max(m);
    }
    // One complex field of the largest FFT size and its transform.
    let bytes = 2 * 16 * (largest as u64).pow(2);
    Ok((ops, bytes))
}

impl Study {
    /// The number of points (saturating).
    pub fn points(&self) -> u64 {
        self.axes
            .iter()
            .fold(1u64, |n, a| n.saturating_mul(a.len() as u64))
    }

    fn quality(&self) -> Quality {
        if self.full {
            Quality::Full
        } else {
            Quality::Preview
        }
    }

    /// Checks the study before it runs: at least one axis and metric, no empty axis, no axis
    /// twice, and every value a design the studio accepts (as `udc-studio sweep` refuses a
    /// spec).
    ///
    /// # Errors
    /// The first problem, naming the axis and the value.
    pub fn check(&self, design: &Design) -> Result<(), SimError> {
        let bad = |what: &str, message: String| Err(SimError::invalid(what, message));
        if self.axes.is_empty() {
            return bad("axes", "add an axis to vary".into());
        }
        if self.metrics.is_empty() {
            return bad("metrics", "pick at least one metric to record".into());
        }
        for (i, a) in self.axes.iter().enumerate() {
            if a.is_empty() {
                return bad(a.param(), "has no value".into());
            }
            if self.axes[..i].iter().any(|b| b.param() == a.param()) {
                return bad(a.param(), "is an axis twice".into());
            }
            if let StudyAxis::Dpi(v) = a
                && let Some(d) = v.iter().find(|d| !(d.is_finite() && **d > 0.0))
            {
                return bad(
                    "dpi",
                    format!("{d} is not a positive number of dots per inch"),
                );
            }
            for d in a.variants(design) {
                let d = d.map_err(|e| SimError::invalid(a.param(), e.to_string()))?;
                d.validate()
                    .map_err(|e| SimError::invalid(a.param(), e.to_string()))?;
            }
        }
        if self.points() > crate::sweep::spec::MAX_POINTS {
            return bad("axes", format!("{} points is too many", self.points()));
        }
        Ok(())
    }

    /// The sweep spec of the study of `design`, saved beside it as `design_file`: `analyze`
    /// of every point with the axes' values, the metrics' columns, and plots of the first
    /// metric against the first axis (one line per tiling, the spread over the seeds) and
    /// the AUC–LTR Pareto front.
    pub fn spec(&self, design: &Design, design_file: &str) -> SweepSpec {
        let mut base =
            BTreeMap::from([("design".to_string(), ParamValue::Text(design_file.into()))]);
        if !self.full {
            base.insert("preview".into(), ParamValue::Bool(true));
        }
        let axes: Vec<SweepAxis> = self
            .axes
            .iter()
            .map(|a| SweepAxis {
                param: a.param().into(),
                values: Some(a.values(design)),
                ..SweepAxis::default()
            })
            .collect();
        let metrics: Vec<String> = self.metrics.iter().map(|m| m.column(design)).collect();
        let has = |p: &str| self.axes.iter().any(|a| a.param() == p);
        let x = self
            .axes
            .iter()
            .find(|a| !matches!(a, StudyAxis::Seeds(_) | StudyAxis::Tiling(_)))
            .or(self.axes.first())
            .map(|a| a.param().to_string())
            .unwrap_or_default();
        let mut plots = Vec::new();
        if let Some(y) = metrics.first() {
            plots.push(PlotSpec {
                kind: PlotKind::MetricVsAxis,
                x: x.clone(),
                y: y.clone(),
                group: (has("tiling") && x != "tiling").then(|| "tiling".into()),
                spread: (has("seed") && x != "seed").then(|| "seed".into()),
                x_smaller_is_better: false,
            });
        }
        let auc = SweepMetric::AucMean.column(design);
        let ltr = SweepMetric::Ltr.column(design);
        if metrics.contains(&auc) && metrics.contains(&ltr) {
            plots.push(PlotSpec {
                kind: PlotKind::Pareto,
                x: ltr,
                y: auc,
                group: None,
                spread: None,
                x_smaller_is_better: false,
            });
        }
        SweepSpec {
            name: format!(
                "{} over {}",
                if design.name.is_empty() {
                    "the design"
                } else {
                    design.name.as_str()
                },
                self.axes
                    .iter()
                    .map(StudyAxis::param)
                    .collect::<Vec<_>>()
                    .join(" × ")
            ),
            job: SweepJob::Analyze,
            base,
            axes,
            metrics,
            plots,
        }
    }

    /// The study's cost before it runs, from the engine's model: each axis value's work
    /// (the FFT sizes of its sampling plan) relative to the design's, times the time one
    /// analysis of the design took here (`reference_ms` at `reference_quality`, scaled by the
    /// model to the study's quality).
    ///
    /// # Errors
    /// A value whose sampling cannot be planned.
    pub fn estimate(
        &self,
        design: &Design,
        reference_ms: f64,
        reference_quality: Quality,
    ) -> Result<StudyEstimate, SimError> {
        let q = self.quality();
        let (base_ops, base_bytes) = work(design, q)?;
        let (reference_ops, _) = work(design, reference_quality)?;
        let mut ratio = base_ops / reference_ops.max(1.0);
        let mut bytes = base_bytes;
        for a in &self.axes {
            let variants = a.variants(design);
            if variants.is_empty() {
                continue;
            }
            let mut sum = 0.0;
            for d in &variants {
                let d = d
                    .as_ref()
                    .map_err(|e| SimError::invalid(a.param(), e.to_string()))?;
                let (ops, b) = work(d, q)?;
                sum += ops / base_ops.max(1.0);
                bytes = bytes.max(b);
            }
            ratio *= sum / variants.len() as f64;
        }
        let points = self.points();
        Ok(StudyEstimate {
            points,
            seconds: points as f64 * ratio * reference_ms.max(0.0) / 1e3,
            bytes_per_point: bytes,
        })
    }
}

/// Values as a designer types them: a list (`80, 150, 300, 600`) or `from:to:count`
/// (`80:600:5`, both ends included).
///
/// # Errors
/// Text that is neither, a count below 1 or above [`crate::sweep::spec::MAX_AXIS_VALUES`], a
/// value that is not a finite number.
pub fn parse_values(text: &str) -> Result<Vec<f64>, String> {
    let number = |s: &str| -> Result<f64, String> {
        let s = s.trim();
        s.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{s:?} is not a number"))
    };
    let parts: Vec<&str> = text.split(':').collect();
    match parts.as_slice() {
        [from, to, count] => {
            let (from, to) = (number(from)?, number(to)?);
            let n: usize = count
                .trim()
                .parse()
                .map_err(|_| format!("{:?} is not a count of values", count.trim()))?;
            if !(1..=crate::sweep::spec::MAX_AXIS_VALUES).contains(&n) {
                return Err(format!(
                    "{n} values: give 1 to {}",
                    crate::sweep::spec::MAX_AXIS_VALUES
                ));
            }
            Ok(crate::sweep::one_axis::values(from, to, n, false))
        }
        [_] => {
            let v: Vec<f64> = text
                .split([',', ' ', ';'])
                .filter(|s| !s.trim().is_empty())
                .map(number)
                .collect::<Result<_, _>>()?;
            if v.is_empty() {
                Err("no value: list them (80, 150, 300) or give from:to:count".into())
            } else {
                Ok(v)
            }
        }
        _ => Err(format!(
            "{text:?}: list values (80, 150, 300) or give from:to:count (80:600:5)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiling_study() -> Study {
        Study {
            axes: vec![
                StudyAxis::Dpi(vec![150.0, 300.0, 600.0]),
                StudyAxis::Tiling(vec![TilingMode::Repeat, TilingMode::RandomD4]),
                StudyAxis::Seeds(3),
            ],
            metrics: vec![SweepMetric::AucMean, SweepMetric::Ltr],
            full: false,
        }
    }

    #[test]
    fn a_study_is_the_product_of_its_axes_and_plots_each_tiling_with_its_seed_spread() {
        let d = Design::default_toled();
        let s = tiling_study();
        assert_eq!(s.points(), 18);
        s.check(&d).expect("a valid study");
        let spec = s.spec(&d, "design.json");
        spec.validate().expect("a valid spec");
        assert_eq!(
            crate::sweep::Points::new(&spec).expect("points").count(),
            18
        );
        assert_eq!(spec.axes[2].values.as_ref().map(Vec::len), Some(3));
        let first_seed = spec.axes[2]
            .values
            .as_ref()
            .and_then(|v| v.first().cloned());
        assert_eq!(first_seed, Some(ParamValue::Int(d.tiling.seed as i64)));
        let p = &spec.plots[0];
        assert_eq!(
            (p.x.as_str(), p.group.as_deref(), p.spread.as_deref()),
            ("dpi", Some("tiling"), Some("seed"))
        );
        assert_eq!(spec.plots[1].kind, PlotKind::Pareto);
        assert_eq!(spec.base.get("preview"), Some(&ParamValue::Bool(true)));
    }

    #[test]
    fn bad_studies_are_refused_naming_the_axis() {
        let d = Design::default_toled();
        let mut s = tiling_study();
        s.axes[0] = StudyAxis::Dpi(vec![150.0, -3.0]);
        assert!(s.check(&d).unwrap_err().to_string().contains("dpi"));
        s.axes[0] = StudyAxis::Number(SweepParameter::FNumber, vec![2.0, 0.0]);
        let e = s.check(&d).unwrap_err().to_string();
        assert!(e.contains("f-number"), "{e}");
        s.axes[0] = StudyAxis::Seeds(2);
        assert!(s.check(&d).unwrap_err().to_string().contains("twice"));
        s.axes.clear();
        assert!(s.check(&d).is_err());
    }

    #[test]
    fn finer_displays_cost_more_by_the_model_and_tilings_cost_the_same() {
        let d = Design::default_toled();
        let one = |axis| Study {
            axes: vec![axis],
            metrics: vec![SweepMetric::AucMean],
            full: false,
        };
        let coarse = one(StudyAxis::Dpi(vec![d.opening.dpi()]))
            .estimate(&d, 100.0, Quality::Preview)
            .expect("costed");
        assert!((coarse.seconds - 0.1).abs() < 1e-9, "{coarse:?}");
        let tilings = one(StudyAxis::Tiling(TilingMode::ALL.to_vec()))
            .estimate(&d, 100.0, Quality::Preview)
            .expect("costed");
        assert!((tilings.seconds - 0.3).abs() < 1e-9, "{tilings:?}");
        let fine = one(StudyAxis::Dpi(vec![4.0 * d.opening.dpi()]))
            .estimate(&d, 100.0, Quality::Preview)
            .expect("costed");
        assert!(fine.seconds >= coarse.seconds, "{fine:?} vs {coarse:?}");
        assert!(fine.bytes_per_point >= coarse.bytes_per_point);
    }

    #[test]
    fn values_parse_as_lists_or_ranges() {
        assert_eq!(
            parse_values("80, 150 300").unwrap(),
            vec![80.0, 150.0, 300.0]
        );
        assert_eq!(parse_values("1:3:3").unwrap(), vec![1.0, 2.0, 3.0]);
        for bad in ["", "1:2", "a, 2", "1:2:0", "nan", "1:2:x"] {
            assert!(parse_values(bad).is_err(), "{bad:?}");
        }
    }
}
