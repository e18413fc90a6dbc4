//! What `udc-studio sensor` produces: the JSON of a run (a contract: field names are fixed, new
//! fields may be added, none renamed) and its images.
//!
//! Images written by [`write_truth_images`] and [`write_strategy_images`] (grey 8-bit PNG
//! unless stated):
//! - `truth.png`: the ground truth through the display tone curve; `truth.exr`: the exposed
//!   scene, electrons per unit pixel (float EXR, channel `Y`);
//! - per strategy, named by its name with `/` as `_` (e.g. `vary-gain_vary-bin`):
//!   `…_capture.png` (tone-mapped), `…_capture.exr` (electrons, float `Y`), `…_gain.png` (gain
//!   on a log scale: black = 1, white = the sensor's maximum), `…_bins.png` (bin side: black 1,
//!   then 2, 4, white 8), `…_saturated.png` (white where saturated).
//!
//! With a colour filter array (`"cfa": "rggb"`) `truth.png` and `…_capture.png` are RGB (each
//! channel through the tone curve), `truth.exr` and `…_capture.exr` stay the luminance (`Y`)
//! the scores use, and `truth_rgb.exr` and `…_capture_rgb.exr` (float `R`, `G`, `B`) add the
//! demosaiced capture and the scene's electrons per channel.

use std::path::{Path, PathBuf};

use ndarray::Array2;
use serde_json::{Value, json};

use crate::IoError;
use crate::numbers::json6 as r;
use crate::photo::hdr::{ExrPrecision, write_exr};
use crate::photo::write_map_png;
use udc_core::sensor::colour::CHANNEL_NAMES;
use udc_core::sensor::{BIN_SIZES, SensorRun, StrategyResult};

fn min_max_mean<T: Copy + Into<f64>>(a: &Array2<T>) -> (f64, f64, f64) {
    let (lo, hi, sum) = a.iter().fold(
        (f64::INFINITY, f64::NEG_INFINITY, 0.0),
        |(lo, hi, sum), v| {
            let v: f64 = (*v).into();
            (lo.min(v), hi.max(v), sum + v)
        },
    );
    (lo, hi, sum / a.len() as f64)
}

/// `{min, max, mean}` of a per-pixel gain map.
pub fn gain_summary(gain: &Array2<f32>) -> Value {
    let (lo, hi, mean) = min_max_mean(gain);
    json!({ "min": r(lo), "max": r(hi), "mean": r(mean) })
}

/// `{min, max, mean, fractions: {"1": f, "2": f, "4": f, "8": f}}` of a per-pixel bin map
/// (fractions of the pixels in bins of each side).
pub fn bin_summary(bin: &Array2<u8>) -> Value {
    let (lo, hi, mean) = min_max_mean(bin);
    let mut counts = [0usize; 256];
    for b in bin {
        counts[usize::from(*b)] += 1;
    }
    let n = bin.len().max(1) as f64;
    let fractions: serde_json::Map<String, Value> = BIN_SIZES
        .iter()
        .map(|s| (s.to_string(), r(counts[*s] as f64 / n)))
        .collect();
    json!({ "min": r(lo), "max": r(hi), "mean": r(mean), "fractions": fractions })
}

/// One element of `strategies`; with a colour filter array it also has `channels`:
/// `{"R": {worst_roi_ssim, mean_ssim, psnr_db}, "G": …, "B": …}`.
pub fn strategy_json(s: &StrategyResult) -> Value {
    let roi: Vec<Vec<Value>> = s
        .roi_ssim
        .outer_iter()
        .map(|row| row.iter().map(|v| r(*v)).collect())
        .collect();
    let mut v = json!({
        "name": s.name,
        "worst_roi_ssim": r(s.worst_roi_ssim),
        "mean_ssim": r(s.mean_ssim),
        "psnr_db": r(s.psnr_db),
        "saturated_fraction": r(s.saturated_fraction),
        "saturated_roi_fraction": r(s.saturated_roi_fraction),
        "dynamic_range_db": r(s.dynamic_range_db),
        "gain_map": gain_summary(&s.gain_map),
        "bin_map": bin_summary(&s.bin_map),
        "roi_ssim": roi,
    });
    if let (Some(colour), Some(obj)) = (&s.colour, v.as_object_mut()) {
        let channels: serde_json::Map<String, Value> = CHANNEL_NAMES
            .iter()
            .zip(&colour.channels)
            .map(|(name, c)| {
                let scores = json!({
                    "worst_roi_ssim": r(c.worst_roi_ssim),
                    "mean_ssim": r(c.mean_ssim),
                    "psnr_db": r(c.psnr_db),
                });
                ((*name).to_string(), scores)
            })
            .collect();
        obj.insert("channels".into(), Value::Object(channels));
    }
    v
}

/// The run's numbers: image size, ROI grid, colour filter array (`cfa`: `none` or `rggb`;
/// with one, `metrics` says the scores are on the demosaiced luminance), exposure, timing and
/// `strategies`, each from what the run kept of it through `strategy` (for a kept run,
/// [`strategy_json`]).
pub fn run_json<S>(run: &SensorRun<S>, strategy: impl Fn(&S) -> Value) -> Value {
    let (rows, cols) = run.electrons.dim();
    let (_, max_e, mean_e) = min_max_mean(&run.electrons);
    json!({
        "image_size_px": [cols, rows],
        "roi_px": run.roi_px,
        "roi_grid": [run.grid.rows, run.grid.cols],
        "electrons_per_radiance": r(run.electrons_per_radiance),
        "electrons_mean": r(mean_e),
        "electrons_max": r(max_e),
        "elapsed_ms": (run.elapsed_ms * 1000.0).round() / 1000.0,
        "cfa": run.cfa.label(),
        "metrics": if run.colour_truth.is_some() {
            "luminance of the demosaiced capture; channels per R, G, B"
        } else {
            "luminance"
        },
        "strategies": run.strategies.iter().map(strategy).collect::<Vec<_>>(),
    })
}

/// The file stem of a strategy: its name with `/` as `_`.
pub fn strategy_stem(name: &str) -> String {
    name.replace('/', "_")
}

/// Writes the ground truth's images listed in the module docs into `dir` (created if
/// missing). Returns the paths written.
///
/// # Errors
/// [`IoError::File`] when the folder or a file cannot be written; [`IoError::Image`] when an
/// image cannot be encoded.
pub fn write_truth_images<S>(dir: &Path, run: &SensorRun<S>) -> Result<Vec<PathBuf>, IoError> {
    std::fs::create_dir_all(dir).map_err(|e| IoError::file("create the output folder", dir, e))?;
    let tone = run.tone;
    let mut written = vec![dir.join("truth.png")];
    match &run.colour_truth {
        Some(t) => write_map_png(&written[0], &t.rgb_e.each_ref(), |v| {
            tone.value(f64::from(v))
        })?,
        None => write_map_png(&written[0], &[&run.electrons], |v| tone.value(v))?,
    }
    let p = dir.join("truth.exr");
    write_exr(&p, &[&run.electrons], ExrPrecision::Float)?;
    written.push(p);
    if let Some(t) = &run.colour_truth {
        let p = dir.join("truth_rgb.exr");
        write_exr(&p, &t.rgb_e.each_ref(), ExrPrecision::Float)?;
        written.push(p);
    }
    Ok(written)
}

/// Writes one strategy's images listed in the module docs into `dir` (created if missing);
/// `max_gain` scales the gain map. Returns the paths written.
///
/// # Errors
/// As [`write_truth_images`].
pub fn write_strategy_images(
    dir: &Path,
    s: &StrategyResult,
    max_gain: f64,
) -> Result<Vec<PathBuf>, IoError> {
    std::fs::create_dir_all(dir).map_err(|e| IoError::file("create the output folder", dir, e))?;
    let stem = strategy_stem(&s.name);
    let path = |suffix: &str| dir.join(format!("{stem}_{suffix}"));
    let mut written = Vec::new();
    let p = path("capture.png");
    match &s.colour {
        Some(c) => write_map_png(&p, &c.rgb_e.each_ref(), |v| s.tone.value(f64::from(v)))?,
        None => write_map_png(&p, &[&s.capture], |v| s.tone.value(v))?,
    }
    written.push(p);
    let log_max = max_gain.max(1.0).ln();
    let p = path("gain.png");
    write_map_png(&p, &[&s.gain_map], |g| {
        if log_max > 0.0 {
            f64::from(g).max(1.0).ln() / log_max
        } else {
            0.0
        }
    })?;
    written.push(p);
    let p = path("bins.png");
    write_map_png(&p, &[&s.bin_map], |b| f64::from(b.max(1)).log2() / 3.0)?;
    written.push(p);
    let p = path("saturated.png");
    write_map_png(&p, &[&s.saturated], |v| f64::from(u8::from(v)))?;
    written.push(p);
    let p = path("capture.exr");
    write_exr(&p, &[&s.capture], ExrPrecision::Float)?;
    written.push(p);
    if let Some(c) = &s.colour {
        let p = path("capture_rgb.exr");
        write_exr(&p, &c.rgb_e.each_ref(), ExrPrecision::Float)?;
        written.push(p);
    }
    Ok(written)
}
