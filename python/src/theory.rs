//! `theory`: the Theory view's closed-form pattern beside the simulated one, for teaching.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use udc_core::analysis::analyze::{AnalyzeOptions, analyze_with};
use udc_core::theory::{Theory, compare};

use crate::{analysis, cancel, design, errors};

/// Channel `channel` of the design's analysis beside its theory (the design's own, or its
/// diffraction orders when it names none), sampled as the Theory view samples it.
#[pyfunction]
#[pyo3(signature = (design_json, channel = 0, quality_name = "full"))]
fn theory<'py>(
    py: Python<'py>,
    design_json: &str,
    channel: usize,
    quality_name: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let design = design::parse(design_json)?;
    let options = AnalyzeOptions {
        quality: analysis::quality(quality_name)?,
        expected_psf: false,
    };
    if channel >= design.channels.len() {
        return Err(errors::value(format!(
            "channel: the design has {} channels (0 to {}); got {channel}",
            design.channels.len(),
            design.channels.len().saturating_sub(1)
        )));
    }
    let theory = design.theory.unwrap_or(Theory::Grating);
    let (comparison, wavelength_nm) = cancel::run(py, |progress| {
        let a = analyze_with(&design, &options, progress).map_err(|e| errors::sim(&e))?;
        let wavelength_nm = a.channels.get(channel).map_or(0.0, |c| c.wavelength_nm);
        let c = compare(&design, theory, &a, channel).map_err(|e| errors::sim(&e))?;
        Ok((c, wavelength_nm))
    })?;
    let period_um = design.opening.pitch_um + design.tiling.wiring_gap_um;
    let out = PyDict::new(py);
    out.set_item("theory", theory.name())?;
    out.set_item(
        "formula",
        theory.formula(wavelength_nm, design.optics.focal_length_mm, period_um),
    )?;
    out.set_item("kind", comparison.kind.label())?;
    out.set_item("x_um", comparison.x_um.into_pyarray(py))?;
    out.set_item("simulated", comparison.simulated.into_pyarray(py))?;
    out.set_item("predicted", comparison.predicted.into_pyarray(py))?;
    out.set_item("deviation", comparison.deviation)?;
    out.set_item("note", comparison.note)?;
    match comparison.mtf {
        Some(mtf) => {
            let m = PyDict::new(py);
            m.set_item("freq_cyc_per_px", mtf.freqs_cyc_per_px.into_pyarray(py))?;
            m.set_item("simulated", mtf.simulated.into_pyarray(py))?;
            m.set_item("predicted", mtf.predicted.into_pyarray(py))?;
            m.set_item("deviation", mtf.deviation)?;
            out.set_item("mtf", m)?;
        }
        None => out.set_item("mtf", py.None())?,
    }
    Ok(out)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(theory, m)?)?;
    Ok(())
}
