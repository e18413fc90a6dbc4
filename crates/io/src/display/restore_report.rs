//! What `udc-studio restore` produces: the JSON of its runs (a contract other tools depend on:
//! field names are fixed, new fields may be added, none renamed) and the images of one run.

use std::path::{Path, PathBuf};

use ndarray::Array2;
use serde_json::{Value, json};

use crate::IoError;
use crate::numbers::json6 as r;
use crate::photo::{DIFFERENCE_GAIN, write_difference_png, write_photo_exr, write_photo_png};
use udc_core::Sample;
use udc_core::phase::imaging::CompareRow;
use udc_core::restore::{DenoiseUsed, Intermediate, RestoreResult};

/// `{"method": "bm3d"|"none", "sigma2": σ² BM3D got on the capture's scale (white ≈ 1) or null,
/// "sigma2_source": "iccp21"|"iccv23"|"override"|null}` of one run.
pub fn denoise_json(used: &DenoiseUsed) -> Value {
    json!({
        "method": used.setting.method_name(),
        "sigma2": used.sigma2.map_or(Value::Null, r),
        "sigma2_source": used.source(),
    })
}

/// One element of `runs`: the light level and the scores, pooled and per channel (named
/// `channel_names[c]`, or by index when a name is missing). `outputs` are the files written.
pub fn run_json<T>(
    result: &RestoreResult<T>,
    channel_names: &[String],
    outputs: &[PathBuf],
) -> Value {
    let channels: Vec<Value> = result
        .channels
        .iter()
        .enumerate()
        .map(|(c, ch)| {
            let mut v = json!({
                "name": channel_names.get(c).cloned().unwrap_or_else(|| c.to_string()),
                "psnr_db": r(ch.psnr_db),
                "ssim": r(ch.ssim),
                "captured_psnr_db": r(ch.captured_psnr_db),
                "denoised_psnr_db": ch.denoised_psnr_db.map_or(Value::Null, r),
                "saturated_fraction": r(ch.saturated_fraction),
            });
            if let (Some(cg), Some(obj)) = (&ch.cg, v.as_object_mut()) {
                obj.insert("cg_iterations".into(), json!(cg.iterations));
                obj.insert(
                    "cg_relative_residual".into(),
                    r(cg.relative_residual.last().copied().unwrap_or(f64::NAN)),
                );
            }
            v
        })
        .collect();
    json!({
        "light_e": r(result.light_e),
        "snr_db": r(result.snr_db),
        "electrons_per_unit": r(result.electrons_per_unit),
        "psnr_db": r(result.psnr_db),
        "ssim": r(result.ssim),
        "captured_psnr_db": r(result.captured_psnr_db),
        "denoise": denoise_json(&result.denoise),
        "denoised_psnr_db": result.denoised_psnr_db.map_or(Value::Null, r),
        "elapsed_ms": (result.elapsed_ms * 1000.0).round() / 1000.0,
        "channels": channels,
        "outputs": outputs.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
    })
}

/// Writes one run's images into `dir` (created if needed), each name starting with `stem`:
/// `{stem}_captured.png` and `.exr`, `{stem}_denoised.png` and `.exr` (only when a denoiser
/// ran), `{stem}_restored.png` and `.exr`, and `{stem}_difference.png` (`|restored − truth|` ×
/// [`DIFFERENCE_GAIN`]). PNGs are 8-bit, clipped to `[0, 1]`; EXRs are float, unclipped.
/// Returns the paths in that order.
///
/// # Errors
/// [`IoError::File`] when the folder or a file cannot be written; [`IoError::Image`] when the
/// planes cannot be encoded. Files written before the error stay.
pub fn write_run_images<T: Sample>(
    dir: &Path,
    stem: &str,
    truth: &[Array2<T>],
    result: &RestoreResult<T>,
) -> Result<Vec<PathBuf>, IoError> {
    write_capture_images(
        dir,
        stem,
        truth,
        &CaptureImages {
            captured: &result.captured,
            denoised: &result.denoised,
            restored: &result.restored,
        },
    )
}

/// The planes of one capture and its restoration; `denoised` is empty when no denoiser ran.
#[derive(Debug, Clone, Copy)]
pub struct CaptureImages<'a, T = f64> {
    /// The capture per channel.
    pub captured: &'a [Array2<T>],
    /// The denoised capture per channel, or empty.
    pub denoised: &'a [Array2<T>],
    /// The restoration per channel.
    pub restored: &'a [Array2<T>],
}

/// [`write_run_images`] for any capture and restoration of `truth` (the phase masks' too).
///
/// # Errors
/// As [`write_run_images`].
pub fn write_capture_images<T: Sample>(
    dir: &Path,
    stem: &str,
    truth: &[Array2<T>],
    images: &CaptureImages<'_, T>,
) -> Result<Vec<PathBuf>, IoError> {
    let mut written = write_stage_images(dir, stem, Intermediate::Captured, images.captured)?;
    if !images.denoised.is_empty() {
        written.extend(write_stage_images(
            dir,
            stem,
            Intermediate::Denoised,
            images.denoised,
        )?);
    }
    written.extend(write_restored_images(dir, stem, truth, images.restored)?);
    Ok(written)
}

/// Writes an intermediate stage's planes as `{stem}_captured` or `{stem}_denoised`, `.png`
/// and `.exr`, into `dir` (created if needed): what `restore --out` writes the moment
/// `restore::simulate_with` hands the planes over. Returns the paths.
///
/// # Errors
/// As [`write_run_images`].
pub fn write_stage_images<T: Sample>(
    dir: &Path,
    stem: &str,
    stage: Intermediate,
    planes: &[Array2<T>],
) -> Result<Vec<PathBuf>, IoError> {
    std::fs::create_dir_all(dir).map_err(|e| IoError::file("create the output folder", dir, e))?;
    let name = match stage {
        Intermediate::Captured => "captured",
        Intermediate::Denoised => "denoised",
    };
    let planes: Vec<&Array2<T>> = planes.iter().collect();
    let png = dir.join(format!("{stem}_{name}.png"));
    write_photo_png(&png, &planes)?;
    let exr = dir.join(format!("{stem}_{name}.exr"));
    write_photo_exr(&exr, &planes)?;
    Ok(vec![png, exr])
}

/// Writes the restoration as `{stem}_restored.png` and `.exr` and its difference from `truth`
/// as `{stem}_difference.png` into `dir` (created if needed). Returns the paths.
///
/// # Errors
/// As [`write_run_images`].
pub fn write_restored_images<T: Sample>(
    dir: &Path,
    stem: &str,
    truth: &[Array2<T>],
    restored: &[Array2<T>],
) -> Result<Vec<PathBuf>, IoError> {
    std::fs::create_dir_all(dir).map_err(|e| IoError::file("create the output folder", dir, e))?;
    let restored: Vec<&Array2<T>> = restored.iter().collect();
    let truth: Vec<&Array2<T>> = truth.iter().collect();
    let png = dir.join(format!("{stem}_restored.png"));
    write_photo_png(&png, &restored)?;
    let exr = dir.join(format!("{stem}_restored.exr"));
    write_photo_exr(&exr, &restored)?;
    let difference = dir.join(format!("{stem}_difference.png"));
    write_difference_png(&difference, &restored, &truth, DIFFERENCE_GAIN)?;
    Ok(vec![png, exr, difference])
}

/// Draws planes as the Restore view's picture of `name` (`captured`, `denoised`, `restored`,
/// `difference`: brightened by [`DIFFERENCE_GAIN`]), a figure with pixel axes, as
/// `{stem}_{name}-figure.svg` and `.png` in `dir` (created if needed). Returns the paths.
///
/// # Errors
/// As [`write_run_images`].
pub fn write_stage_figure<T: Sample>(
    dir: &Path,
    stem: &str,
    name: &str,
    planes: &[Array2<T>],
) -> Result<Vec<PathBuf>, IoError> {
    std::fs::create_dir_all(dir).map_err(|e| IoError::file("create the output folder", dir, e))?;
    let gain = if name == "difference" {
        DIFFERENCE_GAIN
    } else {
        1.0
    };
    let refs: Vec<&Array2<T>> = planes.iter().collect();
    let panel = udc_core::restore::figures::photo_panel(&format!("{stem}: {name}"), &refs, gain);
    crate::figure::write_panel(dir, &format!("{stem}_{name}-figure"), &panel)
}

/// The rows of a phase-mask setup comparison as CSV (`phase restore --compare --out` and the
/// studio's "Save CSV…"): one line per setup, photo and light level, full precision.
pub fn compare_csv(rows: &[CompareRow], photo_names: &[String]) -> String {
    let quote = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    let mut text = String::from("setup,ltr,photo,photons,psnr_db,ssim,unpassed_mse\n");
    for r in rows {
        let photo = photo_names.get(r.photo).map_or("", String::as_str);
        text.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            quote(&r.label),
            r.ltr,
            quote(photo),
            r.photons,
            r.psnr_db,
            r.ssim,
            r.unpassed_mse
        ));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn infinite_psnr_is_null_and_numbers_are_rounded() {
        assert_eq!(r(f64::INFINITY), Value::Null);
        assert_eq!(r(f64::NAN), Value::Null);
        assert_eq!(r(27.123456789), json!(27.1235));
        assert_eq!(r(0.0), json!(0.0));
    }
}
