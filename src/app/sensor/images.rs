//! Pictures of a sensor run: the captures (grey, or RGB on a colour sensor), the gain map (log
//! colour scale), the bin map (one colour per bin size) and the saturation map, uploaded once
//! per run.

use egui::{Color32, ColorImage, TextureHandle, TextureOptions};
use ndarray::Array2;

use crate::app::widgets::colormap::{self, Colormap};
use crate::core::sensor::{BIN_SIZES, SensorRun};

/// Colours of the bin sizes 1, 2, 4, 8 (legend and map).
pub const BIN_COLORS: [Color32; 4] = [
    Color32::from_rgb(40, 40, 48),
    Color32::from_rgb(60, 140, 220),
    Color32::from_rgb(240, 180, 40),
    Color32::from_rgb(230, 70, 60),
];

pub fn bin_color(bin: f64) -> Color32 {
    let i = BIN_SIZES
        .iter()
        .position(|b| (*b as f64 - bin).abs() < 0.5)
        .unwrap_or(0);
    BIN_COLORS[i]
}

/// Colour of gain `g` on a log scale from 1 to `max_gain`.
pub fn gain_color(g: f64, max_gain: f64) -> Color32 {
    let t = if max_gain > 1.0 {
        (g.max(1.0).ln() / max_gain.ln()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    colormap::color(Colormap::Viridis, t as f32)
}

pub fn image_of<T: Copy>(a: &Array2<T>, color: impl Fn(T) -> Color32) -> ColorImage {
    let (h, w) = a.dim();
    ColorImage::new([w, h], a.iter().map(|v| color(*v)).collect())
}

pub fn grey(v: f64) -> Color32 {
    let g = (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    Color32::from_gray(g)
}

/// The colour of pixel `(y, x)` of one (grey) or three (R, G, B) display planes in `[0, 1]`.
fn pixel(planes: &[Array2<f64>], y: usize, x: usize) -> Color32 {
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    match planes {
        [r, g, b] => Color32::from_rgb(byte(r[[y, x]]), byte(g[[y, x]]), byte(b[[y, x]])),
        [p, ..] => grey(p[[y, x]]),
        [] => Color32::BLACK,
    }
}

/// One (grey) or three (R, G, B) display planes as an image.
pub fn display_image(planes: &[Array2<f64>]) -> ColorImage {
    let (h, w) = planes.first().map_or((0, 0), |p| p.dim());
    let pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (y, x)))
        .map(|(y, x)| pixel(planes, y, x))
        .collect();
    ColorImage::new([w, h], pixels)
}

/// `a` left of column `split`, `b` from it on (the split-slider comparison); each one (grey)
/// or three (R, G, B) display planes of one size.
pub fn split_image(a: &[Array2<f64>], b: &[Array2<f64>], split_col: usize) -> ColorImage {
    let (h, w) = a.first().map_or((0, 0), |p| p.dim());
    let mut pixels = Vec::with_capacity(h * w);
    for y in 0..h {
        for x in 0..w {
            pixels.push(match x.cmp(&split_col) {
                std::cmp::Ordering::Less => pixel(a, y, x),
                std::cmp::Ordering::Equal => Color32::YELLOW,
                std::cmp::Ordering::Greater => pixel(b, y, x),
            });
        }
    }
    ColorImage::new([w, h], pixels)
}

/// The uploaded pictures of one run.
pub struct RunTextures {
    pub truth: TextureHandle,
    /// The largest gain of any strategy: the top of the gain maps' shared colour scale.
    pub max_gain: f64,
    /// Per strategy: capture, gain map, bin map, saturation map.
    pub strategies: Vec<[TextureHandle; 4]>,
}

impl RunTextures {
    pub fn new(ctx: &egui::Context, run: &SensorRun, generation: u64) -> Self {
        let max_gain = run
            .strategies
            .iter()
            .flat_map(|s| s.gain_map.iter())
            .fold(1.0f64, |m, g| m.max(f64::from(*g)));
        let up =
            |name: String, img: ColorImage| ctx.load_texture(name, img, TextureOptions::NEAREST);
        let truth = up(
            format!("sensor-{generation}-truth"),
            display_image(&run.truth_display_planes()),
        );
        let strategies = run
            .strategies
            .iter()
            .enumerate()
            .map(|(i, s)| {
                [
                    up(
                        format!("sensor-{generation}-{i}-capture"),
                        display_image(&s.display_planes()),
                    ),
                    up(
                        format!("sensor-{generation}-{i}-gain"),
                        image_of(&s.gain_map, |g| gain_color(f64::from(g), max_gain)),
                    ),
                    up(
                        format!("sensor-{generation}-{i}-bin"),
                        image_of(&s.bin_map, |b| bin_color(f64::from(b))),
                    ),
                    up(
                        format!("sensor-{generation}-{i}-saturated"),
                        image_of(&s.saturated, |v| {
                            if v {
                                Color32::from_rgb(255, 40, 40)
                            } else {
                                Color32::from_gray(20)
                            }
                        }),
                    ),
                ]
            })
            .collect();
        RunTextures {
            truth,
            max_gain,
            strategies,
        }
    }
}
