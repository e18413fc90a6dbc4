//! GDSII: user unit 1 µm, database unit 1 nm, coordinates snapped to the layout's grid.
//!
//! Cells: the opening (`<TOP>_PIXEL`, or one `<TOP>_R90`-style cell per orientation used), the
//! wiring gap of the chrome tone (`<TOP>_GAP`), and the top cell with the notes, the pupil
//! outline, array references for periodic tilings and one reference per pixel for random ones.
//!
//! Everything but the per-pixel references goes through `gds21`. `gds21` only writes a whole
//! in-memory `GdsLibrary`, and 2.6 M `GdsStructRef`s (each with its own `String` name) would
//! take gigabytes, so the top cell's single references are streamed with the small record
//! writer below: `gds21` writes the library up to the top cell's `ENDSTR`, which is cut off, the
//! references are appended record by record, then `ENDSTR` and `ENDLIB` close the file.

use std::io::{BufWriter, Write};
use std::path::Path;

use gds21::{
    GdsArrayRef, GdsBoundary, GdsElement, GdsFloat64, GdsLibrary, GdsPoint, GdsStrans, GdsStruct,
    GdsStructRef, GdsTextElem, GdsUnits,
};

use super::flat_size::{self, CellSize, FlatSizeError};
use super::{ExportOptions, FileCounts, FrameDrawing, GdsCells, MaskLayers, region_bbox_nm};
use crate::IoError;
use crate::fab::{OUTLINE_WIDTH_NM, gds_date, outline_paths};
use udc_core::Progress;
use udc_core::display::tiling::D4;
use udc_core::mask::{MaskError, MaskLayout, Polygon};

/// GDSII counts rows and columns of an array in 16 bits.
const MAX_ARRAY: i64 = 32767;

/// The name of orientation `g`'s cell in per-orientation mode, e.g. `UDC_MASK_MX_R90`.
fn orientation_cell(layout: &MaskLayout, top: &str, g: D4) -> String {
    let p = layout.placement(g);
    let mirror = if p.reflected { "MX_" } else { "" };
    format!("{top}_{mirror}R{}", p.angle_deg)
}

fn points(poly: &Polygon, at: [i64; 2]) -> Vec<GdsPoint> {
    // Coordinates were checked against the 32-bit range when the layout was built.
    let pt = |p: &[i64; 2]| GdsPoint::new((p[0] + at[0]) as i32, (p[1] + at[1]) as i32);
    let mut xy: Vec<GdsPoint> = poly.points_nm.iter().map(pt).collect();
    if let Some(first) = poly.points_nm.first() {
        xy.push(pt(first));
    }
    xy
}

fn boundary(poly: &Polygon, layer: i16, datatype: i16) -> GdsElement {
    GdsElement::GdsBoundary(GdsBoundary {
        layer,
        datatype,
        xy: points(poly, [0, 0]),
        ..Default::default()
    })
}

/// A pixel cell of orientation `g`: its drawn polygons and, when the design has them, its
/// emitters on their own layers (they follow the tile's orientation with the references).
fn pixel_cell(
    name: String,
    layout: &MaskLayout,
    g: D4,
    polys: &[Polygon],
    o: &ExportOptions,
    layers: &MaskLayers,
) -> GdsStruct {
    let mut s = cell(name, polys, o.layer, o.datatype);
    for (k, role) in crate::mask::LayerRole::EMITTERS.into_iter().enumerate() {
        let (layer, datatype) = layers.of(role);
        s.elems.extend(
            layout
                .emitter_polygons(k, g)
                .iter()
                .map(|p| boundary(p, layer, datatype)),
        );
    }
    s
}

fn cell(name: String, polys: &[Polygon], layer: i16, datatype: i16) -> GdsStruct {
    let mut s = GdsStruct::new(name);
    s.elems = polys.iter().map(|p| boundary(p, layer, datatype)).collect();
    s
}

/// Array references of `name` over the region's tiles: consecutive tile rows with the same
/// columns share one array (a block region is one array), split at GDSII's 32767 limit.
fn arrays(layout: &MaskLayout, name: &str, offset: [i64; 2]) -> Vec<GdsElement> {
    let mut out = Vec::new();
    let q = layout.period_nm;
    for (r, run) in super::walk::row_runs(layout) {
        for y0 in (0..run as i64).step_by(MAX_ARRAY as usize) {
            let rows = (run as i64 - y0).min(MAX_ARRAY);
            for x0 in (0..i64::from(r.count)).step_by(MAX_ARRAY as usize) {
                let cols = (i64::from(r.count) - x0).min(MAX_ARRAY);
                let [cx, cy] = layout.tile_corner_nm(r.tx0 + x0, r.ty + y0);
                let (ox, oy) = (cx + offset[0], cy + offset[1]);
                let pt = |x: i64, y: i64| GdsPoint::new(x as i32, y as i32);
                if cols * rows == 1 {
                    // A lone tile is a plain reference, not a 1×1 array.
                    out.push(GdsElement::GdsStructRef(GdsStructRef {
                        name: name.to_string(),
                        xy: pt(ox, oy),
                        ..Default::default()
                    }));
                    continue;
                }
                out.push(GdsElement::GdsArrayRef(GdsArrayRef {
                    name: name.to_string(),
                    xy: [pt(ox, oy), pt(ox + cols * q, oy), pt(ox, oy - rows * q)],
                    cols: cols as i16,
                    rows: rows as i16,
                    ..Default::default()
                }));
            }
        }
    }
    out
}

/// The library up to and including the top cell, with everything but per-pixel references.
fn library(
    layout: &MaskLayout,
    o: &ExportOptions,
    layers: &MaskLayers,
    notes: &[String],
    frame: &FrameDrawing,
) -> GdsLibrary {
    let top = o.top_cell_name();
    let mut lib = GdsLibrary::new("UDCSTUDIO");
    // Database unit 1 nm = 1e-3 user units (1 µm), 1e-9 m.
    lib.units = GdsUnits::new(1e-3, 1e-9);
    let pixel_cell_name = format!("{top}_PIXEL");
    // A region its border policy redrew whole references no pixel cell: none is defined.
    let referenced = !layout.rows.is_empty();
    match o.gds_cells {
        _ if !referenced => {}
        GdsCells::Strans => lib.structs.push(pixel_cell(
            pixel_cell_name.clone(),
            layout,
            D4::IDENTITY,
            &layout.base_polygons,
            o,
            layers,
        )),
        GdsCells::PerOrientation => {
            for &g in &layout.orientations {
                let polys = layout.polygons(g);
                let name = orientation_cell(layout, top, g);
                lib.structs
                    .push(pixel_cell(name, layout, g, &polys, o, layers));
            }
        }
    }
    let mut top_cell = GdsStruct::new(top);
    let bbox = region_bbox_nm(layout);
    for (k, note) in notes.iter().enumerate() {
        top_cell.elems.push(GdsElement::GdsTextElem(GdsTextElem {
            string: note.clone(),
            layer: layers.notes.0,
            texttype: layers.notes.1,
            // One line per note, 10 µm apart, above the region's top-left corner.
            xy: GdsPoint::new(
                bbox[0] as i32,
                (bbox[3] + 10_000 * (notes.len() - k) as i64).min(i64::from(i32::MAX)) as i32,
            ),
            ..Default::default()
        }));
    }
    if let Some(outline) = &layout.pupil_outline {
        // An outline, not a filled disc: a path, split to the XY record limit.
        let ring = points(outline, [0, 0]);
        let ring = &ring[..ring.len().saturating_sub(1)];
        let (l, d) = layers.outline;
        top_cell.elems.extend(
            outline_paths(ring, l, d, OUTLINE_WIDTH_NM)
                .into_iter()
                .map(GdsElement::GdsPath),
        );
    }
    for (role, poly) in &frame.polygons {
        let (l, d) = layers.of(*role);
        top_cell.elems.push(boundary(poly, l, d));
    }
    // What the border policy redrew: flat, on the drawn layer.
    for poly in layout.border.polygons() {
        top_cell
            .elems
            .push(boundary(poly, layers.openings.0, layers.openings.1));
    }
    if let Some(label) = &frame.label {
        // Within i32: the frame's geometry checked its extent.
        top_cell.elems.push(GdsElement::GdsTextElem(GdsTextElem {
            string: label.text.clone(),
            layer: layers.label.0,
            texttype: layers.label.1,
            xy: GdsPoint::new(label.at_nm[0] as i32, label.at_nm[1] as i32),
            ..Default::default()
        }));
    }
    if let Some(gap) = layout.gap_polygon.as_ref().filter(|_| referenced) {
        let name = format!("{top}_GAP");
        lib.structs.push(cell(
            name.clone(),
            std::slice::from_ref(gap),
            o.layer,
            o.datatype,
        ));
        top_cell.elems.extend(arrays(layout, &name, [0, 0]));
    }
    if !layout.mode.is_random() {
        let name = match o.gds_cells {
            GdsCells::Strans => pixel_cell_name,
            GdsCells::PerOrientation => orientation_cell(layout, top, D4::IDENTITY),
        };
        top_cell.elems.extend(arrays(layout, &name, [0, 0]));
    }
    lib.structs.push(top_cell);
    lib.set_all_dates(gds_date(o.deterministic));
    lib
}

/// Encodes one GDSII record: length, record type, data type, payload.
fn record(out: &mut Vec<u8>, rtype: u8, dtype: u8, payload: &[u8]) {
    let len = (4 + payload.len()) as u16;
    out.extend_from_slice(&len.to_be_bytes());
    out.extend_from_slice(&[rtype, dtype]);
    out.extend_from_slice(payload);
}

const SREF: u8 = 0x0A;
const SNAME: u8 = 0x12;
const STRANS: u8 = 0x1A;
const ANGLE: u8 = 0x1C;
const XY: u8 = 0x10;
const ENDEL: u8 = 0x11;
const ENDSTR: u8 = 0x07;
const ENDLIB: u8 = 0x04;

/// The bytes of a reference to `name` up to (not including) its coordinates, and its offset.
fn sref_prefix(name: &str, strans: Option<&GdsStrans>) -> Vec<u8> {
    let mut out = Vec::new();
    record(&mut out, SREF, 0, &[]);
    let mut bytes = name.as_bytes().to_vec();
    if bytes.len() % 2 == 1 {
        bytes.push(0);
    }
    record(&mut out, SNAME, 6, &bytes);
    if let Some(s) = strans {
        record(
            &mut out,
            STRANS,
            1,
            &[if s.reflected { 0x80 } else { 0 }, 0],
        );
        if let Some(a) = s.angle {
            record(&mut out, ANGLE, 5, &GdsFloat64::encode(a).to_be_bytes());
        }
    }
    out.extend_from_slice(&12u16.to_be_bytes());
    out.extend_from_slice(&[XY, 3]);
    out
}

/// Per orientation (indexed like `D4::all()`): the record prefix and the placement offset.
fn sref_table(layout: &MaskLayout, o: &ExportOptions) -> Vec<(Vec<u8>, [i64; 2])> {
    D4::all()
        .into_iter()
        .map(|g| match o.gds_cells {
            GdsCells::Strans => {
                let p = layout.placement(g);
                let strans = (p.reflected || p.angle_deg != 0).then(|| GdsStrans {
                    reflected: p.reflected,
                    angle: (p.angle_deg != 0).then_some(f64::from(p.angle_deg)),
                    ..Default::default()
                });
                let name = format!("{}_PIXEL", o.top_cell_name());
                (sref_prefix(&name, strans.as_ref()), p.offset_nm)
            }
            GdsCells::PerOrientation => {
                let name = orientation_cell(layout, o.top_cell_name(), g);
                (sref_prefix(&name, None), [0, 0])
            }
        })
        .collect()
}

fn d4_index(g: D4) -> usize {
    usize::from(g.transpose) | usize::from(g.flip_lr) << 1 | usize::from(g.flip_ud) << 2
}

/// Writes the GDSII file.
pub(super) fn write(
    layout: &MaskLayout,
    o: &ExportOptions,
    notes: &[String],
    frame: &FrameDrawing,
    path: &Path,
    progress: &Progress,
) -> Result<FileCounts, IoError> {
    let layers = o.mask_layers().map_err(|error| IoError::MaskOptions {
        path: path.to_path_buf(),
        error,
    })?;
    let lib = library(layout, o, &layers, notes, frame);
    let mut head = Vec::new();
    lib.write(&mut head).map_err(|e| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("cannot encode the GDSII library: {e}"),
    })?;
    // The library ends with the top cell's ENDSTR and the ENDLIB; the references go between.
    let tail = [0, 4, ENDSTR, 0, 0, 4, ENDLIB, 0];
    if !head.ends_with(&tail) {
        return Err(IoError::Mask {
            path: path.to_path_buf(),
            message: "unexpected end of the encoded GDSII library".into(),
        });
    }
    head.truncate(head.len() - tail.len());
    let file =
        crate::safe_file::open_reserved(path).map_err(|e| IoError::file("create", path, e))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    let io = |e| IoError::file("write", path, e);
    w.write_all(&head).map_err(io)?;
    let mut references = 0u64;
    let mut bytes = head.len() as u64 + tail.len() as u64;
    if layout.mode.is_random() {
        let table = sref_table(layout, o);
        let rows = layout.rows.len().max(1);
        for (k, r) in layout.rows.iter().enumerate() {
            progress.check().map_err(|_| MaskError::Cancelled)?;
            progress.set(k as f32 / rows as f32);
            for tx in r.tx0..r.tx0 + i64::from(r.count) {
                let (prefix, offset) = &table[d4_index(layout.orientation(tx, r.ty))];
                let [cx, cy] = layout.tile_corner_nm(tx, r.ty);
                w.write_all(prefix).map_err(io)?;
                w.write_all(&((cx + offset[0]) as i32).to_be_bytes())
                    .map_err(io)?;
                w.write_all(&((cy + offset[1]) as i32).to_be_bytes())
                    .map_err(io)?;
                w.write_all(&[0, 4, ENDEL, 0]).map_err(io)?;
                bytes += prefix.len() as u64 + 12;
                references += 1;
            }
        }
    }
    w.write_all(&tail).map_err(io)?;
    w.flush().map_err(io)?;
    let stats = lib.stats();
    let polys: Vec<&GdsBoundary> = lib
        .structs
        .iter()
        .flat_map(|s| s.elems.iter())
        .filter_map(|e| match e {
            GdsElement::GdsBoundary(b) if (b.layer, b.datatype) == (o.layer, o.datatype) => Some(b),
            _ => None,
        })
        .collect();
    Ok(FileCounts {
        polygons: polys.len() as u64,
        vertices: polys.iter().map(|b| b.xy.len() as u64 - 1).sum(),
        references: references + stats.struct_refs as u64,
        arrays: stats.array_refs as u64,
        bytes,
    })
}

/// What [`write`] would produce, without encoding anything.
pub(super) fn estimate(layout: &MaskLayout, o: &ExportOptions) -> FileCounts {
    let stats = layout.stats();
    let cells: Vec<usize> = super::cell_vertex_counts(layout, o.gds_cells);
    let gap = u64::from(layout.gap_polygon.is_some());
    let (border, border_vertices) = layout.border.size();
    let polygons = cells.len() as u64 + gap + border;
    let vertices = cells.iter().sum::<usize>() as u64 + 6 * gap + border_vertices;
    let placed = arrays(layout, "", [0, 0]);
    let singles = placed
        .iter()
        .filter(|e| matches!(e, GdsElement::GdsStructRef(_)))
        .count() as u64;
    let runs = placed.len() as u64 - singles;
    let (references, arrays) = if layout.mode.is_random() {
        (stats.tiles + singles * gap, runs * gap)
    } else {
        (singles * (1 + gap), runs * (1 + gap))
    };
    // Boundary: BOUNDARY, LAYER, DATATYPE, XY header, ENDEL = 24 bytes, 8 per point.
    let boundary_bytes = 24 * polygons + 8 * (vertices + polygons);
    let name = o.top_cell_name().len() as u64 + 8;
    let sref = 4
        + 4
        + name
        + 12
        + 4
        + if o.gds_cells == GdsCells::Strans {
            14
        } else {
            0
        };
    let aref = 4 + 4 + name + 8 + 28 + 4;
    let outline = layout.pupil_outline.as_ref().map_or(0, |p| {
        // PATH: PATH, LAYER, DATATYPE, PATHTYPE, WIDTH, XY header, ENDEL = 38 bytes per path.
        let n = p.points_nm.len() as u64 + 1;
        38 * n.div_ceil(crate::fab::MAX_XY_POINTS as u64 - 1) + 8 * (n + n / 4094)
    });
    let bytes = 600 + boundary_bytes + references * sref + arrays * aref + outline;
    FileCounts {
        polygons,
        vertices,
        references,
        arrays,
        bytes,
    }
}

/// The geometry of a GDSII file, references expanded: polygons on one layer/datatype (µm,
/// y up) and every text string.
pub(super) struct Flat {
    pub polygons_um: Vec<Vec<[f64; 2]>>,
    pub texts: Vec<String>,
}

/// An affine map `p ↦ M p + t` in database units (GDSII and OASIS references).
#[derive(Clone, Copy)]
pub(super) struct Affine {
    m: [[f64; 2]; 2],
    t: [f64; 2],
}

impl Affine {
    pub(super) const IDENTITY: Affine = Affine {
        m: [[1.0, 0.0], [0.0, 1.0]],
        t: [0.0, 0.0],
    };

    pub(super) fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.m[0][0] * p[0] + self.m[0][1] * p[1] + self.t[0],
            self.m[1][0] * p[0] + self.m[1][1] * p[1] + self.t[1],
        ]
    }

    /// `self ∘ (STRANS at xy)`.
    fn then_ref(&self, strans: Option<&GdsStrans>, xy: [f64; 2]) -> Affine {
        let (refl, mag, angle) = strans.map_or((false, 1.0, 0.0), |s| {
            (s.reflected, s.mag.unwrap_or(1.0), s.angle.unwrap_or(0.0))
        });
        self.then(refl, mag, angle, xy)
    }

    /// `self ∘ (reference at xy)`: GDSII and OASIS both reflect about x first, then scale and
    /// rotate counter-clockwise by `angle_deg`, then translate.
    pub(super) fn then(&self, refl: bool, mag: f64, angle_deg: f64, xy: [f64; 2]) -> Affine {
        let (sin, cos) = angle_deg.to_radians().sin_cos();
        let f = if refl { -1.0 } else { 1.0 };
        let local = [[mag * cos, -mag * sin * f], [mag * sin, mag * cos * f]];
        let mut m = [[0.0; 2]; 2];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = self.m[i][0] * local[0][j] + self.m[i][1] * local[1][j];
            }
        }
        Affine {
            m,
            t: self.apply(xy),
        }
    }
}

/// The cell an import reads: the one named, else the one top cell.
///
/// # Errors
/// A name no cell has, or no name and several top cells (both say which cells there are).
fn chosen_top<'a>(lib: &'a GdsLibrary, cell: Option<&str>) -> Result<&'a GdsStruct, String> {
    if let Some(name) = cell {
        return lib.structs.iter().find(|s| s.name == name).ok_or_else(|| {
            let names: Vec<&str> = lib.structs.iter().map(|s| s.name.as_str()).collect();
            format!("no cell `{name}` (its cells: {})", names.join(", "))
        });
    }
    let tops = top_cells(lib);
    match tops.as_slice() {
        [top] => Ok(top),
        _ => {
            let names: Vec<&str> = tops.iter().map(|s| s.name.as_str()).collect();
            Err(format!(
                "expected one top cell, found {} ({}): name the one to read with --cell",
                names.len(),
                names.join(", ")
            ))
        }
    }
}

/// The cells no other cell references: a well-formed mask has one, its top.
fn top_cells(lib: &GdsLibrary) -> Vec<&GdsStruct> {
    let referenced: std::collections::HashSet<&str> = lib
        .structs
        .iter()
        .flat_map(|s| s.elems.iter())
        .filter_map(|e| match e {
            GdsElement::GdsStructRef(r) => Some(r.name.as_str()),
            GdsElement::GdsArrayRef(r) => Some(r.name.as_str()),
            _ => None,
        })
        .collect();
    lib.structs
        .iter()
        .filter(|s| !referenced.contains(s.name.as_str()))
        .collect()
}

/// The pixel grid an array reference (AREF) of a GDSII file's top cell draws: another tool's
/// array of one pixel cell, whose spacing is the pixel pitch and whose origin registers the
/// grid.
#[derive(Debug, Clone, PartialEq)]
pub struct ArrayGrid {
    /// The arrayed cell's name.
    pub cell: String,
    /// The array's origin (its first copy's cell origin), µm.
    pub origin_um: [f64; 2],
    /// From one column to the next, µm.
    pub col_step_um: [f64; 2],
    /// From one row to the next, µm.
    pub row_step_um: [f64; 2],
    /// Columns and rows.
    pub cols: u32,
    /// Rows.
    pub rows: u32,
    /// The bounding box `[x0, y0, x1, y1]` of what the arrayed cell itself draws on the layer,
    /// in its own coordinates (µm); `None` when it draws nothing there directly.
    pub cell_bounds_um: Option<[f64; 4]>,
}

/// The one array reference of the top cell (unrotated, unmirrored, unscaled), when the file
/// has exactly one; `None` otherwise (no array, several, or a transformed one).
///
/// # Errors
/// An unreadable file.
pub fn array_grid(
    path: &Path,
    layer: i16,
    datatype: i16,
    cell: Option<&str>,
) -> Result<Option<ArrayGrid>, IoError> {
    let bytes = crate::safe_file::read_bounded(path, super::MAX_MASK_BYTES, "read the mask")?;
    let lib = GdsLibrary::from_bytes(&bytes).map_err(|e| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("not a readable GDSII file: {e}"),
    })?;
    let scale = lib.units.db_unit() * 1e6;
    let Ok(top) = chosen_top(&lib, cell) else {
        return Ok(None);
    };
    let arrays: Vec<&GdsArrayRef> = top
        .elems
        .iter()
        .filter_map(|e| match e {
            GdsElement::GdsArrayRef(a) => Some(a),
            _ => None,
        })
        .collect();
    let [a] = arrays.as_slice() else {
        return Ok(None);
    };
    let plain = a.strans.as_ref().is_none_or(|t| {
        !t.reflected && t.mag.is_none_or(|m| m == 1.0) && t.angle.is_none_or(|r| r == 0.0)
    });
    if !plain {
        return Ok(None);
    }
    let p = |k: usize| [f64::from(a.xy[k].x) * scale, f64::from(a.xy[k].y) * scale];
    let (o, c, r) = (p(0), p(1), p(2));
    let (cols, rows) = (a.cols.max(1), a.rows.max(1));
    let step = |end: [f64; 2], n: i16| {
        [
            (end[0] - o[0]) / f64::from(n),
            (end[1] - o[1]) / f64::from(n),
        ]
    };
    let cell_bounds_um = lib.structs.iter().find(|s| s.name == a.name).and_then(|s| {
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for e in &s.elems {
            if let GdsElement::GdsBoundary(bd) = e
                && bd.layer == layer
                && bd.datatype == datatype
            {
                for q in &bd.xy {
                    let (x, y) = (f64::from(q.x) * scale, f64::from(q.y) * scale);
                    b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
                }
            }
        }
        b[0].is_finite().then_some(b)
    });
    Ok(Some(ArrayGrid {
        cell: a.name.clone(),
        origin_um: o,
        col_step_um: step(c, cols),
        row_step_um: step(r, rows),
        cols: cols.unsigned_abs().into(),
        rows: rows.unsigned_abs().into(),
        cell_bounds_um,
    }))
}

/// Reads a GDSII file and expands the references of `cell`, by default its top cell (the one
/// no other cell references).
pub(super) fn read(
    path: &Path,
    layer: i16,
    datatype: i16,
    cell: Option<&str>,
) -> Result<Flat, IoError> {
    let err = |message: String| IoError::Mask {
        path: path.to_path_buf(),
        message,
    };
    let bytes = crate::safe_file::read_bounded(path, super::MAX_MASK_BYTES, "read the mask")?;
    if let Some(at) = empty_string_record(&bytes) {
        return Err(err(format!(
            "not a readable GDSII file: the string record at byte {at} is empty"
        )));
    }
    let lib = GdsLibrary::from_bytes(&bytes)
        .map_err(|e| err(format!("not a readable GDSII file: {e}")))?;
    let scale = lib.units.db_unit() * 1e6;
    let top = chosen_top(&lib, cell).map_err(err)?;
    let by_name: std::collections::HashMap<&str, &GdsStruct> =
        lib.structs.iter().map(|s| (s.name.as_str(), s)).collect();
    check_flat_size(&lib.structs, top, layer, datatype).map_err(err)?;
    let mut flat = Flat {
        polygons_um: Vec::new(),
        texts: Vec::new(),
    };
    let mut stack = vec![(top, Affine::IDENTITY, 0usize)];
    // Everything the expansion keeps counts, single references as arrays: nested a dozen
    // levels deep, a few references per cell would otherwise expand to billions.
    let mut expanded = 0usize;
    let mut count = |n: usize| {
        expanded = expanded.saturating_add(n);
        if expanded > MAX_EXPANDED {
            return Err(err(format!(
                "more than {MAX_EXPANDED} cell instances, polygons and notes to expand; import a \
                 smaller mask"
            )));
        }
        Ok(())
    };
    while let Some((s, tf, depth)) = stack.pop() {
        if depth > 32 {
            return Err(err("references nest deeper than 32 levels".into()));
        }
        for e in &s.elems {
            match e {
                GdsElement::GdsBoundary(b) if b.layer == layer && b.datatype == datatype => {
                    count(1)?;
                    let mut pts: Vec<[f64; 2]> =
                        b.xy.iter()
                            .map(|p| tf.apply([f64::from(p.x), f64::from(p.y)]))
                            .map(|p| [p[0] * scale, p[1] * scale])
                            .collect();
                    if pts.len() > 1 && pts.first() == pts.last() {
                        pts.pop();
                    }
                    flat.polygons_um.push(pts);
                }
                GdsElement::GdsBox(b) if b.layer == layer && b.boxtype == datatype => {
                    count(1)?;
                    let pts = b.xy[..4]
                        .iter()
                        .map(|p| tf.apply([f64::from(p.x), f64::from(p.y)]))
                        .map(|p| [p[0] * scale, p[1] * scale])
                        .collect();
                    flat.polygons_um.push(pts);
                }
                GdsElement::GdsPath(path) if path.layer == layer && path.datatype == datatype => {
                    count(1)?;
                    let outline = path_outline(path);
                    if outline.len() >= 3 {
                        flat.polygons_um.push(
                            outline
                                .into_iter()
                                .map(|p| tf.apply(p))
                                .map(|p| [p[0] * scale, p[1] * scale])
                                .collect(),
                        );
                    }
                }
                GdsElement::GdsTextElem(t) => {
                    count(1)?;
                    flat.texts.push(t.string.clone());
                }
                GdsElement::GdsStructRef(r) => {
                    let child = by_name
                        .get(r.name.as_str())
                        .ok_or_else(|| err(format!("reference to a missing cell `{}`", r.name)))?;
                    count(1)?;
                    let xy = [f64::from(r.xy.x), f64::from(r.xy.y)];
                    stack.push((child, tf.then_ref(r.strans.as_ref(), xy), depth + 1));
                }
                GdsElement::GdsArrayRef(a) => {
                    let child = by_name
                        .get(a.name.as_str())
                        .ok_or_else(|| err(format!("reference to a missing cell `{}`", a.name)))?;
                    count(
                        usize::from(a.cols.max(1).unsigned_abs())
                            * usize::from(a.rows.max(1).unsigned_abs()),
                    )?;
                    for xy in array_positions(a) {
                        stack.push((child, tf.then_ref(a.strans.as_ref(), xy), depth + 1));
                    }
                }
                _ => {}
            }
        }
    }
    Ok(flat)
}

/// The outline of a GDSII path (database units): the centre line widened to its width, with
/// mitred corners, its ends flush (type 0), out by half the width (type 2, and type 1, whose
/// round ends this squares) or by its own extensions (type 4). A path of one point or no
/// width draws nothing.
fn path_outline(path: &gds21::GdsPath) -> Vec<[f64; 2]> {
    let half = 0.5 * f64::from(path.width.unwrap_or(0)).abs();
    let mut pts: Vec<[f64; 2]> = Vec::with_capacity(path.xy.len());
    for p in &path.xy {
        let q = [f64::from(p.x), f64::from(p.y)];
        if pts.last() != Some(&q) {
            pts.push(q);
        }
    }
    if pts.len() < 2 || half == 0.0 {
        return Vec::new();
    }
    let (begin, end) = match path.path_type.unwrap_or(0) {
        1 | 2 => (half, half),
        4 => (
            f64::from(path.begin_extn.unwrap_or(0)),
            f64::from(path.end_extn.unwrap_or(0)),
        ),
        _ => (0.0, 0.0),
    };
    let unit = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l = dx.hypot(dy);
        [dx / l, dy / l]
    };
    let n = pts.len();
    let d0 = unit(pts[0], pts[1]);
    let d1 = unit(pts[n - 2], pts[n - 1]);
    pts[0] = [pts[0][0] - d0[0] * begin, pts[0][1] - d0[1] * begin];
    pts[n - 1] = [pts[n - 1][0] + d1[0] * end, pts[n - 1][1] + d1[1] * end];
    // The left normal of each segment; a vertex's offset is the mitre of its two segments'.
    let normals: Vec<[f64; 2]> = pts
        .windows(2)
        .map(|w| {
            let d = unit(w[0], w[1]);
            [-d[1], d[0]]
        })
        .collect();
    let offset = |i: usize| -> [f64; 2] {
        let (a, b) = (
            normals[i.saturating_sub(1).min(n - 2)],
            normals[i.min(n - 2)],
        );
        let m = [a[0] + b[0], a[1] + b[1]];
        let k = 1.0 + a[0] * b[0] + a[1] * b[1];
        // A turn back on itself has no mitre: the segment's own normal.
        if k < 1e-9 {
            return [a[0] * half, a[1] * half];
        }
        [m[0] * half / k, m[1] * half / k]
    };
    let offsets: Vec<[f64; 2]> = (0..n).map(offset).collect();
    let mut outline: Vec<[f64; 2]> = pts
        .iter()
        .zip(&offsets)
        .map(|(p, o)| [p[0] + o[0], p[1] + o[1]])
        .collect();
    outline.extend(
        pts.iter()
            .zip(&offsets)
            .rev()
            .map(|(p, o)| [p[0] - o[0], p[1] - o[1]]),
    );
    outline
}

/// Refuses a hierarchy whose expansion would not fit [`flat_size::MAX_FLAT_BYTES`], before
/// any of it is expanded.
fn check_flat_size(
    structs: &[GdsStruct],
    top: &GdsStruct,
    layer: i16,
    datatype: i16,
) -> Result<(), String> {
    let index: std::collections::HashMap<&str, usize> = structs
        .iter()
        .enumerate()
        .map(|(i, s)| (s.name.as_str(), i))
        .collect();
    let child = |name: &str| {
        index
            .get(name)
            .copied()
            .ok_or_else(|| format!("reference to a missing cell `{name}`"))
    };
    let mut cells = Vec::with_capacity(structs.len());
    for s in structs {
        let mut size = CellSize {
            own_bytes: 0,
            children: Vec::new(),
        };
        for e in &s.elems {
            let own = match e {
                GdsElement::GdsBoundary(b) if b.layer == layer && b.datatype == datatype => {
                    flat_size::polygon_bytes(b.xy.len())
                }
                GdsElement::GdsBox(b) if b.layer == layer && b.boxtype == datatype => {
                    flat_size::polygon_bytes(4)
                }
                GdsElement::GdsPath(p) if p.layer == layer && p.datatype == datatype => {
                    flat_size::polygon_bytes(2 * p.xy.len())
                }
                GdsElement::GdsTextElem(t) => flat_size::text_bytes(t.string.len()),
                GdsElement::GdsStructRef(r) => {
                    size.children.push((child(&r.name)?, 1));
                    0
                }
                GdsElement::GdsArrayRef(a) => {
                    let instances = usize::from(a.cols.max(1).unsigned_abs())
                        * usize::from(a.rows.max(1).unsigned_abs());
                    size.children.push((child(&a.name)?, instances));
                    0
                }
                _ => 0,
            };
            size.own_bytes = size.own_bytes.saturating_add(own);
        }
        cells.push(size);
    }
    match flat_size::flattened_bytes(&cells, child(&top.name)?) {
        Ok(_) => Ok(()),
        Err(FlatSizeError::TooDeep) => Err("references nest deeper than 32 levels".into()),
        Err(FlatSizeError::TooLarge) => Err(format!(
            "its references expand to more than {} MiB of polygons and cell instances; import \
             a smaller mask",
            flat_size::MAX_FLAT_BYTES >> 20
        )),
    }
}

/// The offset of the first string record without data, following the record lengths as gds21
/// reads them: gds21 takes the last byte of every string and panics on an empty one.
fn empty_string_record(bytes: &[u8]) -> Option<usize> {
    const STRING_DATA: u8 = 0x06;
    let mut at = 0;
    while let Some(header) = bytes.get(at..at + 4) {
        let len = usize::from(u16::from_be_bytes([header[0], header[1]]));
        if len < 4 || len % 2 != 0 || header[2] == ENDLIB {
            return None;
        }
        if header[3] == STRING_DATA && len == 4 {
            return Some(at);
        }
        at += len;
    }
    None
}

/// Most cell instances, polygons and notes an import expands.
const MAX_EXPANDED: usize = 20_000_000;

/// Where the instances of an array reference go: `origin + i·column step + j·row step`, the
/// steps being the XY displacement points divided by the counts (GDSII's AREF).
fn array_positions(a: &GdsArrayRef) -> impl Iterator<Item = [f64; 2]> + '_ {
    let p = |k: usize| [f64::from(a.xy[k].x), f64::from(a.xy[k].y)];
    let (o, c, r) = (p(0), p(1), p(2));
    let (cols, rows) = (a.cols.max(1), a.rows.max(1));
    let dc = [
        (c[0] - o[0]) / f64::from(cols),
        (c[1] - o[1]) / f64::from(cols),
    ];
    let dr = [
        (r[0] - o[0]) / f64::from(rows),
        (r[1] - o[1]) / f64::from(rows),
    ];
    (0..rows).flat_map(move |j| {
        (0..cols).map(move |i| {
            let (fi, fj) = (f64::from(i), f64::from(j));
            [
                o[0] + fi * dc[0] + fj * dr[0],
                o[1] + fi * dc[1] + fj * dr[1],
            ]
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(p: &[[f64; 2]]) -> f64 {
        let n = p.len();
        0.5 * (0..n)
            .map(|i| p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1])
            .sum::<f64>()
            .abs()
    }

    fn path(xy: &[(i32, i32)], width: i32, path_type: i16) -> gds21::GdsPath {
        gds21::GdsPath {
            layer: 1,
            datatype: 0,
            xy: xy.iter().map(|&(x, y)| GdsPoint::new(x, y)).collect(),
            width: Some(width),
            path_type: Some(path_type),
            ..Default::default()
        }
    }

    #[test]
    fn a_path_becomes_its_outline_with_its_ends_and_mitred_corners() {
        // Straight, 10 wide: flush ends 100 long, extended ends 110.
        assert_eq!(
            area(&path_outline(&path(&[(0, 0), (100, 0)], 10, 0))),
            1000.0
        );
        assert_eq!(
            area(&path_outline(&path(&[(0, 0), (100, 0)], 10, 2))),
            1100.0
        );
        let mut custom = path(&[(0, 0), (100, 0)], 10, 4);
        custom.begin_extn = Some(20);
        custom.end_extn = Some(0);
        assert_eq!(area(&path_outline(&custom)), 1200.0);
        // An L: the bars' union, its outer corner mitred square.
        let l = path_outline(&path(&[(0, 0), (100, 0), (100, 100)], 10, 0));
        assert!((area(&l) - 2000.0).abs() < 1e-9, "{l:?}");
        assert!(
            l.iter()
                .any(|p| (p[0] - 105.0).abs() < 1e-9 && (p[1] + 5.0).abs() < 1e-9)
        );
        // No width, or one point: nothing.
        assert!(path_outline(&path(&[(0, 0), (100, 0)], 0, 0)).is_empty());
        assert!(path_outline(&path(&[(5, 5), (5, 5)], 10, 0)).is_empty());
    }
}
