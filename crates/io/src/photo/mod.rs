//! Photos for capture-and-restore: read any PNG/JPEG/TIFF/HDR/EXR into three `[row, col]` planes
//! (R, G, B) in `[0, 1]`, and write captures, restorations and difference images back out.
//!
//! Pixel values are taken as linear intensities, with no sRGB decoding (the thesis treats its
//! 8-bit dataset the same way; see `core::restore`): 8-bit values are divided by 255, 16-bit by
//! 65535, and float images (HDR, EXR) are clamped to `[0, 1]`. Grey images give three equal
//! planes; alpha is dropped.
//!
//! Written files: 8-bit PNG (values clipped to `[0, 1]`, grey = round(255·v)), difference PNG
//! (`|a − b|` times a stated gain, clipped), and 32-bit float EXR (values unscaled, unclipped).
//! Every file is encoded in memory and written atomically, like the PSF exports.

pub mod hdr;
pub mod planes;
pub mod testset;

use std::path::{Path, PathBuf};

use image::imageops::FilterType;
use image::{
    DynamicImage, ImageBuffer, ImageDecoder, ImageFormat, ImageReader, Rgb, Rgb32FImage, RgbImage,
};
use ndarray::Array2;

use crate::IoError;
use crate::safe_file::{size_mismatch, write_image};
use udc_core::Sample;

/// The largest photo simulated, in pixels (after any downscale): 4096 × 4096. Each plane is
/// held several times over as `f64` during a simulation.
pub const MAX_PHOTO_PIXELS: u64 = 4096 * 4096;

/// The largest image decoded at all (before any downscale), in pixels: 64 megapixels, so a
/// decompression bomb is refused from its header instead of decoded.
pub const MAX_DECODED_PIXELS: u64 = 64_000_000;

/// The decoder's allocation cap: 64 megapixels of 16-bit RGBA fit, nothing much larger.
const MAX_DECODE_BYTES: u64 = 600 * 1024 * 1024;

/// Gain of difference images: `|restored − truth|` is multiplied by this before it is written,
/// so an error of 0.05 (5 % of full scale) shows as 25 % grey.
pub const DIFFERENCE_GAIN: f64 = 5.0;

/// Loads a photo as three planes R, G, B in `[0, 1]` (see the module docs). With `max_side_px`,
/// a photo whose longer side exceeds it is scaled down (triangle filter, aspect ratio kept) so
/// that its longer side is `max_side_px`.
///
/// # Errors
/// [`IoError::File`] when the file cannot be opened; [`IoError::Image`] when its format is not
/// recognised or supported, it cannot be decoded, it is empty, or it is larger than
/// [`MAX_PHOTO_PIXELS`] (after the downscale); `max_side_px = Some(0)` is an
/// [`IoError::Image`] too.
pub fn load_photo<T: Sample>(
    path: &Path,
    max_side_px: Option<u32>,
) -> Result<Vec<Array2<T>>, IoError> {
    let image_err = |message: String| IoError::Image {
        path: path.to_path_buf(),
        message,
    };
    if max_side_px == Some(0) {
        return Err(image_err(
            "the maximum side must be at least 1 pixel".into(),
        ));
    }
    crate::safe_file::check_regular(path, "read the photo")?;
    let open = || {
        ImageReader::open(path)
            .map_err(|e| IoError::file("read the photo", path, e))?
            // Trust the bytes, not the extension.
            .with_guessed_format()
            .map_err(|e| IoError::file("read the photo", path, e))
    };
    let reader = open()?;
    let reader_format = reader.format();
    if reader_format.is_none() {
        return Err(image_err(
            "not an image in a supported format (PNG, JPEG, TIFF, HDR or EXR)".into(),
        ));
    }
    // The size from the header first, so an oversized photo is refused before it is decoded.
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| image_err(format!("not a readable image: {e}")))?;
    if w == 0 || h == 0 {
        return Err(image_err(format!("the image is empty ({w}×{h} pixels)")));
    }
    if u64::from(w) * u64::from(h) > MAX_DECODED_PIXELS {
        return Err(image_err(format!(
            "the image is {w}×{h} pixels; at most {} megapixels are decoded, even to be scaled \
             down (scale it down first)",
            MAX_DECODED_PIXELS / 1_000_000
        )));
    }
    let scale = max_side_px.map_or(1.0, |m| (f64::from(m) / f64::from(w.max(h))).min(1.0));
    let pixels = (f64::from(w) * scale).round() * (f64::from(h) * scale).round();
    if pixels > MAX_PHOTO_PIXELS as f64 {
        return Err(image_err(format!(
            "the image is {w}×{h} pixels; photos of at most {MAX_PHOTO_PIXELS} pixels are \
             simulated (scale it down, e.g. with a maximum side)"
        )));
    }
    if reader_format == Some(ImageFormat::OpenExr)
        && let Some((dw, dh)) = exr_data_window(path)
        && dw as u64 * dh as u64 > MAX_DECODED_PIXELS
    {
        return Err(image_err(format!(
            "the image's data window is {dw}×{dh} pixels; at most {} megapixels are decoded",
            MAX_DECODED_PIXELS / 1_000_000
        )));
    }
    if reader_format == Some(ImageFormat::Jpeg) {
        check_jpeg_complete(path)?;
    }
    let unreadable = |e: image::ImageError| image_err(format!("not a readable image: {e}"));
    let mut decoder = open()?.into_decoder().map_err(unreadable)?;
    // The decoded image in its own sample type, a scaled-down copy of it, and the planes.
    let decoded = u64::from(decoder.color_type().bytes_per_pixel());
    let scaled = if scale < 1.0 { decoded } else { 0 };
    let kept = pixels as u64 * (scaled + 3 * std::mem::size_of::<T>() as u64);
    crate::decode_budget::check(
        &format!("photo {}", path.display()),
        u64::from(w),
        u64::from(h),
        decoded,
        kept,
    )?;
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    decoder.set_limits(limits).map_err(unreadable)?;
    let img = DynamicImage::from_decoder(decoder).map_err(unreadable)?;
    // Scale down in the decoded type first: a float copy of the full image is 4× its bytes.
    let img = match max_side_px {
        Some(m) if w.max(h) > m => img.resize(m, m, FilterType::Triangle),
        _ => img,
    };
    Ok(planes_of_image(&img))
}

/// Rows converted to float at a time by [`planes_of_image`].
const CONVERT_ROWS: u32 = 256;

/// The R, G, B planes of a decoded image, converted a band of rows at a time, so that a
/// camera-size photo is never held as a whole float copy besides its planes.
fn planes_of_image<T: Sample>(img: &DynamicImage) -> Vec<Array2<T>> {
    let (w, h) = (img.width(), img.height());
    let mut planes = vec![Array2::<T>::default((h as usize, w as usize)); 3];
    for y0 in (0..h).step_by(CONVERT_ROWS as usize) {
        let band = img.crop_imm(0, y0, w, CONVERT_ROWS.min(h - y0)).to_rgb32f();
        for (x, y, px) in band.enumerate_pixels() {
            for (plane, v) in planes.iter_mut().zip(px.0) {
                plane[[(y0 + y) as usize, x as usize]] = T::from_f64(unit(v));
            }
        }
    }
    planes
}

/// A float sample clamped to `[0, 1]`, NaN → 0.
fn unit(v: f32) -> f64 {
    if v.is_nan() {
        0.0
    } else {
        f64::from(v).clamp(0.0, 1.0)
    }
}

/// The largest data window of an OpenEXR file, `(width, height)`; `None` when its header does
/// not read (the decoder then says why). The `image` crate sizes an EXR by its display window
/// but decodes the data window, which a file may make far larger than it says.
pub(crate) fn exr_data_window(path: &Path) -> Option<(usize, usize)> {
    let meta = exr::meta::MetaData::read_from_file(path, false).ok()?;
    meta.headers
        .iter()
        .map(|h| (h.layer_size.0, h.layer_size.1))
        .max_by_key(|&(w, h)| w as u64 * h as u64)
}

/// A JPEG must end with its end-of-image marker: decoders fill a truncated file's missing rows
/// with grey and call it a success.
fn check_jpeg_complete(path: &Path) -> Result<(), IoError> {
    use std::io::{Read, Seek, SeekFrom};
    let mut f = std::fs::File::open(path).map_err(|e| IoError::file("read the photo", path, e))?;
    let len = f
        .seek(SeekFrom::End(0))
        .map_err(|e| IoError::file("read the photo", path, e))?;
    // Some writers pad after the marker; look at the last few hundred bytes.
    let tail_len = len.min(512);
    f.seek(SeekFrom::Start(len - tail_len))
        .map_err(|e| IoError::file("read the photo", path, e))?;
    let mut tail = Vec::with_capacity(tail_len as usize);
    f.take(tail_len)
        .read_to_end(&mut tail)
        .map_err(|e| IoError::file("read the photo", path, e))?;
    if tail.windows(2).any(|w| w == [0xFF, 0xD9]) {
        Ok(())
    } else {
        Err(IoError::Image {
            path: path.to_path_buf(),
            message: "the JPEG is truncated (no end-of-image marker): the file is incomplete"
                .into(),
        })
    }
}

/// The built-in test photo (public domain, in `assets/photos`): what the restore views and
/// `phase restore` use when no photo was chosen.
pub const BUILT_IN_PHOTO_PNG: &[u8] = include_bytes!("../../../../assets/photos/astronaut_256.png");
/// Its name for the screen.
pub const BUILT_IN_PHOTO_NAME: &str = "astronaut (built in, 256 px)";

/// The built-in photo's R, G, B planes.
///
/// # Errors
/// [`IoError::Image`] if the embedded PNG does not decode (a broken build).
pub fn built_in_photo() -> Result<Vec<Array2<f64>>, IoError> {
    let img = image::load_from_memory(BUILT_IN_PHOTO_PNG).map_err(|e| IoError::Image {
        path: PathBuf::from("assets/photos/astronaut_256.png"),
        message: e.to_string(),
    })?;
    Ok(planes_of(&img.to_rgb32f()))
}

/// `planes` (1 grey or 3 R, G, B, all one size) scaled down so the longer side is at most
/// `max_side_px` (triangle filter, aspect ratio kept, as [`load_photo`]); planes that fit are
/// returned as they are. Used to fit the built-in photo to a smaller sensor.
pub fn fit_max_side(planes: Vec<Array2<f64>>, max_side_px: usize) -> Vec<Array2<f64>> {
    let Some((h, w)) = planes.first().map(Array2::dim) else {
        return planes;
    };
    let (Ok(w32), Ok(h32), Ok(m)) = (
        u32::try_from(w),
        u32::try_from(h),
        u32::try_from(max_side_px.max(1)),
    ) else {
        return planes;
    };
    if w.max(h) <= max_side_px || planes.iter().any(|p| p.dim() != (h, w)) {
        return planes;
    }
    let Some(img) = float_image(&planes, (w32, h32)) else {
        return planes;
    };
    let small = img.resize(m, m, FilterType::Triangle);
    planes_of(&small.to_rgb32f())
}

/// `planes` (1 grey or 3 R, G, B, all one size) scaled, up or down, so that they are exactly
/// `width_px` columns wide (triangle filter, aspect ratio kept, at least one row): the phase
/// model's scene as wide as its sensor (thesis §4.4.1). Planes already that wide are returned
/// as they are.
pub fn scale_to_width(planes: Vec<Array2<f64>>, width_px: usize) -> Vec<Array2<f64>> {
    let Some((h, w)) = planes.first().map(Array2::dim) else {
        return planes;
    };
    let rows = ((h as f64 * width_px as f64 / w.max(1) as f64).round() as usize).max(1);
    let (Ok(w32), Ok(h32), Ok(nw), Ok(nh)) = (
        u32::try_from(w),
        u32::try_from(h),
        u32::try_from(width_px.max(1)),
        u32::try_from(rows),
    ) else {
        return planes;
    };
    if w == width_px || planes.iter().any(|p| p.dim() != (h, w)) {
        return planes;
    }
    let Some(img) = float_image(&planes, (w32, h32)) else {
        return planes;
    };
    let scaled = img.resize_exact(nw, nh, FilterType::Triangle);
    let out = planes_of(&scaled.to_rgb32f());
    if planes.len() == 1 {
        // A grey photo stays one plane.
        out.into_iter().take(1).collect()
    } else {
        out
    }
}

/// `planes` (1 grey or 3 R, G, B) of `size` (width, height) as a float RGB image, for the
/// resizers; `None` when they do not make one.
fn float_image(planes: &[Array2<f64>], size: (u32, u32)) -> Option<DynamicImage> {
    let refs: Vec<&Array2<f64>> = planes.iter().collect();
    Rgb32FImage::from_raw(size.0, size.1, interleave(&refs, |v| v as f32))
        .map(DynamicImage::ImageRgb32F)
}

/// The R, G, B planes of a float image, clamped to `[0, 1]` (NaN → 0).
pub fn planes_of(img: &Rgb32FImage) -> Vec<Array2<f64>> {
    let (w, h) = (img.width() as usize, img.height() as usize);
    (0..3)
        .map(|c| {
            Array2::from_shape_fn((h, w), |(y, x)| {
                unit(img.get_pixel(x as u32, y as u32).0[c])
            })
        })
        .collect()
}

/// Width and height of 1 or 3 equal-sized, non-empty planes.
fn planes_size<T>(path: &Path, planes: &[&Array2<T>]) -> Result<(u32, u32), IoError> {
    let bad = |message: String| IoError::Image {
        path: path.to_path_buf(),
        message,
    };
    let Some(first) = planes.first() else {
        return Err(bad("no planes to write".into()));
    };
    if planes.len() != 1 && planes.len() != 3 {
        return Err(bad(format!(
            "{} planes; an image needs 1 (grey) or 3 (R, G, B)",
            planes.len()
        )));
    }
    if planes.iter().any(|p| p.dim() != first.dim()) {
        return Err(bad("the planes differ in size".into()));
    }
    let (rows, cols) = first.dim();
    if rows == 0 || cols == 0 {
        return Err(bad(format!("cannot write an empty {rows}×{cols} image")));
    }
    let w = u32::try_from(cols).map_err(|_| bad("too wide for an image".into()))?;
    let h = u32::try_from(rows).map_err(|_| bad("too tall for an image".into()))?;
    Ok((w, h))
}

/// Interleaved RGB values of 1 (grey, repeated) or 3 planes, mapped through `f`.
fn interleave<S: Sample, T>(planes: &[&Array2<S>], f: impl Fn(f64) -> T) -> Vec<T> {
    let [r, g, b] = match rgb(planes) {
        Some(p) => p,
        None => return Vec::new(),
    };
    r.iter()
        .zip(g.iter())
        .zip(b.iter())
        .flat_map(|((r, g), b)| [f((*r).into()), f((*g).into()), f((*b).into())])
        .collect()
}

/// The R, G, B planes of 1 (grey, repeated) or 3 planes.
fn rgb<'a, S>(planes: &[&'a Array2<S>]) -> Option<[&'a Array2<S>; 3]> {
    match planes {
        [grey] => Some([*grey, *grey, *grey]),
        [r, g, b] => Some([*r, *g, *b]),
        _ => None,
    }
}

/// `round(255·v)` for `v` clipped to `[0, 1]`; NaN → 0.
fn to_u8(v: f64) -> u8 {
    if v.is_nan() {
        0
    } else {
        (255.0 * v.clamp(0.0, 1.0)).round() as u8
    }
}

/// `round(65535·v)` for `v` clipped to `[0, 1]`; NaN → 0. An 8-bit value `k/255` becomes
/// `257·k`, which reads back as exactly `k/255`.
fn to_u16(v: f64) -> u16 {
    if v.is_nan() {
        0
    } else {
        (65535.0 * v.clamp(0.0, 1.0)).round() as u16
    }
}

/// Writes 1 (grey) or 3 (R, G, B) planes as a 16-bit RGB PNG, values clipped to `[0, 1]`: a
/// photo saved for a command to read again (an 8-bit photo's values come back exactly).
///
/// # Errors
/// As [`write_photo_png`].
pub fn write_photo_png16<T: Sample>(path: &Path, planes: &[&Array2<T>]) -> Result<(), IoError> {
    let (w, h) = planes_size(path, planes)?;
    let img = ImageBuffer::<Rgb<u16>, _>::from_raw(w, h, interleave(planes, to_u16))
        .ok_or_else(|| size_mismatch(path))?;
    write_image(path, DynamicImage::ImageRgb16(img), ImageFormat::Png)
}

/// Writes 1 (grey) or 3 (R, G, B) planes as an 8-bit RGB PNG, values clipped to `[0, 1]`.
///
/// # Errors
/// [`IoError::Image`] for a wrong number of planes, planes of different sizes or empty ones, or
/// an encoder failure; [`IoError::File`] when the file cannot be written.
pub fn write_photo_png<T: Sample>(path: &Path, planes: &[&Array2<T>]) -> Result<(), IoError> {
    let (w, h) = planes_size(path, planes)?;
    let img: RgbImage = ImageBuffer::<Rgb<u8>, _>::from_raw(w, h, interleave(planes, to_u8))
        .ok_or_else(|| size_mismatch(path))?;
    write_image(path, DynamicImage::ImageRgb8(img), ImageFormat::Png)
}

/// Writes one map as a grey or three as an RGB 8-bit PNG, each value through `value` and
/// clipped to `[0, 1]`: the picture of maps of any type, without a float copy of them. The
/// rows are converted and compressed one at a time, so a 16-megapixel picture holds neither
/// its 8-bit pixels nor its compressed stream in memory (together 100 MB in RGB).
///
/// # Errors
/// As [`write_photo_png`].
pub fn write_map_png<T: Copy>(
    path: &Path,
    maps: &[&Array2<T>],
    value: impl Fn(T) -> f64,
) -> Result<(), IoError> {
    let (w, h) = planes_size(path, maps)?;
    let encode_err = |e: png::EncodingError| IoError::Image {
        path: path.to_path_buf(),
        message: format!("cannot encode the PNG image: {e}"),
    };
    let temp = crate::safe_file::TempFile::beside(path)?;
    let file = crate::safe_file::open_reserved(temp.path())
        .map_err(|e| IoError::file("write", path, e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(match maps.len() {
        1 => png::ColorType::Grayscale,
        _ => png::ColorType::Rgb,
    });
    enc.set_depth(png::BitDepth::Eight);
    let mut stream = enc
        .write_header()
        .and_then(png::Writer::into_stream_writer)
        .map_err(encode_err)?;
    let mut row = Vec::with_capacity(maps.len() * w as usize);
    for y in 0..h as usize {
        row.clear();
        match maps {
            [grey] => row.extend(grey.row(y).iter().map(|v| to_u8(value(*v)))),
            [r, g, b] => {
                for ((r, g), b) in r.row(y).iter().zip(g.row(y)).zip(b.row(y)) {
                    row.extend([r, g, b].map(|v| to_u8(value(*v))));
                }
            }
            _ => return Err(size_mismatch(path)),
        }
        std::io::Write::write_all(&mut stream, &row)
            .map_err(|e| IoError::file("write", path, e))?;
    }
    stream.finish().map_err(encode_err)?;
    temp.persist()
}

/// Writes `|a − b| · gain` per plane as an 8-bit RGB PNG (clipped at full scale); use
/// [`DIFFERENCE_GAIN`] unless there is a reason to state another gain.
///
/// # Errors
/// As [`write_photo_png`], and when `a` and `b` differ in size or count, or `gain` is not a
/// positive number.
pub fn write_difference_png<A: Sample, B: Sample>(
    path: &Path,
    a: &[&Array2<A>],
    b: &[&Array2<B>],
    gain: f64,
) -> Result<(), IoError> {
    let bad = |message: String| IoError::Image {
        path: path.to_path_buf(),
        message,
    };
    if !(gain.is_finite() && gain > 0.0) {
        return Err(bad(format!(
            "the difference gain must be a positive number (got {gain:?})"
        )));
    }
    if a.len() != b.len() || a.iter().zip(b).any(|(x, y)| x.dim() != y.dim()) {
        return Err(bad("the two images differ in size or channels".into()));
    }
    let (w, h) = planes_size(path, a)?;
    let (Some(a), Some(b)) = (rgb(a), rgb(b)) else {
        return Err(bad("the images need 1 or 3 planes".into()));
    };
    // Pixel by pixel, so no difference planes are held besides the 8-bit image.
    let mut bytes = Vec::with_capacity(3 * w as usize * h as usize);
    for (y, x) in ndarray::indices(a[0].dim()) {
        for (pa, pb) in a.iter().zip(&b) {
            let d: f64 = pa[[y, x]].into() - pb[[y, x]].into();
            bytes.push(to_u8(d.abs() * gain));
        }
    }
    let img: RgbImage =
        ImageBuffer::<Rgb<u8>, _>::from_raw(w, h, bytes).ok_or_else(|| size_mismatch(path))?;
    write_image(path, DynamicImage::ImageRgb8(img), ImageFormat::Png)
}

/// Writes 1 (grey, as three equal channels) or 3 planes as a 32-bit float RGB EXR, unscaled.
///
/// # Errors
/// As [`write_photo_png`].
pub fn write_photo_exr<T: Sample>(path: &Path, planes: &[&Array2<T>]) -> Result<(), IoError> {
    use exr::prelude::{Image, SpecificChannels, Vec2, WritableImage};
    planes_size(path, planes)?;
    let Some([r, g, b]) = rgb(planes) else {
        return Err(IoError::Image {
            path: path.to_path_buf(),
            message: "an image needs 1 or 3 planes".into(),
        });
    };
    let (h, w) = r.dim();
    let f = |p: &Array2<T>, x: usize, y: usize| -> f32 { p[[y, x]].into() as f32 };
    // Written as the pixels are read, through a temp file, so that a camera-size image is not
    // first copied into an interleaved buffer and an encoded one (24 bytes a pixel).
    let image = Image::from_channels(
        (w, h),
        SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| (f(r, x, y), f(g, x, y), f(b, x, y))),
    );
    let temp = crate::safe_file::TempFile::beside(path)?;
    let file = crate::safe_file::open_reserved(temp.path())
        .map_err(|e| IoError::file("write", path, e))?;
    image
        .write()
        .to_buffered(std::io::BufWriter::new(file))
        .map_err(|e| IoError::Image {
            path: path.to_path_buf(),
            message: format!("cannot encode the OpenExr image: {e}"),
        })?;
    temp.persist()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn u8_levels_round_and_clip() {
        assert_eq!(to_u8(0.0), 0);
        assert_eq!(to_u8(1.0), 255);
        assert_eq!(to_u8(2.0), 255);
        assert_eq!(to_u8(-1.0), 0);
        assert_eq!(to_u8(f64::NAN), 0);
        assert_eq!(to_u8(0.5), 128);
    }

    #[test]
    fn an_8_bit_photo_saved_in_16_bits_reads_back_exactly() {
        let planes = built_in_photo().expect("the built-in photo");
        let dir = tempfile::tempdir().expect("a scratch folder");
        let path = dir.path().join("photo.png");
        let refs: Vec<&Array2<f64>> = planes.iter().collect();
        write_photo_png16(&path, &refs).expect("written");
        let back: Vec<Array2<f64>> = load_photo(&path, None).expect("read");
        assert_eq!(back, planes);
        assert_eq!(to_u16(f64::NAN), 0);
        assert_eq!(to_u16(2.0), 65535);
    }
}
