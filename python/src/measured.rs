//! Measured PSFs: `psf import`, `psf compare` and `psf fit` called in-process through `udc-jobs` with
//! typed keyword arguments (the jobs' own serde types), and a PSF set read as numpy arrays.

use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde::de::DeserializeOwned;
use udc_core::Progress;
use udc_io::measured::{SetDefaults, read_psf_set};
use udc_jobs::measured::{CompareJob, FitJob, ImportJob, compare, fit, import};

use crate::cancel;

/// The job of type `J` from keyword arguments (`pixel_um` is the flag `--pixel-um`).
fn job_of<J: DeserializeOwned>(params: &Bound<'_, PyDict>) -> PyResult<J> {
    let mut obj = serde_json::Map::new();
    for (key, value) in params.iter() {
        let key: String = key.extract()?;
        let value: serde_json::Value = pythonize::depythonize(&value)
            .map_err(|e| PyValueError::new_err(format!("{key}: {e}")))?;
        if !value.is_null() {
            obj.insert(key.trim_end_matches('_').replace('_', "-"), value);
        }
    }
    serde_json::from_value(serde_json::Value::Object(obj))
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Runs `job` built from `params` (Ctrl-C cancels it) and returns what its `--json` prints.
fn run_job<'py, J: DeserializeOwned + Sync>(
    py: Python<'py>,
    params: &Bound<'py, PyDict>,
    job: fn(&J, &Progress) -> anyhow::Result<udc_jobs::Report>,
) -> PyResult<Bound<'py, PyAny>> {
    let spec: J = job_of(params)?;
    let progress = Progress::new();
    let report = cancel::wait(
        py,
        || job(&spec, &progress).map_err(|e| crate::jobs::error(&e)),
        || progress.cancel(),
    )?;
    pythonize::pythonize(py, &report.json).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// `psf import` with these parameters; returns what its `--json` prints.
#[pyfunction]
fn psf_import<'py>(py: Python<'py>, params: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyAny>> {
    run_job::<ImportJob>(py, params, import)
}

/// `psf compare` with these parameters; returns what its `--json` prints.
#[pyfunction]
fn psf_compare<'py>(py: Python<'py>, params: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyAny>> {
    run_job::<CompareJob>(py, params, compare)
}

/// `psf fit` with these parameters; returns what its `--json` prints.
#[pyfunction]
fn psf_fit<'py>(py: Python<'py>, params: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyAny>> {
    run_job::<FitJob>(py, params, fit)
}

/// A PSF set from `path` (with its sidecar, or `pixel_um`): `pixel_um`, `source` and
/// `channels`, each a dict of `name`, `wavelength_nm` and `psf` (a float64 array summing to 1).
#[pyfunction]
#[pyo3(signature = (path, pixel_um = None, wavelength_nm = None))]
fn read_psf<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    pixel_um: Option<f64>,
    wavelength_nm: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let set = read_psf_set(
        &path,
        &SetDefaults {
            pixel_um,
            wavelength_nm,
        },
    )
    .map_err(|e| crate::errors::io(&e))?;
    let d = PyDict::new(py);
    d.set_item("pixel_um", set.pixel_um)?;
    d.set_item(
        "source",
        match set.source {
            udc_core::measured::PsfSource::Simulated => "simulated",
            udc_core::measured::PsfSource::Measured => "measured",
        },
    )?;
    let channels = PyList::empty(py);
    for c in set.channels {
        let ch = PyDict::new(py);
        ch.set_item("name", c.name)?;
        ch.set_item("wavelength_nm", c.wavelength_nm)?;
        ch.set_item("psf", c.psf.into_pyarray(py))?;
        channels.append(ch)?;
    }
    d.set_item("channels", channels)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(psf_import, m)?)?;
    m.add_function(wrap_pyfunction!(psf_compare, m)?)?;
    m.add_function(wrap_pyfunction!(psf_fit, m)?)?;
    m.add_function(wrap_pyfunction!(read_psf, m)?)?;
    Ok(())
}
