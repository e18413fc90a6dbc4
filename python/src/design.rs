//! Designs cross the boundary as the design file's JSON text: one format, one validation (the
//! design file's), and the Python `Design` class edits a copy of that document.

use std::path::PathBuf;

use ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use udc_core::Design;
use udc_core::design::TilingMode;
use udc_io::design::{file as design_file, presets as builtin};

use crate::errors;

/// `(name, group, one-line description)` of every built-in preset, in the studio's order.
#[pyfunction]
fn presets() -> Vec<(&'static str, &'static str, String)> {
    builtin::list()
        .into_iter()
        .map(|(name, group, description)| (name, group.label(), description))
        .collect()
}

/// A preset's design file text.
#[pyfunction]
fn preset_json(name: &str) -> PyResult<String> {
    let design = builtin::load_preset(name).map_err(|e| errors::io(&e))?;
    Ok(design_file::to_json(&design))
}

/// A design file's text, validated and written out again in the file format.
#[pyfunction]
fn load_design_json(path: PathBuf) -> PyResult<String> {
    let design = design_file::load_design(&path).map_err(|e| errors::io(&e))?;
    Ok(design_file::to_json(&design))
}

/// Writes a design (given as its JSON text) to a file, atomically.
#[pyfunction]
fn save_design_json(path: PathBuf, text: &str) -> PyResult<()> {
    let design = parse(text)?;
    design_file::save_design(&path, &design).map_err(|e| errors::io(&e))
}

/// Validates design JSON text and returns it in the file format (a `ValueError` names the
/// field that is wrong).
#[pyfunction]
fn check_design_json(text: &str) -> PyResult<String> {
    Ok(design_file::to_json(&parse(text)?))
}

/// The opening's cells (amplitude transmittance in [0, 1]) as an N × N array, rows from the top.
#[pyfunction]
fn cells<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let design = parse(text)?;
    let rows = &design.opening.cells;
    let n = rows.len();
    let grid = Array2::from_shape_fn((n, rows.first().map_or(0, Vec::len)), |(y, x)| {
        rows[y].get(x).copied().unwrap_or(0.0)
    });
    Ok(grid.into_pyarray(py))
}

/// The design with its opening's cells replaced (validated as a design file's would be);
/// emitters on cells that are now open are removed.
#[pyfunction]
fn with_cells(text: &str, cells: PyReadonlyArray2<'_, f64>) -> PyResult<String> {
    let mut design = parse(text)?;
    design.opening.cells = cells
        .as_array()
        .rows()
        .into_iter()
        .map(|row| row.to_vec())
        .collect();
    // Drawn cells replace any polygons, and the emitters keep to the closed cells, as when the
    // opening is edited in the studio.
    design.opening.polygons.clear();
    design.reconcile_subpixels();
    design.validate().map_err(|e| errors::sim(&e))?;
    Ok(design_file::to_json(&design))
}

/// The design with some of its scalar fields changed, validated by the core (its messages name
/// the field, as the CLI's do).
#[pyfunction]
#[pyo3(signature = (text, *, name = None, pitch_um = None, tiling = None, seed = None))]
fn with_fields(
    text: &str,
    name: Option<String>,
    pitch_um: Option<f64>,
    tiling: Option<&str>,
    seed: Option<u64>,
) -> PyResult<String> {
    let mut design = parse(text)?;
    if let Some(name) = name {
        design.name = name;
    }
    if let Some(pitch_um) = pitch_um {
        design.opening.pitch_um = pitch_um;
    }
    if let Some(tiling) = tiling {
        design.tiling.mode = tiling
            .parse::<TilingMode>()
            .map_err(|e| errors::value(e.to_string()))?;
    }
    if let Some(seed) = seed {
        design.tiling.seed = seed;
    }
    design.validate().map_err(|e| errors::sim(&e))?;
    Ok(design_file::to_json(&design))
}

/// Design JSON text as a validated design.
pub fn parse(text: &str) -> PyResult<Design> {
    design_file::parse_design(text).map_err(|e| errors::value(e.to_string()))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_function(wrap_pyfunction!(preset_json, m)?)?;
    m.add_function(wrap_pyfunction!(load_design_json, m)?)?;
    m.add_function(wrap_pyfunction!(save_design_json, m)?)?;
    m.add_function(wrap_pyfunction!(check_design_json, m)?)?;
    m.add_function(wrap_pyfunction!(cells, m)?)?;
    m.add_function(wrap_pyfunction!(with_cells, m)?)?;
    m.add_function(wrap_pyfunction!(with_fields, m)?)?;
    Ok(())
}
