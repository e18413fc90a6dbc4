//! The phase-mask and sensor commands and sweeps, run in-process through the CLI crate: the
//! same parameters (as `--flag value` words), the same one-line messages and the same JSON as
//! `udc-studio phase …`, `udc-studio sensor …` and `udc-studio sweep`.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use udc_core::Progress;
use udc_core::sweep::Shard;
use udc_io::IoError;

use crate::cancel;

/// A command's error: a file problem is an `OSError`, anything else a bad parameter.
fn error(e: &anyhow::Error) -> PyErr {
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

/// Runs `udc-studio WORDS --json` in-process and returns the JSON text it prints; Ctrl-C
/// cancels the command's long steps (the phase propagations, the sensor simulation).
#[pyfunction]
fn run_json(py: Python<'_>, words: Vec<String>) -> PyResult<String> {
    let progress = Arc::new(Progress::new());
    let value = cancel::wait(
        py,
        || udc_cli::run_json(&words, &progress).map_err(|e| error(&e)),
        || progress.cancel(),
    )?;
    serde_json::to_string(&value).map_err(|e| PyValueError::new_err(e.to_string()))
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
    let options = udc_cli::sweep::RunOptions {
        shard: Shard::WHOLE,
        threads,
        quiet: true,
        plots: true,
        hold_after_points: None,
    };
    let summary = cancel::wait(
        py,
        || {
            udc_cli::sweep::run_sweep(&loaded, &out, &options, &progress, &mut |_| {})
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
    m.add_function(wrap_pyfunction!(run_json, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    Ok(())
}
