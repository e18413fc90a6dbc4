//! Perceptual colour maps for images in figures (a PSF, an MTF, a matrix).
//!
//! Each map is matplotlib's, sampled at ten evenly spaced stops and interpolated linearly in
//! sRGB. Ten stops keep the table small while staying within a couple of 8-bit steps of the
//! 256-entry originals, and keep the luminance monotone (a test checks it), so brighter always
//! means more light and a grey-scale print still reads correctly.

use super::Rgb;

/// A sequential colour map from 0 (low) to 1 (high).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Colormap {
    /// Black → purple → orange → pale yellow. Dark means "no light", so PSFs read naturally.
    #[default]
    Inferno,
    /// Dark blue → green → yellow; used where a black background would hide the low end.
    Viridis,
    /// Black → white: the scale of each plane of an RGB composite.
    Gray,
}

/// sRGB stops at `t = k / 9`, from matplotlib's `inferno`.
const INFERNO: [[u8; 3]; 10] = [
    [0x00, 0x00, 0x04],
    [0x1b, 0x0c, 0x41],
    [0x4a, 0x0c, 0x6b],
    [0x78, 0x1c, 0x6d],
    [0xa5, 0x2c, 0x60],
    [0xcf, 0x44, 0x46],
    [0xed, 0x69, 0x25],
    [0xfb, 0x9b, 0x06],
    [0xf7, 0xd1, 0x3d],
    [0xfc, 0xff, 0xa4],
];

/// Black to white in ten equal sRGB steps (interpolation makes it exact in between).
const GRAY: [[u8; 3]; 10] = [
    [0, 0, 0],
    [28, 28, 28],
    [57, 57, 57],
    [85, 85, 85],
    [113, 113, 113],
    [142, 142, 142],
    [170, 170, 170],
    [198, 198, 198],
    [227, 227, 227],
    [255, 255, 255],
];

/// sRGB stops at `t = k / 9`, from matplotlib's `viridis`.
const VIRIDIS: [[u8; 3]; 10] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x28, 0x78],
    [0x3e, 0x49, 0x89],
    [0x31, 0x68, 0x8e],
    [0x26, 0x82, 0x8e],
    [0x1f, 0x9e, 0x89],
    [0x35, 0xb7, 0x79],
    [0x6e, 0xce, 0x58],
    [0xb5, 0xde, 0x2b],
    [0xfd, 0xe7, 0x25],
];

impl Colormap {
    fn stops(self) -> &'static [[u8; 3]; 10] {
        match self {
            Colormap::Inferno => &INFERNO,
            Colormap::Viridis => &VIRIDIS,
            Colormap::Gray => &GRAY,
        }
    }

    /// The map at `t` as sRGB components in `[0, 255]`, unrounded. `t` is clamped to `[0, 1]`;
    /// NaN maps to 0 (the low end), so a bad sample shows as "no signal", never as a bright pixel.
    pub fn rgb(self, t: f32) -> [f32; 3] {
        let stops = self.stops();
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let x = t * (stops.len() - 1) as f32;
        // `x` lies in [0, 9]; the last segment also takes x = 9 exactly.
        let i = (x.floor() as usize).min(stops.len() - 2);
        let f = x - i as f32;
        let (a, b) = (stops[i], stops[i + 1]);
        std::array::from_fn(|k| f32::from(a[k]) + (f32::from(b[k]) - f32::from(a[k])) * f)
    }

    /// The map's name, as matplotlib names it (`inferno`, `viridis`, `gray`).
    pub fn name(self) -> &'static str {
        match self {
            Colormap::Inferno => "inferno",
            Colormap::Viridis => "viridis",
            Colormap::Gray => "gray",
        }
    }

    /// The map at `t` (clamped to `[0, 1]`), rounded to 8 bits a channel.
    pub fn at(self, t: f32) -> Rgb {
        let [r, g, b] = self.rgb(t).map(|c| c.round().clamp(0.0, 255.0) as u8);
        Rgb(r, g, b)
    }
}

/// Relative luminance (Rec. 709 weights on linear light) of an sRGB colour with components in
/// `[0, 255]`; used to check that a map's brightness increases.
pub fn relative_luminance(rgb: [f32; 3]) -> f32 {
    let lin = |c: f32| {
        let c = c / 255.0;
        if c <= 0.040_45 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * lin(rgb[0]) + 0.7152 * lin(rgb[1]) + 0.0722 * lin(rgb[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_are_the_first_and_last_stops() {
        assert_eq!(Colormap::Inferno.at(0.0), Rgb(0, 0, 4));
        assert_eq!(Colormap::Inferno.at(1.0), Rgb(252, 255, 164));
        assert_eq!(Colormap::Viridis.at(0.0), Rgb(68, 1, 84));
        assert_eq!(Colormap::Viridis.at(1.0), Rgb(253, 231, 37));
    }

    #[test]
    fn out_of_range_and_nan_are_clamped() {
        for map in [Colormap::Inferno, Colormap::Viridis, Colormap::Gray] {
            assert_eq!(map.at(-3.0), map.at(0.0));
            assert_eq!(map.at(7.0), map.at(1.0));
            assert_eq!(map.at(f32::NAN), map.at(0.0));
        }
    }

    #[test]
    fn luminance_increases_monotonically() {
        for map in [Colormap::Inferno, Colormap::Viridis, Colormap::Gray] {
            let mut prev = -1.0f32;
            for k in 0..=1000 {
                let y = relative_luminance(map.rgb(k as f32 / 1000.0));
                assert!(y >= prev, "{map:?} darkens at t = {}", k as f32 / 1000.0);
                prev = y;
            }
            // And it spans a useful range.
            let span = relative_luminance(map.rgb(1.0)) - relative_luminance(map.rgb(0.0));
            assert!(span > 0.7, "{map:?} spans only {span}");
        }
    }

    #[test]
    fn midpoint_interpolates_between_stops() {
        // t = 1/18 lies halfway between the first two inferno stops.
        let c = Colormap::Inferno.rgb(1.0 / 18.0);
        assert!((c[0] - 13.5).abs() < 1e-3 && (c[2] - 34.5).abs() < 1e-3);
    }
}
