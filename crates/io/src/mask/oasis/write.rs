//! The OASIS writer: the same cells as the GDSII export, far smaller for random tilings.
//!
//! A random tiling's 2.6 M pixel references become, per tile row and orientation, one
//! PLACEMENT with an irregular-x repetition on the tile grid (type 5): about one byte per
//! pixel instead of GDSII's 48. Periodic tilings are one PLACEMENT per run of identical rows
//! with a regular repetition. Coordinates are integers in database units (1 nm); the END
//! record carries a CRC-32, so a truncated or altered file is detected by any reader.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::encode::{
    END_PADDING, MAGIC, Sink, put_path_points, put_polygon_points, put_real_whole, put_s, put_str,
    put_u, record,
};
use crate::IoError;
use crate::fab::OUTLINE_WIDTH_NM;
use crate::mask::{
    ExportOptions, FileCounts, FrameDrawing, GdsCells, LayerRole, MaskLayers, region_bbox_nm,
};
use udc_core::Progress;
use udc_core::display::tiling::D4;
use udc_core::mask::{MaskError, MaskLayout, Polygon};

/// A cell of the file and its implicit CELLNAME reference number (its index).
struct Cells {
    names: Vec<String>,
    /// Per D4 index (`gds::d4_index`): cell number, OASIS angle code (0–3 for 0–270°), flip,
    /// and the offset added to the tile corner.
    per_orientation: [(u64, u8, bool, [i64; 2]); 8],
    /// The chrome tone's wiring-gap cell.
    gap: Option<u64>,
    top: u64,
}

fn d4_index(g: D4) -> usize {
    usize::from(g.transpose) | usize::from(g.flip_lr) << 1 | usize::from(g.flip_ud) << 2
}

fn cells(layout: &MaskLayout, o: &ExportOptions) -> Cells {
    let top = o.top_cell_name();
    let mut names = Vec::new();
    let mut per_orientation = [(0, 0, false, [0, 0]); 8];
    // A region its border policy redrew whole references no pixel cell: none is defined.
    let referenced = !layout.rows.is_empty();
    match o.gds_cells {
        _ if !referenced => {}
        GdsCells::Strans => {
            names.push(format!("{top}_PIXEL"));
            for g in D4::all() {
                let p = layout.placement(g);
                per_orientation[d4_index(g)] =
                    (0, (p.angle_deg / 90) as u8, p.reflected, p.offset_nm);
            }
        }
        GdsCells::PerOrientation => {
            for &g in &layout.orientations {
                let p = layout.placement(g);
                let mirror = if p.reflected { "MX_" } else { "" };
                per_orientation[d4_index(g)] = (names.len() as u64, 0, false, [0, 0]);
                names.push(format!("{top}_{mirror}R{}", p.angle_deg));
            }
        }
    }
    let gap = layout.gap_polygon.as_ref().filter(|_| referenced).map(|_| {
        names.push(format!("{top}_GAP"));
        names.len() as u64 - 1
    });
    names.push(top.to_string());
    Cells {
        top: names.len() as u64 - 1,
        names,
        per_orientation,
        gap,
    }
}

fn polygon(out: &mut Vec<u8>, poly: &Polygon, (layer, datatype): (i16, i16)) {
    let Some(first) = poly.points_nm.first() else {
        return;
    };
    // Info byte 00PXYRDL: point list, x, y, datatype and layer present; no repetition.
    put_u(out, record::POLYGON);
    out.push(0b0011_1011);
    put_u(out, layer as u64);
    put_u(out, datatype as u64);
    put_polygon_points(out, &poly.points_nm);
    put_s(out, first[0]);
    put_s(out, first[1]);
}

fn text(out: &mut Vec<u8>, s: &str, (layer, texttype): (i16, i16), at: [i64; 2]) {
    // Info byte 0CNXYRTL: explicit string given inline, x, y, texttype and layer present.
    put_u(out, record::TEXT);
    out.push(0b0101_1011);
    put_str(out, s.as_bytes());
    put_u(out, layer as u64);
    put_u(out, texttype as u64);
    put_s(out, at[0]);
    put_s(out, at[1]);
}

/// A PLACEMENT of cell `cell` at `at` (angle code, flip), with `rep` the repetition's bytes
/// (empty for none).
fn placement(out: &mut Vec<u8>, cell: u64, angle: u8, flip: bool, at: [i64; 2], rep: &[u8]) {
    // Info byte CNXYRAAF: explicit cell by number, x, y, repetition, angle, flip.
    put_u(out, record::PLACEMENT);
    let r = if rep.is_empty() { 0 } else { 0b1000 };
    out.push(0b1111_0000 | r | (angle & 3) << 1 | u8::from(flip));
    put_u(out, cell);
    put_s(out, at[0]);
    put_s(out, at[1]);
    out.extend_from_slice(rep);
}

/// Placements of `cell` on every tile of the region: runs of identical tile rows become one
/// regular 2-D repetition anchored at the run's bottom-left tile (OASIS spaces are positive).
/// Returns the number of placements with and without a repetition.
fn tile_arrays(
    out: &mut Vec<u8>,
    layout: &MaskLayout,
    cell: (u64, u8, bool, [i64; 2]),
) -> (u64, u64) {
    let (id, angle, flip, offset) = cell;
    let q = layout.period_nm as u64;
    let (mut arrays, mut singles) = (0, 0);
    for (r, run) in crate::mask::walk::row_runs(layout) {
        let (cols, rows) = (u64::from(r.count), run as u64);
        let [cx, cy] = layout.tile_corner_nm(r.tx0, r.ty + run as i64 - 1);
        let mut rep = Vec::new();
        match (cols, rows) {
            (1, 1) => {}
            (_, 1) => {
                rep.push(2);
                put_u(&mut rep, cols - 2);
                put_u(&mut rep, q);
            }
            (1, _) => {
                rep.push(3);
                put_u(&mut rep, rows - 2);
                put_u(&mut rep, q);
            }
            _ => {
                rep.push(1);
                put_u(&mut rep, cols - 2);
                put_u(&mut rep, rows - 2);
                put_u(&mut rep, q);
                put_u(&mut rep, q);
            }
        }
        if rep.is_empty() {
            singles += 1;
        } else {
            arrays += 1;
        }
        placement(out, id, angle, flip, [cx + offset[0], cy + offset[1]], &rep);
    }
    (arrays, singles)
}

/// Placements of one tile row of a random tiling: per orientation, the first tile and an
/// irregular-x repetition (type 5) whose spaces count tiles. Returns (arrays, singles).
fn random_row(
    out: &mut Vec<u8>,
    layout: &MaskLayout,
    cells: &Cells,
    ty: i64,
    tx0: i64,
    count: u32,
) -> (u64, u64) {
    let mut by_g: [Vec<i64>; 8] = Default::default();
    for tx in tx0..tx0 + i64::from(count) {
        by_g[d4_index(layout.orientation(tx, ty))].push(tx);
    }
    let (mut arrays, mut singles) = (0, 0);
    for (k, txs) in by_g.iter().enumerate() {
        let Some(&first) = txs.first() else { continue };
        let (id, angle, flip, offset) = cells.per_orientation[k];
        let mut rep = Vec::new();
        if txs.len() > 1 {
            rep.push(5);
            put_u(&mut rep, txs.len() as u64 - 2);
            put_u(&mut rep, layout.period_nm as u64);
            for w in txs.windows(2) {
                put_u(&mut rep, (w[1] - w[0]) as u64);
            }
            arrays += 1;
        } else {
            singles += 1;
        }
        let [cx, cy] = layout.tile_corner_nm(first, ty);
        placement(out, id, angle, flip, [cx + offset[0], cy + offset[1]], &rep);
    }
    (arrays, singles)
}

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> IoError + '_ {
    move |e| IoError::file("write", path, e)
}

/// Writes the OASIS file.
pub(crate) fn write(
    layout: &MaskLayout,
    o: &ExportOptions,
    notes: &[String],
    frame: &FrameDrawing,
    path: &Path,
    progress: &Progress,
) -> Result<FileCounts, IoError> {
    let layers: MaskLayers = o.mask_layers().map_err(|error| IoError::MaskOptions {
        path: path.to_path_buf(),
        error,
    })?;
    let cells = cells(layout, o);
    let file =
        crate::safe_file::open_reserved(path).map_err(|e| IoError::file("create", path, e))?;
    let mut w = Sink::new(BufWriter::with_capacity(1 << 20, file));
    let io = io_err(path);
    let mut buf = Vec::new();
    buf.extend_from_slice(MAGIC);
    // START: version, 1000 database units per µm (1 nm), tables in START (offset-flag 0), all
    // six table offsets 0 (no tables; name records are read as they come).
    put_u(&mut buf, record::START);
    put_str(&mut buf, b"1.0");
    put_real_whole(&mut buf, 1000);
    put_u(&mut buf, 0);
    buf.extend_from_slice(&[0; 12]);
    for name in &cells.names {
        put_u(&mut buf, record::CELLNAME_IMPLICIT);
        put_str(&mut buf, name.as_bytes());
    }
    // The layer map inside the file: LAYERNAME records with single-value intervals (type 3),
    // for the roles this file draws.
    let drawn = |role: LayerRole| match role {
        LayerRole::Openings | LayerRole::Outline | LayerRole::Notes => true,
        LayerRole::Label => frame.label.is_some(),
        LayerRole::EmitterRed | LayerRole::EmitterGreen | LayerRole::EmitterBlue => {
            o.written_roles().contains(&role)
        }
        other => frame.polygons.iter().any(|(r, _)| *r == other),
    };
    for role in LayerRole::ALL.into_iter().filter(|r| drawn(*r)) {
        let (l, d) = layers.of(role);
        let id = if matches!(role, LayerRole::Notes | LayerRole::Label) {
            record::LAYERNAME_TEXT
        } else {
            record::LAYERNAME_GEOMETRY
        };
        put_u(&mut buf, id);
        put_str(&mut buf, role.as_str().to_uppercase().as_bytes());
        for v in [l, d] {
            put_u(&mut buf, 3);
            put_u(&mut buf, v as u64);
        }
    }
    let mut counts = FileCounts::default();
    let add_polys = |buf: &mut Vec<u8>, polys: &[Polygon], counts: &mut FileCounts| {
        for p in polys {
            polygon(buf, p, layers.openings);
            counts.polygons += 1;
            counts.vertices += p.points_nm.len() as u64;
        }
    };
    // Emitters ride in the pixel cells, so each tile's placement orients them with the opening.
    let emitters = |buf: &mut Vec<u8>, g: D4| {
        if !o.written_roles().contains(&LayerRole::EmitterRed) {
            return;
        }
        for (k, role) in LayerRole::EMITTERS.into_iter().enumerate() {
            for p in layout.emitter_polygons(k, g) {
                polygon(buf, &p, layers.of(role));
            }
        }
    };
    match o.gds_cells {
        _ if layout.rows.is_empty() => {}
        GdsCells::Strans => {
            put_u(&mut buf, record::CELL_REF);
            put_u(&mut buf, 0);
            add_polys(&mut buf, &layout.base_polygons, &mut counts);
            emitters(&mut buf, D4::IDENTITY);
        }
        GdsCells::PerOrientation => {
            for &g in &layout.orientations {
                put_u(&mut buf, record::CELL_REF);
                put_u(&mut buf, cells.per_orientation[d4_index(g)].0);
                add_polys(&mut buf, &layout.polygons(g), &mut counts);
                emitters(&mut buf, g);
            }
        }
    }
    if let (Some(id), Some(gap)) = (cells.gap, &layout.gap_polygon) {
        put_u(&mut buf, record::CELL_REF);
        put_u(&mut buf, id);
        add_polys(&mut buf, std::slice::from_ref(gap), &mut counts);
    }
    put_u(&mut buf, record::CELL_REF);
    put_u(&mut buf, cells.top);
    let bbox = region_bbox_nm(layout);
    for (k, note) in notes.iter().enumerate() {
        // One line per note, 10 µm apart, above the region's top-left corner (as in GDSII).
        let y = bbox[3] + 10_000 * (notes.len() - k) as i64;
        text(&mut buf, note, layers.notes, [bbox[0], y]);
    }
    if let Some(outline) = &layout.pupil_outline
        && let Some(&first) = outline.points_nm.first()
    {
        // A closed path (first point repeated), flush ends, 1 µm wide: an outline, not a disc.
        let mut ring = outline.points_nm.clone();
        ring.push(first);
        put_u(&mut buf, record::PATH);
        buf.push(0b1111_1011);
        put_u(&mut buf, layers.outline.0 as u64);
        put_u(&mut buf, layers.outline.1 as u64);
        put_u(&mut buf, (OUTLINE_WIDTH_NM / 2) as u64);
        // Extension scheme 0000SSEE: half-width extensions at both ends cover the join.
        put_u(&mut buf, 0b1010);
        put_path_points(&mut buf, &ring);
        put_s(&mut buf, first[0]);
        put_s(&mut buf, first[1]);
    }
    for (role, poly) in &frame.polygons {
        polygon(&mut buf, poly, layers.of(*role));
    }
    if let Some(label) = &frame.label {
        text(&mut buf, &label.text, layers.label, label.at_nm);
    }
    if let Some(id) = cells.gap {
        let (a, s) = tile_arrays(&mut buf, layout, (id, 0, false, [0, 0]));
        counts.arrays += a;
        counts.references += s;
    }
    if !layout.mode.is_random() {
        let (a, s) = tile_arrays(
            &mut buf,
            layout,
            cells.per_orientation[d4_index(D4::IDENTITY)],
        );
        counts.arrays += a;
        counts.references += s;
    }
    w.raw(&buf).map_err(&io)?;
    if layout.mode.is_random() {
        let rows = layout.rows.len().max(1);
        for (k, r) in layout.rows.iter().enumerate() {
            progress.check().map_err(|_| MaskError::Cancelled)?;
            progress.set(k as f32 / rows as f32);
            buf.clear();
            let (a, s) = random_row(&mut buf, layout, &cells, r.ty, r.tx0, r.count);
            counts.arrays += a;
            counts.references += s;
            w.raw(&buf).map_err(&io)?;
        }
    }
    // END: padding to 256 bytes, validation scheme 1 (CRC-32 of every byte before the
    // signature, stored least significant byte first).
    buf.clear();
    put_u(&mut buf, record::END);
    put_str(&mut buf, &[0; END_PADDING]);
    put_u(&mut buf, 1);
    w.raw(&buf).map_err(&io)?;
    let crc = w.crc();
    w.raw(&crc.to_le_bytes()).map_err(&io)?;
    counts.bytes = w.bytes;
    w.into_inner().flush().map_err(&io)?;
    Ok(counts)
}

/// What [`write`] would produce, without encoding anything: the cells exactly, the random
/// tiling's placements from its orientation count (one placement per row and orientation,
/// about one byte per further tile).
pub(crate) fn estimate(layout: &MaskLayout, o: &ExportOptions) -> FileCounts {
    let stats = layout.stats();
    let polys: Vec<usize> = crate::mask::walk::cell_vertex_counts(layout, o.gds_cells);
    let gap = u64::from(layout.gap_polygon.is_some());
    let (border, border_vertices) = layout.border.size();
    let polygons = polys.len() as u64 + gap + border;
    let vertices = polys.iter().sum::<usize>() as u64 + 6 * gap + border_vertices;
    let rows = layout.rows.len() as u64;
    let (arrays, references, placed_bytes) = if layout.mode.is_random() {
        let per_row = (stats.orientations as u64).min(8);
        (rows * per_row, 0, rows * per_row * 14 + stats.tiles)
    } else {
        (rows * (1 + gap), 0, rows * (1 + gap) * 16)
    };
    let outline = layout
        .pupil_outline
        .as_ref()
        .map_or(0, |p| 20 + 3 * p.points_nm.len() as u64);
    FileCounts {
        polygons,
        vertices,
        references,
        arrays,
        bytes: 700 + 12 * polygons + 2 * vertices + placed_bytes + outline,
    }
}
