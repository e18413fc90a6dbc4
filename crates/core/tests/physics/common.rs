//! Designs and optics the physics tests share.

use udc_core::design::{Channel, Design, Opening, Optics, TilingMode};
use udc_core::display::aperture::{Display, Extent, Field, rasterise};

/// A design with an open aperture (one fully open 8-µm cell per tile) and the given optics.
pub fn open_design(optics: Optics, channels: Vec<Channel>) -> Design {
    Design {
        name: "test".into(),
        description: String::new(),
        opening: Opening::open(1, 8.0),
        tiling: udc_core::design::Tiling {
            mode: TilingMode::Repeat,
            seed: 0,
            origin_offset_cells: [0.0, 0.0],
            wiring_gap_um: 0.0,
        },
        optics,
        channels,
        theory: None,
        subpixels: None,
    }
}

/// Small, fast optics: f = 10 mm, f/5 (D = 2 mm = 250 samples), 2 fine samples per 2-µm pixel.
pub fn small_optics() -> Optics {
    Optics {
        recipe: udc_core::design::OpticsRecipe::Custom,
        focal_length_mm: 10.0,
        f_number: 5.0,
        pupil_sample_um: 8.0,
        fine_sample_um: 1.0,
        sensor_pixel_um: 2.0,
        window_px: 128,
        axis_in_pixel_um: [0.5, 0.5],
    }
}

/// The rasterised aperture of a design (display × pupil).
pub fn aperture_of(design: &Design) -> Field {
    let cells = udc_core::display::aperture::effective_cells(&design.opening);
    let display = Display::from_design(design, &cells);
    rasterise(
        &display,
        Extent::Pupil {
            diameter_um: design.optics.pupil_diameter_um(),
        },
        design.optics.pupil_sample_um,
    )
}
