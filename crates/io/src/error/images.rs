//! Images read by a format of their own: openings, planes, HDR scenes.

use thiserror::Error;

use udc_core::design::MAX_CELLS;

/// What is wrong with an image opening (one pixel per cell).
#[derive(Debug, Error)]
pub enum PatternError {
    /// Bytes the `image` crate cannot decode (its own words).
    #[error("not a readable image: {0}")]
    Unreadable(image::ImageError),
    /// An image without pixels.
    #[error("the image is empty ({width}×{height} pixels); an opening needs at least 1×1 cells")]
    Empty {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// An image that is not square: openings are square grids of cells.
    #[error("the image is {width}×{height} pixels; an opening must be square (one pixel per cell)")]
    NotSquare {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// An image with more than [`MAX_CELLS`] pixels per side.
    #[error(
        "the image is {width}×{height} pixels; openings have at most {MAX_CELLS}×{MAX_CELLS} cells"
    )]
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
}

/// What is wrong with an image read as its planes (PNG, TIFF or OpenEXR, as given back by
/// `denoise`).
#[derive(Debug, Error)]
pub enum PlanesError {
    /// A decode the memory budget cannot hold, refused from the header's size.
    #[error(transparent)]
    OverBudget(udc_core::SimError),
    /// An OpenEXR image that cannot be read.
    #[error(transparent)]
    Exr(#[from] HdrError),
    /// An image in a format these readers do not take.
    #[error("a {0:?} image; only PNG, TIFF and OpenEXR images are read here")]
    UnsupportedFormat(image::ImageFormat),
    /// Bytes that are no image format at all.
    #[error("not an image (PNG, TIFF or OpenEXR)")]
    NotAnImage,
    /// A PNG or TIFF the `image` crate cannot decode (its own words).
    #[error("not a readable {format} image: {error}")]
    Unreadable {
        /// `PNG` or `TIFF`.
        format: &'static str,
        /// The decoder's error.
        error: image::ImageError,
    },
    /// An image without pixels.
    #[error("the image is empty ({width}×{height} pixels)")]
    Empty {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// An image of more pixels than are read.
    #[error("the image is {width}×{height} pixels; at most {max_pixels} pixels are read")]
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// The most pixels read.
        max_pixels: u64,
    },
    /// NaN or infinite samples, which any filter would spread.
    #[error("{samples} samples are NaN or infinite; every sample must be a finite number")]
    NonFinite {
        /// How many samples are not finite.
        samples: usize,
    },
}

/// What is wrong with an HDR scene (Radiance `.hdr` or OpenEXR `.exr`).
#[derive(Debug, Error)]
pub enum HdrError {
    /// A decode the memory budget cannot hold, refused from the header's size.
    #[error(transparent)]
    OverBudget(udc_core::SimError),
    /// An extension that names neither format.
    #[error(
        "unsupported HDR image ({}): expected a Radiance .hdr or an OpenEXR .exr file",
        shown_extension(.extension)
    )]
    UnsupportedExtension {
        /// The extension, lower case, without the dot; empty for none.
        extension: String,
    },
    /// Bytes without the EXR magic number.
    #[error("not an OpenEXR file (its first bytes are not the EXR magic number)")]
    NotExr,
    /// An OpenEXR file the `exr` crate cannot read (its own words).
    #[error("not a readable OpenEXR file: {0}")]
    Exr(exr::error::Error),
    /// An image without pixels.
    #[error("the image is empty ({width}×{height} pixels)")]
    Empty {
        /// Width in pixels.
        width: usize,
        /// Height in pixels.
        height: usize,
    },
    /// An image of more pixels than are simulated.
    #[error("the image is {width}×{height} pixels; at most {max_pixels} pixels are simulated")]
    TooLarge {
        /// Width in pixels.
        width: usize,
        /// Height in pixels.
        height: usize,
        /// The most pixels simulated.
        max_pixels: u64,
    },
    /// An OpenEXR compression the `exr` crate does not decode (DWAA, DWAB).
    #[error(
        "the OpenEXR file uses {0} compression, which is not supported (re-save it with ZIP or \
         PIZ)"
    )]
    UnsupportedCompression(exr::compression::Compression),
    /// A subsampled channel (e.g. chroma at half resolution).
    #[error("channel {channel} is subsampled ({x}×{y}), which is not supported")]
    Subsampled {
        /// The channel's name.
        channel: String,
        /// Horizontal sampling period.
        x: usize,
        /// Vertical sampling period.
        y: usize,
    },
    /// A channel whose samples do not fill its layer.
    #[error("channel {channel} does not hold {width}×{height} samples")]
    ChannelSize {
        /// The channel's name.
        channel: String,
        /// The layer's width.
        width: usize,
        /// The layer's height.
        height: usize,
    },
    /// No layer with `R`, `G` and `B` channels, nor one with `Y`.
    #[error("the OpenEXR file has no R, G, B or Y channels (it has: {})", .found.join(", "))]
    NoColourChannels {
        /// The channels the file has.
        found: Vec<String>,
    },
    /// Bytes without the Radiance signature.
    #[error("not a Radiance HDR file (it does not start with the `#?` signature)")]
    NotRadiance,
    /// A Radiance file the `image` crate cannot decode (its own words).
    #[error("not a readable Radiance HDR file: {0}")]
    Radiance(image::ImageError),
}

/// The extension as the message shows it.
fn shown_extension(extension: &str) -> String {
    if extension.is_empty() {
        "no extension".to_string()
    } else {
        format!("`.{extension}`")
    }
}
