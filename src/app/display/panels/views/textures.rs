//! The result views' figures, one per slot, each built and uploaded only when the result or a
//! setting it depends on changes (upload textures once per result, never per frame: per-frame
//! uploads cost more than drawing).

use crate::app::widgets::figure::FigureCache;
use crate::core::analysis::analyze::Quality;
use crate::core::views::Landmarks;

/// Which figure a slot holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Slot {
    Psf,
    LogPsf,
    Rgb,
    Mtf2d,
    ExpectedRealisation,
    ExpectedMean,
}

/// Everything a figure depends on besides its slot: when the key is unchanged the built panel
/// and its uploaded textures are reused as they are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexKey {
    pub generation: u64,
    /// A preview and the full result of one generation differ.
    pub quality: Quality,
    pub channel: usize,
    pub floor_decades: f64,
    /// The reference marks drawn over a PSF.
    pub landmarks: Landmarks,
}

/// The result views' figures.
pub type Textures = FigureCache<Slot, TexKey>;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::figure::Panel;

    fn key(generation: u64, floor_decades: f64) -> TexKey {
        TexKey {
            generation,
            quality: Quality::Full,
            channel: 0,
            floor_decades,
            landmarks: Landmarks::default(),
        }
    }

    #[test]
    fn figures_are_rebuilt_only_when_their_key_changes() {
        let ctx = egui::Context::default();
        let mut t = Textures::default();
        let panel = || Panel {
            title: "p".into(),
            ..Panel::default()
        };
        let a = t.get(&ctx, Slot::LogPsf, key(1, 6.0), panel).panel;
        for _ in 0..10 {
            let again = t.get(&ctx, Slot::LogPsf, key(1, 6.0), panel).panel;
            assert!(std::sync::Arc::ptr_eq(&a, &again));
        }
        assert_eq!(t.builds(), 1);
        // Another slot is independent; a new floor, generation or mark rebuilds in place.
        t.get(&ctx, Slot::Psf, key(1, 0.0), panel);
        assert_eq!(t.builds(), 2);
        t.get(&ctx, Slot::LogPsf, key(1, 4.0), panel);
        t.get(&ctx, Slot::LogPsf, key(2, 4.0), panel);
        assert_eq!(t.builds(), 4);
        let preview = TexKey {
            quality: Quality::Preview,
            ..key(2, 4.0)
        };
        t.get(&ctx, Slot::LogPsf, preview, panel);
        let marked = TexKey {
            landmarks: Landmarks {
                airy: false,
                orders: true,
            },
            ..preview
        };
        t.get(&ctx, Slot::LogPsf, marked, panel);
        assert_eq!(t.builds(), 6);
    }
}
