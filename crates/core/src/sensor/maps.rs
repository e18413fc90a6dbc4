//! A sensor run's pictures as figure panels (`crate::figure`): the scene and a capture as they
//! are seen (through the run's tone curve), the gain map on a log scale, the bin map and the
//! saturation mask by category, the ROI grid over each, and two captures split at a column.
//! Pixel axes: sample `[row, col]` sits at `x = col`, `y = −row` (row 0 at the top).

use std::sync::Arc;

use ndarray::{Array2, Axis as Dim};

use super::{BIN_SIZES, SensorRun, StrategyResult};
use crate::figure::{Annotation, Category, ColorScale, Colormap, Image, Paint, Panel, Rgb};

/// The colours of the bin sizes 1, 2, 4 and 8 (a dark grey for no binning, then blue, amber
/// and red as the bins grow).
pub const BIN_COLOURS: [Rgb; 4] = [
    Rgb(40, 40, 48),
    Rgb(60, 140, 220),
    Rgb(240, 180, 40),
    Rgb(230, 70, 60),
];

/// The bin sizes as categories: `1×1`, `2×2`, `4×4`, `8×8`.
pub fn bin_categories() -> Vec<Category> {
    BIN_SIZES
        .iter()
        .zip(BIN_COLOURS)
        .map(|(b, colour)| Category {
            value: *b as f64,
            label: format!("{b}×{b}"),
            colour,
        })
        .collect()
}

/// A saturation mask's categories: 0 not saturated (near black), 1 saturated (red).
pub fn saturation_categories() -> Vec<Category> {
    vec![
        Category {
            value: 0.0,
            label: "no".into(),
            colour: Rgb(20, 20, 20),
        },
        Category {
            value: 1.0,
            label: "yes".into(),
            colour: Rgb(255, 40, 40),
        },
    ]
}

/// The largest gain of any strategy of `run` (at least 1): the top of the gain maps' shared
/// scale, so that two strategies' maps compare colour for colour.
pub fn max_gain(run: &SensorRun) -> f64 {
    run.strategies
        .iter()
        .flat_map(|s| s.gain_map.iter())
        .map(|g| f64::from(*g))
        .filter(|g| g.is_finite())
        .fold(1.0, f64::max)
}

/// Display-ready planes as shared arrays.
fn shared(planes: Vec<Array2<f64>>) -> Vec<Arc<Array2<f64>>> {
    planes.into_iter().map(Arc::new).collect()
}

/// An image of electrons drawn as the tone-mapped `planes` show them.
fn seen(name: &str, electrons: &Array2<f64>, planes: Vec<Array2<f64>>) -> Image {
    let mut img = Image::pixels(
        name,
        Arc::new(electrons.clone()),
        ColorScale::Linear { max: 1.0 },
        Colormap::Gray,
    )
    .painted(Paint::Display(shared(planes)));
    img.unit = Some("e⁻".into());
    img
}

/// The scene as ground truth: the exposed electrons, tone-mapped.
pub fn scene_panel<S>(run: &SensorRun<S>) -> Panel {
    Panel::picture(
        "Scene (ground truth, tone-mapped)".into(),
        seen("light", &run.electrons, run.truth_display_planes()),
    )
}

/// A strategy's capture (its estimate of the electrons), tone-mapped.
pub fn capture_panel(strategy: &StrategyResult) -> Panel {
    Panel::picture(
        format!("Capture: {}", strategy.name),
        seen("estimate", &strategy.capture, strategy.display_planes()),
    )
}

/// A strategy's gain map on a log scale from 1 to `max_gain` ([`max_gain`]).
pub fn gain_panel(strategy: &StrategyResult, max_gain: f64) -> Panel {
    let values = strategy.gain_map.mapv(f64::from);
    let img = Image::pixels(
        "gain",
        Arc::new(values),
        ColorScale::LogRange {
            low: 1.0,
            high: max_gain.max(1.0),
        },
        Colormap::Viridis,
    );
    Panel::picture(format!("Gain map: {}", strategy.name), img)
}

/// A strategy's bin map, one colour per bin size.
pub fn bin_panel(strategy: &StrategyResult) -> Panel {
    let values = strategy.bin_map.mapv(f64::from);
    let img = Image::pixels(
        "bin",
        Arc::new(values),
        ColorScale::Linear { max: 8.0 },
        Colormap::Gray,
    )
    .painted(Paint::Categories(bin_categories()));
    Panel::picture(format!("Bin map: {}", strategy.name), img)
}

/// Where a strategy saturated, with the share of pixels and of ROIs in the title.
pub fn saturation_panel(strategy: &StrategyResult) -> Panel {
    let values = strategy.saturated.mapv(|v| if v { 1.0 } else { 0.0 });
    let img = Image::pixels(
        "saturated",
        Arc::new(values),
        ColorScale::Linear { max: 1.0 },
        Colormap::Gray,
    )
    .painted(Paint::Categories(saturation_categories()));
    Panel::picture(
        format!(
            "Saturated: {:.2} % of pixels, {:.1} % of ROIs",
            100.0 * strategy.saturated_fraction,
            100.0 * strategy.saturated_roi_fraction
        ),
        img,
    )
}

/// Captures `a` left of column `split_col` and `b` from it on, with the split marked: the
/// two read the same scene, so the seam shows what changes.
pub fn split_panel(a: &StrategyResult, b: &StrategyResult, split_col: usize) -> Panel {
    let (rows, cols) = a.capture.dim();
    let split = split_col.min(cols);
    let mut images = Vec::new();
    let crop = |img: Image, from: usize, to: usize| -> Option<Image> {
        if from >= to || img.values.dim() != (rows, cols) {
            return None;
        }
        let cut = |p: &Array2<f64>| Arc::new(p.slice_axis(Dim(1), (from..to).into()).to_owned());
        let paint = match &img.paint {
            Paint::Display(planes) => Paint::Display(planes.iter().map(|p| cut(p)).collect()),
            other => other.clone(),
        };
        let mut part =
            Image::pixels(&img.name, cut(&img.values), img.scale, img.colormap).painted(paint);
        part.unit = img.unit.clone();
        // Shift the part to where its columns sit in the whole picture.
        part.centre[0] += from as f64;
        Some(part)
    };
    images.extend(crop(
        seen(&format!("A, {}", a.name), &a.capture, a.display_planes()),
        0,
        split,
    ));
    images.extend(crop(
        seen(&format!("B, {}", b.name), &b.capture, b.display_planes()),
        split,
        cols,
    ));
    let mut panel = Panel::picture(format!("A: {} | B: {}", a.name, b.name), images.remove(0));
    panel.images.extend(images);
    panel.annotations.push(Annotation::VLine {
        x: split as f64 - 0.5,
        label: "A | B".into(),
    });
    panel
}

/// The edges between the ROIs of `run` on a `rows × cols` picture: a vertical line every
/// `roi_px` columns and a horizontal one every `roi_px` rows, on the pixels' borders.
pub fn roi_grid(run: &SensorRun) -> Vec<Annotation> {
    let (rows, cols) = run.electrons.dim();
    let roi = run.roi_px;
    if roi == 0 {
        return Vec::new();
    }
    let label = || format!("ROI edges ({roi} px)");
    let vertical = (roi..cols).step_by(roi).map(|x| Annotation::VLine {
        x: x as f64 - 0.5,
        label: label(),
    });
    let horizontal = (roi..rows).step_by(roi).map(|y| Annotation::HLine {
        y: -(y as f64 - 0.5),
        label: label(),
    });
    vertical.chain(horizontal).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Progress;
    use crate::sensor::{Scene, SensorSettings, run};

    fn small_run() -> SensorRun {
        // A left-to-right ramp over four decades: dark and bright regions get different gains
        // and bins.
        let lum =
            Array2::from_shape_fn((64, 96), |(_, c)| 10f64.powf(-4.0 + 4.0 * c as f64 / 95.0));
        let scene = Scene { planes: vec![lum] };
        let settings = SensorSettings {
            roi_px: 32,
            ..SensorSettings::default()
        };
        run(&scene, &settings, &Progress::new()).expect("a sensor run")
    }

    #[test]
    fn the_maps_show_the_runs_own_values_where_they_are() {
        let run = small_run();
        let top = max_gain(&run);
        for s in &run.strategies {
            let bins = bin_panel(s);
            let img = &bins.images[0];
            // The readout at a pixel is the run's own bin there, and its colour its category's.
            let colours = img.colours();
            for (r, c) in [(0, 0), (10, 50), (63, 95)] {
                let [x, y] = img.position(r, c);
                let bin = f64::from(s.bin_map[[r, c]]);
                assert_eq!(img.value_at(x, y), Some(bin));
                let k = BIN_SIZES
                    .iter()
                    .position(|b| *b as f64 == bin)
                    .expect("a bin size");
                assert_eq!(colours[r * 96 + c], BIN_COLOURS[k]);
            }
            let gain = gain_panel(s, top);
            let g = &gain.images[0];
            let (r, c) = (5, 7);
            assert_eq!(g.values[[r, c]], f64::from(s.gain_map[[r, c]]));
            // Unit gain at the bottom of the shared scale, the largest of any strategy at the top.
            assert_eq!(g.scale.unit(1.0), 0.0);
            assert_eq!(g.scale.unit(top), 1.0);
            let sat = saturation_panel(s);
            assert_eq!(
                sat.images[0].values.iter().filter(|v| **v == 1.0).count(),
                s.saturated.iter().filter(|v| **v).count()
            );
        }
    }

    #[test]
    fn the_scene_is_drawn_as_the_tone_curve_shows_it() {
        let run = small_run();
        let panel = scene_panel(&run);
        let img = &panel.images[0];
        let toned = run.truth_display();
        let c = img.colours();
        for (r, col) in [(0, 0), (30, 48), (63, 95)] {
            let expected = (toned[[r, col]].clamp(0.0, 1.0) * 255.0).round() as u8;
            assert_eq!(c[r * 96 + col], Rgb(expected, expected, expected));
            // The readout names electrons, not the tone-mapped value.
            assert_eq!(img.values[[r, col]], run.electrons[[r, col]]);
        }
        assert_eq!(
            panel.y.tick_label(-3.0).as_deref(),
            Some("3"),
            "rows count down"
        );
    }

    #[test]
    fn a_split_shows_a_left_and_b_right_of_the_column() {
        let run = small_run();
        let (a, b) = (&run.strategies[0], &run.strategies[3]);
        let panel = split_panel(a, b, 40);
        assert_eq!(panel.images.len(), 2);
        let left = &panel.images[0];
        let right = &panel.images[1];
        assert_eq!(left.value_at(39.0, -5.0), Some(a.capture[[5, 39]]));
        assert_eq!(left.value_at(40.0, -5.0), None);
        assert_eq!(right.value_at(40.0, -5.0), Some(b.capture[[5, 40]]));
        assert_eq!(right.value_at(95.0, -63.0), Some(b.capture[[63, 95]]));
        // At either end one capture fills the picture.
        assert_eq!(split_panel(a, b, 0).images.len(), 1);
        assert_eq!(split_panel(a, b, 500).images[0].values.dim(), (64, 96));
    }

    #[test]
    fn the_roi_grid_runs_on_the_rois_borders() {
        let run = small_run();
        let lines = roi_grid(&run);
        let xs: Vec<f64> = lines
            .iter()
            .filter_map(|a| match a {
                Annotation::VLine { x, .. } => Some(*x),
                _ => None,
            })
            .collect();
        let ys: Vec<f64> = lines
            .iter()
            .filter_map(|a| match a {
                Annotation::HLine { y, .. } => Some(*y),
                _ => None,
            })
            .collect();
        // 96 columns in ROIs of 32: two inner edges; 64 rows: one.
        assert_eq!(xs, [31.5, 63.5]);
        assert_eq!(ys, [-31.5]);
    }
}
