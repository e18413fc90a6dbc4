//! Opening patterns as images: one image pixel = one cell, white = open.
//!
//! This is the format of the thesis authors' published patterns (`pixelPatterns/*.png`, see
//! `assets/pixel-patterns/`): binary 8-bit PNGs thresholded at 127. Any format the `image` crate
//! decodes is accepted; colour is converted to 8-bit luma and alpha is ignored.

use std::io::Cursor;
use std::path::Path;

use image::{DynamicImage, GrayImage, ImageFormat, ImageReader};

use crate::IoError;
use crate::error::PatternError;
use crate::safe_file::write_atomic;
use udc_core::design::MAX_CELLS;

/// Luma above this (0–255) is an open cell; at or below it a closed one (the thesis threshold).
pub const OPEN_THRESHOLD: u8 = 127;

/// Loads an image opening: one image pixel = one cell, grey > 127 = open (1.0), else closed (0.0).
/// Rows run top to bottom, as in [`udc_core::design::Opening::cells`].
///
/// # Errors
/// [`IoError::File`] when the file cannot be opened; [`IoError::Pattern`] when it cannot be
/// decoded or is not a square image of 1 to [`MAX_CELLS`] pixels per side.
pub fn load_pattern_png(path: &Path) -> Result<Vec<Vec<f64>>, IoError> {
    let pattern_err = |error: PatternError| IoError::Pattern {
        path: path.to_path_buf(),
        error,
    };
    crate::safe_file::check_regular(path, "read the pattern")?;
    let open = || {
        ImageReader::open(path)
            .map_err(|e| IoError::file("read the pattern", path, e))?
            // Trust the bytes, not the extension: a `.png` may hold a JPEG or TIFF.
            .with_guessed_format()
            .map_err(|e| IoError::file("read the pattern", path, e))
    };
    // Check the size from the header first, so a huge image is refused before it is decoded.
    let (w, h) = open()?
        .into_dimensions()
        .map_err(|e| pattern_err(PatternError::Unreadable(e)))?;
    check_size(w, h).map_err(pattern_err)?;
    // That was an EXR's display window; the decoder allocates its data window.
    if open()?.format() == Some(ImageFormat::OpenExr)
        && let Some((dw, dh)) = crate::photo::exr_data_window(path)
        && (dw > MAX_CELLS || dh > MAX_CELLS)
    {
        let side = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        return Err(pattern_err(PatternError::TooLarge {
            width: side(dw),
            height: side(dh),
        }));
    }
    let img = open()?
        .decode()
        .map_err(|e| pattern_err(PatternError::Unreadable(e)))?;
    pattern_from_image(&img).map_err(pattern_err)
}

/// The cells of a decoded image (see [`load_pattern_png`]).
///
/// # Errors
/// A [`PatternError`] with the size found when the image is empty, not square or larger than
/// [`MAX_CELLS`].
pub fn pattern_from_image(img: &DynamicImage) -> Result<Vec<Vec<f64>>, PatternError> {
    check_size(img.width(), img.height())?;
    let luma = img.to_luma8();
    Ok(luma
        .rows()
        .map(|row| {
            row.map(|p| if p.0[0] > OPEN_THRESHOLD { 1.0 } else { 0.0 })
                .collect()
        })
        .collect())
}

fn check_size(width: u32, height: u32) -> Result<(), PatternError> {
    if width == 0 || height == 0 {
        return Err(PatternError::Empty { width, height });
    }
    if width != height {
        return Err(PatternError::NotSquare { width, height });
    }
    if width as usize > MAX_CELLS {
        return Err(PatternError::TooLarge { width, height });
    }
    Ok(())
}

/// Writes cells as an 8-bit grey PNG, one pixel per cell, grey = round(value · 255)
/// (values are clamped to [0, 1] first).
///
/// # Errors
/// [`IoError::Image`] when the grid is empty, ragged or holds a non-finite value;
/// [`IoError::File`] when the file cannot be written.
pub fn save_pattern_png(path: &Path, cells: &[Vec<f64>]) -> Result<(), IoError> {
    let image_err = |message: String| IoError::Image {
        path: path.to_path_buf(),
        message,
    };
    let rows = cells.len();
    let cols = cells.first().map_or(0, Vec::len);
    if rows == 0 || cols == 0 {
        return Err(image_err("cannot save an empty opening".into()));
    }
    let too_big = || {
        image_err(format!(
            "the opening ({rows}×{cols} cells) is too large for an image"
        ))
    };
    let width = u32::try_from(cols).map_err(|_| too_big())?;
    let height = u32::try_from(rows).map_err(|_| too_big())?;
    let mut bytes = Vec::with_capacity(rows * cols);
    for (r, row) in cells.iter().enumerate() {
        if row.len() != cols {
            return Err(image_err(format!(
                "row {r} has {} cells but row 0 has {cols}; the grid must be rectangular",
                row.len()
            )));
        }
        for (c, &v) in row.iter().enumerate() {
            if !v.is_finite() {
                return Err(image_err(format!(
                    "cell [{r}][{c}] is {v}, not a transmittance"
                )));
            }
            bytes.push((v.clamp(0.0, 1.0) * 255.0).round() as u8);
        }
    }
    let img = GrayImage::from_raw(width, height, bytes).ok_or_else(too_big)?;
    let mut png = Vec::new();
    DynamicImage::ImageLuma8(img)
        .write_to(Cursor::new(&mut png), ImageFormat::Png)
        .map_err(|e| image_err(format!("cannot encode the PNG: {e}")))?;
    write_atomic(path, &png)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threshold_is_strictly_above_127() {
        let img = GrayImage::from_raw(2, 2, vec![127, 128, 0, 255]).unwrap();
        let cells = pattern_from_image(&DynamicImage::ImageLuma8(img)).unwrap();
        assert_eq!(cells, vec![vec![0.0, 1.0], vec![0.0, 1.0]]);
    }

    #[test]
    fn rows_run_top_to_bottom() {
        // Only the top-right pixel is white: cell [0][2].
        let mut img = GrayImage::new(3, 3);
        img.put_pixel(2, 0, image::Luma([255]));
        let cells = pattern_from_image(&DynamicImage::ImageLuma8(img)).unwrap();
        assert_eq!(cells[0], vec![0.0, 0.0, 1.0]);
        assert!(cells[1..].iter().flatten().all(|v| *v == 0.0));
    }

    #[test]
    fn non_square_empty_and_oversized_images_are_refused_with_their_size() {
        let e = pattern_from_image(&DynamicImage::new_luma8(4, 3)).unwrap_err();
        assert!(
            matches!(
                e,
                PatternError::NotSquare {
                    width: 4,
                    height: 3
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("4×3"), "{e}");
        let e = pattern_from_image(&DynamicImage::new_luma8(0, 0)).unwrap_err();
        assert!(
            matches!(
                e,
                PatternError::Empty {
                    width: 0,
                    height: 0
                }
            ),
            "{e:?}"
        );
        let n = MAX_CELLS as u32 + 1;
        let e = pattern_from_image(&DynamicImage::new_luma8(n, n)).unwrap_err();
        assert!(
            matches!(e, PatternError::TooLarge { width, height } if (width, height) == (n, n)),
            "{e:?}"
        );
        assert!(e.to_string().contains(&format!("{n}×{n}")), "{e}");
    }

    #[test]
    fn save_then_load_round_trips_a_binary_pattern() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.png");
        let cells = vec![
            vec![1.0, 0.0, 0.0],
            vec![0.0, 1.0, 1.0],
            vec![1.0, 1.0, 0.0],
        ];
        save_pattern_png(&path, &cells).unwrap();
        assert_eq!(load_pattern_png(&path).unwrap(), cells);
    }

    #[test]
    fn grey_levels_are_rounded_value_times_255() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g.png");
        save_pattern_png(&path, &[vec![0.5, 0.2], vec![1.0, 0.0]]).unwrap();
        let img = image::open(&path).unwrap().to_luma8();
        assert_eq!(img.as_raw(), &vec![128, 51, 255, 0]);
    }

    #[test]
    fn ragged_grids_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.png");
        let e = save_pattern_png(&path, &[vec![1.0, 0.0], vec![1.0]]).unwrap_err();
        assert!(e.to_string().contains("row 1"), "{e}");
    }
}
