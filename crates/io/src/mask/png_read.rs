//! Reading a PNG mask written by [`super::png`] back: the grey levels, the pixel size (`pHYs`)
//! and the notes (`tEXt` "Description"), so the axis pixel can be sampled at cell centres.

use std::path::Path;

use png::{Decoder, Transformations, Unit};

use super::png::MAX_PNG_PIXELS;
use crate::IoError;

/// A decoded PNG mask: 8-bit drawn fraction per pixel (0 = none, 255 = all), row 0 at the top.
pub(super) struct PngMask {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// Drawn fraction per pixel in 1/255, `width × height`, row-major.
    pub grey: Vec<u8>,
    /// Side of a pixel in µm, from `pHYs` (`None` when the file has no metric `pHYs`).
    pub um_per_px: Option<f64>,
    /// The lines of the `Description` text chunk (the export's notes).
    pub notes: Vec<String>,
}

/// Reads a grayscale PNG mask (1 or 8 bits; 1-bit pixels are expanded to 0 or 255).
pub(super) fn read(path: &Path) -> Result<PngMask, IoError> {
    let err = |message: String| IoError::Mask {
        path: path.to_path_buf(),
        message,
    };
    let bytes = crate::safe_file::read_bounded(path, super::MAX_MASK_BYTES, "read the mask")?;
    let mut decoder = Decoder::new(std::io::Cursor::new(bytes));
    // Low bit depths become 8-bit (scaled to 0–255), 16-bit is cut to its high byte.
    decoder.set_transformations(Transformations::EXPAND | Transformations::STRIP_16);
    let mut reader = decoder
        .read_info()
        .map_err(|e| err(format!("not a readable PNG file: {e}")))?;
    let info = reader.info();
    let (width, height) = (info.width as usize, info.height as usize);
    if width as u64 * height as u64 > MAX_PNG_PIXELS {
        return Err(err(format!(
            "{width}×{height} pixels is more than {MAX_PNG_PIXELS}"
        )));
    }
    let um_per_px = info
        .pixel_dims
        .filter(|d| d.unit == Unit::Meter && d.xppu > 0 && d.xppu == d.yppu)
        .map(|d| 1e6 / f64::from(d.xppu));
    let notes = info
        .uncompressed_latin1_text
        .iter()
        .filter(|t| t.keyword == "Description")
        .flat_map(|t| t.text.lines().map(str::to_string).collect::<Vec<_>>())
        .collect();
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| err(format!("{width}×{height} pixels do not fit in memory")))?;
    // The decoded rows and the grey level kept of each pixel.
    crate::decode_budget::check(
        &format!("mask {}", path.display()),
        width as u64,
        height as u64,
        1,
        size as u64,
    )?;
    let mut buf = vec![0u8; size];
    let frame = reader
        .next_frame(&mut buf)
        .map_err(|e| err(format!("cannot decode the PNG: {e}")))?;
    let channels = frame.color_type.samples();
    // Grey (+ alpha) or RGB(A): the first sample of each pixel is its grey (or red) level.
    let grey = buf[..frame.buffer_size()]
        .chunks(frame.line_size)
        .take(height)
        .flat_map(|row| row.iter().step_by(channels).take(width).copied())
        .collect::<Vec<u8>>();
    if grey.len() != width * height {
        return Err(err("the PNG's rows are shorter than its width".into()));
    }
    Ok(PngMask {
        width,
        height,
        grey,
        um_per_px,
        notes,
    })
}
