//! Raw frames of a measured PSF, in the file's own units: `.npy` (numpy, any real dtype,
//! `H×W` or `H×W×C`), MATLAB v5 `.mat` (a numeric variable, chosen by name when there are
//! several), TIFF (8/16/32-bit or float, grey or RGB, one page of a multi-page file), PNG
//! (8 or 16 bit) and OpenEXR. The size is checked from the header before anything is decoded.

use std::io::Cursor;
use std::path::Path;

use ndarray::{Array2, Array3, ArrayD, Axis, Ix2, Ix3};

use crate::IoError;
use crate::photo::MAX_DECODED_PIXELS;

/// The largest file read (a float64 frame of 64 megapixels).
pub const MAX_FRAME_BYTES: u64 = 8 * MAX_DECODED_PIXELS;

/// How the samples encode light.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// Proportional to the light (raw sensor counts, float HDR).
    Linear,
    /// 8-bit, gamma-encoded for display: linearised on reading (γ = 2.2), but not radiometric.
    Gamma8,
}

/// A frame as read: one plane (grey) or three (R, G, B), in the file's units.
#[derive(Debug, Clone)]
pub struct RawFrame {
    /// The planes, `[row, col]`.
    pub planes: Vec<Array2<f64>>,
    /// The value of a saturated sample (the integer type's maximum); `None` for float data.
    pub full_scale: Option<f64>,
    /// How the samples encode light.
    pub encoding: Encoding,
    /// Pages (images) in the file; the one read is `page`, counted from 1.
    pub pages: usize,
    /// The page read.
    pub page: usize,
    /// What the reader did or noticed, one line each (a warning says "warning: " first).
    pub notes: Vec<String>,
}

/// Which part of a file to read.
#[derive(Debug, Clone, Default)]
pub struct FramePick {
    /// The page of a multi-page TIFF, from 1; required when it has several.
    pub page: Option<usize>,
    /// The variable of a `.mat` file; required when it holds several numeric ones.
    pub variable: Option<String>,
}

fn bad(path: &Path, message: impl Into<String>) -> IoError {
    IoError::Image {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

fn check_pixels(path: &Path, width: u64, height: u64) -> Result<(), IoError> {
    if width == 0 || height == 0 {
        return Err(bad(
            path,
            format!("the frame is empty ({width}×{height} pixels)"),
        ));
    }
    if width * height > MAX_DECODED_PIXELS {
        return Err(bad(
            path,
            format!(
                "the frame is {width}×{height} pixels; at most {} megapixels are read (crop it \
                 around the PSF first)",
                MAX_DECODED_PIXELS / 1_000_000
            ),
        ));
    }
    crate::decode_budget::check(
        &format!("PSF frame {}", path.display()),
        width,
        height,
        FRAME_DECODE_BYTES_PER_PIXEL,
        0,
    )
    .map_err(IoError::Invalid)
}

/// Peak bytes per pixel of a frame's decode: an RGB frame's samples widened to f64 beside the
/// three f64 planes made from them (the file itself was checked as it was read).
const FRAME_DECODE_BYTES_PER_PIXEL: u64 = 2 * 3 * 8;

/// Reads one frame of `path`, choosing its kind by its first bytes (`.npy`, `.mat` v5, TIFF,
/// PNG, OpenEXR).
///
/// # Errors
/// An unreadable or unknown file, a size over [`MAX_DECODED_PIXELS`], a `.mat` v7.3 (HDF5)
/// file, a variable or page that is missing or not chosen, non-finite samples.
pub fn read_frame(path: &Path, pick: &FramePick) -> Result<RawFrame, IoError> {
    let bytes = crate::safe_file::read_bounded(path, MAX_FRAME_BYTES, "read the PSF frame")?;
    let frame = if bytes.starts_with(b"\x93NUMPY") {
        npy(path, &bytes)?
    } else if bytes.starts_with(b"MATLAB") {
        mat(path, &bytes, pick.variable.as_deref())?
    } else if bytes.starts_with(b"II*\0") || bytes.starts_with(b"MM\0*") {
        tiff(path, &bytes, pick.page)?
    } else if bytes.starts_with(b"\x89PNG") {
        png(path, &bytes)?
    } else if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        let what = format!("PSF frame {}", path.display());
        let (planes, _) = crate::photo::hdr::read_exr(&bytes, &what)
            .map_err(|e| bad(path, format!("not a readable OpenEXR file: {e}")))?;
        let planes: Vec<Array2<f64>> = planes.into_iter().map(|p| p.mapv(f64::from)).collect();
        let planes = if planes.len() >= 3 {
            planes.into_iter().take(3).collect()
        } else {
            planes.into_iter().take(1).collect()
        };
        linear(planes, None)
    } else if bytes.starts_with(b"\x89HDF") {
        return Err(bad(
            path,
            "an HDF5 file: save the array as .npy or as a MATLAB v7 .mat",
        ));
    } else {
        return Err(bad(
            path,
            "not a PSF file this reads: .npy, MATLAB v5 .mat, TIFF, PNG or OpenEXR",
        ));
    };
    if let Some(((r, c), v)) = frame
        .planes
        .iter()
        .find_map(|p| p.indexed_iter().find(|(_, v)| !v.is_finite()))
    {
        return Err(bad(path, format!("holds {v} at row {r}, column {c}")));
    }
    Ok(frame)
}

fn linear(planes: Vec<Array2<f64>>, full_scale: Option<f64>) -> RawFrame {
    RawFrame {
        planes,
        full_scale,
        encoding: Encoding::Linear,
        pages: 1,
        page: 1,
        notes: Vec::new(),
    }
}

/// Planes of a 2-D (grey) or 3-D (`H×W×C`, C = 1 or 3; or `C×H×W` with C = 3) array.
fn planes_of(path: &Path, a: ArrayD<f64>) -> Result<Vec<Array2<f64>>, IoError> {
    let shape = a.shape().to_vec();
    match shape.len() {
        2 => {
            check_pixels(path, shape[1] as u64, shape[0] as u64)?;
            Ok(vec![
                a.into_dimensionality::<Ix2>()
                    .map_err(|e| bad(path, e.to_string()))?,
            ])
        }
        3 => {
            let a: Array3<f64> = a
                .into_dimensionality::<Ix3>()
                .map_err(|e| bad(path, e.to_string()))?;
            let (axis, n) = match shape.as_slice() {
                [_, _, c] if *c == 1 || *c == 3 => (2, *c),
                [c, _, _] if *c == 3 => (0, 3),
                _ => {
                    return Err(bad(
                        path,
                        format!("an array of shape {shape:?}: a PSF is H×W, or H×W×3 (R, G, B)"),
                    ));
                }
            };
            let planes: Vec<Array2<f64>> = (0..n)
                .map(|c| a.index_axis(Axis(axis), c).to_owned())
                .collect();
            if let Some(p) = planes.first() {
                check_pixels(path, p.ncols() as u64, p.nrows() as u64)?;
            }
            Ok(planes)
        }
        _ => Err(bad(
            path,
            format!("an array of shape {shape:?}: a PSF is H×W, or H×W×3 (R, G, B)"),
        )),
    }
}

/// A `.npy` array of any real dtype; integer types set the full scale.
fn npy(path: &Path, bytes: &[u8]) -> Result<RawFrame, IoError> {
    use ndarray_npy::ReadNpyExt;
    let read_err =
        |e: ndarray_npy::ReadNpyError| bad(path, format!("not a readable .npy array: {e}"));
    // Try the dtypes a PSF comes in, widest first; the header names one.
    macro_rules! try_as {
        ($t:ty, $full:expr) => {
            if let Ok(a) = ArrayD::<$t>::read_npy(Cursor::new(bytes)) {
                return Ok(linear(planes_of(path, a.mapv(|v| v as f64))?, $full));
            }
        };
    }
    try_as!(f64, None);
    try_as!(f32, None);
    try_as!(u16, Some(f64::from(u16::MAX)));
    try_as!(u8, Some(f64::from(u8::MAX)));
    try_as!(u32, Some(f64::from(u32::MAX)));
    try_as!(i32, None);
    try_as!(i16, None);
    try_as!(i64, None);
    try_as!(u64, None);
    Err(read_err(
        ArrayD::<f64>::read_npy(Cursor::new(bytes))
            .err()
            .unwrap_or(ndarray_npy::ReadNpyError::MissingData),
    ))
}

/// A MATLAB v5 file's numeric variable (column-major, as MATLAB stores it).
fn mat(path: &Path, bytes: &[u8], variable: Option<&str>) -> Result<RawFrame, IoError> {
    let header = String::from_utf8_lossy(&bytes[..bytes.len().min(116)]);
    if header.contains("MATLAB 7.3") {
        return Err(bad(
            path,
            "a MATLAB v7.3 file, which is HDF5: save it with save(..., '-v7') or as .npy",
        ));
    }
    let file = matfile::MatFile::parse(Cursor::new(bytes))
        .map_err(|e| bad(path, format!("not a readable MATLAB v5 file: {e:?}")))?;
    let names: Vec<&str> = file.arrays().iter().map(matfile::Array::name).collect();
    let array = match variable {
        Some(v) => file.find_by_name(v).ok_or_else(|| {
            bad(
                path,
                format!("no variable `{v}` (it holds: {})", names.join(", ")),
            )
        })?,
        None => match file.arrays().as_slice() {
            [one] => one,
            [] => return Err(bad(path, "the file holds no numeric variable")),
            _ => {
                return Err(bad(
                    path,
                    format!(
                        "it holds several variables ({}): choose one with --variable",
                        names.join(", ")
                    ),
                ));
            }
        },
    };
    use matfile::NumericData as D;
    let (real, full): (Vec<f64>, Option<f64>) = match array.data() {
        D::Double { real, .. } => (real.clone(), None),
        D::Single { real, .. } => (real.iter().map(|v| f64::from(*v)).collect(), None),
        D::UInt16 { real, .. } => (
            real.iter().map(|v| f64::from(*v)).collect(),
            Some(f64::from(u16::MAX)),
        ),
        D::UInt8 { real, .. } => (
            real.iter().map(|v| f64::from(*v)).collect(),
            Some(f64::from(u8::MAX)),
        ),
        D::UInt32 { real, .. } => (
            real.iter().map(|v| f64::from(*v)).collect(),
            Some(f64::from(u32::MAX)),
        ),
        D::Int16 { real, .. } => (real.iter().map(|v| f64::from(*v)).collect(), None),
        D::Int32 { real, .. } => (real.iter().map(|v| f64::from(*v)).collect(), None),
        D::Int8 { real, .. } => (real.iter().map(|v| f64::from(*v)).collect(), None),
        D::Int64 { real, .. } => (real.iter().map(|v| *v as f64).collect(), None),
        D::UInt64 { real, .. } => (real.iter().map(|v| *v as f64).collect(), None),
    };
    // MATLAB's order is column-major: read it with reversed axes, then transpose them back.
    let size = array.size().clone();
    let reversed: Vec<usize> = size.iter().rev().copied().collect();
    let a = ArrayD::from_shape_vec(reversed, real)
        .map_err(|e| bad(path, format!("variable `{}`: {e}", array.name())))?
        .reversed_axes();
    let a = a.as_standard_layout().to_owned();
    Ok(linear(planes_of(path, a)?, full))
}

/// One page of a TIFF, in its integer units.
fn tiff(path: &Path, bytes: &[u8], page: Option<usize>) -> Result<RawFrame, IoError> {
    use tiff::decoder::{Decoder, DecodingResult};
    let err = |e: tiff::TiffError| bad(path, format!("not a readable TIFF: {e}"));
    let mut dec = Decoder::new(Cursor::new(bytes)).map_err(err)?;
    // Count the pages by walking the directory chain (headers only).
    let mut pages = 1;
    while dec.more_images() {
        dec.next_image().map_err(err)?;
        pages += 1;
    }
    let page = match (page, pages) {
        (Some(p), n) if p == 0 || p > n => {
            return Err(bad(
                path,
                format!("page {p} does not exist: it has {n} (1 … {n})"),
            ));
        }
        (Some(p), _) => p,
        (None, 1) => 1,
        (None, n) => {
            return Err(bad(
                path,
                format!("it has {n} pages (a focus stack?): choose one with --page (1 … {n})"),
            ));
        }
    };
    dec.seek_to_image(page - 1).map_err(err)?;
    let (w, h) = dec.dimensions().map_err(err)?;
    check_pixels(path, u64::from(w), u64::from(h))?;
    let colour = dec.colortype().map_err(err)?;
    let channels = match colour {
        tiff::ColorType::Gray(_) => 1,
        tiff::ColorType::RGB(_) => 3,
        other => {
            return Err(bad(
                path,
                format!("a {other:?} TIFF: a PSF frame is grey or RGB"),
            ));
        }
    };
    let (samples, full): (Vec<f64>, Option<f64>) = match dec.read_image().map_err(err)? {
        DecodingResult::U8(v) => (v.iter().map(|x| f64::from(*x)).collect(), Some(255.0)),
        DecodingResult::U16(v) => (v.iter().map(|x| f64::from(*x)).collect(), Some(65535.0)),
        DecodingResult::U32(v) => (
            v.iter().map(|x| f64::from(*x)).collect(),
            Some(f64::from(u32::MAX)),
        ),
        DecodingResult::F32(v) => (v.iter().map(|x| f64::from(*x)).collect(), None),
        DecodingResult::F64(v) => (v, None),
        DecodingResult::I16(v) => (v.iter().map(|x| f64::from(*x)).collect(), None),
        DecodingResult::I32(v) => (v.iter().map(|x| f64::from(*x)).collect(), None),
        _ => return Err(bad(path, "a TIFF sample type a PSF is not stored in")),
    };
    let (w, h) = (w as usize, h as usize);
    if samples.len() != w * h * channels {
        return Err(bad(
            path,
            format!(
                "page {page} holds {} samples, not {w}×{h}×{channels}",
                samples.len()
            ),
        ));
    }
    let planes = (0..channels)
        .map(|c| Array2::from_shape_fn((h, w), |(y, x)| samples[(y * w + x) * channels + c]))
        .collect();
    let mut frame = if full == Some(255.0) {
        gamma8(planes)
    } else {
        linear(planes, full)
    };
    frame.pages = pages;
    frame.page = page;
    Ok(frame)
}

/// A PNG: 16-bit as counts, 8-bit as gamma-encoded values linearised.
fn png(path: &Path, bytes: &[u8]) -> Result<RawFrame, IoError> {
    use image::{ImageFormat, ImageReader};
    let err = |e: image::ImageError| bad(path, format!("not a readable PNG: {e}"));
    let reader = || ImageReader::with_format(Cursor::new(bytes), ImageFormat::Png);
    let (w, h) = reader().into_dimensions().map_err(err)?;
    check_pixels(path, u64::from(w), u64::from(h))?;
    let img = reader().decode().map_err(err)?;
    let (w, h) = (w as usize, h as usize);
    let sixteen = matches!(
        img.color(),
        image::ColorType::L16
            | image::ColorType::La16
            | image::ColorType::Rgb16
            | image::ColorType::Rgba16
    );
    let planes: Vec<Array2<f64>> = if img.color().has_color() {
        let raw = img.to_rgb16().into_raw();
        (0..3)
            .map(|c| Array2::from_shape_fn((h, w), |(y, x)| f64::from(raw[(y * w + x) * 3 + c])))
            .collect()
    } else {
        let raw = img.to_luma16().into_raw();
        vec![Array2::from_shape_fn((h, w), |(y, x)| {
            f64::from(raw[y * w + x])
        })]
    };
    if sixteen {
        Ok(linear(planes, Some(65535.0)))
    } else {
        // to_luma16 widened 8-bit v to v·257: back to 0 … 255.
        Ok(gamma8(planes.into_iter().map(|p| p / 257.0).collect()))
    }
}

/// An 8-bit frame: display-encoded, linearised with γ = 2.2 on the 0 … 255 scale, with the
/// warning that it is not radiometric (and how much of it is clipped).
fn gamma8(planes: Vec<Array2<f64>>) -> RawFrame {
    let n = planes.first().map_or(0, Array2::len).max(1);
    let zeros = planes
        .first()
        .map_or(0, |p| p.iter().filter(|v| **v == 0.0).count());
    let full = planes
        .first()
        .map_or(0, |p| p.iter().filter(|v| **v >= 255.0).count());
    let planes = planes
        .into_iter()
        .map(|p| p.mapv(|v| 255.0 * (v / 255.0).clamp(0.0, 1.0).powf(2.2)))
        .collect();
    let mut frame = linear(planes, Some(255.0));
    frame.encoding = Encoding::Gamma8;
    frame.notes.push(format!(
        "warning: an 8-bit gamma-encoded image is not radiometric: linearised with γ = 2.2, but \
         {:.0} % of its pixels are clipped at black and {full} at white; use it for the PSF's \
         shape, not its levels (a 16-bit or float file of the raw sensor is)",
        100.0 * zeros as f64 / n as f64
    ));
    frame
}
