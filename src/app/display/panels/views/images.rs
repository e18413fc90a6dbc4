//! Pure helpers of the result views: arrays → images, image placement in plot coordinates and
//! the teaching-overlay geometry. No `Ui` here, so all of it is unit-tested.

use std::ops::RangeInclusive;

use egui::{Color32, ColorImage};
use ndarray::Array2;

use crate::app::widgets::colormap::Colormap;
use crate::core::figure::palette::CHANNELS;

/// Default depth of the log views: six decades below the peak show the display's faint
/// diffraction orders without drowning the image in round-off noise.
pub const DEFAULT_FLOOR_DECADES: f64 = 6.0;
/// Range the floor slider offers.
pub const FLOOR_DECADES_RANGE: RangeInclusive<f64> = 2.0..=9.0;

/// Largest finite value of `a`, or 0 when there is none above 0.
pub fn peak(a: &Array2<f64>) -> f64 {
    a.iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
}

/// `log10(v / reference)`, clamped below at `−floor_decades`: the log of zero (or of a negative
/// round-off value) would be −∞, so the scale stops at the floor instead.
pub fn log_decades(v: f64, reference: f64, floor_decades: f64) -> f64 {
    if !(reference > 0.0) || !(v > 0.0) {
        return -floor_decades;
    }
    (v / reference).log10().clamp(-floor_decades, f64::INFINITY)
}

/// Position of `v` on a log colour scale: 0 at `reference · 10^−floor` and below, 1 at
/// `reference` and above.
pub fn log_unit(v: f64, reference: f64, floor_decades: f64) -> f32 {
    let floor = floor_decades.max(f64::MIN_POSITIVE);
    ((log_decades(v, reference, floor) + floor) / floor).clamp(0.0, 1.0) as f32
}

/// Position of `v` on a linear colour scale from 0 to `max`.
pub fn linear_unit(v: f64, max: f64) -> f32 {
    if !(max > 0.0) || !v.is_finite() {
        return 0.0;
    }
    (v / max).clamp(0.0, 1.0) as f32
}

/// A colour image of `a` (`[row, col]`, row 0 at the top) with the colour of each sample
/// chosen by `unit` ∈ [0, 1].
fn mapped_image(a: &Array2<f64>, map: Colormap, unit: impl Fn(f64) -> f32) -> ColorImage {
    let (rows, cols) = a.dim();
    let pixels = a.iter().map(|v| map.color(unit(*v))).collect();
    ColorImage::new([cols, rows], pixels)
}

/// `a` on a linear scale from 0 to `max`.
pub fn linear_image(a: &Array2<f64>, max: f64, map: Colormap) -> ColorImage {
    mapped_image(a, map, |v| linear_unit(v, max))
}

/// `a` on a log scale from `reference · 10^−floor` to `reference`.
pub fn log_image(a: &Array2<f64>, reference: f64, floor_decades: f64, map: Colormap) -> ColorImage {
    mapped_image(a, map, |v| log_unit(v, reference, floor_decades))
}

/// Which colour (0 red, 1 green, 2 blue) a channel name stands for, if any.
pub fn rgb_role(name: &str) -> Option<usize> {
    match name.trim().to_ascii_lowercase().as_str() {
        "r" | "red" => Some(0),
        "g" | "green" => Some(1),
        "b" | "blue" => Some(2),
        _ => None,
    }
}

/// The display colour of a channel: red, green or blue by name, grey for anything else.
pub fn channel_color(name: &str) -> Color32 {
    match rgb_role(name).and_then(|i| CHANNELS.get(i)) {
        Some(&c) => crate::app::widgets::figure::color32(c),
        None => Color32::from_gray(150),
    }
}

/// Which channel index feeds the red, green and blue planes of the composite: by name when any
/// channel is called R/G/B, otherwise the first three in order.
pub fn rgb_slots(names: &[&str]) -> [Option<usize>; 3] {
    let mut slots = [None; 3];
    for (i, name) in names.iter().enumerate() {
        if let Some(k) = rgb_role(name) {
            slots[k].get_or_insert(i);
        }
    }
    if slots.iter().all(Option::is_none) {
        for (k, slot) in slots.iter_mut().enumerate() {
            *slot = (k < names.len()).then_some(k);
        }
    }
    slots
}

/// RGB composite of up to three equally sized arrays: each normalised to its own peak (so a dim
/// channel is not lost) and mapped on a log scale with `floor_decades`. A missing plane, or one
/// whose size differs from the first present one, stays black.
pub fn rgb_composite(planes: [Option<&Array2<f64>>; 3], floor_decades: f64) -> ColorImage {
    let Some(dim) = planes.iter().flatten().map(|a| a.dim()).next() else {
        return ColorImage::filled([1, 1], Color32::BLACK);
    };
    let (rows, cols) = dim;
    let mut rgb = vec![0u8; rows * cols * 3];
    for (k, plane) in planes.iter().enumerate() {
        let Some(a) = plane.filter(|a| a.dim() == dim) else {
            continue;
        };
        let p = peak(a);
        for (i, v) in a.iter().enumerate() {
            rgb[i * 3 + k] = (log_unit(*v, p, floor_decades) * 255.0).round() as u8;
        }
    }
    ColorImage::from_rgb([cols, rows], &rgb)
}

/// A centred square grid of `n` samples spaced `step` (µm on the sensor, or cycles/pixel),
/// with sample `n / 2` at 0 (lib.rs centring). Plot coordinates: x = `step·(col − n/2)` to the
/// right, y = `step·(n/2 − row)` upwards, so row 0 (the image's top row) is drawn at the top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Samples per side.
    pub n: usize,
    /// Spacing between samples: µm on the sensor for a PSF, cycles/pixel for an MTF.
    pub step: f64,
}

impl Grid {
    fn centre_index(&self) -> f64 {
        (self.n / 2) as f64
    }

    /// Plot coordinates `[x, y]` of sample `[row, col]`.
    pub fn position(&self, row: usize, col: usize) -> [f64; 2] {
        let c = self.centre_index();
        [self.step * (col as f64 - c), self.step * (c - row as f64)]
    }

    /// Centre of the whole image in plot coordinates (half a sample off 0 for even `n`).
    pub fn image_centre(&self) -> [f64; 2] {
        let mid = (self.n as f64 - 1.0) / 2.0;
        let c = self.centre_index();
        [self.step * (mid - c), self.step * (c - mid)]
    }

    /// Width and height of the image in plot units (each sample covers one `step`).
    pub fn image_size(&self) -> [f64; 2] {
        [self.n as f64 * self.step; 2]
    }

    /// The sample `[row, col]` under the plot point `(x, y)`, if it lies on the grid.
    pub fn index_at(&self, x: f64, y: f64) -> Option<[usize; 2]> {
        if !(self.step > 0.0) {
            return None;
        }
        let c = self.centre_index();
        let col = (x / self.step + c).round();
        let row = (c - y / self.step).round();
        let n = self.n as f64;
        ((0.0..n).contains(&col) && (0.0..n).contains(&row)).then_some([row as usize, col as usize])
    }
}

/// Half-width of the centred square that holds every sample of `a` at or above `threshold`
/// (where the light is, on `grid`), with one sample to spare; at least four samples and at most
/// the image's own half-width. The views open on this square instead of the whole window.
pub fn light_half_extent(a: &Array2<f64>, grid: Grid, threshold: f64) -> f64 {
    let image_half = grid.image_size()[0] / 2.0;
    if !(grid.step > 0.0) {
        return image_half;
    }
    let reach = a
        .indexed_iter()
        .filter(|(_, v)| v.is_finite() && **v >= threshold && **v > 0.0)
        .map(|((row, col), _)| {
            let [x, y] = grid.position(row, col);
            x.abs().max(y.abs())
        })
        .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.max(r))));
    match reach {
        Some(r) => (r + 1.5 * grid.step).clamp(4.0 * grid.step, image_half.max(4.0 * grid.step)),
        None => image_half,
    }
}

/// A number in a short readable form: fixed for moderate magnitudes, scientific otherwise.
pub fn format_value(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (0.01..1000.0).contains(&a) {
        format!("{v:.3}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_mapping_stops_at_the_floor() {
        assert_eq!(log_decades(0.0, 1.0, 6.0), -6.0);
        assert_eq!(log_decades(-1e-20, 1.0, 6.0), -6.0);
        assert_eq!(log_decades(1e-9, 1.0, 6.0), -6.0);
        assert_eq!(log_decades(1.0, 0.0, 6.0), -6.0);
        assert!((log_decades(1e-3, 1.0, 6.0) + 3.0).abs() < 1e-12);
        assert_eq!(log_unit(0.0, 1.0, 6.0), 0.0);
        assert_eq!(log_unit(1.0, 1.0, 6.0), 1.0);
        assert_eq!(log_unit(5.0, 1.0, 6.0), 1.0);
        assert!((log_unit(1e-3, 1.0, 6.0) - 0.5).abs() < 1e-6);
        assert!((log_unit(0.02, 2.0, 4.0) - 0.5).abs() < 1e-6);
        assert!(log_unit(f64::NAN, 1.0, 6.0).is_finite());
    }

    #[test]
    fn images_are_row_major_with_row_zero_on_top() {
        // 2 rows × 3 cols, bright sample at row 0, col 2.
        let mut a = Array2::zeros((2, 3));
        a[[0, 2]] = 4.0;
        a[[1, 0]] = 2.0;
        let img = linear_image(&a, 4.0, Colormap::Inferno);
        assert_eq!(img.size, [3, 2]);
        assert_eq!(img.pixels[2], Colormap::Inferno.color(1.0));
        assert_eq!(img.pixels[3], Colormap::Inferno.color(0.5));
        assert_eq!(img.pixels[0], Colormap::Inferno.color(0.0));
        let log = log_image(&a, 4.0, 6.0, Colormap::Inferno);
        assert_eq!(log.pixels[2], Colormap::Inferno.color(1.0));
        assert_eq!(log.pixels[0], Colormap::Inferno.color(0.0));
    }

    #[test]
    fn rgb_composite_normalises_each_channel_to_its_own_peak() {
        let mut r = Array2::zeros((2, 2));
        r[[0, 0]] = 1e-6; // a dim channel still reaches full red
        r[[1, 1]] = 1e-9; // three decades down: half way on a 6-decade scale
        let mut g = Array2::zeros((2, 2));
        g[[0, 1]] = 0.5;
        let img = rgb_composite([Some(&r), Some(&g), None], 6.0);
        assert_eq!(img.size, [2, 2]);
        assert_eq!(img.pixels[0], Color32::from_rgb(255, 0, 0));
        assert_eq!(img.pixels[1], Color32::from_rgb(0, 255, 0));
        assert_eq!(img.pixels[3], Color32::from_rgb(128, 0, 0));
        // A plane of another size is ignored rather than misplaced.
        let odd = Array2::from_elem((3, 3), 1.0);
        let img = rgb_composite([Some(&r), None, Some(&odd)], 6.0);
        assert!(img.pixels.iter().all(|c| c.b() == 0));
        assert_eq!(rgb_composite([None, None, None], 6.0).size, [1, 1]);
    }

    #[test]
    fn rgb_slots_follow_names_then_order() {
        assert_eq!(rgb_slots(&["B", "G", "R"]), [Some(2), Some(1), Some(0)]);
        assert_eq!(rgb_slots(&["R", "G", "NIR"]), [Some(0), Some(1), None]);
        assert_eq!(rgb_slots(&["x", "y"]), [Some(0), Some(1), None]);
        assert_eq!(channel_color("red"), channel_color("R"));
        assert_eq!(channel_color("NIR"), Color32::from_gray(150));
    }

    #[test]
    fn grid_places_the_axis_at_zero_and_inverts_index_at() {
        let g = Grid { n: 6, step: 2.0 };
        assert_eq!(g.position(3, 3), [0.0, 0.0]);
        assert_eq!(g.position(0, 5), [4.0, 6.0]);
        assert_eq!(g.image_size(), [12.0, 12.0]);
        // Even n: the image extends half a sample further to the left and to the top.
        assert_eq!(g.image_centre(), [-1.0, 1.0]);
        for row in 0..6 {
            for col in 0..6 {
                let [x, y] = g.position(row, col);
                assert_eq!(g.index_at(x + 0.9, y - 0.9), Some([row, col]));
            }
        }
        assert_eq!(g.index_at(-7.1, 0.0), None);
        assert_eq!(g.index_at(0.0, 7.1), None);
        let odd = Grid { n: 5, step: 1.0 };
        assert_eq!(odd.image_centre(), [0.0, 0.0]);
    }

    #[test]
    fn views_open_on_where_the_light_is() {
        let g = Grid { n: 64, step: 2.0 };
        let mut a = Array2::zeros((64, 64));
        a[[32, 32]] = 1.0;
        // Light 10 samples right of and 5 below the axis, and a faint sample far out.
        a[[37, 42]] = 0.1;
        a[[0, 0]] = 1e-9;
        assert_eq!(light_half_extent(&a, g, 1e-6), 20.0 + 3.0);
        // A lower threshold reaches the faint corner: the whole image.
        assert_eq!(light_half_extent(&a, g, 1e-10), 64.0);
        // A lone peak still opens on a few samples, and no light shows everything.
        let mut spot = Array2::zeros((64, 64));
        spot[[32, 32]] = 1.0;
        assert_eq!(light_half_extent(&spot, g, 0.5), 8.0);
        assert_eq!(light_half_extent(&Array2::zeros((64, 64)), g, 0.5), 64.0);
    }

    #[test]
    fn values_format_compactly() {
        assert_eq!(format_value(0.0), "0");
        assert_eq!(format_value(0.125), "0.125");
        assert_eq!(format_value(1.5e-5), "1.50e-5");
    }
}
