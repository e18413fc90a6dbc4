//! Photos on screen: a loaded photo with its name, the built-in one, and planes as a picture.

use egui::{Color32, ColorImage};
use ndarray::Array2;

use crate::io::{IoError, photo};

/// A loaded photo: a name for the screen and one plane per channel in `[0, 1]`.
#[derive(Debug)]
pub struct Photo {
    /// Name shown with the pictures (usually the file name).
    pub name: String,
    /// One plane per channel (1 grey or 3 R, G, B), values in `[0, 1]`, `[row, col]`.
    pub planes: Vec<Array2<f64>>,
}

/// The built-in photo, named for the screen.
pub(crate) fn built_in() -> Result<Photo, IoError> {
    Ok(Photo {
        name: photo::BUILT_IN_PHOTO_NAME.into(),
        planes: photo::built_in_photo()?,
    })
}

/// Planes (1 grey or 3 R, G, B) as an 8-bit picture, values × `scale` clipped to [0, 1].
pub(crate) fn color_image(planes: &[&Array2<f64>], scale: f64) -> ColorImage {
    let Some(first) = planes.first() else {
        return ColorImage::new([1, 1], vec![Color32::BLACK]);
    };
    let (h, w) = first.dim();
    let byte = |v: f64| ((v * scale).clamp(0.0, 1.0) * 255.0).round() as u8;
    let pixels = (0..h * w)
        .map(|i| {
            let (y, x) = (i / w, i % w);
            let c = |k: usize| {
                planes
                    .get(k)
                    .or(planes.first())
                    .map_or(0, |p| byte(p[[y, x]]))
            };
            Color32::from_rgb(c(0), c(1), c(2))
        })
        .collect();
    ColorImage::new([w, h], pixels)
}
