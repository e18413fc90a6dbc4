//! The typed jobs (`phase psf`, `phase restore`, `sensor`, …) and the sweep runner, called
//! in-process through `udc-jobs`: a job is built from its keyword arguments by the same serde
//! types the CLI's flags fill, evaluated by the same [`udc_jobs::evaluate`], and its result
//! handed back as Python objects (no command line, no JSON text in between).

use std::path::PathBuf;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use udc_core::Progress;
use udc_core::sweep::{Shard, SweepJob};
use udc_io::IoError;
use udc_jobs::{JobSpec, Params, evaluate};

use crate::cancel;

/// A job's error: a file problem is an `OSError`, anything else a bad parameter.
pub(crate) fn error(e: &anyhow::Error) -> PyErr {
    let message = format!("{e:#}");
    let file_problem = e.chain().any(|cause| {
        cause
            .downcast_ref::<IoError>()
            .is_some_and(|io| !matches!(io, IoError::Invalid(_) | IoError::UnknownPreset(_)))
    });
    if file_problem {
        PyOSError::new_err(message)
    } else {
        PyValueError::new_err(message)
    }
}

/// The job named `job` (`"phase-psf"`, as a sweep spec names it).
fn kind_of(job: &str) -> PyResult<SweepJob> {
    SweepJob::ALL
        .into_iter()
        .find(|k| k.as_str() == job)
        .ok_or_else(|| {
            let names: Vec<&str> = SweepJob::ALL.iter().map(|k| k.as_str()).collect();
            PyValueError::new_err(format!(
                "unknown job {job:?} (expected one of: {})",
                names.join(", ")
            ))
        })
}

/// Keyword arguments as the job's parameters: `angle_deg` is `angle-deg`, a trailing `_` is
/// dropped (`lambda_`).
pub(crate) fn params_of(params: &Bound<'_, PyDict>) -> PyResult<Params> {
    let mut out = Params::new();
    for (key, value) in params.iter() {
        let key: String = key.extract()?;
        let name = key.trim_end_matches('_').replace('_', "-");
        let value: serde_json::Value = pythonize::depythonize(&value)
            .map_err(|e| PyValueError::new_err(format!("{key}: {e}")))?;
        out.insert(name, value);
    }
    Ok(out)
}

/// Evaluates job `job` with these parameters and returns its result (the object `--json`
/// prints, as dicts, lists and numbers); Ctrl-C cancels its long steps.
#[pyfunction]
fn evaluate_job<'py>(
    py: Python<'py>,
    job: &str,
    params: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = JobSpec::from_params(kind_of(job)?, &params_of(params)?).map_err(|e| error(&e))?;
    let progress = Progress::new();
    let report = cancel::wait(
        py,
        || evaluate(&spec, &progress).map_err(|e| error(&e)),
        || progress.cancel(),
    )?;
    pythonize::pythonize(py, &report.json).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Runs a sweep spec into `out` (resuming a folder that holds part of it) and returns its
/// summary; Ctrl-C stops it after the points in flight, keeping them.
#[pyfunction]
#[pyo3(signature = (spec, out, threads = None))]
fn sweep<'py>(
    py: Python<'py>,
    spec: PathBuf,
    out: PathBuf,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let loaded = udc_io::sweep::load_spec(&spec).map_err(|e| crate::errors::io(&e))?;
    let progress = Progress::new();
    let options = udc_jobs::sweep::RunOptions {
        shard: Shard::WHOLE,
        threads,
        plots: true,
        check_values: true,
        hold_after_points: None,
    };
    let summary = cancel::wait(
        py,
        || {
            udc_jobs::sweep::run_sweep(&loaded, &out, &options, &progress, &mut |_| {})
                .map_err(|e| error(&e))
        },
        || progress.cancel(),
    )?;
    let out_dict = PyDict::new(py);
    out_dict.set_item("computed", summary.computed)?;
    out_dict.set_item("skipped", summary.skipped)?;
    out_dict.set_item("failed", summary.failed)?;
    out_dict.set_item("complete", summary.complete)?;
    out_dict.set_item("plots", summary.plots)?;
    Ok(out_dict)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(evaluate_job, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    Ok(())
}
