//! PSF images and MTF tables: what `analyze` computed, as files other tools read.
//!
//! - `psf_C.exr`: the sensor PSF of channel `C`, unscaled (it sums to 1), as 32-bit float EXR.
//!   EXR has no grey pixel type in the `image` crate, so grey is written as RGB with three equal
//!   channels.
//! - `psf_C.png`: 16-bit grey, linear, scaled so the peak is 65535.
//! - `log_psf_C.png`: 8-bit grey of `log10(psf / peak)` from `−`[`LOG_PSF_FLOOR_DECADES`] (black)
//!   to 0 (white); see the constant.
//! - `psf_rgb.exr`: the three channels' PSFs as R, G, B (only for 3-channel analyses).
//! - `mtf.csv`: per channel the horizontal and vertical MTF slices and the radial minimum and mean,
//!   one row per ring (conventions.md §3).
//!
//! Every file is encoded in memory and written through a temp file and a rename, so an
//! interrupted export never leaves half an image behind.

use std::path::{Path, PathBuf};

use image::{DynamicImage, GrayImage, ImageBuffer, ImageFormat, Luma, Rgb, Rgb32FImage};
use ndarray::Array2;

use crate::IoError;
use crate::error::TableError;
use crate::safe_file::{size_mismatch, write_atomic, write_image};
use udc_core::analysis::analyze::{Analysis, ChannelAnalysis};

/// Dynamic range of log-PSF images, in decades. A log-PSF image maps `log10(psf / peak)` linearly
/// from `−LOG_PSF_FLOOR_DECADES` (grey 0, black) to 0 (the peak, white). Values more than this
/// many decades below the peak — including exact zeros, whose logarithm is −∞ — clip to the
/// floor, so the image never holds −∞ or NaN. Six decades show the faint diffraction orders of a
/// display PSF without drowning them in round-off noise.
pub const LOG_PSF_FLOOR_DECADES: f64 = 6.0;

/// The log-PSF level in `[0, 1]` of `value` for a PSF whose peak is `peak_value` (see
/// [`LOG_PSF_FLOOR_DECADES`]). Zero, negative and non-finite ratios sit on the floor (0).
pub fn log_psf_level(value: f64, peak_value: f64) -> f64 {
    let ratio = value / peak_value;
    if !(ratio > 0.0) || !ratio.is_finite() {
        return 0.0;
    }
    let decades = ratio.log10().clamp(-LOG_PSF_FLOOR_DECADES, 0.0);
    1.0 + decades / LOG_PSF_FLOOR_DECADES
}

/// Largest finite value of the PSF, or 0 when it has none above 0.
fn peak_of(psf: &Array2<f64>) -> f64 {
    psf.iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
}

/// Image width and height of a PSF (`[row, col]` → `(cols, rows)`).
fn image_size(path: &Path, psf: &Array2<f64>) -> Result<(u32, u32), IoError> {
    let (rows, cols) = psf.dim();
    let bad = |why: &str| IoError::Image {
        path: path.to_path_buf(),
        message: format!("cannot write a {rows}×{cols} PSF: {why}"),
    };
    if rows == 0 || cols == 0 {
        return Err(bad("it is empty"));
    }
    let w = u32::try_from(cols).map_err(|_| bad("too large for an image"))?;
    let h = u32::try_from(rows).map_err(|_| bad("too large for an image"))?;
    Ok((w, h))
}

/// Writes a PSF as a 32-bit float EXR, values unscaled, grey as three equal RGB channels.
///
/// # Errors
/// [`IoError::Image`] for an empty PSF or an encoder failure, [`IoError::File`] when the file
/// cannot be written.
pub fn write_psf_exr(path: &Path, psf: &Array2<f64>) -> Result<(), IoError> {
    write_rgb_psf_exr(path, [psf, psf, psf])
}

/// Writes three PSFs of the same size as the R, G and B channels of a 32-bit float EXR.
///
/// # Errors
/// [`IoError::Image`] when the PSFs are empty or differ in size, or the encoder fails;
/// [`IoError::File`] when the file cannot be written.
pub fn write_rgb_psf_exr(path: &Path, psfs: [&Array2<f64>; 3]) -> Result<(), IoError> {
    let (w, h) = image_size(path, psfs[0])?;
    if psfs.iter().any(|p| p.dim() != psfs[0].dim()) {
        return Err(IoError::Image {
            path: path.to_path_buf(),
            message: format!(
                "the R, G, B PSFs differ in size ({:?}, {:?}, {:?})",
                psfs[0].dim(),
                psfs[1].dim(),
                psfs[2].dim()
            ),
        });
    }
    // `iter()` walks each array in logical row-major order, the order of image pixels.
    let data: Vec<f32> = psfs[0]
        .iter()
        .zip(psfs[1].iter())
        .zip(psfs[2].iter())
        .flat_map(|((r, g), b)| [*r as f32, *g as f32, *b as f32])
        .collect();
    let img: Rgb32FImage =
        ImageBuffer::<Rgb<f32>, _>::from_raw(w, h, data).ok_or_else(|| size_mismatch(path))?;
    write_image(path, DynamicImage::ImageRgb32F(img), ImageFormat::OpenExr)
}

/// Writes a PSF as a 16-bit grey PNG scaled so its peak is 65535 (zero stays 0; negative and
/// non-finite values are written as 0). An all-zero PSF gives a black image.
///
/// # Errors
/// As [`write_psf_exr`].
pub fn write_psf_png16(path: &Path, psf: &Array2<f64>) -> Result<(), IoError> {
    let (w, h) = image_size(path, psf)?;
    let peak = peak_of(psf);
    let scale = if peak > 0.0 {
        f64::from(u16::MAX) / peak
    } else {
        0.0
    };
    let data: Vec<u16> = psf
        .iter()
        .map(|v| {
            if v.is_finite() {
                (v * scale).round().clamp(0.0, f64::from(u16::MAX)) as u16
            } else {
                0
            }
        })
        .collect();
    let img =
        ImageBuffer::<Luma<u16>, _>::from_raw(w, h, data).ok_or_else(|| size_mismatch(path))?;
    write_image(path, DynamicImage::ImageLuma16(img), ImageFormat::Png)
}

/// Writes the log-PSF as an 8-bit grey PNG: grey = round(255 · level), level per
/// [`log_psf_level`] (0 at [`LOG_PSF_FLOOR_DECADES`] below the peak, 1 at the peak).
///
/// # Errors
/// As [`write_psf_exr`].
pub fn write_log_psf_png(path: &Path, psf: &Array2<f64>) -> Result<(), IoError> {
    let (w, h) = image_size(path, psf)?;
    let peak = peak_of(psf);
    let data: Vec<u8> = psf
        .iter()
        .map(|v| (255.0 * log_psf_level(*v, peak)).round() as u8)
        .collect();
    let img = GrayImage::from_raw(w, h, data).ok_or_else(|| size_mismatch(path))?;
    write_image(path, DynamicImage::ImageLuma8(img), ImageFormat::Png)
}

/// A CSV field, quoted when it holds a comma, quote or line break (RFC 4180).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The MTF table as CSV text (see [`write_mtf_csv`]).
///
/// # Errors
/// [`TableError::NoChannel`] when the analysis has no channel, [`TableError::MtfRings`] when its
/// channels' MTFs have different numbers of rings.
pub fn mtf_csv(analysis: &Analysis) -> Result<String, TableError> {
    let first = analysis.channels.first().ok_or(TableError::NoChannel)?;
    let freqs = first.mtf.freqs_cyc_per_px();
    for ch in &analysis.channels {
        let m = &ch.mtf;
        let n = freqs.len();
        if [
            m.horizontal.len(),
            m.vertical.len(),
            m.radial_min.len(),
            m.radial_mean.len(),
        ] != [n; 4]
        {
            return Err(TableError::MtfRings {
                channel: ch.name.clone(),
                rings: n,
                first: first.name.clone(),
            });
        }
    }
    let mut out = String::from("freq_cyc_per_px");
    for ch in &analysis.channels {
        for column in ["horizontal", "vertical", "radial_min", "radial_mean"] {
            out.push(',');
            out.push_str(&csv_field(&format!("{}_{column}", ch.name)));
        }
    }
    out.push('\n');
    for (d, f) in freqs.iter().enumerate() {
        out.push_str(&f.to_string());
        for ch in &analysis.channels {
            let m = &ch.mtf;
            for v in [
                m.horizontal[d],
                m.vertical[d],
                m.radial_min[d],
                m.radial_mean[d],
            ] {
                out.push(',');
                out.push_str(&v.to_string());
            }
        }
        out.push('\n');
    }
    Ok(out)
}

/// Writes the MTF table: header `freq_cyc_per_px,R_horizontal,R_vertical,R_radial_min,
/// R_radial_mean,G_…` (one group of four per channel, named after it), then one row per ring
/// `d = 0 … N/2 − 1` at frequency `d/N` cycles/pixel.
///
/// # Errors
/// [`IoError::Table`] for an analysis without channels or with mismatched MTFs,
/// [`IoError::File`] when the file cannot be written.
pub fn write_mtf_csv(path: &Path, analysis: &Analysis) -> Result<(), IoError> {
    let text = mtf_csv(analysis).map_err(|error| IoError::Table {
        path: path.to_path_buf(),
        error,
    })?;
    write_atomic(path, text.as_bytes())
}

/// File-name stems for the channels: the name with anything but ASCII letters, digits, `-` and
/// `_` replaced by `_` (channel names are user text), made unique by appending the index.
fn file_stems(channels: &[ChannelAnalysis]) -> Vec<String> {
    let mut stems: Vec<String> = Vec::with_capacity(channels.len());
    for (i, ch) in channels.iter().enumerate() {
        let mut stem: String = ch
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        if stem.is_empty() || stems.contains(&stem) || stem.eq_ignore_ascii_case("rgb") {
            stem = format!("{stem}{i}");
        }
        stems.push(stem);
    }
    stems
}

/// The channels to write as R, G, B: by name when they are called R, G and B (in any order),
/// otherwise in analysis order. `None` unless there are exactly three channels.
fn rgb_channels(channels: &[ChannelAnalysis]) -> Option<[&ChannelAnalysis; 3]> {
    let [a, b, c] = channels else { return None };
    let named = |n: &str| {
        let mut it = channels.iter().filter(|ch| ch.name.eq_ignore_ascii_case(n));
        match (it.next(), it.next()) {
            (Some(ch), None) => Some(ch),
            _ => None,
        }
    };
    match (named("R"), named("G"), named("B")) {
        (Some(r), Some(g), Some(b)) => Some([r, g, b]),
        _ => Some([a, b, c]),
    }
}

/// Writes every output of an analysis into `dir` (created if needed): per channel `C`
/// `psf_C.exr`, `psf_C.png` and `log_psf_C.png`, then `psf_rgb.exr` when there are exactly three
/// channels, then `mtf.csv`. Channel names are made file-safe (see the module docs).
///
/// # Errors
/// [`IoError::File`] when the folder or a file cannot be written; [`IoError::Image`] /
/// [`IoError::Table`] when a PSF or the MTF cannot be encoded. Files written before the error stay.
pub fn write_analysis_outputs(dir: &Path, analysis: &Analysis) -> Result<Vec<PathBuf>, IoError> {
    std::fs::create_dir_all(dir).map_err(|e| IoError::file("create the output folder", dir, e))?;
    let mut written = Vec::new();
    for (ch, stem) in analysis.channels.iter().zip(file_stems(&analysis.channels)) {
        let exr = dir.join(format!("psf_{stem}.exr"));
        write_psf_exr(&exr, &ch.psf)?;
        written.push(exr);
        let png = dir.join(format!("psf_{stem}.png"));
        write_psf_png16(&png, &ch.psf)?;
        written.push(png);
        let log = dir.join(format!("log_psf_{stem}.png"));
        write_log_psf_png(&log, &ch.psf)?;
        written.push(log);
    }
    if let Some([r, g, b]) = rgb_channels(&analysis.channels) {
        let rgb = dir.join("psf_rgb.exr");
        write_rgb_psf_exr(&rgb, [&r.psf, &g.psf, &b.psf])?;
        written.push(rgb);
    }
    let csv = dir.join("mtf.csv");
    write_mtf_csv(&csv, analysis)?;
    written.push(csv);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_levels_span_the_floor_and_never_go_below_it() {
        assert_eq!(log_psf_level(2.0, 2.0), 1.0);
        assert_eq!(log_psf_level(1e-3, 1.0), 0.5);
        assert_eq!(log_psf_level(1e-6, 1.0), 0.0);
        assert_eq!(log_psf_level(1e-9, 1.0), 0.0);
        assert_eq!(log_psf_level(0.0, 1.0), 0.0);
        assert_eq!(log_psf_level(-1.0, 1.0), 0.0);
        assert_eq!(log_psf_level(f64::NAN, 1.0), 0.0);
        assert_eq!(log_psf_level(1.0, 0.0), 0.0);
    }

    #[test]
    fn csv_fields_with_commas_are_quoted() {
        assert_eq!(csv_field("R"), "R");
        assert_eq!(csv_field("a,b\"c"), "\"a,b\"\"c\"");
    }
}
