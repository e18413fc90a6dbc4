//! SVG: user units are micrometres (the `viewBox`), the physical size is given in millimetres
//! (CSS has no µm unit). SVG's y axis points down, so the mask frame's y is negated. The drawn
//! polygons are black paths (even-odd fill, so keyhole bridges vanish) in group `drawn`; the
//! pupil outline is a red circle in group `pupil`; the notes are in `<desc>`. The die frame and
//! alignment marks (when asked for) are blue paths in groups `frame` and `marks`, the label a
//! `<text id="label">`; the view box then grows to hold them. Written as a stream, tile row by
//! tile row.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::{FileCounts, FrameDrawing, LayerRole, for_each_flat_polygon};
use crate::IoError;
use udc_core::Progress;
use udc_core::mask::{MaskError, MaskLayout};

/// SVG files beyond this many polygons are refused (several GB; use GDSII).
pub const MAX_SVG_POLYGONS: u64 = 20_000_000;

/// `n / 10^digits` as the shortest exact decimal (integer arithmetic, so no float noise such
/// as 0.30000000000000004, and no trailing zeros).
fn decimal(n: i64, digits: u32) -> String {
    let sign = if n < 0 { "-" } else { "" };
    let a = n.unsigned_abs();
    let scale = 10u64.pow(digits);
    let frac = a % scale;
    if frac == 0 {
        return format!("{sign}{}", a / scale);
    }
    let text = format!("{frac:0width$}", width = digits as usize);
    format!("{sign}{}.{}", a / scale, text.trim_end_matches('0'))
}

/// Nanometres as micrometres (at most three decimals).
fn um(nm: i64) -> String {
    decimal(nm, 3)
}

/// Micrometres from the design snapped to the 1 nm database unit, as [`um`] writes them.
fn um_snapped(um_value: f64) -> String {
    um((um_value * 1000.0).round() as i64)
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
    frame: &FrameDrawing,
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
    let file =
        crate::safe_file::open_reserved(path).map_err(|e| IoError::file("create", path, e))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    let io = |e| IoError::file("write", path, e);
    let [x0, y0, mut x1, mut y1] = frame.extent_nm;
    if let Some(l) = &frame.label {
        // The letters stand on the anchor; monospace letters are about 0.6 of their height wide.
        y1 = y1.max(l.at_nm[1] + l.height_nm);
        x1 = x1.max(l.at_nm[0] + l.height_nm * 6 / 10 * l.text.len() as i64);
    }
    let (w_nm, h_nm) = (x1 - x0, y1 - y0);
    writeln!(
        w,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}mm\" height=\"{}mm\" viewBox=\"{} {} {} {}\">",
        decimal(w_nm, 6),
        decimal(h_nm, 6),
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
            um_snapped(layout.pupil_diameter_um / 2.0),
            um_snapped(layout.pupil_diameter_um / 500.0)
        )
        .map_err(io)?;
    }
    frame_svg(&mut w, frame).map_err(io)?;
    writeln!(w, "</svg>").map_err(io)?;
    w.flush().map_err(io)?;
    drop(w);
    counts.bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    Ok(counts)
}

/// The frame's and marks' groups and the label, when there are any.
fn frame_svg(w: &mut impl Write, frame: &FrameDrawing) -> std::io::Result<()> {
    for role in [LayerRole::Frame, LayerRole::Marks] {
        let polys: Vec<_> = frame.polygons.iter().filter(|(r, _)| *r == role).collect();
        if polys.is_empty() {
            continue;
        }
        writeln!(
            w,
            "<g id=\"{}\" fill=\"#00c\" stroke=\"none\">",
            role.as_str()
        )?;
        for (_, p) in polys {
            let d: Vec<String> = p
                .points_nm
                .iter()
                .map(|q| format!("{} {}", um(q[0]), um(-q[1])))
                .collect();
            writeln!(w, "<path d=\"M{}Z\"/>", d.join(" L"))?;
        }
        writeln!(w, "</g>")?;
    }
    if let Some(l) = &frame.label {
        writeln!(
            w,
            "<text id=\"label\" x=\"{}\" y=\"{}\" font-size=\"{}\" font-family=\"monospace\" fill=\"#00c\">{}</text>",
            um(l.at_nm[0]),
            um(-l.at_nm[1]),
            um(l.height_nm),
            escape(&l.text)
        )?;
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::decimal;

    #[test]
    fn decimals_are_exact_and_short() {
        assert_eq!(decimal(300, 3), "0.3");
        assert_eq!(decimal(-1500, 3), "-1.5");
        assert_eq!(decimal(168_000, 3), "168");
        assert_eq!(decimal(1, 6), "0.000001");
        assert_eq!(decimal(-7, 3), "-0.007");
    }
}
