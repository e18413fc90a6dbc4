//! The studio's window icon.
//!
//! The PNG is embedded rather than read at start-up so the binary needs no installed assets to
//! show its icon; the 256 px rendering is what window managers and task switchers scale from.
//! `assets/icon/render.sh` regenerates it from the SVG.

/// The studio's icon for the window and task switcher.
///
/// Returns `None` rather than panicking if the embedded PNG ever fails to decode: a missing icon
/// is cosmetic, and the studio should still open.
#[must_use]
pub fn window_icon() -> Option<egui::IconData> {
    let png = include_bytes!("../../assets/icon/hicolor/256x256/apps/udc-studio.png");
    let rgba = image::load_from_memory(png).ok()?.to_rgba8();
    let (width, height) = rgba.dimensions();
    Some(egui::IconData {
        rgba: rgba.into_raw(),
        width,
        height,
    })
}
