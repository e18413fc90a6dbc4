//! HDR scenes for the sensor previewer: read Radiance `.hdr` and OpenEXR `.exr` into a
//! [`Scene`] of linear relative radiance, and write scenes and captures as compressed EXR.
//!
//! - **Radiance** (`.hdr`, `.pic`): RGBE, decoded by the `image` crate.
//! - **OpenEXR** (`.exr`): half, float or uint samples, scan lines or tiles, the compressions of
//!   the `exr` crate (none, RLE, ZIP, ZIPS, PIZ, PXR24, B44, B44A; not DWAA/DWAB). The first layer
//!   with `R`, `G` and `B` channels gives three planes; failing that, one with a `Y` channel
//!   gives one luminance plane. Alpha and other channels are ignored; the largest resolution
//!   level is read; the data window's top-left is `[0, 0]`.
//!
//! **Values.** Samples are relative radiance and stay unscaled. What a scene cannot hold is
//! handled explicitly and counted in the [`HdrReport`]: negative samples (e.g. from a camera's
//! black-level subtraction) and NaN become 0; `+∞` (half-float overflow) becomes the largest
//! finite sample of the file. The extension picks the format; a file whose bytes do not match it,
//! an unsupported extension, a corrupt or truncated file and an image larger than
//! [`MAX_PHOTO_PIXELS`] are errors naming the path.

use std::io::Cursor;
use std::path::Path;

use exr::prelude::{
    AnyChannel, Encoding, FlatSamples, Image, Layer, LayerAttributes, ReadChannels, ReadLayers,
    SpecificChannels, Vec2, WritableImage, f16,
};
use image::{ImageFormat, ImageReader};
use ndarray::Array2;

use crate::IoError;
use crate::error::HdrError;
use crate::photo::MAX_PHOTO_PIXELS;

/// Largest HDR file read: a 4096² RGBA float EXR, uncompressed, is 268 MB.
pub const MAX_HDR_BYTES: u64 = 512 * 1024 * 1024;
use udc_core::sensor::Scene;

/// What loading found besides the pixels.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct HdrReport {
    /// `"OpenEXR"` or `"Radiance"`.
    pub format: String,
    /// The channels read (`R, G, B` or `Y`).
    pub channels: Vec<String>,
    /// Samples below 0, set to 0.
    pub negative_samples: usize,
    /// NaN samples, set to 0.
    pub nan_samples: usize,
    /// `+∞` samples, set to the largest finite sample.
    pub infinite_samples: usize,
}

impl HdrReport {
    /// One line per kind of repaired sample, for the CLI and the studio; empty when none were.
    pub fn notes(&self) -> Vec<String> {
        let mut v = Vec::new();
        if self.negative_samples > 0 {
            v.push(format!(
                "{} negative samples set to 0",
                self.negative_samples
            ));
        }
        if self.nan_samples > 0 {
            v.push(format!("{} NaN samples set to 0", self.nan_samples));
        }
        if self.infinite_samples > 0 {
            v.push(format!(
                "{} infinite samples set to the largest finite one",
                self.infinite_samples
            ));
        }
        v
    }
}

/// Loads an HDR scene (see the module docs).
///
/// # Errors
/// [`IoError::File`] when the file cannot be read; [`IoError::Hdr`] naming the path for an
/// unsupported extension, bytes that are not the format the extension says, a corrupt or
/// truncated file, unsupported content (no RGB or Y channels, subsampled channels, DWA
/// compression), an empty image or one over [`MAX_PHOTO_PIXELS`].
pub fn load_hdr(path: &Path) -> Result<Scene, IoError> {
    load_hdr_with_report(path).map(|(scene, _)| scene)
}

/// [`load_hdr`], also returning what was repaired.
///
/// # Errors
/// As [`load_hdr`].
pub fn load_hdr_with_report(path: &Path) -> Result<(Scene, HdrReport), IoError> {
    crate::safe_file::check_regular(path, "read the HDR image")?;
    let bad = |error: HdrError| IoError::Hdr {
        path: path.to_path_buf(),
        error,
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let exr = match ext.as_str() {
        "exr" => true,
        "hdr" | "pic" => false,
        _ => return Err(bad(HdrError::UnsupportedExtension { extension: ext })),
    };
    let (planes, channels) = {
        // The file's bytes go before the planes are widened to f64.
        let bytes = crate::safe_file::read_bounded(path, MAX_HDR_BYTES, "read the HDR image")?;
        let what = "HDR image";
        if exr {
            let (planes, channels) = read_exr(&bytes, what).map_err(bad)?;
            (Err(planes), channels)
        } else {
            let (planes, channels) = read_radiance(&bytes, what).map_err(bad)?;
            (Ok(planes), channels)
        }
    };
    let mut report = HdrReport {
        format: if exr { "OpenEXR" } else { "Radiance" }.into(),
        channels,
        ..HdrReport::default()
    };
    let planes = planes.unwrap_or_else(|f32_planes| repair(f32_planes, &mut report));
    Ok((Scene { planes }, report))
}

/// The built-in sample scene (`assets/hdr/StillLife_620x423.exr`: oil lamps and glasses, a
/// dynamic range of about 2·10⁶), so the sensor previewer has a scene before any file is opened.
pub const SAMPLE_SCENE_NAME: &str = "StillLife (built-in sample)";

/// Decodes the built-in sample scene.
///
/// # Errors
/// Never for the shipped file; a message if it were corrupt.
pub fn sample_scene() -> Result<Scene, IoError> {
    const SAMPLE_EXR: &[u8] = include_bytes!("../../../../assets/hdr/StillLife_620x423.exr");
    let (planes, _) = read_exr(SAMPLE_EXR, SAMPLE_SCENE_NAME).map_err(|error| IoError::Hdr {
        path: SAMPLE_SCENE_NAME.into(),
        error,
    })?;
    let planes = repair(planes, &mut HdrReport::default());
    Ok(Scene { planes })
}

fn check_size(width: usize, height: usize) -> Result<(), HdrError> {
    if width == 0 || height == 0 {
        return Err(HdrError::Empty { width, height });
    }
    if (width as u64) * (height as u64) > MAX_PHOTO_PIXELS {
        return Err(HdrError::TooLarge {
            width,
            height,
            max_pixels: MAX_PHOTO_PIXELS,
        });
    }
    Ok(())
}

/// Peak bytes per pixel of a scene's decode besides the file: its f32 planes and the f64 planes
/// [`repair`] widens them to (three of each), or the decoder's buffer beside the f32 planes.
const SCENE_DECODE_BYTES_PER_PIXEL: u64 = 3 * (4 + 8);

/// Refuses a scene decode over the memory budget, from the header's size (`decode_budget`):
/// `decoder_bytes_per_pixel` the decoder's own buffer, `bytes` the file held meanwhile.
fn check_decode_budget(
    what: &str,
    (width, height): (u64, u64),
    decoder_bytes_per_pixel: u64,
    bytes: &[u8],
) -> Result<(), HdrError> {
    let per_pixel = decoder_bytes_per_pixel.max(SCENE_DECODE_BYTES_PER_PIXEL);
    crate::decode_budget::check(what, width, height, per_pixel, bytes.len() as u64)
        .map_err(HdrError::OverBudget)
}

/// The EXR's planes (`[row, col]`, f32 widened) and channel names; `what` names it in a
/// refusal over the memory budget.
pub(crate) fn read_exr(
    bytes: &[u8],
    what: &str,
) -> Result<(Vec<Array2<f32>>, Vec<String>), HdrError> {
    const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
    if bytes.len() < 4 || bytes[..4] != MAGIC {
        return Err(HdrError::NotExr);
    }
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(HdrError::Exr)?;
    for header in &meta.headers {
        check_size(header.layer_size.0, header.layer_size.1)?;
        if matches!(
            header.compression,
            exr::compression::Compression::DWAA(_) | exr::compression::Compression::DWAB(_)
        ) {
            return Err(HdrError::UnsupportedCompression(header.compression));
        }
    }
    // Every channel of every layer is decoded (f16 or 32-bit samples), before one is chosen.
    let decoded_per_pixel: u64 = meta
        .headers
        .iter()
        .map(|h| 4 * h.channels.list.len() as u64)
        .sum();
    let largest = meta
        .headers
        .iter()
        .map(|h| (h.layer_size.0 as u64, h.layer_size.1 as u64))
        .max_by_key(|&(w, h)| w * h)
        .unwrap_or((0, 0));
    check_decode_budget(what, largest, decoded_per_pixel + 3 * 4, bytes)?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(HdrError::Exr)?;
    for want in [&["R", "G", "B"][..], &["Y"][..]] {
        for layer in &image.layer_data {
            let list = &layer.channel_data.list;
            let found: Vec<&AnyChannel<FlatSamples>> = want
                .iter()
                .filter_map(|n| list.iter().find(|c| c.name.to_string() == *n))
                .collect();
            if found.len() != want.len() {
                continue;
            }
            let (w, h) = (layer.size.0, layer.size.1);
            let mut planes = Vec::with_capacity(found.len());
            for c in found {
                if c.sampling.0 != 1 || c.sampling.1 != 1 {
                    return Err(HdrError::Subsampled {
                        channel: c.name.to_string(),
                        x: c.sampling.0,
                        y: c.sampling.1,
                    });
                }
                let values: Vec<f32> = c.sample_data.values_as_f32().collect();
                let plane =
                    Array2::from_shape_vec((h, w), values).map_err(|_| HdrError::ChannelSize {
                        channel: c.name.to_string(),
                        width: w,
                        height: h,
                    })?;
                planes.push(plane);
            }
            return Ok((planes, want.iter().map(|s| s.to_string()).collect()));
        }
    }
    Err(HdrError::NoColourChannels {
        found: image
            .layer_data
            .iter()
            .flat_map(|l| l.channel_data.list.iter().map(|c| c.name.to_string()))
            .collect(),
    })
}

/// The Radiance file's R, G, B planes, straight to f64: RGBE holds only finite samples ≥ 0, so
/// nothing needs the repair an EXR's samples do, and no f32 copy is made. `what` names it in a
/// refusal over the memory budget.
fn read_radiance(bytes: &[u8], what: &str) -> Result<(Vec<Array2<f64>>, Vec<String>), HdrError> {
    if !bytes.starts_with(b"#?") {
        return Err(HdrError::NotRadiance);
    }
    let reader = || ImageReader::with_format(Cursor::new(bytes), ImageFormat::Hdr);
    let (w, h) = reader().into_dimensions().map_err(HdrError::Radiance)?;
    check_size(w as usize, h as usize)?;
    // The decoder's RGB f32 buffer beside the f64 planes.
    check_decode_budget(what, (u64::from(w), u64::from(h)), 3 * 4 + 3 * 8, bytes)?;
    let img = reader().decode().map_err(HdrError::Radiance)?.into_rgb32f();
    let (w, h) = (img.width() as usize, img.height() as usize);
    let raw = img.into_raw();
    let planes = (0..3)
        .map(|c| Array2::from_shape_fn((h, w), |(y, x)| f64::from(raw[(y * w + x) * 3 + c])))
        .collect();
    Ok((planes, vec!["R".into(), "G".into(), "B".into()]))
}

/// Widens to f64 and repairs negative, NaN and infinite samples (see the module docs).
fn repair(planes: Vec<Array2<f32>>, report: &mut HdrReport) -> Vec<Array2<f64>> {
    let largest = planes
        .iter()
        .flat_map(|p| p.iter())
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    planes
        .into_iter()
        .map(|p| {
            p.mapv(|v| {
                if v.is_nan() {
                    report.nan_samples += 1;
                    0.0
                } else if v == f32::INFINITY {
                    report.infinite_samples += 1;
                    f64::from(largest)
                } else if v < 0.0 {
                    report.negative_samples += 1;
                    0.0
                } else {
                    f64::from(v)
                }
            })
        })
        .collect()
}

/// Sample precision of a written EXR.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExrPrecision {
    /// 16-bit half floats (≈ 3 significant digits, up to 65504): compact, for scenes.
    Half,
    /// 32-bit floats: for captures and anything measured.
    Float,
}

/// Writes planes as a ZIP-compressed scan-line EXR: three planes as `R`, `G`, `B`, one as `Y`
/// (luminance). Values unscaled; written atomically, encoded as the pixels are read (no copy of
/// the samples or of the encoded file in memory).
///
/// # Errors
/// [`IoError::Image`] for a wrong number of planes, planes of different or empty sizes, or an
/// encoder failure; [`IoError::File`] when the file cannot be written.
pub fn write_exr<T: udc_core::Sample>(
    path: &Path,
    planes: &[&Array2<T>],
    precision: ExrPrecision,
) -> Result<(), IoError> {
    let bad = |message: String| IoError::Image {
        path: path.to_path_buf(),
        message,
    };
    if planes.len() != 1 && planes.len() != 3 {
        return Err(bad(format!(
            "{} planes; an EXR is written from 1 (Y) or 3 (R, G, B)",
            planes.len()
        )));
    }
    let (h, w) = planes[0].dim();
    if h == 0 || w == 0 || planes.iter().any(|p| p.dim() != (h, w)) {
        return Err(bad("the planes are empty or differ in size".into()));
    }
    let temp = crate::safe_file::TempFile::beside(path)?;
    let file = crate::safe_file::open_reserved(temp.path())
        .map_err(|e| IoError::file("write", path, e))?;
    let out = std::io::BufWriter::new(file);
    let at = |p: &Array2<T>, Vec2(x, y): Vec2<usize>| -> f64 { p[[y, x]].into() };
    let half = |v: f64| f16::from_f64(v);
    // f64 to f32 is the precision asked for.
    #[allow(clippy::cast_possible_truncation)]
    let single = |v: f64| v as f32;
    macro_rules! encode {
        ($channels:expr) => {
            Image::from_layer(Layer::new(
                (w, h),
                LayerAttributes::default(),
                Encoding::SMALL_LOSSLESS,
                $channels,
            ))
            .write()
            .to_buffered(out)
        };
    }
    let written = match (planes, precision) {
        ([y], ExrPrecision::Half) => encode!(
            SpecificChannels::build()
                .with_channel("Y")
                .with_pixel_fn(|p| (half(at(y, p)),))
        ),
        ([y], ExrPrecision::Float) => encode!(
            SpecificChannels::build()
                .with_channel("Y")
                .with_pixel_fn(|p| (single(at(y, p)),))
        ),
        ([r, g, b], ExrPrecision::Half) => encode!(SpecificChannels::rgb(|p| (
            half(at(r, p)),
            half(at(g, p)),
            half(at(b, p))
        ))),
        ([r, g, b], ExrPrecision::Float) => encode!(SpecificChannels::rgb(|p| (
            single(at(r, p)),
            single(at(g, p)),
            single(at(b, p))
        ))),
        _ => {
            return Err(bad(
                "an EXR is written from 1 (Y) or 3 (R, G, B) planes".into()
            ));
        }
    };
    written.map_err(|e| bad(format!("cannot encode the EXR image: {e}")))?;
    temp.persist()
}

/// Writes a scene (three planes R, G, B or one Y) as EXR; see [`write_exr`].
///
/// # Errors
/// As [`write_exr`].
pub fn write_scene_exr(path: &Path, scene: &Scene, precision: ExrPrecision) -> Result<(), IoError> {
    let planes: Vec<&Array2<f64>> = scene.planes.iter().collect();
    write_exr(path, &planes, precision)
}
