//! The Restore view's pictures as figure panels (`crate::figure`): the capture, the denoised
//! capture, the restoration and its difference from the truth, each in pixels with the
//! display's colours. Pure functions of the planes; the studio draws them, `restore --out
//! --figures` writes them.

use std::sync::Arc;

use ndarray::Array2;

use crate::Sample;
use crate::figure::{ColorScale, Colormap, Image, Paint, Panel};

/// A photo's planes (one grey or R, G, B, on the `[0, 1]` scale) as a picture titled `title`,
/// each value times `gain` (a difference image is brightened to be seen) and clipped to
/// `[0, 1]`; the readout names the mean of the planes.
pub fn photo_panel<T: Sample>(title: &str, planes: &[&Array2<T>], gain: f64) -> Panel {
    let seen: Vec<Arc<Array2<f64>>> = planes
        .iter()
        .map(|p| Arc::new(p.mapv(|v| (v.into() * gain).clamp(0.0, 1.0))))
        .collect();
    let values = match seen.as_slice() {
        [] => Array2::zeros((0, 0)),
        [one] => (**one).clone(),
        many => {
            let k = many.len() as f64;
            let dim = many[0].dim();
            let mut sum = Array2::zeros(dim);
            for p in many.iter().filter(|p| p.dim() == dim) {
                sum += &**p;
            }
            sum / k
        }
    };
    let image = Image::pixels(
        "value",
        Arc::new(values),
        ColorScale::Linear { max: 1.0 },
        Colormap::Gray,
    )
    .painted(Paint::Display(seen));
    Panel::picture(title.into(), image)
}

/// `|restored − truth|` per plane (planes of other sizes are left out).
pub fn difference_planes<T: Sample>(
    restored: &[Array2<T>],
    truth: &[Array2<T>],
) -> Vec<Array2<f64>> {
    restored
        .iter()
        .zip(truth)
        .filter(|(r, t)| r.dim() == t.dim())
        .map(|(r, t)| {
            ndarray::Zip::from(r)
                .and(t)
                .map_collect(|a, b| ((*a).into() - (*b).into()).abs())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_photo_panel_keeps_the_colours_and_clips_the_gain() {
        let r = Array2::from_elem((2, 3), 0.5f32);
        let g = Array2::from_elem((2, 3), 0.1f32);
        let b = Array2::from_elem((2, 3), 0.0f32);
        let p = photo_panel("restored", &[&r, &g, &b], 4.0);
        assert_eq!(p.x.unit.as_deref(), Some("px"));
        let img = &p.images[0];
        assert_eq!(img.values.dim(), (2, 3));
        let Paint::Display(planes) = &img.paint else {
            panic!("display planes")
        };
        // 0.5 × 4 clips at 1; 0.1 × 4 = 0.4.
        assert_eq!(planes[0][[0, 0]], 1.0);
        assert!((planes[1][[1, 2]] - 0.4).abs() < 1e-6);
        assert!((img.values[[0, 0]] - 1.4 / 3.0).abs() < 1e-6);
    }

    #[test]
    fn the_difference_is_absolute_per_plane() {
        let r = vec![Array2::from_elem((1, 2), 0.25f64)];
        let t = vec![Array2::from_elem((1, 2), 0.75f64)];
        let d = difference_planes(&r, &t);
        assert_eq!(d[0][[0, 1]], 0.5);
    }
}
