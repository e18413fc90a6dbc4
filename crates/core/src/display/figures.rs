//! The tiled display as a figure: its transmission over the pupil plane (1 open, 0 opaque)
//! with the lens pupil's rim, so a designer sees how many tiles the camera looks through.

use std::sync::Arc;

use ndarray::Array2;

use crate::figure::{Annotation, Axis, ColorScale, Colormap, Image, Paint, Panel};

/// `transmission` (`side × side` samples `sample_um` apart, centred on the optical axis) with
/// the rim of a pupil `pupil_diameter_um` across.
pub fn tiling_panel(
    transmission: Arc<Array2<f64>>,
    sample_um: f64,
    pupil_diameter_um: f64,
) -> Panel {
    let (rows, cols) = transmission.dim();
    Panel {
        title: "The tiled display over the lens pupil".into(),
        x: Axis::new("x", Some("µm")),
        y: Axis::new("y", Some("µm")),
        images: vec![Image {
            name: "transmission".into(),
            unit: None,
            values: transmission,
            centre: [0.0, 0.0],
            size: [cols as f64 * sample_um, rows as f64 * sample_um],
            scale: ColorScale::Linear { max: 1.0 },
            colormap: Colormap::Gray,
            paint: Paint::Mapped,
        }],
        annotations: vec![Annotation::Ring {
            centre: [0.0, 0.0],
            radius: pupil_diameter_um / 2.0,
            label: "lens pupil".into(),
        }],
        equal_aspect: true,
        ..Panel::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_display_is_centred_with_the_pupil_rim_over_it() {
        let t = Arc::new(Array2::from_shape_fn((4, 4), |(r, c)| ((r + c) % 2) as f64));
        let p = tiling_panel(t, 10.0, 30.0);
        let img = &p.images[0];
        assert_eq!(img.size, [40.0, 40.0]);
        // Sample (0, 0) is the top-left cell, 15 µm left and up of the axis.
        assert_eq!(img.position(0, 0), [-15.0, 15.0]);
        assert_eq!(
            p.annotations,
            vec![Annotation::Ring {
                centre: [0.0, 0.0],
                radius: 15.0,
                label: "lens pupil".into()
            }]
        );
    }
}
