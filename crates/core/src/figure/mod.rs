//! Figures as data: panels of series with named axes and units, bands, annotations (rings,
//! lattices, marker lines) and one palette, described once by pure functions and drawn by
//! each front end its own way: the studio with egui_plot, files with plotters (PNG and SVG),
//! Python as arrays with this metadata. Nothing here knows how a figure is drawn.

mod colormap;
mod image;

pub use colormap::{Colormap, relative_luminance};
pub use image::{Category, ColorScale, Image, Paint, log_decades, peak, short_value};

/// A colour, 8 bits a channel (sRGB).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

/// The colours every figure draws with.
pub mod palette {
    use super::Rgb;

    /// One colour a series, in order (matplotlib's "tab10" start, readable on white and on a
    /// dark theme).
    pub const SERIES: [Rgb; 6] = [
        Rgb(31, 119, 180),
        Rgb(214, 39, 40),
        Rgb(44, 160, 44),
        Rgb(148, 103, 189),
        Rgb(255, 127, 14),
        Rgb(23, 190, 207),
    ];

    /// The colour of series `i`, cycling.
    pub fn series(i: usize) -> Rgb {
        SERIES[i % SERIES.len()]
    }

    /// The colours of a camera's red, green and blue channels in plots and overlays.
    pub const CHANNELS: [Rgb; 3] = [Rgb(230, 75, 60), Rgb(60, 175, 80), Rgb(70, 130, 235)];

    /// Which colour (0 red, 1 green, 2 blue) a channel name stands for, if any.
    pub fn rgb_role(name: &str) -> Option<usize> {
        match name.trim().to_ascii_lowercase().as_str() {
            "r" | "red" => Some(0),
            "g" | "green" => Some(1),
            "b" | "blue" => Some(2),
            _ => None,
        }
    }

    /// The colour of a channel named R, G or B (or red, green, blue), if it is one.
    pub fn channel(name: &str) -> Option<Rgb> {
        rgb_role(name).and_then(|i| CHANNELS.get(i).copied())
    }

    /// Annotations drawn over data (rings, lattices, marker lines).
    pub const ANNOTATION: Rgb = Rgb(255, 170, 0);

    /// A reference drawn beside the data (the bare T-OLED, the unfolded lens), dashed.
    pub const REFERENCE: Rgb = Rgb(150, 150, 150);

    /// The colour of a wavelength, blue at 400 nm through green to red at 700 nm (thesis
    /// Fig. 4.4): the hue runs from 240° down to 0° at 90 % saturation, full value.
    pub fn wavelength(nm: f64) -> Rgb {
        let t = ((nm - 400.0) / 300.0).clamp(0.0, 1.0);
        let hue = 240.0 * (1.0 - t);
        let (s, v) = (0.9, 1.0);
        let c = v * s;
        let x = c * (1.0 - ((hue / 60.0) % 2.0 - 1.0).abs());
        let (r, g, b) = match (hue / 60.0) as u32 {
            0 => (c, x, 0.0),
            1 => (x, c, 0.0),
            2 => (0.0, c, x),
            3 => (0.0, x, c),
            _ => (x, 0.0, c),
        };
        let m = v - c;
        let byte = |u: f64| ((u + m) * 255.0).round().clamp(0.0, 255.0) as u8;
        Rgb(byte(r), byte(g), byte(b))
    }
}

/// One axis: what it measures and in what unit; a categorical axis names its positions
/// `0, 1, 2, …`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Axis {
    /// What the axis measures (`pitch`, `AUC of the radial-minimum MTF`).
    pub label: String,
    /// Its unit (`µm`, `cycles/pixel`); `None` for a pure number or a unit already in the label.
    pub unit: Option<String>,
    /// Names of the positions of a categorical axis (a tiling, a display), by index.
    pub categories: Option<Vec<String>>,
    /// The axis counts downward (a matrix's rows, row 0 at the top): values are stored
    /// negated, so that they grow down the page, and shown as their magnitude.
    pub downward: bool,
    /// Values are stored as their log10 and shown as powers of ten (`1e-3`).
    pub log10: bool,
    /// The range the plot opens on (and returns to); `None`: the data's.
    pub view: Option<[f64; 2]>,
    /// Where the studio puts the ticks (the light levels of a comparison), in stored values;
    /// `None`, and in files: where the renderer puts them.
    pub ticks: Option<Vec<f64>>,
}

impl Axis {
    /// An axis of a quantity in a unit.
    pub fn new(label: impl Into<String>, unit: Option<&str>) -> Self {
        Axis {
            label: label.into(),
            unit: unit.map(str::to_string),
            categories: None,
            downward: false,
            log10: false,
            view: None,
            ticks: None,
        }
    }

    /// The axis of a quantity drawn on a log scale: values stored as their log10.
    pub fn log10(label: impl Into<String>, unit: Option<&str>) -> Self {
        Axis {
            log10: true,
            ..Axis::new(label, unit)
        }
    }

    /// The same axis opening on `lo … hi`.
    pub fn with_view(self, lo: f64, hi: f64) -> Self {
        Axis {
            view: Some([lo, hi]),
            ..self
        }
    }

    /// The tick label of the stored `value`: on a log axis the number itself (`250`, `0.01`),
    /// or a power of ten (`1e-6`) for a whole decade far from 1; the magnitude on a downward
    /// axis; else `None` for the renderer's own number.
    pub fn tick_label(&self, value: f64) -> Option<String> {
        if self.log10 {
            let whole = (value - value.round()).abs() < 1e-9;
            Some(if whole && !(-2.0..=4.0).contains(&value.round()) {
                format!("1e{}", value.round())
            } else {
                let v = 10f64.powf(value);
                // Three significant digits at most, no trailing zeros.
                let digits = (2.0 - v.log10().floor()).clamp(0.0, 12.0) as usize;
                let text = format!("{v:.digits$}");
                if text.contains('.') {
                    text.trim_end_matches('0').trim_end_matches('.').to_string()
                } else {
                    text
                }
            })
        } else if self.downward {
            // A tick at the top row arrives as ±1e-14 or so (the plot's own arithmetic): it
            // reads "0", not "-0".
            let shown = -value;
            let shown = if shown.abs() < 1e-9 { 0.0 } else { shown };
            Some(format!("{shown}"))
        } else {
            None
        }
    }

    /// The axis of a quantity counted downward ([`Axis::downward`]).
    pub fn downward(label: impl Into<String>, unit: Option<&str>) -> Self {
        Axis {
            downward: true,
            ..Axis::new(label, unit)
        }
    }

    /// The number shown for the stored `value`: its magnitude on a downward axis.
    pub fn shown(&self, value: f64) -> f64 {
        if self.downward { -value } else { value }
    }

    /// The axis title as drawn: `label (unit)`.
    pub fn title(&self) -> String {
        match &self.unit {
            Some(u) => format!("{} ({u})", self.label),
            None => self.label.clone(),
        }
    }

    /// The tick label at `value`: the category there on a categorical axis (nothing between
    /// categories), else `None` for the renderer's own number.
    pub fn category_at(&self, value: f64) -> Option<String> {
        let names = self.categories.as_ref()?;
        let i = value.round();
        Some(if (value - i).abs() < 1e-6 && i >= 0.0 {
            names.get(i as usize).cloned().unwrap_or_default()
        } else {
            String::new()
        })
    }
}

/// Segments of a drawn ring: smooth at any size a plot draws it.
pub const RING_SEGMENTS: usize = 96;

/// A circle of `radius` around `centre` as a closed polyline of `segments` (at least 3).
pub fn circle_points(centre: [f64; 2], radius: f64, segments: usize) -> Vec<[f64; 2]> {
    let segments = segments.max(3);
    (0..=segments)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / segments as f64;
            [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
        })
        .collect()
}

/// How a series is marked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A line through the points.
    Line,
    /// The points alone (a cloud).
    Points,
    /// A line with a dot at each point.
    LineAndPoints,
    /// A thinner dashed line: a reference drawn beside the data (the bare T-OLED, the unfolded
    /// lens).
    DashedLine,
    /// A bar from 0 to each point's y, 0.8 of the panel's closest spacing of bars wide.
    Bars,
    /// Hollow diamonds: a reference's values at points, around the data's filled ones (the
    /// closed form's diffraction orders).
    Hollow,
    /// A thin, fainter line: a companion of a main curve (the radial mean beside the minimum).
    FaintLine,
    /// A dotted line: a third curve of one colour (a horizontal slice).
    DottedLine,
    /// A faint dotted vertical rule at each point's x, under the curves (where an MTF repeats).
    Rules,
}

/// One named series of points.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Its legend entry.
    pub name: String,
    /// Its colour.
    pub colour: Rgb,
    /// How it is marked.
    pub mark: Mark,
    /// `[x, y]` in the axes' units, in drawing order.
    pub points: Vec<[f64; 2]>,
    /// A shaded spread around it, `[x, low, high]` (the sweep plots: mean ± SD over the seeds),
    /// when there is one.
    pub band: Option<Vec<[f64; 3]>>,
}

impl Series {
    /// A series without a band.
    pub fn new(name: impl Into<String>, colour: Rgb, mark: Mark, points: Vec<[f64; 2]>) -> Self {
        Series {
            name: name.into(),
            colour,
            mark,
            points,
            band: None,
        }
    }
}

/// Something drawn over the data to read it by: a physics landmark or a marker.
#[derive(Debug, Clone, PartialEq)]
pub enum Annotation {
    /// A circle (the Airy disc's first dark ring).
    Ring {
        /// Its centre, in the axes' units.
        centre: [f64; 2],
        /// Its radius, in the axes' units.
        radius: f64,
        /// What it marks.
        label: String,
    },
    /// Points of a lattice (the diffraction orders of a periodic tiling).
    Lattice {
        /// The lattice points, in the axes' units.
        points: Vec<[f64; 2]>,
        /// What they mark.
        label: String,
    },
    /// A vertical line at `x`.
    VLine {
        /// Where.
        x: f64,
        /// What it marks.
        label: String,
    },
    /// A horizontal line at `y`.
    HLine {
        /// Where.
        y: f64,
        /// What it marks.
        label: String,
    },
}

/// One plot: axes, series and annotations under a title.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Its title.
    pub title: String,
    /// The horizontal axis.
    pub x: Axis,
    /// The vertical axis.
    pub y: Axis,
    /// The data, drawn in order.
    pub series: Vec<Series>,
    /// Drawn over the data.
    pub annotations: Vec<Annotation>,
    /// Images under the data (a PSF, a matrix); the first one's scale is the colour bar.
    pub images: Vec<Image>,
    /// The legend's rows, each a list of series names (a row per channel); empty: one row.
    pub legend_rows: Vec<Vec<String>>,
    /// One axis unit is as long on screen in x as in y (a picture, not a graph).
    pub equal_aspect: bool,
}

impl Panel {
    /// A picture in pixels: `image` on x and y axes in px, rows counted down, one pixel square.
    pub fn picture(title: String, image: Image) -> Panel {
        Panel {
            title,
            x: Axis::new("x", Some("px")),
            y: Axis::downward("y", Some("px")),
            images: vec![image],
            equal_aspect: true,
            ..Panel::default()
        }
    }

    /// Whether the panel needs a legend: more than one series to tell apart (one series is
    /// named by the title, and a legend box would hide part of a small plot).
    pub fn wants_legend(&self) -> bool {
        let mut names: Vec<&str> = self.series.iter().map(|s| s.name.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        names.len() > 1
    }

    /// The corner of the data's range with the fewest points in its quarter: where a legend
    /// hides the least (the bottom right first on a tie, then the top right).
    pub fn quietest_corner(&self) -> Corner {
        let Some(([x0, x1], [y0, y1])) = self.data_bounds() else {
            return Corner::RightBottom;
        };
        let (mx, my) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let mut counts = [0usize; 4];
        for p in self.series.iter().flat_map(|s| &s.points) {
            if p[0].is_finite() && p[1].is_finite() {
                let right = p[0] >= mx;
                let top = p[1] >= my;
                counts[usize::from(right) * 2 + usize::from(!top)] += 1;
            }
        }
        // Index: 0 left top, 1 left bottom, 2 right top, 3 right bottom.
        let order = [3, 2, 0, 1];
        let best = order
            .iter()
            .copied()
            .min_by_key(|i| counts[*i])
            .unwrap_or(3);
        [
            Corner::LeftTop,
            Corner::LeftBottom,
            Corner::RightTop,
            Corner::RightBottom,
        ][best]
    }

    /// The width of the panel's bars: 0.8 of the closest spacing of their x (1 for one bar).
    pub fn bar_width(&self) -> f64 {
        let mut xs: Vec<f64> = self
            .series
            .iter()
            .filter(|s| s.mark == Mark::Bars)
            .flat_map(|s| s.points.iter().map(|p| p[0]))
            .filter(|x| x.is_finite())
            .collect();
        xs.sort_by(f64::total_cmp);
        let gap = xs
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|d| *d > 0.0)
            .fold(f64::INFINITY, f64::min);
        if gap.is_finite() { 0.8 * gap } else { 1.0 }
    }

    /// The smallest and largest x and y of the data (bands and images included), ignoring
    /// non-finite values; `None` when there is none.
    pub fn data_bounds(&self) -> Option<([f64; 2], [f64; 2])> {
        let mut x = [f64::INFINITY, f64::NEG_INFINITY];
        let mut y = x;
        let mut add = |px: f64, py: f64| {
            if px.is_finite() && py.is_finite() {
                x = [x[0].min(px), x[1].max(px)];
                y = [y[0].min(py), y[1].max(py)];
            }
        };
        for img in &self.images {
            add(
                img.centre[0] - img.size[0] / 2.0,
                img.centre[1] - img.size[1] / 2.0,
            );
            add(
                img.centre[0] + img.size[0] / 2.0,
                img.centre[1] + img.size[1] / 2.0,
            );
        }
        for s in &self.series {
            for p in &s.points {
                add(p[0], p[1]);
            }
            for b in s.band.iter().flatten() {
                add(b[0], b[1]);
                add(b[0], b[2]);
            }
        }
        x[0].is_finite().then_some((x, y))
    }
}

/// A corner of a panel's plotting area.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    /// Top left.
    LeftTop,
    /// Bottom left.
    LeftBottom,
    /// Top right.
    RightTop,
    /// Bottom right.
    RightBottom,
}

/// The sides a figure file may have, pixels (PNG) or user units (SVG): enough for a slide's
/// thumbnail, and a poster's 6000 px without a gigabyte of pixels.
pub const FIGURE_SIDE_PX: std::ops::RangeInclusive<u32> = 240..=6000;

/// A figure file's format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FigureFormat {
    /// Scalable: plots stay sharp in a paper.
    Svg,
    /// Pixels at the chosen size.
    Png,
}

impl FigureFormat {
    /// The format a file name's extension names (`.svg`, `.png`, any case).
    pub fn of_path(path: &std::path::Path) -> Option<FigureFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "svg" => Some(FigureFormat::Svg),
            "png" => Some(FigureFormat::Png),
            _ => None,
        }
    }
}

/// A figure: one or more panels side by side and a caption.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figure {
    /// The panels, left to right.
    pub panels: Vec<Panel>,
    /// A sentence under the figure, when it has one.
    pub caption: Option<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_axis_title_carries_its_unit() {
        assert_eq!(Axis::new("pitch", Some("µm")).title(), "pitch (µm)");
        assert_eq!(Axis::new("AUC", None).title(), "AUC");
    }

    #[test]
    fn a_log_axis_shows_numbers_near_one_and_powers_of_ten_far_from_it() {
        let a = Axis::log10("light", None);
        assert_eq!(a.tick_label(250f64.log10()).as_deref(), Some("250"));
        assert_eq!(a.tick_label(4.0).as_deref(), Some("10000"));
        assert_eq!(a.tick_label(-1.0).as_deref(), Some("0.1"));
        assert_eq!(a.tick_label(-6.0).as_deref(), Some("1e-6"));
        assert_eq!(a.tick_label(5.0).as_deref(), Some("1e5"));
        assert_eq!(
            Axis::downward("row", None).tick_label(-3.0).as_deref(),
            Some("3")
        );
        assert_eq!(
            Axis::downward("row", None).tick_label(0.0).as_deref(),
            Some("0")
        );
        assert_eq!(
            Axis::downward("row", None).tick_label(2.8e-14).as_deref(),
            Some("0")
        );
        assert_eq!(Axis::new("x", None).tick_label(3.0), None);
    }

    #[test]
    fn a_categorical_axis_names_whole_positions_only() {
        let mut a = Axis::new("tiling", None);
        assert_eq!(a.category_at(1.0), None);
        a.categories = Some(vec!["repeat".into(), "random".into()]);
        assert_eq!(a.category_at(1.0).as_deref(), Some("random"));
        assert_eq!(a.category_at(0.5).as_deref(), Some(""));
        assert_eq!(a.category_at(5.0).as_deref(), Some(""));
        assert_eq!(a.category_at(-1.0).as_deref(), Some(""));
    }

    #[test]
    fn bounds_cover_points_and_bands_and_skip_non_finite_values() {
        let mut p = Panel::default();
        assert_eq!(p.data_bounds(), None);
        p.series.push(Series {
            name: "a".into(),
            colour: palette::series(0),
            mark: Mark::Line,
            points: vec![[1.0, 2.0], [f64::NAN, 100.0], [3.0, 4.0]],
            band: Some(vec![[1.0, 0.5, 2.5], [3.0, 3.0, 9.0]]),
        });
        assert_eq!(p.data_bounds(), Some(([1.0, 3.0], [0.5, 9.0])));
        assert!(!p.wants_legend());
    }

    #[test]
    fn a_ring_closes_on_itself_at_its_radius() {
        let ring = circle_points([1.0, -2.0], 3.0, 8);
        assert_eq!(ring.len(), 9);
        assert_eq!(ring.first(), Some(&[4.0, -2.0]));
        let last = ring.last().copied().unwrap_or_default();
        assert!((last[0] - 4.0).abs() < 1e-12 && (last[1] + 2.0).abs() < 1e-12);
        assert!(
            ring.iter()
                .all(|p| ((p[0] - 1.0).hypot(p[1] + 2.0) - 3.0).abs() < 1e-12)
        );
    }

    #[test]
    fn wavelengths_run_from_blue_through_green_to_red() {
        assert_eq!(palette::wavelength(400.0), Rgb(25, 25, 255));
        assert_eq!(palette::wavelength(700.0), Rgb(255, 25, 25));
        let g = palette::wavelength(550.0);
        assert!(g.1 > g.0 && g.1 > g.2, "550 nm is green: {g:?}");
        assert_eq!(palette::wavelength(300.0), palette::wavelength(400.0));
    }

    #[test]
    fn bars_are_narrower_than_their_spacing_and_one_legend_entry_a_name() {
        let bar = |x: f64| Series {
            name: "lenslets".into(),
            colour: palette::series(0),
            mark: Mark::Bars,
            points: vec![[x, 1.0]],
            band: None,
        };
        let p = Panel {
            series: vec![bar(401.0), bar(411.0), bar(431.0)],
            ..Panel::default()
        };
        assert!((p.bar_width() - 8.0).abs() < 1e-12);
        assert!(!p.wants_legend(), "bars of one name are one entry");
    }

    #[test]
    fn the_legend_goes_where_the_data_is_not() {
        let line = |pts: Vec<[f64; 2]>| Series {
            name: "a".into(),
            colour: palette::series(0),
            mark: Mark::Line,
            points: pts,
            band: None,
        };
        // A rising line over a flat low one (scores against light): the top left is empty.
        let p = Panel {
            series: vec![
                line(vec![[0.0, 1.0], [1.0, 1.5], [3.0, 3.0], [4.0, 4.0]]),
                line(vec![[0.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0]]),
            ],
            ..Panel::default()
        };
        assert_eq!(p.quietest_corner(), Corner::LeftTop);
        // Falling lines (an MTF): the bottom left or top right; the top right wins the tie.
        let q = Panel {
            series: vec![line(vec![[0.0, 4.0], [1.0, 3.0], [3.0, 1.0], [4.0, 0.0]])],
            ..Panel::default()
        };
        assert_eq!(q.quietest_corner(), Corner::RightTop);
    }

    #[test]
    fn the_palette_cycles() {
        assert_eq!(palette::series(0), palette::series(palette::SERIES.len()));
        assert_ne!(palette::series(0), palette::series(1));
    }
}
