//! The window icon: the PNG embedded in the binary decodes to the icon the studio sets, and every
//! size `assets/icon/render.sh` writes for the desktop's hicolor theme is there at its size.

use std::path::Path;

use udc_studio::app::icon::window_icon;

/// The sizes `assets/icon/render.sh` renders.
const SIZES: [u32; 9] = [16, 22, 24, 32, 48, 64, 128, 256, 512];

#[test]
fn the_window_icon_is_a_256_px_rgba_picture() {
    let icon = window_icon().expect("the embedded PNG decodes");
    assert_eq!((icon.width, icon.height), (256, 256));
    assert_eq!(icon.rgba.len(), 256 * 256 * 4);

    let pixels: Vec<&[u8]> = icon.rgba.chunks_exact(4).collect();
    let opaque = pixels.iter().filter(|p| p[3] == 255).count();
    // The rounded square fills most of the canvas; only its corners and margin are transparent.
    assert!(
        opaque > pixels.len() / 2,
        "only {opaque} of {} pixels are opaque",
        pixels.len()
    );
    let first = pixels[0];
    assert!(
        pixels.iter().any(|p| *p != first),
        "every pixel is the same colour"
    );
    // The diffraction spot is bright over a dark background.
    let luma = |p: &[u8]| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]);
    let centre = pixels[128 * 256 + 128];
    let corner_inside = pixels[40 * 256 + 128 - 60];
    assert!(
        luma(centre) > 600 && luma(corner_inside) < 300,
        "centre {centre:?}, background {corner_inside:?}"
    );
}

#[test]
fn every_hicolor_size_is_rendered_at_its_size() {
    let hicolor = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/icon/hicolor");
    for n in SIZES {
        let path = hicolor.join(format!("{n}x{n}/apps/udc-studio.png"));
        let img = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .to_rgba8();
        assert_eq!(img.dimensions(), (n, n), "{}", path.display());
    }
    assert!(
        hicolor.join("scalable/apps/udc-studio.svg").is_file(),
        "the scalable SVG is missing"
    );
}
