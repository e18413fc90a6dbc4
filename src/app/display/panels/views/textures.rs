//! The uploaded images of the result views, one per slot, each rebuilt only when the result or
//! a setting it depends on changes (upload textures once per result, never per frame: per-frame uploads cost more than drawing).

use std::collections::HashMap;

use egui::{ColorImage, TextureHandle, TextureId, TextureOptions};

use crate::core::analysis::analyze::Quality;

/// Which image a texture holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Slot {
    Psf,
    LogPsf,
    Rgb,
    Mtf2d,
    ExpectedRealisation,
    ExpectedMean,
}

/// Everything an image depends on besides its slot: when the key is unchanged the uploaded
/// texture is reused as is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexKey {
    pub generation: u64,
    /// A preview and the full result of one generation differ.
    pub quality: Quality,
    pub channel: usize,
    pub floor_decades: f64,
}

/// The uploaded images, one per slot, rebuilt only when their key changes.
#[derive(Default)]
pub struct Textures {
    slots: HashMap<Slot, (TexKey, TextureHandle)>,
    /// Number of images built so far (lets tests prove nothing is rebuilt per frame).
    builds: u64,
}

impl Textures {
    /// The texture of `slot` for `key`: `build` runs (and the image is uploaded) only when the
    /// slot is empty or holds another key; otherwise the uploaded texture is reused.
    pub fn get(
        &mut self,
        ctx: &egui::Context,
        slot: Slot,
        key: TexKey,
        build: impl FnOnce() -> ColorImage,
    ) -> TextureId {
        // Nearest sampling: every sensor pixel stays a crisp square when zoomed in.
        let options = TextureOptions::NEAREST;
        match self.slots.get_mut(&slot) {
            Some((k, handle)) if *k == key => handle.id(),
            Some((k, handle)) => {
                self.builds += 1;
                handle.set(build(), options);
                *k = key;
                handle.id()
            }
            None => {
                self.builds += 1;
                let handle = ctx.load_texture(format!("views/{slot:?}"), build(), options);
                let id = handle.id();
                self.slots.insert(slot, (key, handle));
                id
            }
        }
    }

    /// Images built and uploaded so far.
    pub fn builds(&self) -> u64 {
        self.builds
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(generation: u64, floor_decades: f64) -> TexKey {
        TexKey {
            generation,
            quality: Quality::Full,
            channel: 0,
            floor_decades,
        }
    }

    #[test]
    fn textures_are_rebuilt_only_when_their_key_changes() {
        let ctx = egui::Context::default();
        let mut t = Textures::default();
        let img = || ColorImage::filled([2, 2], egui::Color32::RED);
        let a = t.get(&ctx, Slot::LogPsf, key(1, 6.0), img);
        for _ in 0..10 {
            assert_eq!(t.get(&ctx, Slot::LogPsf, key(1, 6.0), img), a);
        }
        assert_eq!(t.builds(), 1);
        // Another slot is independent; a new floor or generation rebuilds in place.
        t.get(&ctx, Slot::Psf, key(1, 0.0), img);
        assert_eq!(t.builds(), 2);
        assert_eq!(t.get(&ctx, Slot::LogPsf, key(1, 4.0), img), a);
        assert_eq!(t.get(&ctx, Slot::LogPsf, key(2, 4.0), img), a);
        assert_eq!(t.builds(), 4);
        let preview = TexKey {
            quality: Quality::Preview,
            ..key(2, 4.0)
        };
        t.get(&ctx, Slot::LogPsf, preview, img);
        assert_eq!(t.builds(), 5);
    }
}
