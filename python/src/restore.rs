//! `denoise` and `restore`: BM3D on an array, and a photo captured through a display and
//! restored, with the same settings and defaults as `udc-studio denoise` and `restore`.
//!
//! Images are float arrays in [0, 1], `H × W` (grey) or `H × W × C`; results come back in the
//! layout they came in.

use std::path::PathBuf;

use clap::ValueEnum;
use ndarray::{Array2, Array3, ArrayViewD, Axis, Ix2, Ix3};
use numpy::{IntoPyArray, PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::restore::capture::REFERENCE_LTR;
use udc_core::restore::{
    CaptureSettings, CgSettings, Denoise, Light, Method, Padding, Recipe, RestoreSettings, simulate,
};
use udc_io::display::restore_report;
use udc_jobs::denoise::{DenoiseFlags, DenoiseMethod};

use crate::{cancel, design, errors};

/// Whether an image came as one grey plane or as channels last.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    Grey,
    ChannelsLast,
}

/// An image array as the core's planes.
fn planes_of(image: &ArrayViewD<'_, f64>, what: &str) -> PyResult<(Vec<Array2<f64>>, Layout)> {
    // The planes are a copy: an image beyond the memory budget is refused before it is made.
    udc_core::budget::check(
        &format!("copying a {:?} image", image.shape()),
        (image.len() * std::mem::size_of::<f64>()) as u64,
        "pass a smaller image",
    )
    .map_err(|e| errors::sim(&e))?;
    if let Ok(grey) = image.view().into_dimensionality::<Ix2>() {
        return Ok((vec![grey.to_owned()], Layout::Grey));
    }
    if let Ok(cube) = image.view().into_dimensionality::<Ix3>()
        && (1..=4).contains(&cube.len_of(Axis(2)))
    {
        let planes = cube.axis_iter(Axis(2)).map(|p| p.to_owned()).collect();
        return Ok((planes, Layout::ChannelsLast));
    }
    Err(errors::value(format!(
        "{what}: expected an H×W grey or H×W×C colour array (C from 1 to 4), got shape {:?}",
        image.shape()
    )))
}

/// Planes back into the layout the caller used.
fn array_of<'py>(
    py: Python<'py>,
    mut planes: Vec<Array2<f64>>,
    layout: Layout,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if layout == Layout::Grey && planes.len() == 1 {
        // The one plane moves into numpy without a copy.
        let plane = planes.pop().unwrap_or_default();
        return Ok(plane.into_dyn().into_pyarray(py));
    }
    let (h, w) = planes.first().map_or((0, 0), Array2::dim);
    if planes.iter().any(|p| p.dim() != (h, w)) {
        return Err(errors::value("image planes of different sizes"));
    }
    // Built row-major (C order), as numpy and image libraries expect H × W × C.
    let cube = Array3::from_shape_fn((h, w, planes.len()), |(y, x, c)| planes[c][[y, x]]);
    Ok(cube.into_dyn().into_pyarray(py))
}

/// BM3D (CBM3D for three channels) of an image with noise variance `sigma2` on its [0, 1] scale.
#[pyfunction]
fn denoise<'py>(
    py: Python<'py>,
    image: PyReadonlyArrayDyn<'py, f64>,
    sigma2: f64,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (planes, layout) = planes_of(&image.as_array(), "image")?;
    let out = cancel::run(py, |progress| {
        udc_core::denoise::bm3d(&planes, sigma2, progress).map_err(|e| errors::sim(&e))
    })?;
    array_of(py, out, layout)
}

/// A photo as the CLI's `restore --image` reads it: H × W × 3 (R, G, B) in [0, 1], scaled down
/// so its longer side is at most `max_side_px` when given.
#[pyfunction]
#[pyo3(signature = (path, max_side_px = None))]
fn load_photo(
    py: Python<'_>,
    path: PathBuf,
    max_side_px: Option<u32>,
) -> PyResult<Bound<'_, PyArrayDyn<f64>>> {
    if max_side_px == Some(0) {
        return Err(errors::value(
            "max_side_px: must be at least 1 pixel (got 0)",
        ));
    }
    let planes = cancel::wait(
        py,
        || udc_io::photo::load_photo(&path, max_side_px).map_err(|e| errors::io(&e)),
        || {},
    )?;
    array_of(py, planes, Layout::ChannelsLast)
}

/// The denoiser of a restoration: `"bm3d"` (the capture's own noise unless `sigma2` is given) or
/// `"none"`, resolved as `restore --denoise … --denoise-sigma2 …` resolves them.
fn denoise_setting(method: &str, sigma2: Option<&Bound<'_, PyAny>>) -> PyResult<Denoise> {
    use udc_jobs::denoise::{Caller, Sigma2Arg};
    let denoise = DenoiseMethod::from_str(method, false).map_err(|_| {
        errors::value(format!(
            "denoise: expected \"bm3d\" or \"none\" (got {method:?})"
        ))
    })?;
    // A number, `"matched"` for the capture's own noise or `"table"` for the authors' table;
    // anything else says so in one line.
    let denoise_sigma2 = match sigma2 {
        None => None,
        Some(v) => Some(if let Ok(x) = v.extract::<f64>() {
            Sigma2Arg::Value(x)
        } else if let Ok(t) = v.extract::<String>() {
            t.parse::<Sigma2Arg>()
                .map_err(|e| errors::value(format!("denoise_sigma2: {e}")))?
        } else {
            return Err(errors::value(format!(
                "denoise_sigma2: expected a number, \"matched\" or \"table\" (got {})",
                v.get_type().name()?
            )));
        }),
    };
    DenoiseFlags {
        denoise,
        denoise_sigma2,
    }
    .resolve_for(Recipe::Iccp21, Caller::Python)
    .map_err(|e| errors::value(format!("{e:#}")))
}

/// The restoration algorithm: `"wiener"` with `nsr`, or `"cg"` with `lambda_` and `iterations`.
fn method_setting(
    name: &str,
    nsr: Option<f64>,
    lambda: Option<f64>,
    iterations: Option<usize>,
) -> PyResult<(Method, Padding)> {
    let cg = CgSettings::default();
    match name {
        "wiener" => Ok((
            Method::Wiener {
                nsr: nsr.unwrap_or(udc_core::restore::THESIS_NSR),
            },
            Padding::Double,
        )),
        // Conjugate gradients do not depend on the padding: the smallest grid, as the CLI.
        "cg" => Ok((
            Method::Cg(CgSettings {
                lambda: lambda.unwrap_or(cg.lambda),
                iterations: iterations.unwrap_or(cg.iterations),
                ..cg
            }),
            Padding::Linear,
        )),
        other => Err(errors::value(format!(
            "method: expected \"wiener\" or \"cg\" (got {other:?})"
        ))),
    }
}

/// Captures `image` through the design at one light level and restores it (denoise, then
/// deblur). Exactly one of `light_e` and `snr_db` is given.
#[pyfunction]
#[pyo3(signature = (
    design_json, image, *, light_e = None, snr_db = None, denoise = "bm3d",
    denoise_sigma2 = None, method = "wiener", nsr = None, lambda_ = None, iterations = None,
    adc_bits = None, noise_seed = 0, backend = "cpu"
))]
#[allow(clippy::too_many_arguments)]
fn restore<'py>(
    py: Python<'py>,
    design_json: &str,
    image: PyReadonlyArrayDyn<'py, f64>,
    light_e: Option<f64>,
    snr_db: Option<f64>,
    denoise: &str,
    denoise_sigma2: Option<Bound<'py, PyAny>>,
    method: &str,
    nsr: Option<f64>,
    lambda_: Option<f64>,
    iterations: Option<usize>,
    adc_bits: Option<u32>,
    noise_seed: u64,
    backend: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let design = design::parse(design_json)?;
    let flag = udc_jobs::backend::BackendFlag {
        backend: crate::analysis::backend(backend)?,
    };
    let route = flag
        .route()
        .map_err(|e| errors::value(format!("backend {backend}: {e}")))?;
    let (photo, layout) = planes_of(&image.as_array(), "image")?;
    // In f32, as `udc-studio restore` holds a photo: the same run gives the same numbers.
    let photo: Vec<Array2<f32>> = photo.into_iter().map(|p| p.mapv(|v| v as f32)).collect();
    let widen = |planes: Vec<Array2<f32>>| -> Vec<Array2<f64>> {
        planes.into_iter().map(|p| p.mapv(f64::from)).collect()
    };
    let light = match (light_e, snr_db) {
        (Some(e), None) => Light::ElectronsAtPeak(e),
        (None, Some(s)) => Light::SnrDb(s),
        _ => {
            return Err(errors::value(
                "give exactly one light level: light_e (electrons at white) or snr_db",
            ));
        }
    };
    let (method, padding) = method_setting(method, nsr, lambda_, iterations)?;
    let denoise = denoise_setting(denoise, denoise_sigma2.as_ref())?;
    let settings = |ltr_relative: f64| RestoreSettings {
        capture: CaptureSettings {
            light,
            adc_bits,
            ltr_relative,
            seed: noise_seed,
            ..CaptureSettings::default()
        },
        method,
        padding,
        denoise,
    };
    // The photo and the settings are checked before the analysis, which is the slow part.
    udc_core::restore::check(&photo, &settings(1.0)).map_err(|e| errors::sim(&e))?;
    if photo.len() != design.channels.len() {
        return Err(errors::value(format!(
            "the design has {} channels but the image has {}; restore needs one image channel \
             per design channel",
            design.channels.len(),
            photo.len()
        )));
    }
    let (result, names, light_warning) = cancel::run(py, |progress| {
        let options = AnalyzeOptions {
            quality: Quality::Full,
            expected_psf: false,
        };
        let analysis =
            analyze_with_route(&design, &options, &route, progress).map_err(|e| errors::sim(&e))?;
        let psfs: Vec<&Array2<f64>> = analysis.channels.iter().map(|c| &c.psf).collect();
        let names: Vec<String> = analysis.channels.iter().map(|c| c.name.clone()).collect();
        let result = simulate(
            &photo,
            &psfs,
            &settings(analysis.ltr / REFERENCE_LTR),
            progress,
        )
        .map_err(|e| errors::sim(&e))?;
        let light_warning = udc_core::analysis::light::capture_light_warning(&analysis);
        Ok((result, names, light_warning))
    })?;
    // A window that drops light makes the capture too clean (conventions §5): a UserWarning,
    // as `restore` prints one line.
    if let Some(w) = light_warning {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        let text = std::ffi::CString::new(w).map_err(|e| errors::value(e.to_string()))?;
        PyErr::warn(py, category.as_any(), &text, 1)?;
    }
    let out = PyDict::new(py);
    // The run's object, with the `backend` object where the CPU was not asked for.
    let mut json = restore_report::run_json(&result, &names, &[]);
    flag.note(&route, &mut json);
    out.set_item(
        "json",
        serde_json::to_string(&json).map_err(|e| errors::value(e.to_string()))?,
    )?;
    out.set_item("adapter", route.adapter())?;
    out.set_item("backend_note", route.note())?;
    out.set_item("psnr_db", result.psnr_db)?;
    out.set_item("ssim", result.ssim)?;
    out.set_item("captured_psnr_db", result.captured_psnr_db)?;
    out.set_item("denoised_psnr_db", result.denoised_psnr_db)?;
    out.set_item("denoise_sigma2", result.denoise.sigma2)?;
    out.set_item("light_e", result.light_e)?;
    out.set_item("snr_db", result.snr_db)?;
    out.set_item("captured", array_of(py, widen(result.captured), layout)?)?;
    if !result.denoised.is_empty() {
        out.set_item("denoised", array_of(py, widen(result.denoised), layout)?)?;
    }
    out.set_item("restored", array_of(py, widen(result.restored), layout)?)?;
    Ok(out)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(denoise, m)?)?;
    m.add_function(wrap_pyfunction!(load_photo, m)?)?;
    m.add_function(wrap_pyfunction!(restore, m)?)?;
    Ok(())
}
