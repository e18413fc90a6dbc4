//! Figures handed to Python as arrays plus metadata: the same panels (`udc_core::figure`) the
//! command line draws to PNG and SVG and the studio draws on screen.

use std::path::PathBuf;

use ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use udc_core::figure::{Annotation, Axis, ColorScale, Image, Mark, Paint, Panel, Rgb};

fn axis<'py>(py: Python<'py>, a: &Axis) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("label", &a.label)?;
    d.set_item("unit", &a.unit)?;
    d.set_item("title", a.title())?;
    d.set_item("categories", &a.categories)?;
    d.set_item("downward", a.downward)?;
    d.set_item("log10", a.log10)?;
    d.set_item("view", a.view.map(|v| v.to_vec()))?;
    Ok(d)
}

fn colour(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// `rows` as an N×K float array.
fn array<'py, const K: usize>(
    py: Python<'py>,
    rows: &[[f64; K]],
) -> Bound<'py, numpy::PyArray2<f64>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    Array2::from_shape_vec((rows.len(), K), flat)
        .unwrap_or_else(|_| Array2::zeros((0, K)))
        .into_pyarray(py)
}

/// One panel as a dict: `title`, `x` and `y` axes (`label`, `unit`, `title`, `categories`),
/// `series` (`name`, `colour` as `#rrggbb`, `mark`, `points` N×2, `band` N×3 `[x, low, high]`
/// or `None`) and `annotations` (`kind`, `label` and the kind's numbers).
pub fn panel<'py>(py: Python<'py>, p: &Panel) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("title", &p.title)?;
    d.set_item("x", axis(py, &p.x)?)?;
    d.set_item("y", axis(py, &p.y)?)?;
    let series = PyList::empty(py);
    for s in &p.series {
        let e = PyDict::new(py);
        e.set_item("name", &s.name)?;
        e.set_item("colour", colour(s.colour))?;
        e.set_item(
            "mark",
            match s.mark {
                Mark::Line => "line",
                Mark::Points => "points",
                Mark::LineAndPoints => "line-and-points",
                Mark::DashedLine => "dashed-line",
                Mark::Bars => "bars",
                Mark::Hollow => "hollow",
                Mark::FaintLine => "faint-line",
                Mark::DottedLine => "dotted-line",
                Mark::Rules => "rules",
            },
        )?;
        e.set_item("points", array(py, &s.points))?;
        match &s.band {
            Some(b) => e.set_item("band", array(py, b))?,
            None => e.set_item("band", py.None())?,
        }
        series.append(e)?;
    }
    d.set_item("series", series)?;
    let notes = PyList::empty(py);
    for a in &p.annotations {
        let e = PyDict::new(py);
        match a {
            Annotation::Ring {
                centre,
                radius,
                label,
            } => {
                e.set_item("kind", "ring")?;
                e.set_item("centre", centre.to_vec())?;
                e.set_item("radius", radius)?;
                e.set_item("label", label)?;
            }
            Annotation::Lattice { points, label } => {
                e.set_item("kind", "lattice")?;
                e.set_item("points", array(py, points))?;
                e.set_item("label", label)?;
            }
            Annotation::VLine { x, label } => {
                e.set_item("kind", "vline")?;
                e.set_item("x", x)?;
                e.set_item("label", label)?;
            }
            Annotation::HLine { y, label } => {
                e.set_item("kind", "hline")?;
                e.set_item("y", y)?;
                e.set_item("label", label)?;
            }
        }
        notes.append(e)?;
    }
    d.set_item("annotations", notes)?;
    let images = PyList::empty(py);
    for img in &p.images {
        images.append(image(py, img)?)?;
    }
    d.set_item("images", images)?;
    d.set_item("equal_aspect", p.equal_aspect)?;
    d.set_item("legend_rows", &p.legend_rows)?;
    Ok(d)
}

/// One image as a dict: `name`, `unit`, `values` (rows × columns, row 0 at the top), `extent`
/// `[left, right, bottom, top]` (matplotlib's `imshow` extent), `scale` (`kind` `linear` with
/// `max`, `log` with `reference` and `floor_decades`, or `log-range` with `low` and `high`),
/// `colormap` (matplotlib's name), `paint` (`mapped`, `composite`, `display` or `categories`,
/// then with `categories`: `value`, `label`, `rgb` each) and `rgb` (rows × columns × 3,
/// `uint8`: the colours the studio and the files draw).
fn image<'py>(py: Python<'py>, img: &Image) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &img.name)?;
    d.set_item("unit", &img.unit)?;
    d.set_item("values", img.values.as_ref().clone().into_pyarray(py))?;
    let (cx, cy, w, h) = (img.centre[0], img.centre[1], img.size[0], img.size[1]);
    d.set_item(
        "extent",
        vec![cx - w / 2.0, cx + w / 2.0, cy - h / 2.0, cy + h / 2.0],
    )?;
    let scale = PyDict::new(py);
    match img.scale {
        ColorScale::Linear { max } => {
            scale.set_item("kind", "linear")?;
            scale.set_item("max", max)?;
        }
        ColorScale::Log {
            reference,
            floor_decades,
        } => {
            scale.set_item("kind", "log")?;
            scale.set_item("reference", reference)?;
            scale.set_item("floor_decades", floor_decades)?;
        }
        ColorScale::LogRange { low, high } => {
            scale.set_item("kind", "log-range")?;
            scale.set_item("low", low)?;
            scale.set_item("high", high)?;
        }
    }
    d.set_item("scale", scale)?;
    d.set_item("colormap", img.colormap.name())?;
    let paint = match &img.paint {
        Paint::Mapped => "mapped",
        Paint::Composite(_) => "composite",
        Paint::Display(_) => "display",
        Paint::Categories(_) => "categories",
    };
    d.set_item("paint", paint)?;
    if let Paint::Categories(cats) = &img.paint {
        let list = PyList::empty(py);
        for c in cats {
            let entry = PyDict::new(py);
            entry.set_item("value", c.value)?;
            entry.set_item("label", &c.label)?;
            entry.set_item("rgb", (c.colour.0, c.colour.1, c.colour.2))?;
            list.append(entry)?;
        }
        d.set_item("categories", list)?;
    }
    let (rows, cols) = img.values.dim();
    let flat: Vec<u8> = img
        .colours()
        .into_iter()
        .flat_map(|c| [c.0, c.1, c.2])
        .collect();
    let rgb = ndarray::Array3::from_shape_vec((rows, cols, 3), flat)
        .unwrap_or_else(|_| ndarray::Array3::zeros((0, 0, 3)));
    d.set_item("rgb", rgb.into_pyarray(py))?;
    Ok(d)
}

/// The display workspace's figures of a design (its JSON text): for each channel its PSF,
/// log-PSF (down to `floor_decades` below the peak) and 2-D MTF, then the RGB composite and
/// the MTF curves, as the studio's views draw them (landmarks as `airy` and `orders` ask).
#[pyfunction]
#[pyo3(signature = (design_json, quality, floor_decades, airy, orders, backend = "cpu"))]
fn view_figures<'py>(
    py: Python<'py>,
    design_json: &str,
    quality: &str,
    floor_decades: f64,
    airy: bool,
    orders: bool,
    backend: &str,
) -> PyResult<Bound<'py, PyList>> {
    use udc_core::analysis::analyze::{AnalyzeOptions, analyze_with_route};
    use udc_core::views::{
        Landmarks, MtfFamilies, PsfScale, mtf_curves_panel, mtf2d_panel, psf_panel, rgb_panel,
    };
    if !(floor_decades.is_finite() && floor_decades > 0.0) {
        return Err(crate::errors::value(format!(
            "floor_decades: must be a finite number > 0 (got {floor_decades})"
        )));
    }
    let design = crate::design::parse(design_json)?;
    let options = AnalyzeOptions {
        quality: crate::analysis::quality(quality)?,
        expected_psf: false,
    };
    let route = udc_jobs::backend::route(crate::analysis::backend(backend)?)
        .map_err(|e| crate::errors::value(format!("backend {backend}: {e}")))?;
    let a = crate::cancel::run(py, |progress| {
        analyze_with_route(&design, &options, &route, progress).map_err(|e| crate::errors::sim(&e))
    })?;
    // `auto` on the CPU says why, as `analyze` does.
    if let Some(note) = route.note() {
        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        let text = std::ffi::CString::new(note).map_err(|e| crate::errors::value(e.to_string()))?;
        PyErr::warn(py, category.as_any(), &text, 1)?;
    }
    let marks = Landmarks { airy, orders };
    let list = PyList::empty(py);
    for ch in &a.channels {
        list.append(panel(
            py,
            &psf_panel(&design, &a, ch, PsfScale::Linear, marks),
        )?)?;
        let log = PsfScale::Log { floor_decades };
        list.append(panel(py, &psf_panel(&design, &a, ch, log, marks))?)?;
        list.append(panel(py, &mtf2d_panel(ch, floor_decades))?)?;
    }
    if let Some(rgb) = rgb_panel(&a, floor_decades) {
        list.append(panel(py, &rgb)?)?;
    }
    let curves = mtf_curves_panel(&a, None, MtfFamilies::default(), Some(&design));
    list.append(panel(py, &curves)?)?;
    Ok(list)
}

/// The figures of a sweep's results folder: one panel per plot its spec asks for (or the
/// defaults), as `udc-studio sweep` draws them into `OUT/plots/`.
#[pyfunction]
fn sweep_figures(py: Python<'_>, out: PathBuf) -> PyResult<Bound<'_, PyList>> {
    use udc_io::sweep::plots::{panel_of, plot_data, plot_title, plots_for};
    let manifest =
        udc_io::sweep::manifest::read_manifest(&out).map_err(|e| crate::errors::io(&e))?;
    let list = PyList::empty(py);
    for p in plots_for(&manifest) {
        let data = plot_data(&out, &manifest, &p).map_err(|e| crate::errors::io(&e))?;
        list.append(panel(py, &panel_of(&p, &data, &plot_title(&manifest, &p)))?)?;
    }
    Ok(list)
}

/// Fig. 5.3 for a sensor: (a) contrast and noise at one light level and pitch, with the cutoff
/// and Nyquist marked; (b) the optimal pitch against the light. The studio's Optimal pitch view.
#[pyfunction]
#[pyo3(signature = (light_e_per_um2, pitch_um, sensor, snr_t))]
fn sensor_pitch_figures<'py>(
    py: Python<'py>,
    light_e_per_um2: f64,
    pitch_um: f64,
    sensor: &str,
    snr_t: f64,
) -> PyResult<Bound<'py, PyList>> {
    use udc_core::sensor::{SensorSpec, figures};
    let spec = SensorSpec::named(sensor).ok_or_else(|| {
        crate::errors::value(format!(
            "sensor: unknown {sensor:?} (expected one of: {})",
            udc_core::sensor::PRESET_NAMES.join(", ")
        ))
    })?;
    for (name, v) in [
        ("light_e_per_um2", light_e_per_um2),
        ("pitch_um", pitch_um),
        ("snr_t", snr_t),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(crate::errors::value(format!(
                "{name}: must be a finite number > 0 (got {v})"
            )));
        }
    }
    let list = PyList::empty(py);
    list.append(panel(
        py,
        &figures::contrast_panel(light_e_per_um2, pitch_um, &spec, snr_t),
    )?)?;
    list.append(panel(py, &figures::optimal_pitch_panel(&spec, snr_t))?)?;
    Ok(list)
}

/// `udc-studio figure` for a design given as its JSON, with these parameters (`view`, `out`,
/// `channel`, `width_px`…, as the command's flags); returns what its `--json` prints.
#[pyfunction]
fn save_figure<'py>(
    py: Python<'py>,
    design_json: &str,
    params: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    use udc_jobs::FromParams;
    use udc_jobs::display::{FigureJob, figure_of};
    let design = crate::design::parse(design_json)?;
    let job = FigureJob::from_params(&crate::jobs::params_of(params)?)
        .map_err(|e| crate::jobs::error(&e))?;
    let progress = udc_core::Progress::new();
    let report = crate::cancel::wait(
        py,
        || figure_of(&design, &job, &progress).map_err(|e| crate::jobs::error(&e)),
        || progress.cancel(),
    )?;
    pythonize::pythonize(py, &report.json)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(save_figure, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_figures, m)?)?;
    m.add_function(wrap_pyfunction!(view_figures, m)?)?;
    m.add_function(wrap_pyfunction!(sensor_pitch_figures, m)?)?;
    Ok(())
}
