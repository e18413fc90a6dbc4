//! The typed job layer: one struct per job ([`JobSpec`]) and one [`evaluate`] that the command
//! line, the Python package, sweeps, `reproduce` and the studio all call, and the one sweep
//! runner ([`sweep::run_sweep`]) that drives it point by point.
//!
//! A job's struct is its parameters, each with its name, unit, help and default once: clap reads
//! them as the CLI's flags, serde as a sweep point's or a Python call's parameters
//! ([`JobSpec::from_params`]). A job computes a [`Report`]: its JSON object (what `--json`
//! prints, a sweep row's metrics, the Python call's result) and its text table; it prints
//! nothing, and its long steps report to and are cancelled by a [`Progress`].

/// Appends a line to a report's text, as `println!` would print it.
macro_rules! outln {
    ($report:expr) => {
        $report.text.push('\n')
    };
    ($report:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($report.text, $($arg)*);
    }};
}

/// Appends to a report's text, as `print!` would print it.
macro_rules! out {
    ($report:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        let _ = write!($report.text, $($arg)*);
    }};
}

pub mod backend;
pub mod choice;
pub mod denoise;
pub mod display;
pub mod flags;
pub mod measured;
mod params;
pub mod phase;
mod report;
pub mod sensor;
pub mod sweep;

pub use params::{FromParams, Params, params_of};
pub use report::Report;

use anyhow::Result;
use serde_json::Value;
use udc_core::Progress;
use udc_core::sweep::SweepJob;

/// One job and its parameters.
#[derive(Debug, Clone)]
pub enum JobSpec {
    /// `analyze`: PSF, MTF, AUC, LTR and invertibility of a display design.
    Analyze(display::AnalyzeJob),
    /// `restore`: a photo captured through a display and restored.
    Restore(display::RestoreJob),
    /// `phase psf`: the double MLA's PSFs against the bare T-OLED.
    PhasePsf(phase::PsfJob),
    /// `phase invertibility`: the invertibility matrix V over λ0 and λ.
    PhaseInvertibility(phase::InvertibilityJob),
    /// `phase optimize`: folding wavelengths allocated to lenslets.
    PhaseOptimize(phase::OptimizeJob),
    /// `phase restore`: a photo through the phase masks, restored.
    PhaseRestore(phase::RestoreJob),
    /// `sensor`: spatially-varying gain and binning on an HDR scene.
    Sensor(sensor::SensorJob),
    /// `sensor flat-patch`: a flat patch read at one gain and bin.
    SensorFlatPatch(sensor::FlatPatchJob),
}

impl JobSpec {
    /// The job named `kind` with these parameters (names as the CLI's flags without `--`:
    /// `pitch-um`; a repeated name is a list); parameters left out take their defaults.
    ///
    /// # Errors
    /// An unknown parameter, or a value of the wrong type, naming the parameter.
    pub fn from_params(kind: SweepJob, params: &Params) -> Result<JobSpec> {
        Ok(match kind {
            SweepJob::Analyze => JobSpec::Analyze(FromParams::from_params(params)?),
            SweepJob::Restore => JobSpec::Restore(FromParams::from_params(params)?),
            SweepJob::PhasePsf => JobSpec::PhasePsf(FromParams::from_params(params)?),
            SweepJob::PhaseInvertibility => {
                JobSpec::PhaseInvertibility(FromParams::from_params(params)?)
            }
            SweepJob::PhaseOptimize => JobSpec::PhaseOptimize(FromParams::from_params(params)?),
            SweepJob::PhaseRestore => JobSpec::PhaseRestore(FromParams::from_params(params)?),
            SweepJob::Sensor => JobSpec::Sensor(FromParams::from_params(params)?),
            SweepJob::SensorFlatPatch => JobSpec::SensorFlatPatch(FromParams::from_params(params)?),
        })
    }

    /// Which job this is.
    pub fn kind(&self) -> SweepJob {
        match self {
            JobSpec::Analyze(_) => SweepJob::Analyze,
            JobSpec::Restore(_) => SweepJob::Restore,
            JobSpec::PhasePsf(_) => SweepJob::PhasePsf,
            JobSpec::PhaseInvertibility(_) => SweepJob::PhaseInvertibility,
            JobSpec::PhaseOptimize(_) => SweepJob::PhaseOptimize,
            JobSpec::PhaseRestore(_) => SweepJob::PhaseRestore,
            JobSpec::Sensor(_) => SweepJob::Sensor,
            JobSpec::SensorFlatPatch(_) => SweepJob::SensorFlatPatch,
        }
    }

    /// Checks what can be checked without computing: the parameters' ranges and, for display
    /// jobs, that the design resolves (files read, preset known).
    ///
    /// # Errors
    /// The first parameter refused.
    pub fn check(&self) -> Result<()> {
        match self {
            JobSpec::Analyze(j) => j.selection.resolve().map(|_| ()),
            JobSpec::Restore(j) => j.check().and_then(|()| j.selection.resolve().map(|_| ())),
            _ => Ok(()),
        }
        .map_err(flags::name_flags)
    }

    /// The hash of the display design the job resolves (`None` for jobs without one): sweep
    /// rows that share it share the design.
    ///
    /// # Errors
    /// A design that cannot be resolved.
    pub fn design_hash(&self) -> Result<Option<String>> {
        let selection = match self {
            JobSpec::Analyze(j) => &j.selection,
            JobSpec::Restore(j) => &j.selection,
            _ => return Ok(None),
        };
        Ok(Some(udc_io::design::hash::design_hash(
            &selection.resolve()?,
        )))
    }
}

/// Computes a job: its JSON object and its text table. Long steps report to `progress` and stop
/// at its next check once it is cancelled.
///
/// # Errors
/// The job's own refusal (a bad value, naming its flag; an unreadable file; a refused size) or
/// cancellation.
pub fn evaluate(job: &JobSpec, progress: &Progress) -> Result<Report> {
    match job {
        JobSpec::Analyze(j) => display::analyze(j, progress),
        JobSpec::Restore(j) => display::restore(j, progress),
        JobSpec::PhasePsf(j) => phase::psf(j, progress),
        JobSpec::PhaseInvertibility(j) => phase::invertibility(j, progress),
        JobSpec::PhaseOptimize(j) => phase::optimize(j, progress),
        JobSpec::PhaseRestore(j) => phase::restore(j, progress),
        JobSpec::Sensor(j) => sensor::sensor(j, progress),
        JobSpec::SensorFlatPatch(j) => sensor::flat_patch(j, progress),
    }
    .map_err(flags::name_flags)
}

/// A job's JSON object with the name of the build that made it (`tool_version`), as printed
/// objects carry it.
pub fn with_tool_version(mut value: Value) -> Value {
    if let Some(obj) = value.as_object_mut() {
        obj.entry("tool_version")
            .or_insert_with(|| udc_io::TOOL_VERSION.into());
    }
    value
}
