//! DXF: closed LWPOLYLINEs in micrometres (`$INSUNITS` = µm, `$MEASUREMENT` = metric), drawing
//! version R2000 (older versions have no LWPOLYLINE and the writer would drop them).
//!
//! References are expanded: every pixel's polygons are written (DXF blocks with mirrored inserts
//! are poorly supported by CAM tools). The drawn layer is `L<layer>D<datatype>_<TONE>`, the pupil
//! outline and the TEXT notes are on `NOTES`.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use dxf::entities::{Entity, EntityType, LwPolyline, Text};
use dxf::enums::{AcadVersion, DrawingUnits, Units};
use dxf::tables::Layer;
use dxf::{Drawing, LwPolylineVertex, Point};

use super::{ExportOptions, FileCounts, for_each_flat_polygon, region_bbox_nm};
use crate::core::Progress;
use crate::core::mask::{MaskError, MaskLayout, Tone};
use crate::io::IoError;

/// DXF drawings live in memory while they are written; beyond this, use GDSII.
pub const MAX_DXF_POLYGONS: u64 = 500_000;

const NOTES_LAYER: &str = "NOTES";

fn layer_name(layer: i16, datatype: i16) -> String {
    format!("L{layer}D{datatype}")
}

fn polyline(points_um: impl Iterator<Item = [f64; 2]>, layer: &str) -> Entity {
    let mut p = LwPolyline {
        vertices: points_um
            .map(|[x, y]| LwPolylineVertex {
                x,
                y,
                ..Default::default()
            })
            .collect(),
        ..Default::default()
    };
    p.set_is_closed(true);
    let mut e = Entity::new(EntityType::LwPolyline(p));
    e.common.layer = layer.to_string();
    e
}

fn um(p: &[i64; 2]) -> [f64; 2] {
    [p[0] as f64 * 1e-3, p[1] as f64 * 1e-3]
}

/// Writes the DXF file.
pub(super) fn write(
    layout: &MaskLayout,
    o: &ExportOptions,
    notes: &[String],
    path: &Path,
    progress: &Progress,
) -> Result<FileCounts, IoError> {
    let stats = layout.stats();
    if stats.flat_polygons > MAX_DXF_POLYGONS {
        return Err(MaskError::TooLarge(format!(
            "{} polygons is more than a DXF file may hold here ({MAX_DXF_POLYGONS}); \
             export GDSII, which references one cell per pixel",
            stats.flat_polygons
        ))
        .into());
    }
    let mut drawing = Drawing::new();
    drawing.header.version = AcadVersion::R2000;
    drawing.header.default_drawing_units = Units::Microns;
    drawing.header.drawing_units = DrawingUnits::Metric;
    let drawn = format!(
        "{}_{}",
        layer_name(o.layer, o.datatype),
        o.spec.tone.as_str().to_uppercase()
    );
    for name in [drawn.as_str(), NOTES_LAYER] {
        drawing.add_layer(Layer {
            name: name.to_string(),
            ..Default::default()
        });
    }
    let mut counts = FileCounts::default();
    for_each_flat_polygon(layout, progress, |poly| {
        drawing.add_entity(polyline(poly.iter().map(um), &drawn));
        counts.polygons += 1;
        counts.vertices += poly.len() as u64;
        Ok(())
    })?;
    if let Some(outline) = &layout.pupil_outline {
        drawing.add_entity(polyline(outline.points_nm.iter().map(um), NOTES_LAYER));
    }
    let bbox = region_bbox_nm(layout);
    for (k, note) in notes.iter().enumerate() {
        let text = Text {
            location: Point::new(
                bbox[0] as f64 * 1e-3,
                bbox[3] as f64 * 1e-3 + 10.0 * (notes.len() - k) as f64,
                0.0,
            ),
            text_height: 5.0,
            value: note.clone(),
            ..Default::default()
        };
        let mut e = Entity::new(EntityType::Text(text));
        e.common.layer = NOTES_LAYER.to_string();
        drawing.add_entity(e);
    }
    let file = File::create(path).map_err(|e| IoError::file("create", path, e))?;
    let mut w = BufWriter::new(file);
    drawing.save(&mut w).map_err(|e| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("cannot write the DXF drawing: {e}"),
    })?;
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
        // About 330 bytes of entity header per polyline and 45 per vertex.
        bytes: 20_000 + 330 * s.flat_polygons + 45 * s.flat_vertices,
    }
}

/// Reads closed LWPOLYLINEs on the layer `L<layer>D<datatype>` (any `_TONE` suffix) in µm, and
/// every TEXT (plus a `TONE=` note derived from the layer's suffix).
pub(super) fn read(path: &Path, layer: i16, datatype: i16) -> Result<super::Drawn, IoError> {
    let bytes = crate::io::safe_file::read_bounded(path, super::MAX_MASK_BYTES, "read the mask")?;
    let drawing = Drawing::load(&mut std::io::Cursor::new(bytes)).map_err(|e| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("not a readable DXF file: {e}"),
    })?;
    let name = layer_name(layer, datatype);
    let mut polygons = Vec::new();
    let mut texts = Vec::new();
    for e in drawing.entities() {
        let l = e.common.layer.as_str();
        match &e.specific {
            EntityType::LwPolyline(p) if l == name || l.starts_with(&format!("{name}_")) => {
                if let Some(t) = l
                    .strip_prefix(&format!("{name}_"))
                    .and_then(|suffix| suffix.to_lowercase().parse::<Tone>().ok())
                {
                    texts.push(format!("TONE={}", t.as_str().to_uppercase()));
                }
                polygons.push(p.vertices.iter().map(|v| [v.x, v.y]).collect());
            }
            EntityType::Text(t) => texts.push(t.value.clone()),
            _ => {}
        }
    }
    Ok((polygons, texts))
}
