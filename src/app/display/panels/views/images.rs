//! What the result views share about images: the log views' depth, a channel's display colour,
//! and the small log-scale thumbnails of the Field & depth view (the full-size image figures
//! come from `core::views`).

use std::ops::RangeInclusive;

use egui::{Color32, ColorImage};
use ndarray::Array2;

use crate::app::widgets::colormap::{self, Colormap};
use crate::core::figure::ColorScale;

/// Default depth of the log views: six decades below the peak show the display's faint
/// diffraction orders without drowning the image in round-off noise.
pub const DEFAULT_FLOOR_DECADES: f64 = 6.0;
/// Range the floor slider offers.
pub const FLOOR_DECADES_RANGE: RangeInclusive<f64> = 2.0..=9.0;

/// `a` (`[row, col]`, row 0 at the top) on a log scale from `reference · 10^−floor` to
/// `reference`.
pub fn log_image(a: &Array2<f64>, reference: f64, floor_decades: f64, map: Colormap) -> ColorImage {
    let scale = ColorScale::Log {
        reference,
        floor_decades,
    };
    let (rows, cols) = a.dim();
    let pixels = a
        .iter()
        .map(|v| colormap::color(map, scale.unit(*v)))
        .collect();
    ColorImage::new([cols, rows], pixels)
}

/// The display colour of a channel: red, green or blue by name, grey for anything else.
pub fn channel_color(name: &str) -> Color32 {
    match crate::core::figure::palette::channel(name) {
        Some(c) => crate::app::widgets::figure::color32(c),
        None => Color32::from_gray(150),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::figure::palette::CHANNELS;

    #[test]
    fn thumbnails_are_row_major_with_row_zero_on_top() {
        // 2 rows × 3 cols, bright sample at row 0, col 2.
        let mut a = Array2::zeros((2, 3));
        a[[0, 2]] = 4.0;
        a[[1, 0]] = 2.0;
        let log = log_image(&a, 4.0, 6.0, Colormap::Inferno);
        assert_eq!(log.size, [3, 2]);
        assert_eq!(log.pixels[2], colormap::color(Colormap::Inferno, 1.0));
        assert_eq!(log.pixels[0], colormap::color(Colormap::Inferno, 0.0));
    }

    #[test]
    fn channels_take_their_colour_by_name() {
        assert_eq!(
            channel_color("R"),
            crate::app::widgets::figure::color32(CHANNELS[0])
        );
        assert_eq!(
            channel_color("blue"),
            crate::app::widgets::figure::color32(CHANNELS[2])
        );
        assert_eq!(channel_color("550nm"), Color32::from_gray(150));
    }
}
