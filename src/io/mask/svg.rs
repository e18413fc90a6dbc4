//! SVG: user units are micrometres (the `viewBox`), the physical size is given in millimetres
//! (CSS has no µm unit). SVG's y axis points down, so the mask frame's y is negated. The drawn
//! polygons are black paths (even-odd fill, so keyhole bridges vanish) in group `drawn`; the
//! pupil outline is a red circle in group `pupil`; the notes are in `<desc>`. Written as a
//! stream, tile row by tile row.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use super::{FileCounts, for_each_flat_polygon, region_bbox_nm};
use crate::core::Progress;
use crate::core::mask::{MaskError, MaskLayout};
use crate::io::IoError;

/// SVG files beyond this many polygons are refused (several GB; use GDSII).
pub const MAX_SVG_POLYGONS: u64 = 20_000_000;

/// Nanometres as micrometres with exactly three decimals (no float noise).
fn um(nm: i64) -> String {
    let sign = if nm < 0 { "-" } else { "" };
    let a = nm.unsigned_abs();
    if a.is_multiple_of(1000) {
        format!("{sign}{}", a / 1000)
    } else {
        format!("{sign}{}.{:03}", a / 1000, a % 1000)
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Writes the SVG file.
pub(super) fn write(
    layout: &MaskLayout,
    notes: &[String],
    path: &Path,
    progress: &Progress,
) -> Result<FileCounts, IoError> {
    let flat = layout.stats().flat_polygons;
    if flat > MAX_SVG_POLYGONS {
        return Err(MaskError::TooLarge(format!(
            "{flat} polygons is more than an SVG file may hold here ({MAX_SVG_POLYGONS}); \
             export GDSII, which references one cell per pixel"
        ))
        .into());
    }
    let file = File::create(path).map_err(|e| IoError::file("create", path, e))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    let io = |e| IoError::file("write", path, e);
    let [x0, y0, x1, y1] = region_bbox_nm(layout);
    let (w_nm, h_nm) = (x1 - x0, y1 - y0);
    writeln!(
        w,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}mm\" height=\"{}mm\" viewBox=\"{} {} {} {}\">",
        w_nm as f64 * 1e-6,
        h_nm as f64 * 1e-6,
        um(x0),
        um(-y1),
        um(w_nm),
        um(h_nm)
    )
    .map_err(io)?;
    writeln!(w, "<desc>{}</desc>", escape(&notes.join("\n"))).map_err(io)?;
    writeln!(
        w,
        "<g id=\"drawn\" fill=\"#000\" fill-rule=\"evenodd\" stroke=\"none\">"
    )
    .map_err(io)?;
    let mut counts = FileCounts::default();
    let mut line = String::new();
    for_each_flat_polygon(layout, progress, |poly| {
        line.clear();
        line.push_str("<path d=\"M");
        for (k, p) in poly.iter().enumerate() {
            if k > 0 {
                line.push_str(" L");
            }
            line.push_str(&format!("{} {}", um(p[0]), um(-p[1])));
        }
        line.push_str("Z\"/>\n");
        counts.polygons += 1;
        counts.vertices += poly.len() as u64;
        w.write_all(line.as_bytes()).map_err(io)
    })?;
    writeln!(w, "</g>").map_err(io)?;
    if layout.pupil_outline.is_some() {
        writeln!(
            w,
            "<g id=\"pupil\"><circle cx=\"0\" cy=\"0\" r=\"{}\" fill=\"none\" stroke=\"#d00\" stroke-width=\"{}\"/></g>",
            layout.pupil_diameter_um / 2.0,
            layout.pupil_diameter_um / 500.0
        )
        .map_err(io)?;
    }
    writeln!(w, "</svg>").map_err(io)?;
    w.flush().map_err(io)?;
    drop(w);
    counts.bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    Ok(counts)
}

/// What [`write`] would produce.
pub(super) fn estimate(layout: &MaskLayout) -> FileCounts {
    let s = layout.stats();
    FileCounts {
        polygons: s.flat_polygons,
        vertices: s.flat_vertices,
        references: 0,
        arrays: 0,
        // About 12 bytes of path syntax per polygon and 20 per vertex.
        bytes: 1_000 + 12 * s.flat_polygons + 20 * s.flat_vertices,
    }
}
