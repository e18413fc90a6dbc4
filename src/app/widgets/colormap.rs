//! The studio's colour maps are the figure model's ([`crate::core::figure::Colormap`]); this
//! turns their colours into egui's.

use egui::Color32;

pub use crate::core::figure::Colormap;

/// The colour of `map` at `t` (clamped to `[0, 1]`, NaN at the low end), as egui draws it.
pub fn color(map: Colormap, t: f32) -> Color32 {
    crate::app::widgets::figure::color32(map.at(t))
}
