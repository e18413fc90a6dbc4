//! `analyze`: the same analysis, advice and JSON as `udc-studio analyze --json`, with the
//! arrays behind the numbers as numpy arrays.

use std::time::Instant;

use ndarray::{Array1, Array2, Array3, Axis};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strum::VariantArray;
use udc_core::analysis::advice::{self, AdviceScope};
use udc_core::analysis::analyze::{Analysis, AnalyzeOptions, Quality, analyze_with_route};
use udc_core::psf::route::Backend;
use udc_io::display::report;

use crate::{cancel, design, errors};

/// The quality names Python passes, as the closed set the core uses.
pub fn quality(name: &str) -> PyResult<Quality> {
    match name {
        "full" => Ok(Quality::Full),
        "preview" => Ok(Quality::Preview),
        other => Err(errors::value(format!(
            "quality: expected \"full\" or \"preview\" (got {other:?})"
        ))),
    }
}

/// The backend names Python passes (`cpu`, `gpu`, `auto`), as the core's closed set.
pub fn backend(name: &str) -> PyResult<Backend> {
    Backend::VARIANTS
        .iter()
        .copied()
        .find(|b| <&str>::from(*b) == name)
        .ok_or_else(|| {
            errors::value(format!(
                "backend: expected \"cpu\", \"gpu\" or \"auto\" (got {name:?})"
            ))
        })
}

/// Analyses a design (its JSON text); the dict holds the arrays and the CLI's JSON text.
#[pyfunction]
#[pyo3(signature = (design_json, quality_name = "full", advice = "warnings", backend_name = "cpu"))]
fn analyze<'py>(
    py: Python<'py>,
    design_json: &str,
    quality_name: &str,
    advice: &str,
    backend_name: &str,
) -> PyResult<Bound<'py, PyDict>> {
    // Which warnings get a fix, each checked by a further analysis (`--advice` is "all").
    let scope = match advice {
        "warnings" => Some(AdviceScope::Warnings),
        "all" => Some(AdviceScope::All),
        "none" => None,
        other => {
            return Err(errors::value(format!(
                "advice: expected \"warnings\", \"all\" or \"none\" (got {other:?})"
            )));
        }
    };
    let design = design::parse(design_json)?;
    let options = AnalyzeOptions {
        quality: quality(quality_name)?,
        // As the CLI without `--out`: the expected PSF is only written to files.
        expected_psf: false,
    };
    let route = udc_jobs::backend::route(backend(backend_name)?)
        .map_err(|e| errors::value(format!("backend {backend_name}: {e}")))?;
    let (analysis, call_ms) = cancel::run(py, |progress| {
        let t0 = Instant::now();
        let mut a =
            analyze_with_route(&design, &options, &route, progress).map_err(|e| errors::sim(&e))?;
        if let Some(scope) = scope {
            advice::advise_in(&design, &mut a.warnings, scope, progress)
                .map_err(|e| errors::sim(&e))?;
        }
        Ok((a, t0.elapsed().as_secs_f64() * 1e3))
    })?;
    // `analyze --json`'s object, with the `backend` object where the CPU was not asked for.
    let mut json = udc_jobs::Report {
        json: report::analysis_json(&analysis),
        text: String::new(),
    };
    udc_jobs::backend::report(&mut json, backend(backend_name)?, &route);
    let out = to_dict(py, analysis)?;
    out.set_item(
        "json",
        serde_json::to_string(&json.json).map_err(|e| errors::value(e.to_string()))?,
    )?;
    // The whole call inside Rust (analysis and advice), what the Python call is measured
    // against (benches/python_peers.py).
    out.set_item("call_ms", call_ms)?;
    out.set_item("adapter", route.adapter())?;
    out.set_item("backend_note", route.note())?;
    Ok(out)
}

fn to_dict(py: Python<'_>, a: Analysis) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    out.set_item(
        "json",
        serde_json::to_string(&report::analysis_json(&a))
            .map_err(|e| errors::value(e.to_string()))?,
    )?;
    let names: Vec<&str> = a.channels.iter().map(|c| c.name.as_str()).collect();
    out.set_item("channels", names)?;
    out.set_item(
        "wavelength_nm",
        Array1::from_iter(a.channels.iter().map(|c| c.wavelength_nm)).into_pyarray(py),
    )?;
    out.set_item(
        "auc",
        Array1::from_iter(a.channels.iter().map(|c| c.mtf.auc_radial_min)).into_pyarray(py),
    )?;
    out.set_item(
        "invertibility",
        Array1::from_iter(a.channels.iter().map(|c| c.invertibility)).into_pyarray(py),
    )?;
    out.set_item(
        "energy_in_window",
        Array1::from_iter(a.channels.iter().map(|c| c.energy_in_window)).into_pyarray(py),
    )?;
    if let Some(first) = a.channels.first() {
        out.set_item(
            "freq_cyc_per_px",
            Array1::from(first.mtf.freqs_cyc_per_px()).into_pyarray(py),
        )?;
    }
    out.set_item(
        "radial_min",
        rows(a.channels.iter().map(|c| c.mtf.radial_min.as_slice()))?.into_pyarray(py),
    )?;
    out.set_item(
        "radial_mean",
        rows(a.channels.iter().map(|c| c.mtf.radial_mean.as_slice()))?.into_pyarray(py),
    )?;
    out.set_item(
        "psf",
        stack(a.channels.iter().map(|c| &c.psf))?.into_pyarray(py),
    )?;
    out.set_item(
        "mtf",
        stack(a.channels.iter().map(|c| &c.mtf.centred))?.into_pyarray(py),
    )?;
    let warnings: Vec<&str> = report::warning_messages(&a.warnings);
    out.set_item("warnings", warnings)?;
    out.set_item("ltr", a.ltr)?;
    out.set_item("open_fraction", a.open_fraction)?;
    out.set_item("invertibility_loss", a.invertibility_loss)?;
    out.set_item("window_px", a.window_px)?;
    out.set_item("sensor_pixel_um", a.sensor_pixel_um)?;
    out.set_item("elapsed_ms", a.elapsed_ms)?;
    Ok(out)
}

/// Channels × H × W from per-channel planes of one size.
fn stack<'a>(planes: impl Iterator<Item = &'a Array2<f64>>) -> PyResult<Array3<f64>> {
    let views: Vec<_> = planes.map(|p| p.view()).collect();
    ndarray::stack(Axis(0), &views).map_err(|e| errors::value(format!("channel planes: {e}")))
}

/// Channels × n from per-channel curves of one length.
fn rows<'a>(curves: impl Iterator<Item = &'a [f64]>) -> PyResult<Array2<f64>> {
    let views: Vec<_> = curves.map(ndarray::ArrayView1::from).collect();
    ndarray::stack(Axis(0), &views).map_err(|e| errors::value(format!("channel curves: {e}")))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(analyze, m)?)?;
    Ok(())
}
