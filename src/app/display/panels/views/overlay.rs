//! The reference marks over the PSF images: the lens's Airy ring and the display's
//! diffraction orders, each switched on or off above the plot.

use super::images::Grid;
use super::plots::PsfOverlay;
use crate::app::display::panels::Shown;
use crate::core::analysis::analyze::ChannelAnalysis;
use crate::core::theory::landmarks::{airy_radius_um, order_lattice, order_spacing_um};

/// Which reference marks are drawn over the PSF images.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OverlayChoice {
    /// The Airy ring of the lens alone.
    pub airy: bool,
    /// The display's diffraction orders (off by default: on a periodic display they sit on the
    /// peaks they explain and would hide them).
    pub orders: bool,
}

impl Default for OverlayChoice {
    fn default() -> Self {
        OverlayChoice {
            airy: true,
            orders: false,
        }
    }
}

/// The diffraction orders and Airy ring of a channel chosen in `choice`, over `grid`.
pub(super) fn psf_overlay(
    shown: &Shown,
    ch: &ChannelAnalysis,
    grid: Grid,
    choice: OverlayChoice,
) -> PsfOverlay {
    let d = &shown.design;
    let period_um = d.opening.pitch_um + d.tiling.wiring_gap_um;
    let spacing = order_spacing_um(ch.wavelength_nm, d.optics.focal_length_mm, period_um);
    let half_extent = grid.image_size()[0] / 2.0;
    PsfOverlay {
        order_spacing_um: spacing,
        lattice_um: if choice.orders {
            order_lattice(spacing, half_extent, 64)
        } else {
            Vec::new()
        },
        airy_radius_um: choice
            .airy
            .then(|| airy_radius_um(ch.wavelength_nm, d.optics.f_number)),
    }
}
