//! Images read and written as they are, for tools that must give back what they were given
//! (the `denoise` command, the denoising test set): grey stays one plane, colour is three
//! (R, G, B), and the file kind is kept.
//!
//! **Reading.** The bytes decide the kind, not the extension: PNG (8/16-bit), TIFF (8/16-bit,
//! and 32-bit float RGB, as far as the `image` crate decodes TIFF) and OpenEXR (half or float;
//! `R, G, B` or `Y`, through [`crate::photo::hdr`]'s reader). Integer samples are scaled to `[0, 1]`
//! (8-bit ÷ 255, 16-bit ÷ 65535), float samples are kept unscaled and unclamped (a noisy image
//! may dip below 0); alpha is dropped. Unlike [`crate::photo::load_photo`], nothing is clamped or
//! repaired: a NaN or infinite sample is an error, since any filter would spread it.
//!
//! **Writing.** PNG and TIFF as 16-bit (grey or RGB; values clipped to `[0, 1]`, level
//! `round(65535·v)`), OpenEXR as 32-bit float (`Y` or `R, G, B`, unscaled), all atomically.

use std::io::Cursor;
use std::path::Path;

use image::{DynamicImage, ImageBuffer, ImageDecoder, ImageFormat, ImageReader, Luma, Rgb};
use ndarray::Array2;

use crate::IoError;
use crate::error::PlanesError;
use crate::photo::MAX_PHOTO_PIXELS;
use crate::photo::hdr::{ExrPrecision, MAX_HDR_BYTES, read_exr, write_exr};
use crate::safe_file::{size_mismatch, write_image};

/// The decoder's allocation cap, as the photo reader's: 64 megapixels of 16-bit RGBA fit.
const MAX_DECODE_BYTES: u64 = 600 * 1024 * 1024;

/// A file kind [`read_planes`] reads and [`write_planes`] writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageKind {
    /// PNG: read at 8 or 16 bits, written at 16.
    Png,
    /// TIFF: read at 8 or 16 bits or as 32-bit float, written at 16 bits.
    Tiff,
    /// OpenEXR: read as half or float, written as 32-bit float.
    Exr,
}

impl ImageKind {
    /// The kind's name for messages.
    pub fn name(self) -> &'static str {
        match self {
            ImageKind::Png => "PNG",
            ImageKind::Tiff => "TIFF",
            ImageKind::Exr => "OpenEXR",
        }
    }

    /// The extensions that name this kind, the usual one first.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            ImageKind::Png => &["png"],
            ImageKind::Tiff => &["tif", "tiff"],
            ImageKind::Exr => &["exr"],
        }
    }

    /// The kind a path's extension names (any case).
    ///
    /// # Errors
    /// [`IoError::Image`] for no extension or one that is not `.png`, `.tif`, `.tiff` or `.exr`.
    pub fn of_extension(path: &Path) -> Result<Self, IoError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        [ImageKind::Png, ImageKind::Tiff, ImageKind::Exr]
            .into_iter()
            .find(|k| k.extensions().contains(&ext.as_str()))
            .ok_or_else(|| {
                let shown = if ext.is_empty() {
                    "no extension".to_string()
                } else {
                    format!("the extension `.{ext}`")
                };
                IoError::Image {
                    path: path.to_path_buf(),
                    message: format!(
                        "unknown image kind ({shown}): name it .png, .tif, .tiff or .exr"
                    ),
                }
            })
    }
}

/// An image's planes and the kind of file they came from.
#[derive(Debug, Clone)]
pub struct ImagePlanes {
    /// One plane (grey) or three (R, G, B), `[row, col]`, all one size.
    pub planes: Vec<Array2<f64>>,
    /// The file kind, from its bytes.
    pub kind: ImageKind,
}

impl ImagePlanes {
    /// `(width, height)` in pixels.
    pub fn size(&self) -> (usize, usize) {
        self.planes
            .first()
            .map_or((0, 0), |p| (p.ncols(), p.nrows()))
    }
}

/// Reads an image as its planes (see the module docs).
///
/// # Errors
/// [`IoError::File`] / [`IoError::NotAFile`] / [`IoError::TooLarge`] when the file cannot be
/// read; [`IoError::Planes`] naming the path when it is not a PNG, TIFF or OpenEXR image, cannot
/// be decoded, is empty, larger than [`MAX_PHOTO_PIXELS`], or holds a NaN or infinite sample.
pub fn read_planes(path: &Path) -> Result<ImagePlanes, IoError> {
    let bad = |error: PlanesError| IoError::Planes {
        path: path.to_path_buf(),
        error,
    };
    let bytes = crate::safe_file::read_bounded(path, MAX_HDR_BYTES, "read the image")?;
    let (planes, kind) = if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        let (planes, _) = read_exr(&bytes, "image").map_err(|e| bad(PlanesError::Exr(e)))?;
        let planes = planes.into_iter().map(|p| p.mapv(f64::from)).collect();
        (planes, ImageKind::Exr)
    } else {
        decode_png_or_tiff(&bytes).map_err(bad)?
    };
    let bad_samples = planes
        .iter()
        .flat_map(|p: &Array2<f64>| p.iter())
        .filter(|v| !v.is_finite())
        .count();
    if bad_samples > 0 {
        return Err(bad(PlanesError::NonFinite {
            samples: bad_samples,
        }));
    }
    Ok(ImagePlanes { planes, kind })
}

/// Decodes PNG or TIFF bytes into 1 or 3 planes, sizes checked from the header first.
fn decode_png_or_tiff(bytes: &[u8]) -> Result<(Vec<Array2<f64>>, ImageKind), PlanesError> {
    let (format, kind) = match image::guess_format(bytes) {
        Ok(ImageFormat::Png) => (ImageFormat::Png, ImageKind::Png),
        Ok(ImageFormat::Tiff) => (ImageFormat::Tiff, ImageKind::Tiff),
        Ok(other) => return Err(PlanesError::UnsupportedFormat(other)),
        Err(_) => return Err(PlanesError::NotAnImage),
    };
    let unreadable = |error| PlanesError::Unreadable {
        format: kind.name(),
        error,
    };
    let reader = || ImageReader::with_format(Cursor::new(bytes), format);
    let (width, height) = reader().into_dimensions().map_err(unreadable)?;
    if width == 0 || height == 0 {
        return Err(PlanesError::Empty { width, height });
    }
    // The photo reader's decode cap is higher because it can scale down; nothing here does.
    if u64::from(width) * u64::from(height) > MAX_PHOTO_PIXELS {
        return Err(PlanesError::TooLarge {
            width,
            height,
            max_pixels: MAX_PHOTO_PIXELS,
        });
    }
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    let mut decoder = reader().into_decoder().map_err(unreadable)?;
    // The decoded samples and the f64 planes built from them, beside the file's bytes.
    let decoded = decoder.color_type();
    let planes = if decoded.has_color() { 3 } else { 1 };
    crate::decode_budget::check(
        "image",
        u64::from(width),
        u64::from(height),
        u64::from(decoded.bytes_per_pixel()) + 8 * planes,
        bytes.len() as u64,
    )
    .map_err(PlanesError::OverBudget)?;
    decoder.set_limits(limits).map_err(unreadable)?;
    let img = DynamicImage::from_decoder(decoder).map_err(unreadable)?;
    Ok((planes_of(&img), kind))
}

/// One plane for grey (with or without alpha), three for colour; integers scaled to `[0, 1]`.
fn planes_of(img: &DynamicImage) -> Vec<Array2<f64>> {
    let (w, h) = (img.width() as usize, img.height() as usize);
    if img.color().has_color() {
        let raw = img.to_rgb32f().into_raw();
        (0..3)
            .map(|c| Array2::from_shape_fn((h, w), |(y, x)| f64::from(raw[(y * w + x) * 3 + c])))
            .collect()
    } else {
        let raw = img.to_luma32f().into_raw();
        vec![Array2::from_shape_fn((h, w), |(y, x)| {
            f64::from(raw[y * w + x])
        })]
    }
}

/// `round(65535·v)` for `v` clipped to `[0, 1]`; NaN → 0.
fn to_u16(v: f64) -> u16 {
    if v.is_nan() {
        0
    } else {
        (65535.0 * v.clamp(0.0, 1.0)).round() as u16
    }
}

/// Writes 1 (grey) or 3 (R, G, B) planes as `kind` (see the module docs).
///
/// # Errors
/// [`IoError::Image`] for a plane count other than 1 or 3, empty planes or planes of different
/// sizes, or an encoder failure; [`IoError::File`] when the file cannot be written.
pub fn write_planes(path: &Path, planes: &[&Array2<f64>], kind: ImageKind) -> Result<(), IoError> {
    let bad = |message: String| IoError::Image {
        path: path.to_path_buf(),
        message,
    };
    let Some(first) = planes.first() else {
        return Err(bad("no planes to write".into()));
    };
    if planes.len() != 1 && planes.len() != 3 {
        return Err(bad(format!(
            "{} planes; an image is written from 1 (grey) or 3 (R, G, B)",
            planes.len()
        )));
    }
    let (rows, cols) = first.dim();
    if rows == 0 || cols == 0 || planes.iter().any(|p| p.dim() != (rows, cols)) {
        return Err(bad("the planes are empty or differ in size".into()));
    }
    let format = match kind {
        ImageKind::Exr => return write_exr(path, planes, ExrPrecision::Float),
        ImageKind::Png => ImageFormat::Png,
        ImageKind::Tiff => ImageFormat::Tiff,
    };
    let w = u32::try_from(cols).map_err(|_| bad("too wide for an image".into()))?;
    let h = u32::try_from(rows).map_err(|_| bad("too tall for an image".into()))?;
    let img = if let [grey] = planes {
        let data: Vec<u16> = grey.iter().map(|v| to_u16(*v)).collect();
        ImageBuffer::<Luma<u16>, _>::from_raw(w, h, data).map(DynamicImage::ImageLuma16)
    } else {
        // `iter()` walks each plane in row-major order, the order of image pixels.
        let data: Vec<u16> = planes[0]
            .iter()
            .zip(planes[1].iter())
            .zip(planes[2].iter())
            .flat_map(|((r, g), b)| [to_u16(*r), to_u16(*g), to_u16(*b)])
            .collect();
        ImageBuffer::<Rgb<u16>, _>::from_raw(w, h, data).map(DynamicImage::ImageRgb16)
    };
    let img = img.ok_or_else(|| size_mismatch(path))?;
    write_image(path, img, format)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn u16_levels_round_and_clip() {
        assert_eq!(to_u16(0.0), 0);
        assert_eq!(to_u16(1.0), 65535);
        assert_eq!(to_u16(1.5), 65535);
        assert_eq!(to_u16(-0.1), 0);
        assert_eq!(to_u16(f64::NAN), 0);
        assert_eq!(to_u16(0.5), 32768);
    }

    #[test]
    fn kinds_follow_the_extension_in_any_case() {
        assert_eq!(
            ImageKind::of_extension(Path::new("a/b.PNG")).ok(),
            Some(ImageKind::Png)
        );
        assert_eq!(
            ImageKind::of_extension(Path::new("b.tiff")).ok(),
            Some(ImageKind::Tiff)
        );
        assert_eq!(
            ImageKind::of_extension(Path::new("b.tif")).ok(),
            Some(ImageKind::Tiff)
        );
        assert_eq!(
            ImageKind::of_extension(Path::new("b.exr")).ok(),
            Some(ImageKind::Exr)
        );
        assert!(ImageKind::of_extension(Path::new("b.jpg")).is_err());
        assert!(ImageKind::of_extension(Path::new("b")).is_err());
    }
}
