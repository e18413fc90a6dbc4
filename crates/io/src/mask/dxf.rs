//! DXF: closed LWPOLYLINEs in micrometres (`$INSUNITS` = µm, `$MEASUREMENT` = metric), drawing
//! version R2000 (older versions have no LWPOLYLINE and the writer would drop them).
//!
//! References are expanded: every pixel's polygons are written (DXF blocks with mirrored inserts
//! are poorly supported by CAM tools). The drawn layer is `L<layer>D<datatype>_<TONE>`, the pupil
//! outline and the TEXT notes are on `NOTES`; the die frame, alignment marks and label (when
//! asked for) on `FRAME`, `MARKS` and `LABEL`, the label a TEXT of its own height.
//!
//! The `dxf` crate writes table heads without a handle (group 5), which strict readers repair
//! (ezdxf's `recover` counts one fix per table); [`TableHandles`] adds them while the file is
//! written. `$EXTMIN`/`$EXTMAX` are the bounding box of the polylines (the notes' text lies
//! above it and is not counted: a text's width depends on the reader's font).

use std::io::{BufWriter, Write};
use std::path::Path;

use dxf::entities::{Entity, EntityType, LwPolyline, Text};
use dxf::enums::{AcadVersion, DrawingUnits, Units};
use dxf::tables::Layer;
use dxf::{Drawing, Handle, LwPolylineVertex, Point};

use super::{
    ExportOptions, FileCounts, FrameDrawing, LayerRole, for_each_flat_polygon, region_bbox_nm,
};
use crate::IoError;
use udc_core::Progress;
use udc_core::mask::{MaskError, MaskLayout, Tone};

/// DXF drawings live in memory while they are written; beyond this, use GDSII.
pub const MAX_DXF_POLYGONS: u64 = 500_000;

const NOTES_LAYER: &str = "NOTES";

/// The DXF layer of a frame role: its upper-case name (DXF layers are names, not numbers).
fn role_layer(role: LayerRole) -> String {
    role.as_str().to_uppercase()
}

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

/// Nanometres as micrometres: dividing (not multiplying by 1e-3) gives the double nearest the
/// decimal, so a shortest round-trip writer prints 0.3, not 0.30000000000000004.
fn um(p: &[i64; 2]) -> [f64; 2] {
    [p[0] as f64 / 1000.0, p[1] as f64 / 1000.0]
}

/// Writes the DXF file.
pub(super) fn write(
    layout: &MaskLayout,
    o: &ExportOptions,
    notes: &[String],
    frame: &FrameDrawing,
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
    if o.deterministic {
        fix_header_dates(&mut drawing);
    }
    let drawn = format!(
        "{}_{}",
        layer_name(o.layer, o.datatype),
        o.spec.tone.as_str().to_uppercase()
    );
    let mut layers = vec![drawn.clone(), NOTES_LAYER.to_string()];
    for role in [LayerRole::Frame, LayerRole::Marks] {
        if frame.polygons.iter().any(|(r, _)| *r == role) {
            layers.push(role_layer(role));
        }
    }
    if frame.label.is_some() {
        layers.push(role_layer(LayerRole::Label));
    }
    for name in layers {
        drawing.add_layer(Layer {
            name,
            ..Default::default()
        });
    }
    let mut counts = FileCounts::default();
    // [min x, min y, max x, max y] of every polyline vertex, in nm (exact until written).
    let mut ext = [i64::MAX, i64::MAX, i64::MIN, i64::MIN];
    let mut extend = |poly: &[[i64; 2]]| {
        for p in poly {
            ext = [
                ext[0].min(p[0]),
                ext[1].min(p[1]),
                ext[2].max(p[0]),
                ext[3].max(p[1]),
            ];
        }
    };
    for_each_flat_polygon(layout, progress, |poly| {
        extend(poly);
        drawing.add_entity(polyline(poly.iter().map(um), &drawn));
        counts.polygons += 1;
        counts.vertices += poly.len() as u64;
        Ok(())
    })?;
    if let Some(outline) = &layout.pupil_outline {
        extend(&outline.points_nm);
        drawing.add_entity(polyline(outline.points_nm.iter().map(um), NOTES_LAYER));
    }
    for (role, poly) in &frame.polygons {
        extend(&poly.points_nm);
        drawing.add_entity(polyline(poly.points_nm.iter().map(um), &role_layer(*role)));
    }
    if let Some(label) = &frame.label {
        let [x, y] = um(&label.at_nm);
        let text = Text {
            location: Point::new(x, y, 0.0),
            text_height: label.height_nm as f64 / 1000.0,
            value: label.text.clone(),
            ..Default::default()
        };
        let mut e = Entity::new(EntityType::Text(text));
        e.common.layer = role_layer(LayerRole::Label);
        drawing.add_entity(e);
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
    if ext[0] <= ext[2] {
        let ([x0, y0], [x1, y1]) = (um(&[ext[0], ext[1]]), um(&[ext[2], ext[3]]));
        drawing.header.minimum_drawing_extents = Point::new(x0, y0, 0.0);
        drawing.header.maximum_drawing_extents = Point::new(x1, y1, 0.0);
    }
    // The table heads' handles come after every handle the crate gave out, and `$HANDSEED`
    // (written from `next_available_handle`) moves past them.
    let first = drawing.header.next_available_handle.0;
    drawing.header.next_available_handle = Handle(first + TABLE_HANDLES);
    let file =
        crate::safe_file::open_reserved(path).map_err(|e| IoError::file("create", path, e))?;
    let mut w = TableHandles::new(BufWriter::new(file), first);
    drawing.save(&mut w).map_err(|e| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("cannot write the DXF drawing: {e}"),
    })?;
    w.finish().map_err(|e| IoError::file("write", path, e))?;
    counts.bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    Ok(counts)
}

/// The GDSII writer's fixed date (2000-01-01 00:00) for the header's creation and update
/// times, and nil GUIDs: the crate fills them with the clock and random GUIDs, so two
/// deterministic exports would otherwise differ.
fn fix_header_dates(drawing: &mut Drawing) {
    use chrono::TimeZone;
    let utc = chrono::DateTime::<chrono::Utc>::from_timestamp(946_684_800, 0).unwrap_or_default();
    // Local by its wall-clock reading, so the bytes do not depend on the machine's time zone.
    let local = chrono::Local
        .from_local_datetime(&utc.naive_utc())
        .earliest()
        .unwrap_or_else(|| utc.with_timezone(&chrono::Local));
    let h = &mut drawing.header;
    (h.creation_date, h.update_date) = (local, local);
    (h.creation_date_universal, h.update_date_universal) = (utc, utc);
    h.fingerprint_guid = Default::default();
    h.version_guid = Default::default();
}

/// Handles reserved for table heads: R2000 has nine tables.
const TABLE_HANDLES: u64 = 16;

/// A writer that gives each `0/TABLE` head a handle (group 5) and owner (group 330 = 0) right
/// after its `2/<name>` pair, as AutoCAD writes them.
struct TableHandles<W: Write> {
    inner: W,
    /// The bytes of the line being written.
    line: Vec<u8>,
    /// Lines written so far: even lines are group codes, odd lines values.
    lines: u64,
    /// The group code of the current pair.
    code: String,
    /// The previous pair was `0/TABLE`.
    after_table: bool,
    /// The next handle to give, and the first one not to.
    next: u64,
    end: u64,
}

impl<W: Write> TableHandles<W> {
    fn new(inner: W, first: u64) -> Self {
        TableHandles {
            inner,
            line: Vec::new(),
            lines: 0,
            code: String::new(),
            after_table: false,
            next: first,
            end: first + TABLE_HANDLES,
        }
    }

    fn line_done(&mut self) -> std::io::Result<()> {
        self.inner.write_all(&self.line)?;
        let text = String::from_utf8_lossy(&self.line).trim().to_string();
        self.line.clear();
        self.lines += 1;
        if self.lines % 2 == 1 {
            self.code = text;
            return Ok(());
        }
        let head = std::mem::replace(&mut self.after_table, false);
        if self.code == "0" {
            self.after_table = text == "TABLE";
        } else if self.code == "2" && head && self.next < self.end {
            write!(self.inner, "  5\r\n{:X}\r\n330\r\n0\r\n", self.next)?;
            self.next += 1;
        }
        Ok(())
    }

    /// Writes what is left and flushes.
    fn finish(mut self) -> std::io::Result<()> {
        self.inner.write_all(&self.line)?;
        self.inner.flush()
    }
}

impl<W: Write> Write for TableHandles<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        for &b in buf {
            self.line.push(b);
            if b == b'\n' {
                self.line_done()?;
            }
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
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

/// Reads closed LWPOLYLINEs on the layer `L<layer>D<datatype>` (any `_TONE` suffix), or on the
/// layer named `named` (another tool's, such as `OPEN`; DXF names ignore case), in µm, block
/// inserts expanded (scaled, rotated, arrayed; an entity on layer `0` inside a block takes the
/// insert's layer, as DXF has it), and every TEXT (plus a `TONE=` note derived from the layer's
/// suffix).
pub(super) fn read(
    path: &Path,
    layer: i16,
    datatype: i16,
    named: Option<&str>,
) -> Result<super::Drawn, IoError> {
    let bytes = crate::safe_file::read_bounded(path, super::MAX_MASK_BYTES, "read the mask")?;
    let unreadable = |why: String| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("not a readable DXF file: {why}"),
    };
    // The dxf crate panics on some values it cannot represent (a Julian date past chrono's
    // range in `$TDCREATE`, say): for the import that is a file it cannot read. It parses the
    // bytes it owns, so nothing it leaves half-built outlives the panic.
    let loaded = std::panic::catch_unwind(move || Drawing::load(&mut std::io::Cursor::new(bytes)));
    let drawing = match loaded {
        Ok(drawing) => drawing.map_err(|e| unreadable(e.to_string()))?,
        Err(panic) => {
            let why = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a value is out of range".into());
            return Err(unreadable(why));
        }
    };
    let numbered = layer_name(layer, datatype);
    let wanted = |l: &str| -> Option<Option<Tone>> {
        match named {
            Some(n) => l.eq_ignore_ascii_case(n).then_some(None),
            None if l == numbered => Some(None),
            None => l
                .strip_prefix(&format!("{numbered}_"))
                .map(|suffix| suffix.to_lowercase().parse::<Tone>().ok()),
        }
    };
    let blocks: std::collections::HashMap<String, &dxf::Block> = drawing
        .blocks()
        .map(|b| (b.name.to_ascii_uppercase(), b))
        .collect();
    let mut out = Expansion {
        polygons: Vec::new(),
        texts: Vec::new(),
        visits: 0,
    };
    let top: Vec<&Entity> = drawing.entities().collect();
    expand(&top, Affine::IDENTITY, "0", 0, &blocks, &wanted, &mut out).map_err(unreadable)?;
    Ok((out.polygons, out.texts))
}

/// Most polygons, texts and inserts one import expands (a block arrayed in a block arrayed…
/// would otherwise run on for hours).
const MAX_DXF_EXPANDED: usize = 4_000_000;

/// What [`expand`] collects.
struct Expansion {
    polygons: Vec<Vec<[f64; 2]>>,
    texts: Vec<String>,
    visits: usize,
}

/// A 2-D affine map `p ↦ [a b; c d]·p + t`.
#[derive(Debug, Clone, Copy)]
struct Affine {
    m: [f64; 4],
    t: [f64; 2],
}

impl Affine {
    const IDENTITY: Affine = Affine {
        m: [1.0, 0.0, 0.0, 1.0],
        t: [0.0, 0.0],
    };

    fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.m[0] * p[0] + self.m[1] * p[1] + self.t[0],
            self.m[2] * p[0] + self.m[3] * p[1] + self.t[1],
        ]
    }

    /// `self ∘ other`: `other` first.
    fn then_inner(&self, other: &Affine) -> Affine {
        let [a, b, c, d] = self.m;
        let [e, f, g, h] = other.m;
        Affine {
            m: [a * e + b * g, a * f + b * h, c * e + d * g, c * f + d * h],
            t: self.apply(other.t),
        }
    }
}

/// The map of an INSERT's copy `(col, row)`: from block coordinates (less the base point),
/// scaled, moved by the array offset, rotated, placed at the insert's location.
fn insert_map(ins: &dxf::entities::Insert, base: [f64; 2], col: i16, row: i16) -> Affine {
    let (sin, cos) = ins.rotation.to_radians().sin_cos();
    let (sx, sy) = (ins.x_scale_factor, ins.y_scale_factor);
    let offset = [
        f64::from(col) * ins.column_spacing,
        f64::from(row) * ins.row_spacing,
    ];
    // local = S·(p − base) + offset; world = R·local + location.
    let local = [sx * -base[0] + offset[0], sy * -base[1] + offset[1]];
    Affine {
        m: [cos * sx, -sin * sy, sin * sx, cos * sy],
        t: [
            cos * local[0] - sin * local[1] + ins.location.x,
            sin * local[0] + cos * local[1] + ins.location.y,
        ],
    }
}

/// Collects the wanted polylines and every text of `entities` under `tf`, inserts expanded;
/// `inherited` is the layer an entity on layer `0` takes (its insert's).
fn expand(
    entities: &[&Entity],
    tf: Affine,
    inherited: &str,
    depth: usize,
    blocks: &std::collections::HashMap<String, &dxf::Block>,
    wanted: &dyn Fn(&str) -> Option<Option<Tone>>,
    out: &mut Expansion,
) -> Result<(), String> {
    if depth > 16 {
        return Err("block inserts nest deeper than 16 levels".into());
    }
    for e in entities {
        out.visits += 1;
        if out.visits > MAX_DXF_EXPANDED {
            return Err(format!(
                "more than {MAX_DXF_EXPANDED} entities to expand; import a smaller drawing"
            ));
        }
        let layer = if e.common.layer == "0" {
            inherited
        } else {
            e.common.layer.as_str()
        };
        match &e.specific {
            EntityType::LwPolyline(p) => {
                if let Some(tone) = wanted(layer) {
                    if let Some(t) = tone {
                        out.texts
                            .push(format!("TONE={}", t.as_str().to_uppercase()));
                    }
                    out.polygons
                        .push(p.vertices.iter().map(|v| tf.apply([v.x, v.y])).collect());
                }
            }
            EntityType::Text(t) => out.texts.push(t.value.clone()),
            EntityType::Insert(ins) => {
                let Some(block) = blocks.get(&ins.name.to_ascii_uppercase()) else {
                    return Err(format!("an insert of a missing block `{}`", ins.name));
                };
                let base = [block.base_point.x, block.base_point.y];
                let inner: Vec<&Entity> = block.entities.iter().collect();
                for col in 0..ins.column_count.max(1) {
                    for row in 0..ins.row_count.max(1) {
                        let map = tf.then_inner(&insert_map(ins, base, col, row));
                        expand(&inner, map, layer, depth + 1, blocks, wanted, out)?;
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}
