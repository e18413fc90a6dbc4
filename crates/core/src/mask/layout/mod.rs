//! Where every pixel of a mask goes: the snapped tile geometry, the region's tiles, each tile's
//! D4 orientation and how a GDSII reference (reflection + rotation) realises it.
//!
//! A tile's *corner frame* has its origin at the tile's top-left corner, x right, y up: the
//! opening square is `[0, pitch] × [−pitch, 0]` and the wiring gap lies right of it and below it,
//! as in the simulation (`aperture.rs`). Tile `(tx, ty)` (tile `(0, 0)` holds the optical axis,
//! `ty` grows downwards) has its corner at `origin + (tx·period, −ty·period)`.

pub mod border;

use super::polygons::{BinaryGrid, Ring, trace_polygons};
use super::{MaskError, MaskSpec, Tone, binary_pattern};
use crate::design::{Design, TilingMode};
use crate::display::tiling::{D4, orbit, tile_orientation};
use border::BorderEdit;

pub use super::region::MaskRegion;

/// A run of consecutive tiles in one tile row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TileRow {
    /// Tile row (0 holds the optical axis; grows downwards).
    pub ty: i64,
    /// First tile column of the run.
    pub tx0: i64,
    /// Tiles in the run.
    pub count: u32,
}

/// A polygon in nanometres (mask frame or a tile's corner frame), first point not repeated.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Polygon {
    /// Vertices `[x, y]` in nm.
    pub points_nm: Vec<[i64; 2]>,
}

impl Polygon {
    /// Absolute area in µm².
    pub fn area_um2(&self) -> f64 {
        let n = self.points_nm.len();
        let twice: i128 = (0..n)
            .map(|i| {
                let [x0, y0] = self.points_nm[i];
                let [x1, y1] = self.points_nm[(i + 1) % n];
                i128::from(x0) * i128::from(y1) - i128::from(x1) * i128::from(y0)
            })
            .sum();
        (twice as f64 / 2.0).abs() * 1e-6
    }
}

/// How a GDSII reference carries the base tile onto a tile of orientation `g`: reflect about
/// the x-axis (if `reflected`), rotate by `angle_deg` counter-clockwise, then translate by the
/// tile's corner plus `offset_nm`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Placement {
    /// Whether the base tile is reflected about the x-axis before rotating.
    pub reflected: bool,
    /// Counter-clockwise rotation: 0, 90, 180 or 270.
    pub angle_deg: u16,
    /// Linear part `[[a, b], [c, d]]`: `x' = a·x + b·y`, `y' = c·x + d·y`.
    pub matrix: [[i64; 2]; 2],
    /// Translation within the corner frame, nm (the tile's corner is added on top).
    pub offset_nm: [i64; 2],
}

impl Placement {
    /// Carries a base-tile point `[x, y]` (corner frame, nm) to its place in the oriented tile
    /// (corner frame).
    pub fn apply(&self, p: [i64; 2]) -> [i64; 2] {
        let m = self.matrix;
        [
            m[0][0] * p[0] + m[0][1] * p[1] + self.offset_nm[0],
            m[1][0] * p[0] + m[1][1] * p[1] + self.offset_nm[1],
        ]
    }
}

/// Counts and areas of a laid-out mask (the drawn layer only).
#[derive(Debug, Clone, PartialEq)]
pub struct MaskStats {
    /// Pixels in the region.
    pub tiles: u64,
    /// Distinct D4 orientations among the tiles.
    pub orientations: usize,
    /// Polygons and vertices of one tile's drawing (identity orientation, gap included).
    pub polygons_per_tile: usize,
    /// Vertices of one tile's drawing.
    pub vertices_per_tile: usize,
    /// Polygons and vertices once every reference is expanded.
    pub flat_polygons: u64,
    /// Vertices once every reference is expanded.
    pub flat_vertices: u64,
    /// Area of everything drawn (openings, or chrome for the chrome tone), µm².
    pub drawn_area_um2: f64,
    /// Clear area (what light passes), whatever the tone.
    pub open_area_um2: f64,
    /// `tiles × period²`.
    pub region_area_um2: f64,
}

impl MaskStats {
    /// Clear area over region area, in `[0, 1]`.
    pub fn open_fraction(&self) -> f64 {
        if self.region_area_um2 > 0.0 {
            self.open_area_um2 / self.region_area_um2
        } else {
            0.0
        }
    }
}

/// A laid-out mask: geometry snapped to the grid, the tiles of the region and their
/// orientations. Building one is cheap; writers then stream the tiles.
#[derive(Debug, Clone)]
pub struct MaskLayout {
    /// The region, tone and grid the layout was made for.
    pub spec: MaskSpec,
    /// Snapping grid, nm.
    pub grid_nm: i64,
    /// Cells per side of the opening.
    pub n: usize,
    /// Display pixel pitch `T` snapped to the grid, nm.
    pub pitch_nm: i64,
    /// Pitch plus wiring gap.
    pub period_nm: i64,
    /// Cell boundaries `b_0 = 0 … b_n = pitch` along a tile side (cells may differ by one grid
    /// step when the cell size is not a whole number of steps).
    pub bounds_nm: Vec<i64>,
    /// Top-left corner of tile (0, 0).
    pub origin_nm: [i64; 2],
    /// The region's tiles, as runs along tile rows sorted by row.
    pub region_rows: Vec<TileRow>,
    /// The tiles drawn by reference: the region's, less those the border policy redraws
    /// ([`BorderEdit::replaced`]).
    pub rows: Vec<TileRow>,
    /// Total tiles in the region.
    pub tiles: u64,
    /// What the border policy drew instead of, or beside, the referenced tiles.
    pub border: BorderEdit,
    /// Tiling mode; with the seed it picks each tile's orientation as the simulation does.
    pub mode: TilingMode,
    /// Seed of the random tile orientations.
    pub seed: u64,
    /// Drawn cells of the identity orientation (the openings, or their complement for chrome).
    pub drawn: BinaryGrid,
    /// Orientations used by at least one referenced tile, in `D4::all()` order.
    pub orientations: Vec<D4>,
    /// The drawn polygons of the identity orientation, corner frame.
    pub base_polygons: Vec<Polygon>,
    /// The R, G, B emitter cells of the identity orientation, when the design has an emitter
    /// layer (thesis §3.7); exported on their own layers.
    pub emitters: Option<[Vec<Vec<bool>>; 3]>,
    /// Chrome tone with a wiring gap: the gap around one tile (right and below), corner frame.
    pub gap_polygon: Option<Polygon>,
    /// Pupil region: the pupil outline, mask frame.
    pub pupil_outline: Option<Polygon>,
    /// Lens pupil diameter `f / F#`, µm.
    pub pupil_diameter_um: f64,
}

/// Most tiles a mask may reference one by one (a 4K display has 8.3 M).
pub const MAX_TILES: u64 = 100_000_000;

fn snap(v: f64, grid: i64) -> i64 {
    (v / grid as f64).round() as i64 * grid
}

impl MaskLayout {
    /// Lays out `design` as `spec` says.
    ///
    /// # Errors
    /// [`MaskError::Design`] for an invalid design, [`MaskError::EmptyPattern`] when nothing is
    /// open, [`MaskError::Invalid`] for a grid coarser than a cell, and
    /// [`MaskError::TooLarge`] when a coordinate leaves the 32-bit GDSII range or the region
    /// has more than [`MAX_TILES`] pixels.
    pub fn new(design: &Design, spec: &MaskSpec) -> Result<Self, MaskError> {
        design.validate()?;
        if spec.grid_nm == 0 {
            return Err(MaskError::Invalid("the grid must be at least 1 nm".into()));
        }
        let grid = i64::from(spec.grid_nm);
        // Before the extent check, which counts the margin in.
        border::margin_nm(spec.border, spec.tone, spec.margin_um, grid)?;
        let pattern = binary_pattern(design);
        if pattern.count_open() == 0 {
            return Err(MaskError::EmptyPattern);
        }
        let n = pattern.width();
        let pitch_um = design.opening.pitch_um;
        let gap_um = design.tiling.wiring_gap_um;
        // Guard the f64 → i64 conversions before snapping anything.
        if pitch_um + gap_um > 1e9 {
            return Err(MaskError::TooLarge(format!(
                "a pitch of {pitch_um} µm does not fit 32-bit coordinates"
            )));
        }
        let pitch_nm = snap(pitch_um * 1e3, grid);
        if pitch_nm < grid * n as i64 {
            return Err(MaskError::Invalid(format!(
                "the pitch ({pitch_um} µm) is finer than {n} cells of the {grid} nm grid; \
                 use a finer grid"
            )));
        }
        let period_nm = pitch_nm + snap(gap_um * 1e3, grid);
        let bounds_nm: Vec<i64> = (0..=n)
            .map(|k| snap(k as f64 * pitch_nm as f64 / n as f64, grid))
            .collect();
        let cell_um = pitch_um / n as f64;
        let [ox, oy] = design.tiling.origin_offset_cells;
        let origin_nm = [
            snap(-(ox + 0.5) * cell_um * 1e3, grid),
            snap((oy + 0.5) * cell_um * 1e3, grid),
        ];
        let drawn = match spec.tone {
            Tone::Open => pattern.clone(),
            Tone::Chrome => pattern.inverted(),
        };
        let pupil_diameter_um = design.optics.pupil_diameter_um();
        let mut layout = MaskLayout {
            spec: spec.clone(),
            grid_nm: grid,
            n,
            pitch_nm,
            period_nm,
            bounds_nm,
            origin_nm,
            region_rows: Vec::new(),
            rows: Vec::new(),
            tiles: 0,
            border: BorderEdit::default(),
            mode: design.tiling.mode,
            seed: design.tiling.seed,
            drawn,
            orientations: Vec::new(),
            base_polygons: Vec::new(),
            emitters: design
                .subpixels
                .as_ref()
                .filter(|sp| sp.cells.len() == n)
                .map(|sp| {
                    crate::design::Subpixel::ALL.map(|s| {
                        sp.cells
                            .iter()
                            .map(|r| r.iter().map(|v| *v == Some(s)).collect())
                            .collect()
                    })
                }),
            gap_polygon: None,
            pupil_outline: None,
            pupil_diameter_um,
        };
        layout.region_rows = layout.region_rows()?;
        layout.tiles = layout.region_rows.iter().map(|r| u64::from(r.count)).sum();
        layout.check_extent()?;
        layout.base_polygons = layout.polygons(D4::IDENTITY);
        if spec.tone == Tone::Chrome && period_nm > pitch_nm {
            let (p, q) = (pitch_nm, period_nm);
            layout.gap_polygon = Some(Polygon {
                points_nm: vec![[0, -q], [q, -q], [q, 0], [p, 0], [p, -p], [0, -p]],
            });
        }
        layout.border = border::edit(
            &layout,
            &layout.region_rows,
            &pattern,
            spec.border,
            spec.margin_um,
        )?;
        layout.rows = without(&layout.region_rows, &layout.border.replaced);
        layout.orientations = layout.used_orientations(&layout.rows);
        if layout.rows.is_empty() && layout.border.polygons().next().is_none() {
            return Err(MaskError::Invalid(format!(
                "the border policy `{}` left nothing to draw: every opening of the region \
                 crosses its edge; export a larger region or use --border cut",
                spec.border.as_str()
            )));
        }
        if spec.region == MaskRegion::Pupil {
            layout.pupil_outline = Some(layout.outline());
        }
        Ok(layout)
    }

    /// Top-left corner of tile `(tx, ty)`, mask frame.
    #[inline]
    pub fn tile_corner_nm(&self, tx: i64, ty: i64) -> [i64; 2] {
        [
            self.origin_nm[0] + tx * self.period_nm,
            self.origin_nm[1] - ty * self.period_nm,
        ]
    }

    /// The orientation of tile `(tx, ty)` (the simulation's choice, `tiling::tile_orientation`).
    #[inline]
    pub fn orientation(&self, tx: i64, ty: i64) -> D4 {
        tile_orientation(self.mode, self.seed, tx, ty)
    }

    /// The drawn cells of a tile in orientation `g`.
    pub fn drawn_grid(&self, g: D4) -> BinaryGrid {
        let rows: Vec<Vec<bool>> = (0..self.n)
            .map(|r| (0..self.n).map(|c| self.drawn.get(c, r)).collect())
            .collect();
        BinaryGrid::from_rows(&g.apply(&rows))
    }

    /// The drawn polygons of a tile in orientation `g`, corner frame (gap not included).
    pub fn polygons(&self, g: D4) -> Vec<Polygon> {
        trace_polygons(&self.drawn_grid(g), self.spec.max_vertices)
            .iter()
            .map(|r| self.ring_to_polygon(r))
            .collect()
    }

    /// The emitter polygons of colour `k` (0 = R, 1 = G, 2 = B) of a tile in orientation `g`,
    /// corner frame; empty without an emitter layer.
    pub fn emitter_polygons(&self, k: usize, g: D4) -> Vec<Polygon> {
        let Some(rows) = self.emitters.as_ref().and_then(|e| e.get(k)) else {
            return Vec::new();
        };
        trace_polygons(
            &BinaryGrid::from_rows(&g.apply(rows)),
            self.spec.max_vertices,
        )
        .iter()
        .map(|r| self.ring_to_polygon(r))
        .collect()
    }

    /// A ring on the half-cell lattice of one tile, in nanometres (corner frame).
    pub fn ring_to_polygon(&self, ring: &Ring) -> Polygon {
        let coord = |half: i64| -> i64 {
            let k = (half / 2) as usize;
            if half % 2 == 0 {
                self.bounds_nm[k]
            } else {
                // Keyhole bridges run along row middles.
                snap(
                    (self.bounds_nm[k] + self.bounds_nm[k + 1]) as f64 / 2.0,
                    self.grid_nm,
                )
            }
        };
        Polygon {
            points_nm: ring
                .points
                .iter()
                .map(|&[x, y]| [coord(x), -coord(-y)])
                .collect(),
        }
    }

    /// The reference transform of orientation `g` (see [`Placement`]).
    pub fn placement(&self, g: D4) -> Placement {
        placement_of(g, self.pitch_nm)
    }

    fn region_rows(&self) -> Result<Vec<TileRow>, MaskError> {
        match self.spec.region {
            MaskRegion::Block { cols, rows } => {
                if cols == 0 || rows == 0 {
                    return Err(MaskError::Invalid("the region is empty".into()));
                }
                if u64::from(cols) * u64::from(rows) > MAX_TILES {
                    return Err(MaskError::TooLarge(format!(
                        "{cols}×{rows} pixels is more than the {MAX_TILES} a mask may hold"
                    )));
                }
                let tx0 = -i64::from(cols / 2);
                let ty0 = -i64::from(rows / 2);
                Ok((0..i64::from(rows))
                    .map(|k| TileRow {
                        ty: ty0 + k,
                        tx0,
                        count: cols,
                    })
                    .collect())
            }
            MaskRegion::Pupil => self.pupil_rows(),
        }
    }

    /// Rows of the tiles whose period square overlaps the pupil disc.
    fn pupil_rows(&self) -> Result<Vec<TileRow>, MaskError> {
        let r_nm = self.pupil_diameter_um * 500.0;
        let q = self.period_nm as f64;
        if r_nm / q > 1e6 {
            return Err(MaskError::TooLarge(format!(
                "the pupil ({} mm) spans more than a million pixels",
                self.pupil_diameter_um / 1e3
            )));
        }
        let overlaps = |tx: i64, ty: i64| {
            let [cx, cy] = self.tile_corner_nm(tx, ty).map(|v| v as f64);
            let dx = (cx.max(-(cx + q))).max(0.0);
            let dy = ((cy - q).max(-cy)).max(0.0);
            dx * dx + dy * dy < r_nm * r_nm
        };
        let [x0, y0] = self.origin_nm.map(|v| v as f64);
        let ty_lo = ((y0 - r_nm) / q).floor() as i64 - 1;
        let ty_hi = ((y0 + r_nm) / q).ceil() as i64 + 1;
        let mut rows = Vec::new();
        let mut tiles = 0u64;
        for ty in ty_lo..=ty_hi {
            // A first guess from the disc, then widened or narrowed to the exact test.
            let mut tx0 = ((-r_nm - x0) / q).floor() as i64;
            let mut tx1 = ((r_nm - x0) / q).ceil() as i64;
            while tx0 <= tx1 && !overlaps(tx0, ty) {
                tx0 += 1;
            }
            while tx1 >= tx0 && !overlaps(tx1, ty) {
                tx1 -= 1;
            }
            if tx0 > tx1 {
                continue;
            }
            while overlaps(tx0 - 1, ty) {
                tx0 -= 1;
            }
            while overlaps(tx1 + 1, ty) {
                tx1 += 1;
            }
            let count = (tx1 - tx0 + 1) as u32;
            tiles += u64::from(count);
            rows.push(TileRow { ty, tx0, count });
        }
        if tiles > MAX_TILES {
            return Err(MaskError::TooLarge(format!(
                "the pupil covers {tiles} pixels, more than the {MAX_TILES} a mask may hold"
            )));
        }
        Ok(rows)
    }

    /// Every coordinate must fit GDSII's signed 32-bit integers (nanometres).
    fn check_extent(&self) -> Result<(), MaskError> {
        let limit = i64::from(i32::MAX);
        let mut worst = 0i64;
        for r in &self.region_rows {
            let a = self.tile_corner_nm(r.tx0, r.ty);
            let b = self.tile_corner_nm(r.tx0 + i64::from(r.count), r.ty + 1);
            worst = worst.max(a[0].abs()).max(a[1].abs());
            worst = worst.max(b[0].abs()).max(b[1].abs());
        }
        // Completed openings reach a pixel beyond the region, a chrome margin its width.
        let margin_nm = border::margin_nm(
            self.spec.border,
            self.spec.tone,
            self.spec.margin_um,
            self.grid_nm,
        )?;
        let beyond = self.period_nm as f64 + margin_nm.unwrap_or(0) as f64;
        worst = worst.saturating_add(beyond as i64);
        if self.spec.region == MaskRegion::Pupil {
            worst = worst.max((self.pupil_diameter_um * 500.0).ceil() as i64);
        }
        if worst > limit {
            return Err(MaskError::TooLarge(format!(
                "it reaches {:.1} mm from the optical axis; GDSII's 32-bit coordinates in \
                 nanometres stop at ±{:.1} mm",
                worst as f64 / 1e6,
                limit as f64 / 1e6
            )));
        }
        Ok(())
    }

    /// The orientations some tile of `rows` uses (stops early once the orbit is complete).
    fn used_orientations(&self, rows: &[TileRow]) -> Vec<D4> {
        let all = orbit(self.mode);
        let mut seen = [false; 8];
        let index = |g: D4| {
            usize::from(g.transpose) | usize::from(g.flip_lr) << 1 | usize::from(g.flip_ud) << 2
        };
        let mut found = 0;
        'rows: for r in rows {
            for tx in r.tx0..r.tx0 + i64::from(r.count) {
                let i = index(self.orientation(tx, r.ty));
                if !seen[i] {
                    seen[i] = true;
                    found += 1;
                    if found == all.len() {
                        break 'rows;
                    }
                }
            }
        }
        D4::all().into_iter().filter(|g| seen[index(*g)]).collect()
    }

    /// The pupil circle with enough vertices that its sagitta stays within the grid.
    fn outline(&self) -> Polygon {
        let r_nm = self.pupil_diameter_um * 500.0;
        let step = (1.0 - self.grid_nm as f64 / r_nm).clamp(-1.0, 1.0).acos();
        let k = if step > 0.0 {
            (std::f64::consts::PI / step).ceil() as usize
        } else {
            64
        };
        let k = k.clamp(64, self.spec.max_vertices.max(64));
        Polygon {
            points_nm: (0..k)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / k as f64;
                    [
                        snap(r_nm * a.cos(), self.grid_nm),
                        snap(r_nm * a.sin(), self.grid_nm),
                    ]
                })
                .collect(),
        }
    }

    /// Counts and areas (the drawn layer).
    pub fn stats(&self) -> MaskStats {
        let base_area: f64 = self.base_polygons.iter().map(Polygon::area_um2).sum();
        let gap_area = self.gap_polygon.as_ref().map_or(0.0, Polygon::area_um2);
        let tile_drawn_um2 = base_area + gap_area;
        let period_um = self.period_nm as f64 * 1e-3;
        let tile_um2 = period_um * period_um;
        let tile_open_um2 = match self.spec.tone {
            Tone::Open => base_area,
            Tone::Chrome => tile_um2 - tile_drawn_um2,
        };
        let gap = usize::from(self.gap_polygon.is_some());
        let polygons_per_tile = self.base_polygons.len() + gap;
        let vertices_per_tile = self
            .base_polygons
            .iter()
            .map(|p| p.points_nm.len())
            .sum::<usize>()
            + 6 * gap;
        let edit = &self.border;
        let replaced = edit.replaced.len() as u64;
        let referenced = self.tiles - replaced;
        let area = |ps: &[Polygon]| ps.iter().map(Polygon::area_um2).sum::<f64>();
        let (inside_um2, outside_um2) = (area(&edit.inside), area(&edit.outside));
        let inside_drawn_um2 = referenced as f64 * tile_drawn_um2 + inside_um2;
        let region_um2 = self.tiles as f64 * tile_um2;
        let open_area_um2 = match self.spec.tone {
            Tone::Open => referenced as f64 * tile_open_um2 + inside_um2,
            Tone::Chrome => region_um2 - inside_drawn_um2,
        };
        let (extra, extra_vertices) = edit.size();
        MaskStats {
            tiles: self.tiles,
            orientations: self.used_orientations(&self.region_rows).len(),
            polygons_per_tile,
            vertices_per_tile,
            flat_polygons: referenced * polygons_per_tile as u64 + extra,
            flat_vertices: referenced * vertices_per_tile as u64 + extra_vertices,
            drawn_area_um2: inside_drawn_um2 + outside_um2,
            open_area_um2,
            region_area_um2: region_um2,
        }
    }
}

/// `rows` less the tiles `(tx, ty)` of `gone` (sorted by row, then column): runs split around
/// them, emptied rows left out.
fn without(rows: &[TileRow], gone: &[(i64, i64)]) -> Vec<TileRow> {
    if gone.is_empty() {
        return rows.to_vec();
    }
    let mut out = Vec::new();
    for r in rows {
        let lo = gone.partition_point(|&(_, ty)| ty < r.ty);
        let hi = gone.partition_point(|&(_, ty)| ty <= r.ty);
        let mut from = r.tx0;
        let end = r.tx0 + i64::from(r.count);
        for &(tx, _) in &gone[lo..hi] {
            if tx > from {
                out.push(TileRow {
                    ty: r.ty,
                    tx0: from,
                    count: (tx - from) as u32,
                });
            }
            from = from.max(tx + 1);
        }
        if end > from {
            out.push(TileRow {
                ty: r.ty,
                tx0: from,
                count: (end - from) as u32,
            });
        }
    }
    out
}

/// The reference transform of D4 element `g` for tiles of side `pitch_nm` (corner frame).
///
/// `D4::source` says which base cell lands where; as a map of the tile square
/// `[0, 1] × [−1, 0]` (y up) onto itself it is an isometry `placed = A·base + t`. GDSII's STRANS
/// applies the x-axis reflection first, then the rotation, so `A = R(angle)·diag(1, −reflected)`.
pub fn placement_of(g: D4, pitch_nm: i64) -> Placement {
    // The source map placed → base on the unit tile, evaluated at three points (affine).
    let source = |x: i64, y: i64| -> [i64; 2] {
        let (u, w) = (x, -y);
        let w1 = if g.flip_ud { 1 - w } else { w };
        let u1 = if g.flip_lr { 1 - u } else { u };
        let (us, ws) = if g.transpose { (w1, u1) } else { (u1, w1) };
        [us, -ws]
    };
    let t = source(0, 0);
    let (e0, e1) = (source(1, 0), source(0, 1));
    // Source linear part S (columns = images of the unit vectors); placed = Sᵀ(base − t).
    let s = [[e0[0] - t[0], e1[0] - t[0]], [e0[1] - t[1], e1[1] - t[1]]];
    let a = [[s[0][0], s[1][0]], [s[0][1], s[1][1]]];
    let offset = [
        -(a[0][0] * t[0] + a[0][1] * t[1]) * pitch_nm,
        -(a[1][0] * t[0] + a[1][1] * t[1]) * pitch_nm,
    ];
    let reflected = a[0][0] * a[1][1] - a[0][1] * a[1][0] < 0;
    // R = A·diag(1, −1) when reflected; its first column is (cos, sin) of the angle.
    let r0 = [a[0][0], a[1][0]];
    let angle_deg = match r0 {
        [1, 0] => 0,
        [0, 1] => 90,
        [-1, 0] => 180,
        _ => 270,
    };
    Placement {
        reflected,
        angle_deg,
        matrix: a,
        offset_nm: offset,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placement_realises_d4_source_on_every_cell() {
        let n = 5usize;
        let pattern: Vec<Vec<u32>> = (0..n)
            .map(|r| (0..n).map(|c| (r * n + c) as u32).collect())
            .collect();
        for g in D4::all() {
            let placed = g.apply(&pattern);
            let p = placement_of(g, n as i64 * 2);
            for (r, row) in pattern.iter().enumerate() {
                for (c, &value) in row.iter().enumerate() {
                    // Base cell centre in half-cell units (pitch = 2n), corner frame.
                    let [x, y] = p.apply([2 * c as i64 + 1, -(2 * r as i64 + 1)]);
                    let (pc, pr) = ((x / 2) as usize, ((-y) / 2) as usize);
                    assert_eq!(placed[pr][pc], value, "{g:?} cell ({r}, {c})");
                }
            }
            // The STRANS decomposition rebuilds the matrix.
            let rad = f64::from(p.angle_deg).to_radians();
            let (cos, sin) = (rad.cos().round() as i64, rad.sin().round() as i64);
            let m = if p.reflected { -1 } else { 1 };
            assert_eq!(p.matrix, [[cos, -sin * m], [sin, cos * m]], "{g:?}");
        }
    }

    #[test]
    fn regions_parse() {
        assert_eq!("pixel".parse::<MaskRegion>(), Ok(MaskRegion::PIXEL));
        assert_eq!("pupil".parse::<MaskRegion>(), Ok(MaskRegion::Pupil));
        assert_eq!(
            "1080x2400".parse::<MaskRegion>(),
            Ok(MaskRegion::Block {
                cols: 1080,
                rows: 2400
            })
        );
        assert!("0x3".parse::<MaskRegion>().is_err());
        assert!("big".parse::<MaskRegion>().is_err());
    }
}
