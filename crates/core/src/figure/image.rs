//! Images in figures: an array of values placed on the axes, drawn through a colour scale and a
//! colour map (a PSF, an MTF, the V matrix, a sensor map). The mapping from value to colour is
//! written once here; the studio uploads the colours as a texture, the file renderer draws them,
//! Python gets the values with this metadata.

use std::sync::Arc;

use ndarray::Array2;

use super::{Colormap, Rgb};

/// How values map onto the colour map's `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ColorScale {
    /// 0 … `max`, linear.
    Linear {
        /// The value drawn at the top of the map.
        max: f64,
    },
    /// `reference · 10^−floor_decades` … `reference`, logarithmic, read relative to the
    /// reference (a PSF: "peak", "1e-3").
    Log {
        /// The value drawn at the top of the map (the peak).
        reference: f64,
        /// Decades below the reference drawn before the map bottoms out.
        floor_decades: f64,
    },
    /// `low` … `high`, logarithmic, read as values (a gain map: 1×, 2×, 4×…).
    LogRange {
        /// The value drawn at the bottom of the map.
        low: f64,
        /// The value drawn at the top.
        high: f64,
    },
}

/// How an image's samples get their colours.
#[derive(Debug, Clone, PartialEq)]
pub enum Paint {
    /// Each value through the image's scale and colour map.
    Mapped,
    /// An RGB composite: the red, green and blue planes, each through the image's scale
    /// relative to its own peak (so a dim channel is not lost), black where a plane is missing
    /// or of another size; `values` is the plane the readout names.
    Composite([Option<Arc<Array2<f64>>>; 3]),
    /// Planes ready to be seen, each in `[0, 1]`: one grey or three (R, G, B) sharing one
    /// scale (a tone-mapped photo keeps its white balance); `values` is what the readout names.
    Display(Vec<Arc<Array2<f64>>>),
    /// One colour per category: a sample takes the colour of the category whose value it
    /// equals (a bin map, a saturation mask), black when none; a key replaces the colour bar.
    Categories(Vec<Category>),
}

/// One category of a [`Paint::Categories`] image.
#[derive(Debug, Clone, PartialEq)]
pub struct Category {
    /// The sample value it stands for.
    pub value: f64,
    /// Its name in the key and the readout ("2×2 bins").
    pub label: String,
    /// Its colour.
    pub colour: Rgb,
}

impl Paint {
    /// The category whose value `v` is (within half a unit's round-off), if the paint has
    /// categories.
    pub fn category(&self, v: f64) -> Option<&Category> {
        match self {
            Paint::Categories(cats) => cats.iter().find(|c| (c.value - v).abs() < 1e-9),
            _ => None,
        }
    }

    /// Whether a colour bar explains the colours (a mapped image or a composite): a
    /// categorical image has a key instead, a display-ready one needs neither.
    pub fn has_colour_bar(&self) -> bool {
        matches!(self, Paint::Mapped | Paint::Composite(_))
    }
}

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

impl ColorScale {
    /// Position of `v` on the map, in `[0, 1]`: a non-finite or non-positive sample sits at
    /// the bottom ("no light"), never at the top.
    pub fn unit(self, v: f64) -> f32 {
        match self {
            ColorScale::Linear { max } => {
                if !(max > 0.0) || !v.is_finite() {
                    return 0.0;
                }
                (v / max).clamp(0.0, 1.0) as f32
            }
            ColorScale::Log {
                reference,
                floor_decades,
            } => {
                let floor = floor_decades.max(f64::MIN_POSITIVE);
                ((log_decades(v, reference, floor) + floor) / floor).clamp(0.0, 1.0) as f32
            }
            ColorScale::LogRange { low, high } => {
                if !(low > 0.0 && high > low && v > 0.0) {
                    return 0.0;
                }
                ((v / low).ln() / (high / low).ln()).clamp(0.0, 1.0) as f32
            }
        }
    }

    /// The same scale with its top at `reference` (a log scale's floor stays as many decades
    /// below it; a linear one runs from 0 to it).
    pub fn relative_to(self, reference: f64) -> ColorScale {
        match self {
            ColorScale::Linear { .. } => ColorScale::Linear { max: reference },
            ColorScale::Log { floor_decades, .. } => ColorScale::Log {
                reference,
                floor_decades,
            },
            ColorScale::LogRange { low, high } => ColorScale::LogRange {
                low: low * reference / high,
                high: reference,
            },
        }
    }

    /// The smallest value the colour map tells apart from no light: the floor of a log scale,
    /// 1 % of the maximum of a linear one (darker than that reads as black).
    pub fn visible_threshold(self) -> f64 {
        match self {
            ColorScale::Linear { max } => 0.01 * max,
            ColorScale::Log {
                reference,
                floor_decades,
            } => reference * 10f64.powf(-floor_decades),
            ColorScale::LogRange { low, .. } => low,
        }
    }

    /// The colour bar's labelled ticks: `(position on the map, value)`, bottom to top. Linear:
    /// quarters of the maximum; log: every decade below the reference (every other one past
    /// six), as `10^−d` times the reference.
    pub fn ticks(self) -> Vec<(f32, f64)> {
        match self {
            ColorScale::Linear { max } => (0..=4)
                .map(|k| (k as f32 / 4.0, max * f64::from(k) / 4.0))
                .collect(),
            ColorScale::Log {
                reference,
                floor_decades,
            } => {
                let decades = floor_decades.round().max(1.0) as i32;
                let every = if decades > 6 { 2 } else { 1 };
                let mut t: Vec<(f32, f64)> = (0..=decades)
                    .filter(|d| d % every == 0 || *d == decades)
                    .map(|d| {
                        let at = 1.0 - f64::from(d) / floor_decades;
                        (at.clamp(0.0, 1.0) as f32, reference * 10f64.powi(-d))
                    })
                    .collect();
                t.reverse();
                t
            }
            ColorScale::LogRange { low, high } => log_range_ticks(low, high)
                .into_iter()
                .map(|v| (ColorScale::LogRange { low, high }.unit(v), v))
                .collect(),
        }
    }

    /// The colour bar's tick labels, bottom to top: a relative log scale's as decades below
    /// the peak (`1e-3`, `peak`), the others as their values (`0.25`, `16`).
    pub fn tick_labels(self) -> Vec<(f32, String)> {
        self.ticks()
            .into_iter()
            .map(|(t, v)| {
                let label = match self {
                    ColorScale::Log { reference, .. } if reference > 0.0 => {
                        let d = (reference / v).log10().round() as i32;
                        if d == 0 {
                            "peak".into()
                        } else {
                            format!("1e-{d}")
                        }
                    }
                    _ => short_value(v),
                };
                (t, label)
            })
            .collect()
    }
}

/// Ticks of a log range: the 1-2-5 steps within `low … high` (whole powers of ten only when
/// those are more than six), with both ends.
fn log_range_ticks(low: f64, high: f64) -> Vec<f64> {
    if !(low > 0.0 && high > low && high.is_finite()) {
        return vec![low];
    }
    let decades = (high / low).log10();
    let steps: &[f64] = if decades > 3.0 {
        &[1.0]
    } else {
        &[1.0, 2.0, 5.0]
    };
    let mut out = vec![low];
    let mut power = 10f64.powf(low.log10().floor());
    while power <= high {
        for m in steps {
            let v = m * power;
            // Skip a step too close to an end to be read apart from it.
            let apart = |e: f64| (v / e).log10().abs() > 0.08 * decades.max(0.5);
            if v > low && v < high && apart(low) && apart(high) {
                out.push(v);
            }
        }
        power *= 10.0;
    }
    out.push(high);
    out
}

/// A number in a short readable form: three significant digits or so for moderate
/// magnitudes (`344`, `86`, `0.5`, `0.0123`), scientific otherwise (`1.5e-5`).
pub fn short_value(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (0.01..1000.0).contains(&a) {
        let decimals = (2.0 - a.log10().floor()).max(0.0) as usize;
        let text = format!("{v:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        let text = format!("{v:.2e}");
        match text.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => text,
        }
    }
}

/// An image on a panel's axes: `values[[row, col]]`, row 0 at the top, covering the rectangle
/// of `size` around `centre` (axes units), each sample one cell.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// What a value is, for the readout and the colour bar ("PSF", "V").
    pub name: String,
    /// The values' unit, when they have one.
    pub unit: Option<String>,
    /// The samples.
    pub values: Arc<Array2<f64>>,
    /// Centre of the image on the axes.
    pub centre: [f64; 2],
    /// Width and height of the image on the axes.
    pub size: [f64; 2],
    /// How values map onto the colour map.
    pub scale: ColorScale,
    /// The colour map.
    pub colormap: Colormap,
    /// How the samples get their colours.
    pub paint: Paint,
}

impl Image {
    /// The colour of every sample, row-major from the top row.
    pub fn colours(&self) -> Vec<Rgb> {
        let planes = match &self.paint {
            Paint::Mapped => {
                return self
                    .values
                    .iter()
                    .map(|v| self.colormap.at(self.scale.unit(*v)))
                    .collect();
            }
            Paint::Categories(_) => {
                return self
                    .values
                    .iter()
                    .map(|v| self.paint.category(*v).map_or(Rgb(0, 0, 0), |c| c.colour))
                    .collect();
            }
            Paint::Display(planes) => return self.display_colours(planes),
            Paint::Composite(planes) => planes,
        };
        let dim = self.values.dim();
        let mut rgb = vec![[0u8; 3]; dim.0 * dim.1];
        for (k, plane) in planes.iter().enumerate() {
            let Some(a) = plane.as_ref().filter(|a| a.dim() == dim) else {
                continue;
            };
            let scale = self.scale.relative_to(peak(a));
            for (px, v) in rgb.iter_mut().zip(a.iter()) {
                px[k] = (scale.unit(*v) * 255.0).round() as u8;
            }
        }
        rgb.into_iter().map(|[r, g, b]| Rgb(r, g, b)).collect()
    }

    /// The colours of display-ready planes: grey from one, R, G, B from three (black where a
    /// plane is of another size than `values`).
    fn display_colours(&self, planes: &[Arc<Array2<f64>>]) -> Vec<Rgb> {
        let dim = self.values.dim();
        let byte = |v: f64| {
            if v.is_finite() {
                (v.clamp(0.0, 1.0) * 255.0).round() as u8
            } else {
                0
            }
        };
        let n = dim.0 * dim.1;
        let fits = |p: &Arc<Array2<f64>>| p.dim() == dim;
        match planes {
            [r, g, b] if fits(r) && fits(g) && fits(b) => r
                .iter()
                .zip(g.iter())
                .zip(b.iter())
                .map(|((r, g), b)| Rgb(byte(*r), byte(*g), byte(*b)))
                .collect(),
            [p, ..] if fits(p) => p
                .iter()
                .map(|v| {
                    let g = byte(*v);
                    Rgb(g, g, g)
                })
                .collect(),
            _ => vec![Rgb(0, 0, 0); n],
        }
    }

    /// An image of `values` drawn through `scale` and `colormap`, one sample per axes unit,
    /// sample `[row, col]` centred on `x = col`, `y = −row` (a picture in pixels, row 0 at the
    /// top, as a downward axis shows it).
    pub fn pixels(
        name: &str,
        values: Arc<Array2<f64>>,
        scale: ColorScale,
        colormap: Colormap,
    ) -> Image {
        let (rows, cols) = values.dim();
        Image {
            name: name.into(),
            unit: None,
            values,
            centre: [(cols as f64 - 1.0) / 2.0, -(rows as f64 - 1.0) / 2.0],
            size: [cols as f64, rows as f64],
            scale,
            colormap,
            paint: Paint::Mapped,
        }
    }

    /// The same image painted `paint`.
    pub fn painted(self, paint: Paint) -> Image {
        Image { paint, ..self }
    }

    /// The value under the pointer as a readout names it: the category's label, or the value
    /// in its unit.
    pub fn describe(&self, v: f64) -> String {
        if let Some(c) = self.paint.category(v) {
            return format!("{}: {}", self.name, c.label);
        }
        let unit = self
            .unit
            .as_ref()
            .map_or(String::new(), |u| format!(" {u}"));
        format!("{} = {}{unit}", self.name, short_value(v))
    }

    /// Half-width of the square about the axes' origin that holds every sample at or above
    /// `threshold` (where the light is), one and a half cells to spare; at least four cells and
    /// at most the image's own half-width. Views open on this square, not the whole window.
    pub fn lit_half_extent(&self, threshold: f64) -> f64 {
        let image_half = self.size[0].max(self.size[1]) / 2.0;
        let cell = self.cell()[0].max(self.cell()[1]);
        if !(cell > 0.0) {
            return image_half;
        }
        let reach = self
            .values
            .indexed_iter()
            .filter(|(_, v)| v.is_finite() && **v >= threshold && **v > 0.0)
            .map(|((row, col), _)| {
                let [x, y] = self.position(row, col);
                x.abs().max(y.abs())
            })
            .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.max(r))));
        match reach {
            // The sample's centre plus half a cell is its edge; one more cell to spare.
            Some(r) => (r + 1.5 * cell).clamp(4.0 * cell, image_half.max(4.0 * cell)),
            None => image_half,
        }
    }

    /// Width and height of one sample on the axes.
    pub fn cell(&self) -> [f64; 2] {
        let (rows, cols) = self.values.dim();
        [
            self.size[0] / cols.max(1) as f64,
            self.size[1] / rows.max(1) as f64,
        ]
    }

    /// The sample `[row, col]` under the axes point `(x, y)`, if it lies on the image.
    pub fn index_at(&self, x: f64, y: f64) -> Option<[usize; 2]> {
        let (rows, cols) = self.values.dim();
        let [w, h] = self.cell();
        if !(w > 0.0 && h > 0.0) {
            return None;
        }
        let col = ((x - (self.centre[0] - self.size[0] / 2.0)) / w).floor();
        let row = (((self.centre[1] + self.size[1] / 2.0) - y) / h).floor();
        ((0.0..cols as f64).contains(&col) && (0.0..rows as f64).contains(&row))
            .then_some([row as usize, col as usize])
    }

    /// The axes point at the centre of sample `[row, col]`.
    pub fn position(&self, row: usize, col: usize) -> [f64; 2] {
        let [w, h] = self.cell();
        [
            self.centre[0] - self.size[0] / 2.0 + (col as f64 + 0.5) * w,
            self.centre[1] + self.size[1] / 2.0 - (row as f64 + 0.5) * h,
        ]
    }

    /// The value under `(x, y)`, if any.
    pub fn value_at(&self, x: f64, y: f64) -> Option<f64> {
        let [r, c] = self.index_at(x, y)?;
        self.values.get([r, c]).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: Array2<f64>, scale: ColorScale) -> Image {
        Image {
            name: "v".into(),
            unit: None,
            values: Arc::new(values),
            centre: [0.0, 0.0],
            size: [4.0, 2.0],
            scale,
            colormap: Colormap::Gray,
            paint: Paint::Mapped,
        }
    }

    #[test]
    fn a_sample_is_found_where_it_is_drawn() {
        let a = Array2::from_shape_fn((2, 4), |(r, c)| (10 * r + c) as f64);
        let img = image(a, ColorScale::Linear { max: 13.0 });
        for r in 0..2 {
            for c in 0..4 {
                let [x, y] = img.position(r, c);
                assert_eq!(img.index_at(x, y), Some([r, c]));
            }
        }
        // Row 0 is the top: the upper half of the rectangle.
        assert_eq!(img.index_at(-1.9, 0.9), Some([0, 0]));
        assert_eq!(img.value_at(1.9, -0.9), Some(13.0));
        assert_eq!(img.index_at(2.1, 0.0), None);
        assert_eq!(img.index_at(0.0, -1.1), None);
    }

    #[test]
    fn log_mapping_stops_at_the_floor() {
        assert_eq!(log_decades(0.0, 1.0, 6.0), -6.0);
        assert_eq!(log_decades(-1e-20, 1.0, 6.0), -6.0);
        assert_eq!(log_decades(1e-9, 1.0, 6.0), -6.0);
        assert_eq!(log_decades(1.0, 0.0, 6.0), -6.0);
        assert!((log_decades(1e-3, 1.0, 6.0) + 3.0).abs() < 1e-12);
        let log = |reference, floor_decades| ColorScale::Log {
            reference,
            floor_decades,
        };
        assert_eq!(log(1.0, 6.0).unit(5.0), 1.0);
        assert!((log(2.0, 4.0).unit(0.02) - 0.5).abs() < 1e-6);
        assert!(log(1.0, 6.0).unit(f64::NAN).is_finite());
    }

    #[test]
    fn the_scales_put_the_peak_at_the_top_and_no_light_at_the_bottom() {
        let lin = ColorScale::Linear { max: 2.0 };
        assert_eq!(lin.unit(2.0), 1.0);
        assert_eq!(lin.unit(1.0), 0.5);
        assert_eq!(lin.unit(f64::NAN), 0.0);
        assert_eq!(lin.unit(-1.0), 0.0);
        let log = ColorScale::Log {
            reference: 1.0,
            floor_decades: 4.0,
        };
        assert_eq!(log.unit(1.0), 1.0);
        assert!((log.unit(1e-2) - 0.5).abs() < 1e-6);
        assert_eq!(log.unit(0.0), 0.0);
        assert_eq!(log.unit(1e-9), 0.0);
        assert!((log.visible_threshold() - 1e-4).abs() < 1e-18);
        assert_eq!(lin.visible_threshold(), 0.02);
    }

    #[test]
    fn colour_bar_ticks_run_from_the_bottom_to_the_peak() {
        let t = ColorScale::Log {
            reference: 2.0,
            floor_decades: 3.0,
        }
        .ticks();
        assert_eq!(t.first(), Some(&(0.0, 2e-3)));
        assert_eq!(t.last(), Some(&(1.0, 2.0)));
        assert!(t.windows(2).all(|w| w[0].0 < w[1].0 && w[0].1 < w[1].1));
        let l = ColorScale::Linear { max: 8.0 }.ticks();
        assert_eq!(l.len(), 5);
        assert_eq!(l[2], (0.5, 4.0));
    }

    #[test]
    fn colours_follow_the_scale_and_the_map() {
        let a = Array2::from_shape_vec((1, 3), vec![0.0, 1.0, 2.0]).unwrap_or_default();
        let img = image(a, ColorScale::Linear { max: 2.0 });
        let c = img.colours();
        assert_eq!(c[0], Rgb(0, 0, 0));
        assert_eq!(c[2], Rgb(255, 255, 255));
        assert_eq!(c[1], Colormap::Gray.at(0.5));
    }

    #[test]
    fn a_composite_scales_each_plane_to_its_own_peak() {
        let bright = Arc::new(Array2::from_elem((1, 2), 100.0));
        let dim = Arc::new(Array2::from_shape_vec((1, 2), vec![1e-3, 1e-9]).unwrap_or_default());
        let mut img = image(
            (*bright).clone(),
            ColorScale::Log {
                reference: 1.0,
                floor_decades: 3.0,
            },
        );
        img.paint = Paint::Composite([Some(bright), Some(dim), None]);
        let c = img.colours();
        // Red at its own peak everywhere; green full where it peaks, black past 3 decades
        // below; blue missing.
        assert_eq!(c[0], Rgb(255, 255, 0));
        assert_eq!(c[1], Rgb(255, 0, 0));
    }

    #[test]
    fn the_lit_square_holds_the_light_and_no_more() {
        // 9×9 cells of 1 µm centred on 0, light only within ±2 µm of the centre.
        let a = Array2::from_shape_fn((9, 9), |(r, c)| {
            if r.abs_diff(4) <= 2 && c.abs_diff(4) <= 2 {
                1.0
            } else {
                0.0
            }
        });
        let mut img = image(a, ColorScale::Linear { max: 1.0 });
        img.size = [9.0, 9.0];
        assert_eq!(img.lit_half_extent(0.5), 4.0_f64.max(2.0 + 1.5));
        // Nothing lit: the whole image.
        assert_eq!(img.lit_half_extent(2.0), 4.5);
    }

    #[test]
    fn a_log_range_puts_its_ends_at_the_ends_and_reads_in_values() {
        let g = ColorScale::LogRange {
            low: 1.0,
            high: 16.0,
        };
        assert_eq!(g.unit(1.0), 0.0);
        assert_eq!(g.unit(16.0), 1.0);
        assert!(
            (g.unit(4.0) - 0.5).abs() < 1e-6,
            "4× is halfway on a log scale"
        );
        assert_eq!(g.unit(0.5), 0.0);
        assert_eq!(g.unit(f64::NAN), 0.0);
        let labels: Vec<String> = g.tick_labels().into_iter().map(|(_, l)| l).collect();
        assert_eq!(labels, ["1", "2", "5", "10", "16"]);
        let t = g.ticks();
        assert!(t.windows(2).all(|w| w[0].0 < w[1].0 && w[0].1 < w[1].1));
        assert_eq!(g.visible_threshold(), 1.0);
        // One gain everywhere: one tick, nothing divides by zero.
        let flat = ColorScale::LogRange {
            low: 1.0,
            high: 1.0,
        };
        assert_eq!(flat.unit(1.0), 0.0);
        assert_eq!(flat.ticks().len(), 1);
    }

    #[test]
    fn relative_log_ticks_read_as_decades_below_the_peak() {
        let labels: Vec<String> = ColorScale::Log {
            reference: 5.0,
            floor_decades: 2.0,
        }
        .tick_labels()
        .into_iter()
        .map(|(_, l)| l)
        .collect();
        assert_eq!(labels, ["1e-2", "1e-1", "peak"]);
    }

    #[test]
    fn short_values_keep_three_digits_and_drop_trailing_zeros() {
        assert_eq!(short_value(0.0), "0");
        assert_eq!(short_value(344.4), "344");
        assert_eq!(short_value(0.5), "0.5");
        assert_eq!(short_value(16.0), "16");
        assert_eq!(short_value(0.01234), "0.0123");
        assert_eq!(short_value(1.5e-5), "1.5e-5");
        assert_eq!(short_value(2.0e6), "2e6");
    }

    #[test]
    fn display_planes_are_drawn_as_they_are_and_share_one_scale() {
        let a = |v: Vec<f64>| Arc::new(Array2::from_shape_vec((1, 2), v).unwrap_or_default());
        let values = Array2::zeros((1, 2));
        let grey = image(values.clone(), ColorScale::Linear { max: 1.0 })
            .painted(Paint::Display(vec![a(vec![0.0, 0.5])]));
        assert_eq!(grey.colours(), [Rgb(0, 0, 0), Rgb(128, 128, 128)]);
        // A dim blue stays dim: no plane is stretched to its own peak (that would tint).
        let rgb = image(values, ColorScale::Linear { max: 1.0 }).painted(Paint::Display(vec![
            a(vec![1.0, 2.0]),
            a(vec![1.0, f64::NAN]),
            a(vec![0.2, -1.0]),
        ]));
        assert_eq!(rgb.colours(), [Rgb(255, 255, 51), Rgb(255, 0, 0)]);
        assert!(!rgb.paint.has_colour_bar());
    }

    #[test]
    fn categories_colour_their_values_and_name_them() {
        let cats = vec![
            Category {
                value: 1.0,
                label: "1×1".into(),
                colour: Rgb(1, 2, 3),
            },
            Category {
                value: 2.0,
                label: "2×2".into(),
                colour: Rgb(4, 5, 6),
            },
        ];
        let a = Array2::from_shape_vec((1, 3), vec![2.0, 1.0, 7.0]).unwrap_or_default();
        let img = image(a, ColorScale::Linear { max: 1.0 }).painted(Paint::Categories(cats));
        assert_eq!(img.colours(), [Rgb(4, 5, 6), Rgb(1, 2, 3), Rgb(0, 0, 0)]);
        assert_eq!(img.describe(2.0), "v: 2×2");
        assert_eq!(img.describe(7.0), "v = 7");
        assert!(!img.paint.has_colour_bar());
    }

    #[test]
    fn a_pixel_image_puts_sample_centres_on_whole_coordinates() {
        let a = Arc::new(Array2::from_shape_fn((3, 5), |(r, c)| (10 * r + c) as f64));
        let img = Image::pixels("v", a, ColorScale::Linear { max: 1.0 }, Colormap::Gray);
        assert_eq!(img.position(0, 0), [0.0, 0.0]);
        assert_eq!(img.position(2, 4), [4.0, -2.0]);
        assert_eq!(img.value_at(3.0, -1.0), Some(13.0));
    }
}
