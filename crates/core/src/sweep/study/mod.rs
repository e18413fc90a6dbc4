//! A study of the design on screen (the studio's New study…): axes picked from the design's own
//! parameters, the metrics to record, and the sweep spec they make ([`Study::spec`]), which the
//! one sweep runner runs and `udc-studio sweep` runs the same. A display design is analysed
//! (`analyze`), or captured and restored when an axis is a light level or a method
//! (`restore`, on the Restore view's photo); a phase-mask design runs `phase psf`. Before
//! anything runs, a study is checked value by value as the command line would check it
//! ([`Study::check`]) and costed by the engine's model ([`Study::estimate`]).

mod axis;
mod estimate;
mod metric;

use std::collections::BTreeMap;

pub use axis::{StudyAxis, grown, parse_plans, parse_steps, parse_values};
pub use estimate::{StudyEstimate, StudyTimes};
pub use metric::{PHASE_PLOT_CHANNEL, StudyMetric};

use crate::SimError;
use crate::design::Design;
use crate::phase::{Lambda0Plan, PhaseDesign, Surface};
use crate::restore::{CgSettings, Denoise, Sigma2, THESIS_NSR};
use crate::sweep::one_axis::{SweepMetric, SweepParameter};
use crate::sweep::{Axis as SweepAxis, ParamValue, PlotKind, PlotSpec, SweepJob, SweepSpec};

pub use crate::design::UM_PER_INCH;

/// What a study varies.
#[derive(Debug, Clone, PartialEq)]
pub enum StudySubject {
    /// A display layout (the Display workspace's design).
    Display(Box<Design>),
    /// A double-MLA phase-mask design (the Phase workspace's).
    Phase(Box<PhaseDesign>),
}

/// How a restoring study restores: the Restore view's settings besides the photo, the light
/// level and the method (which may be axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestoreSetup {
    /// SNR in dB of the capture when it is not an axis.
    pub snr_db: f64,
    /// The method when it is not an axis.
    pub method: crate::restore::RestoreMethod,
    /// Wiener's noise-to-signal ratio.
    pub nsr: f64,
    /// The gradient penalty of conjugate gradients.
    pub lambda: f64,
    /// The photon and read noise's seed.
    pub noise_seed: u64,
    /// The denoiser before deblurring.
    pub denoise: Denoise,
}

impl Default for RestoreSetup {
    fn default() -> Self {
        RestoreSetup {
            snr_db: 32.0,
            method: crate::restore::RestoreMethod::Wiener,
            nsr: THESIS_NSR,
            lambda: CgSettings::default().lambda,
            noise_seed: 0,
            denoise: Denoise::default(),
        }
    }
}

/// Where a study's inputs are saved (paths the spec names).
#[derive(Debug, Clone, PartialEq)]
pub struct StudyFiles {
    /// The display design's file.
    pub design: String,
    /// The photo a restoring study captures.
    pub photo: Option<String>,
    /// The opening axis's designs, value by value ([`Study::opening_designs`]).
    pub opening_designs: Vec<String>,
}

/// An opening variant's name: its open fraction to 4 decimals.
fn fraction_name(d: &Design) -> f64 {
    (crate::display::opening_ops::open_fraction(&d.opening.cells) * 1e4).round() / 1e4
}

/// A study: what it varies, its axes (their Cartesian product are the points), the metrics
/// recorded and the sampling quality.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// The design varied.
    pub subject: StudySubject,
    /// The axes, the last varying fastest.
    pub axes: Vec<StudyAxis>,
    /// The metrics recorded for every point.
    pub metrics: Vec<StudyMetric>,
    /// Full quality (the thesis's numbers) instead of the interactive preview.
    pub full: bool,
    /// How a restoring study restores.
    pub restore: RestoreSetup,
}

impl Study {
    /// The number of points (saturating).
    pub fn points(&self) -> u64 {
        self.axes
            .iter()
            .fold(1u64, |n, a| n.saturating_mul(a.len() as u64))
    }

    /// The job every point runs: `phase psf` for a phase-mask design, `restore` when an axis
    /// is a light level or a method or a restoration metric is recorded, else `analyze`.
    pub fn job(&self) -> SweepJob {
        match &self.subject {
            StudySubject::Phase(_) => SweepJob::PhasePsf,
            StudySubject::Display(_)
                if self.axes.iter().any(StudyAxis::restores)
                    || self
                        .metrics
                        .iter()
                        .any(|m| matches!(m, StudyMetric::PsnrDb | StudyMetric::Ssim)) =>
            {
                SweepJob::Restore
            }
            StudySubject::Display(_) => SweepJob::Analyze,
        }
    }

    /// The designs of the opening axis, value by value (empty without one): the spec names
    /// them as files ([`StudyFiles::opening_designs`]).
    pub fn opening_designs(&self) -> Vec<Design> {
        match (
            &self.subject,
            self.axes.iter().find_map(|a| match a {
                StudyAxis::Opening(k) => Some(k),
                _ => None,
            }),
        ) {
            (StudySubject::Display(d), Some(steps)) => steps.iter().map(|k| grown(d, *k)).collect(),
            _ => Vec::new(),
        }
    }

    /// Whether the points capture and restore a photo (the spec then names one).
    pub fn needs_photo(&self) -> bool {
        self.job() == SweepJob::Restore
    }

    /// The display design metrics are named by (the phase masks' channels need none).
    fn display_design(&self) -> Design {
        match &self.subject {
            StudySubject::Display(d) => (**d).clone(),
            StudySubject::Phase(_) => Design::default_toled(),
        }
    }

    /// Checks the study before it runs: at least one axis and metric, no empty axis, no axis
    /// twice, every axis and metric one the design's job has, and every value a design the
    /// studio accepts (as `udc-studio sweep` refuses a spec).
    ///
    /// # Errors
    /// The first problem, naming the axis and the value.
    pub fn check(&self) -> Result<(), SimError> {
        let bad = |what: &str, message: String| Err(SimError::invalid(what, message));
        if self.axes.is_empty() {
            return bad("axes", "add an axis to vary".into());
        }
        if self.metrics.is_empty() {
            return bad("metrics", "pick at least one metric to record".into());
        }
        let job = self.job();
        let names = self.display_design();
        if let Some(m) = self.metrics.iter().find(|m| !m.recorded_by(job)) {
            return bad(
                "metrics",
                format!(
                    "{} is not recorded by a {} study",
                    m.label(&names),
                    job.as_str()
                ),
            );
        }
        for (i, a) in self.axes.iter().enumerate() {
            if a.is_empty() {
                return bad(a.param(), "has no value".into());
            }
            if self.axes[..i].iter().any(|b| b.param() == a.param()) {
                return bad(a.param(), "is an axis twice".into());
            }
            self.check_axis(a)?;
        }
        if let StudySubject::Phase(d) = &self.subject {
            check_phase_base(d, &self.axes)?;
        }
        if job == SweepJob::Restore {
            let r = &self.restore;
            if !(r.nsr.is_finite() && r.nsr >= 0.0 && r.lambda.is_finite() && r.lambda > 0.0) {
                return bad(
                    "restore",
                    "the Restore view's NSR or λ is not a usable number".into(),
                );
            }
        }
        if self.points() > crate::sweep::spec::MAX_POINTS {
            return bad("axes", format!("{} points is too many", self.points()));
        }
        Ok(())
    }

    fn check_axis(&self, a: &StudyAxis) -> Result<(), SimError> {
        let bad = |message: String| Err(SimError::invalid(a.param(), message));
        let finite_positive = |v: &[f64], what: &str| {
            v.iter()
                .find(|x| !(x.is_finite() && **x > 0.0))
                .map_or(Ok(()), |x| bad(format!("{x} is not a positive {what}")))
        };
        match (&self.subject, a) {
            (StudySubject::Display(d), _) if a.is_phase() => bad(format!(
                "is a phase-mask axis; {} is a display layout",
                display_name(d)
            )),
            (StudySubject::Phase(_), StudyAxis::Number(SweepParameter::PitchUm, v)) => {
                finite_positive(v, "pitch in µm")?;
                self.check_phase_variants(a)
            }
            (
                StudySubject::Phase(_),
                StudyAxis::Fold(_) | StudyAxis::Lambda0(_) | StudyAxis::OpenRatio(_),
            ) => {
                self.check_phase_variants(a)
            }
            (StudySubject::Phase(_), _) => {
                bad("is not an axis of a phase-mask design (its pitch, fold, λ0 plan or open ratio are)".into())
            }
            (StudySubject::Display(_), StudyAxis::Dpi(v)) => {
                finite_positive(v, "number of dots per inch")?;
                self.check_display_variants(a)
            }
            (StudySubject::Display(d), StudyAxis::Opening(steps)) => {
                let mut names: Vec<f64> = Vec::new();
                for k in steps {
                    let g = grown(d, *k);
                    let name = fraction_name(&g);
                    if name == 0.0 {
                        return bad(format!("{k} cells shrinks the opening to nothing"));
                    }
                    if names.contains(&name) {
                        return bad(format!(
                            "{k} cells gives the opening of another value (open fraction \
                             {name})"
                        ));
                    }
                    names.push(name);
                }
                self.check_display_variants(a)
            }
            (StudySubject::Display(_), StudyAxis::SnrDb(v)) => v
                .iter()
                .find(|x| !x.is_finite() || x.abs() > 200.0)
                .map_or(Ok(()), |x| bad(format!("{x} dB is not a usable SNR"))),
            (StudySubject::Display(_), _) => self.check_display_variants(a),
        }
    }

    fn check_display_variants(&self, a: &StudyAxis) -> Result<(), SimError> {
        let StudySubject::Display(design) = &self.subject else {
            return Ok(());
        };
        for d in a.variants(design) {
            let d = d.map_err(|e| SimError::invalid(a.param(), e.to_string()))?;
            d.validate()
                .map_err(|e| SimError::invalid(a.param(), e.to_string()))?;
        }
        Ok(())
    }

    fn check_phase_variants(&self, a: &StudyAxis) -> Result<(), SimError> {
        let StudySubject::Phase(design) = &self.subject else {
            return Ok(());
        };
        for d in a.phase_variants(design).into_iter().flatten() {
            d.validate()
                .map_err(|e| SimError::invalid(a.param(), e.to_string()))?;
        }
        Ok(())
    }

    /// The sweep spec of the study, its inputs saved as `files`: the job of every point with
    /// the axes' values, the metrics' columns, and plots of the first metric against the
    /// first axis that is not a tiling, method or seed (one line per value of the next axis
    /// but the seeds, the spread over the seeds) and, when both are recorded, the AUC–LTR
    /// Pareto front.
    pub fn spec(&self, files: &StudyFiles) -> SweepSpec {
        let job = self.job();
        let names = self.display_design();
        let mut base = match &self.subject {
            StudySubject::Display(_) => {
                BTreeMap::from([("design".to_string(), ParamValue::Text(files.design.clone()))])
            }
            StudySubject::Phase(d) => phase_base(d),
        };
        // `restore` analyses the design at full quality always: it has no preview.
        if !self.full && job != SweepJob::Restore {
            base.insert("preview".into(), ParamValue::Bool(true));
        }
        if job == SweepJob::Restore {
            self.restore_base(&mut base, files);
        }
        // An axis sets its parameter at every point: the base does not repeat it.
        for a in &self.axes {
            base.remove(a.param());
        }
        let first_seed = match &self.subject {
            StudySubject::Display(d) => d.tiling.seed,
            StudySubject::Phase(_) => 0,
        };
        let opening = self.opening_designs();
        let axes: Vec<SweepAxis> = self
            .axes
            .iter()
            .map(|a| match a {
                // The variants are design files, named by their open fractions.
                StudyAxis::Opening(_) => SweepAxis {
                    param: a.param().into(),
                    values: Some(
                        opening
                            .iter()
                            .map(|d| ParamValue::Float(fraction_name(d)))
                            .collect(),
                    ),
                    label: true,
                    with: BTreeMap::from([(
                        "design".to_string(),
                        files
                            .opening_designs
                            .iter()
                            .map(|f| ParamValue::Text(f.clone()))
                            .collect(),
                    )]),
                    ..SweepAxis::default()
                },
                _ => SweepAxis {
                    param: a.param().into(),
                    values: Some(a.values(first_seed)),
                    ..SweepAxis::default()
                },
            })
            .collect();
        if !opening.is_empty() {
            base.remove("design");
        }
        let metrics: Vec<String> = self.metrics.iter().map(|m| m.column(&names)).collect();
        let has = |p: &str| self.axes.iter().any(|a| a.param() == p);
        let groups = |a: &StudyAxis| {
            matches!(
                a,
                StudyAxis::Seeds(_) | StudyAxis::Tiling(_) | StudyAxis::Method(_)
            )
        };
        let x = self
            .axes
            .iter()
            .find(|a| !groups(a))
            .or(self.axes.first())
            .map(|a| a.param().to_string())
            .unwrap_or_default();
        // One line per value of the next axis (never a band across tilings, methods or light
        // levels), the seeds the spread.
        let group = self
            .axes
            .iter()
            .map(StudyAxis::param)
            .find(|p| *p != x && *p != "seed")
            .map(String::from);
        let mut plots = Vec::new();
        if let Some(y) = self.metrics.first() {
            plots.push(PlotSpec {
                kind: PlotKind::MetricVsAxis,
                x: x.clone(),
                y: y.plot_column(&names),
                group,
                spread: (has("seed") && x != "seed").then(|| "seed".into()),
                x_smaller_is_better: false,
            });
        }
        let auc = StudyMetric::Analysis(SweepMetric::AucMean);
        let ltr = StudyMetric::Analysis(SweepMetric::Ltr);
        if self.metrics.contains(&auc) && self.metrics.contains(&ltr) {
            plots.push(PlotSpec {
                kind: PlotKind::Pareto,
                x: ltr.column(&names),
                y: auc.column(&names),
                group: None,
                spread: None,
                x_smaller_is_better: false,
            });
        }
        let name = match &self.subject {
            StudySubject::Display(d) => display_name(d).to_string(),
            StudySubject::Phase(d) => format!("the {} µm phase masks", d.pitch_um),
        };
        SweepSpec {
            name: format!(
                "{name} over {}",
                self.axes
                    .iter()
                    .map(StudyAxis::param)
                    .collect::<Vec<_>>()
                    .join(" × ")
            ),
            job,
            base,
            axes,
            metrics,
            plots,
        }
    }

    /// The restore job's settings that are not axes: the photo, the light level, the method
    /// and the Restore view's numbers.
    fn restore_base(&self, base: &mut BTreeMap<String, ParamValue>, files: &StudyFiles) {
        let r = &self.restore;
        let has = |p: &str| self.axes.iter().any(|a| a.param() == p);
        if let Some(photo) = &files.photo {
            base.insert("image".into(), ParamValue::Text(photo.clone()));
        }
        if !has("snr-db") {
            base.insert("snr-db".into(), ParamValue::Float(r.snr_db));
        }
        if !has("method") {
            base.insert("method".into(), ParamValue::Text(r.method.name().into()));
        }
        base.insert("nsr".into(), ParamValue::Float(r.nsr));
        base.insert("lambda".into(), ParamValue::Float(r.lambda));
        base.insert(
            "noise-seed".into(),
            ParamValue::Int(i64::try_from(r.noise_seed).unwrap_or(i64::MAX)),
        );
        match r.denoise {
            Denoise::None => {
                base.insert("denoise".into(), ParamValue::Text("none".into()));
            }
            Denoise::Bm3d { sigma2 } => {
                base.insert("denoise".into(), ParamValue::Text("bm3d".into()));
                let s = match sigma2 {
                    Sigma2::Matched => ParamValue::Text("matched".into()),
                    Sigma2::Thesis(_) => ParamValue::Text("table".into()),
                    Sigma2::Fixed(v) => ParamValue::Float(v),
                };
                base.insert("denoise-sigma2".into(), s);
            }
        }
    }
}

/// The design's name for messages ("the design" when it has none).
fn display_name(d: &Design) -> &str {
    if d.name.is_empty() {
        "the design"
    } else {
        d.name.as_str()
    }
}

/// What `phase psf` cannot be told: a camera other than the thesis's, or a λ0 that has no
/// name (the optimizer's counts, hand-edited λ0) when the λ0 plan is not an axis.
fn check_phase_base(d: &PhaseDesign, axes: &[StudyAxis]) -> Result<(), SimError> {
    if d.camera != PhaseDesign::thesis(d.pitch_um, d.fold).camera {
        return Err(SimError::invalid(
            "camera",
            "this design's camera differs from the thesis's, and `phase psf` has no flags              for it: a study of it cannot be rerun from its spec",
        ));
    }
    let plan_axis = axes.iter().any(|a| matches!(a, StudyAxis::Lambda0(_)));
    if !plan_axis && Lambda0Plan::of(&d.lambda0).is_none() {
        return Err(SimError::invalid(
            "lambda0",
            "this design's λ0 (the optimizer's counts or edited per lenslet) has no name the              command takes: add a λ0-plan axis (fixed:530, uniform, optimized)",
        ));
    }
    Ok(())
}

/// `phase psf`'s flags for `d` (the pitch's focal length left to follow it where it does).
fn phase_base(d: &PhaseDesign) -> BTreeMap<String, ParamValue> {
    let mut b = BTreeMap::new();
    let mut put = |k: &str, v: ParamValue| {
        b.insert(k.to_string(), v);
    };
    put("pitch-um", ParamValue::Float(d.pitch_um));
    put("fold", ParamValue::Float(d.fold));
    if d.f_mla_um != d.pitch_um {
        put("f-mla-um", ParamValue::Float(d.f_mla_um));
    }
    put("n", ParamValue::Float(d.refractive_index));
    put("open-ratio", ParamValue::Float(d.open_ratio));
    if let Some(step) = d.height_step_um {
        put("height-step-um", ParamValue::Float(step));
        put(
            "height-rounding",
            ParamValue::Text(<&str>::from(d.height_rounding).into()),
        );
    }
    put(
        "sampling",
        ParamValue::Text(<&str>::from(d.sampling).into()),
    );
    if let Some(plan) = Lambda0Plan::of(&d.lambda0) {
        put("lambda0", ParamValue::Text(plan.as_arg()));
    }
    if d.surface == Surface::Unfolded {
        put("unfolded", ParamValue::Bool(true));
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Quality;
    use crate::design::TilingMode;
    use crate::restore::RestoreMethod;

    fn display(axes: Vec<StudyAxis>, metrics: Vec<StudyMetric>) -> Study {
        Study {
            subject: StudySubject::Display(Box::default()),
            axes,
            metrics,
            full: false,
            restore: RestoreSetup::default(),
        }
    }

    fn tiling_study() -> Study {
        display(
            vec![
                StudyAxis::Dpi(vec![150.0, 300.0, 600.0]),
                StudyAxis::Tiling(vec![TilingMode::Repeat, TilingMode::RandomD4]),
                StudyAxis::Seeds(3),
            ],
            vec![
                StudyMetric::Analysis(SweepMetric::AucMean),
                StudyMetric::Analysis(SweepMetric::Ltr),
            ],
        )
    }

    fn files() -> StudyFiles {
        StudyFiles {
            design: "design.json".into(),
            photo: Some("photo.png".into()),
            opening_designs: Vec::new(),
        }
    }

    #[test]
    fn an_opening_axis_names_its_variants_by_open_fraction_and_links_their_files() {
        let mut s = display(
            vec![StudyAxis::Opening(vec![-1, 0, 1])],
            vec![StudyMetric::Analysis(SweepMetric::Ltr)],
        );
        s.check().expect("valid");
        let designs = s.opening_designs();
        assert_eq!(designs.len(), 3);
        let f = StudyFiles {
            opening_designs: vec!["a.json".into(), "b.json".into(), "c.json".into()],
            ..files()
        };
        let spec = s.spec(&f);
        spec.validate().expect("a valid spec");
        let axis = &spec.axes[0];
        assert!(axis.label);
        // The 5-of-21 slit shrunk to 3 and grown to 7 columns.
        let named: Vec<f64> = axis
            .values
            .iter()
            .flatten()
            .filter_map(ParamValue::as_f64)
            .collect();
        assert_eq!(named, [0.1429, 0.2381, 0.3333]);
        assert_eq!(axis.with["design"].len(), 3);
        assert!(
            !spec.base.contains_key("design"),
            "each point's design is its variant"
        );
        // Shrinking the slit away, or two steps that give one opening, are refused.
        s.axes[0] = StudyAxis::Opening(vec![0, -3]);
        assert!(s.check().unwrap_err().to_string().contains("nothing"));
        s.axes[0] = StudyAxis::Opening(vec![10, 11]);
        assert!(s.check().unwrap_err().to_string().contains("another value"));
    }

    fn phase(axes: Vec<StudyAxis>) -> Study {
        Study {
            subject: StudySubject::Phase(Box::new(PhaseDesign::thesis(42.0, 1.0))),
            axes,
            metrics: vec![StudyMetric::PhaseInvertibility, StudyMetric::PhaseLtr],
            full: false,
            restore: RestoreSetup::default(),
        }
    }

    #[test]
    fn a_study_is_the_product_of_its_axes_and_plots_each_tiling_with_its_seed_spread() {
        let d = Design::default_toled();
        let s = tiling_study();
        assert_eq!(s.points(), 18);
        assert_eq!(s.job(), SweepJob::Analyze);
        s.check().expect("a valid study");
        let spec = s.spec(&files());
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
        assert!(
            !spec.base.contains_key("image"),
            "an analysis needs no photo"
        );
    }

    #[test]
    fn light_and_method_axes_restore_the_photo_with_the_views_settings() {
        let mut s = display(
            vec![
                StudyAxis::SnrDb(vec![24.0, 32.0, 40.0]),
                StudyAxis::Method(RestoreMethod::ALL.to_vec()),
            ],
            vec![StudyMetric::PsnrDb, StudyMetric::Analysis(SweepMetric::Ltr)],
        );
        s.restore.nsr = 0.02;
        assert_eq!(s.job(), SweepJob::Restore);
        s.check().expect("valid");
        let spec = s.spec(&files());
        assert_eq!(spec.job, SweepJob::Restore);
        assert_eq!(
            spec.base.get("image"),
            Some(&ParamValue::Text("photo.png".into()))
        );
        assert_eq!(spec.base.get("nsr"), Some(&ParamValue::Float(0.02)));
        // The axes set the light and the method; the base does not repeat them.
        assert!(!spec.base.contains_key("snr-db") && !spec.base.contains_key("method"));
        assert_eq!(spec.metrics, ["runs.0.psnr_db", "ltr"]);
        assert!(!spec.base.contains_key("preview"), "restore has no preview");
        let p = &spec.plots[0];
        assert_eq!(
            (p.x.as_str(), p.y.as_str(), p.group.as_deref()),
            ("snr-db", "runs.0.psnr_db", Some("method"))
        );
        // A restore job reports no per-channel AUC: refused before anything runs.
        s.metrics
            .push(StudyMetric::Analysis(SweepMetric::InvertibilityLoss));
        let e = s.check().unwrap_err().to_string();
        assert!(e.contains("L_inv") && e.contains("restore"), "{e}");
        // Nor does an analysis report a PSNR: recording one makes the study restore.
        let only = display(vec![StudyAxis::Dpi(vec![150.0])], vec![StudyMetric::Ssim]);
        assert_eq!(only.job(), SweepJob::Restore);
        let spec = only.spec(&files());
        assert_eq!(spec.base.get("snr-db"), Some(&ParamValue::Float(32.0)));
        assert_eq!(
            spec.base.get("method"),
            Some(&ParamValue::Text("wiener".into()))
        );
    }

    #[test]
    fn a_phase_study_runs_phase_psf_with_the_designs_flags() {
        let s = phase(vec![
            StudyAxis::Fold(vec![1.0, 5.0]),
            StudyAxis::Lambda0(vec![Lambda0Plan::Fixed(530.0), Lambda0Plan::Uniform]),
        ]);
        s.check().expect("valid");
        let spec = s.spec(&files());
        assert_eq!(spec.job, SweepJob::PhasePsf);
        assert_eq!(spec.base.get("pitch-um"), Some(&ParamValue::Float(42.0)));
        assert!(!spec.base.contains_key("design"));
        assert!(!spec.base.contains_key("lambda0"), "an axis, not the base");
        assert_eq!(
            spec.axes[1].values,
            Some(vec![
                ParamValue::Text("fixed:530".into()),
                ParamValue::Text("uniform".into())
            ])
        );
        let p = &spec.plots[0];
        assert_eq!(
            (p.x.as_str(), p.y.as_str(), p.group.as_deref()),
            ("fold", "channels.G.invertibility", Some("lambda0"))
        );
        // Display axes and metrics do not apply to phase masks, nor the reverse.
        let e = phase(vec![StudyAxis::Dpi(vec![300.0])])
            .check()
            .unwrap_err()
            .to_string();
        assert!(e.contains("phase-mask design"), "{e}");
        let e = tiling_study_with(StudyAxis::Fold(vec![1.0]))
            .check()
            .unwrap_err()
            .to_string();
        assert!(e.contains("phase-mask axis"), "{e}");
        let e = phase(vec![StudyAxis::Fold(vec![1.0, -2.0])])
            .check()
            .unwrap_err()
            .to_string();
        assert!(e.contains("fold"), "{e}");
        // A λ0 with no name needs the plan as an axis.
        let mut counts = PhaseDesign::thesis(42.0, 1.0);
        counts.lambda0 = crate::phase::Lambda0::PerLenslet {
            nm: vec![530.0; crate::phase::geometry::lenslet_count(&counts)],
        };
        let mut s = phase(vec![StudyAxis::Fold(vec![1.0])]);
        s.subject = StudySubject::Phase(Box::new(counts));
        let e = s.check().unwrap_err().to_string();
        assert!(e.contains("λ0-plan axis"), "{e}");
    }

    fn tiling_study_with(axis: StudyAxis) -> Study {
        let mut s = tiling_study();
        s.axes.push(axis);
        s
    }

    /// The DPI axis's designs are sampled as the thesis's presets: the slit reads its open
    /// fraction at every DPI (8 µm samples would read 0.175 at 600 DPI, 0.222 at 150 DPI's
    /// 169.3 µm pitch).
    #[test]
    fn every_dpi_axis_point_reads_the_slits_light() {
        use crate::analysis::analyze::{AnalyzeOptions, analyze_with};
        let s = display(
            vec![StudyAxis::Dpi(vec![
                100.0,
                150.0,
                200.0,
                UM_PER_INCH / 42.0,
            ])],
            vec![StudyMetric::Analysis(SweepMetric::Ltr)],
        );
        let StudySubject::Display(d) = &s.subject else {
            unreachable!()
        };
        let options = AnalyzeOptions {
            quality: Quality::Preview,
            expected_psf: false,
        };
        for point in s.axes[0].variants(d) {
            let point = point.expect("a design");
            let a = analyze_with(&point, &options, &crate::Progress::new()).expect("analysed");
            assert!(
                (a.ltr - 5.0 / 21.0).abs() < 2e-3,
                "{} DPI: LTR {}",
                point.opening.dpi(),
                a.ltr
            );
        }
    }

    #[test]
    fn bad_studies_are_refused_naming_the_axis() {
        let mut s = tiling_study();
        s.axes[0] = StudyAxis::Dpi(vec![150.0, -3.0]);
        assert!(s.check().unwrap_err().to_string().contains("dpi"));
        s.axes[0] = StudyAxis::Number(SweepParameter::FNumber, vec![2.0, 0.0]);
        let e = s.check().unwrap_err().to_string();
        assert!(e.contains("f-number"), "{e}");
        s.axes[0] = StudyAxis::SnrDb(vec![f64::NAN]);
        assert!(s.check().unwrap_err().to_string().contains("snr-db"));
        s.axes[0] = StudyAxis::Seeds(2);
        assert!(s.check().unwrap_err().to_string().contains("twice"));
        s.axes.clear();
        assert!(s.check().is_err());
    }

    #[test]
    fn finer_displays_cost_more_by_the_model_and_tilings_cost_the_same() {
        let d = Design::default_toled();
        let one = |axis| {
            display(
                vec![axis],
                vec![StudyMetric::Analysis(SweepMetric::AucMean)],
            )
        };
        let times = StudyTimes {
            on_screen: Some((100.0, Quality::Preview)),
            restore_ms: None,
        };
        let cost = |s: Study| s.estimate(&times).expect("costed").expect("timed");
        let coarse = cost(one(StudyAxis::Dpi(vec![d.opening.dpi()])));
        assert!((coarse.seconds - 0.1).abs() < 1e-9, "{coarse:?}");
        let tilings = cost(one(StudyAxis::Tiling(TilingMode::ALL.to_vec())));
        assert!((tilings.seconds - 0.3).abs() < 1e-9, "{tilings:?}");
        let fine = cost(one(StudyAxis::Dpi(vec![4.0 * d.opening.dpi()])));
        assert!(
            fine.seconds > 1.5 * coarse.seconds,
            "{fine:?} vs {coarse:?}"
        );
        assert!(fine.bytes_per_point > coarse.bytes_per_point);
        // A restoring study waits for the Restore view's time, then adds it per point.
        let restoring = one(StudyAxis::SnrDb(vec![24.0, 40.0]));
        assert_eq!(restoring.estimate(&times).expect("costed"), None);
        let with = StudyTimes {
            restore_ms: Some(400.0),
            ..times
        };
        let e = restoring.estimate(&with).expect("costed").expect("timed");
        assert!((e.seconds - 2.0 * 0.5).abs() < 1e-9, "{e:?}");
        assert!(!e.at_least);
    }

    #[test]
    fn a_phase_study_costs_its_quality_and_flags_what_the_model_does_not_know() {
        let times = StudyTimes {
            on_screen: Some((200.0, Quality::Preview)),
            restore_ms: None,
        };
        let folds = phase(vec![StudyAxis::Fold(vec![1.0, 2.0, 5.0])]);
        let e = folds.estimate(&times).expect("costed").expect("timed");
        assert!((e.seconds - 0.6).abs() < 1e-9 && !e.at_least, "{e:?}");
        let mut full = folds.clone();
        full.full = true;
        let f = full.estimate(&times).expect("costed").expect("timed");
        // 4× finer display samples, twice the sensor directions.
        assert!((f.seconds / e.seconds - 8.0).abs() < 1e-9, "{f:?}");
        let plans = phase(vec![StudyAxis::Lambda0(vec![
            Lambda0Plan::Fixed(530.0),
            Lambda0Plan::Optimized,
        ])]);
        assert!(
            plans
                .estimate(&times)
                .expect("costed")
                .expect("timed")
                .at_least
        );
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
        assert_eq!(
            parse_plans("fixed:530, uniform").unwrap(),
            vec![Lambda0Plan::Fixed(530.0), Lambda0Plan::Uniform]
        );
        assert!(parse_plans("fixed:530, best").unwrap_err().contains("best"));
    }
}
