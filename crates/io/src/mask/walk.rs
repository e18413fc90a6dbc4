//! Walks over a laid-out region that several writers share: the pixel cells' vertex counts,
//! the region's bounding box, and every drawn polygon with references expanded.

use super::GdsCells;
use crate::IoError;
use udc_core::Progress;
use udc_core::display::tiling::D4;
use udc_core::mask::{MaskError, MaskLayout, Polygon, TileRow};

/// Vertex counts of the polygons in the pixel cells (one cell, or one per orientation used), as
/// the GDSII and OASIS writers lay them out.
pub(super) fn cell_vertex_counts(layout: &MaskLayout, cells: GdsCells) -> Vec<usize> {
    match cells {
        GdsCells::Strans => layout
            .base_polygons
            .iter()
            .map(|p| p.points_nm.len())
            .collect(),
        GdsCells::PerOrientation => layout
            .orientations
            .iter()
            .flat_map(|g| layout.polygons(*g))
            .map(|p| p.points_nm.len())
            .collect(),
    }
}

/// The bounding box of the region's tiles, mask frame: `[min_x, min_y, max_x, max_y]` (nm).
pub fn region_bbox_nm(layout: &MaskLayout) -> [i64; 4] {
    let mut b = [i64::MAX, i64::MAX, i64::MIN, i64::MIN];
    for r in &layout.region_rows {
        let a = layout.tile_corner_nm(r.tx0, r.ty);
        let z = layout.tile_corner_nm(r.tx0 + i64::from(r.count), r.ty + 1);
        b = [
            b[0].min(a[0]),
            b[1].min(z[1]),
            b[2].max(z[0]),
            b[3].max(a[1]),
        ];
    }
    let beyond = layout.border.outside.iter();
    for o in layout.pupil_outline.iter().chain(beyond) {
        for p in &o.points_nm {
            b = [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ];
        }
    }
    b
}

/// Calls `f` with every drawn polygon of the region, references expanded (mask frame), tile
/// row by tile row; reports progress and stops when cancelled.
pub(super) fn for_each_flat_polygon(
    layout: &MaskLayout,
    progress: &Progress,
    mut f: impl FnMut(&[[i64; 2]]) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let mut cache: Vec<(D4, Vec<Polygon>)> = Vec::new();
    let mut buf: Vec<[i64; 2]> = Vec::new();
    let rows = layout.rows.len().max(1);
    for (k, r) in layout.rows.iter().enumerate() {
        progress.check().map_err(|_| MaskError::Cancelled)?;
        progress.set(k as f32 / rows as f32);
        for tx in r.tx0..r.tx0 + i64::from(r.count) {
            let g = layout.orientation(tx, r.ty);
            let idx = match cache.iter().position(|(h, _)| *h == g) {
                Some(i) => i,
                None => {
                    cache.push((g, layout.polygons(g)));
                    cache.len() - 1
                }
            };
            let [cx, cy] = layout.tile_corner_nm(tx, r.ty);
            let gap = layout.gap_polygon.iter();
            for poly in cache[idx].1.iter().chain(gap) {
                buf.clear();
                buf.extend(poly.points_nm.iter().map(|p| [p[0] + cx, p[1] + cy]));
                f(&buf)?;
            }
        }
    }
    for poly in layout.border.polygons() {
        f(&poly.points_nm)?;
    }
    Ok(())
}

/// The region's tile rows grouped into runs of consecutive rows with the same columns (a block
/// region is one run; a pupil, one run per row): each run's first row and its length. GDSII
/// arrays and OASIS repetitions place one cell over a run at once.
pub(super) fn row_runs(layout: &MaskLayout) -> Vec<(TileRow, usize)> {
    let rows = &layout.rows;
    let mut out = Vec::new();
    let mut k = 0;
    while k < rows.len() {
        let r = rows[k];
        let mut run = 1;
        while k + run < rows.len()
            && rows[k + run].tx0 == r.tx0
            && rows[k + run].count == r.count
            && rows[k + run].ty == r.ty + run as i64
        {
            run += 1;
        }
        out.push((r, run));
        k += run;
    }
    out
}
