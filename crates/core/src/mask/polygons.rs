//! Merging the open cells of a binary grid into few rectilinear polygons.
//!
//! Mask writers reject a polygon per cell (a 512² pattern would be a quarter of a million
//! squares), so the open cells are traced as region boundaries instead:
//!
//! 1. Every side between an open cell and a closed one (or the outside) is a unit edge, directed
//!    so that the open cell lies on its left. Edges chain into closed loops; where two open cells
//!    touch only at a corner the walk turns left, hugging its own cell, so open regions are
//!    4-connected and every loop is a simple curve.
//! 2. Counter-clockwise loops are outer boundaries, clockwise loops are holes. Each hole is
//!    *keyholed* into its region: a zero-width bridge runs along the middle of a cell row from
//!    the hole's rightmost edge to the first boundary on its right (the outer loop or another,
//!    already bridged hole), so each region becomes one polygon without holes.
//! 3. A region whose polygon has more vertices than allowed (GDSII: 8190) is cut in two halves of
//!    its bounding box and each half traced again, recursively.
//!
//! Coordinates are on the *half-cell lattice*: point `[x, y]` lies `x/2` cells right of the
//! grid's top-left corner and `y/2` cells above it (y up, as in GDSII), so rows have negative y.
//! Half cells are needed only for the bridges, which run along row middles.

/// A binary grid of cells, row-major, row 0 at the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BinaryGrid {
    width: usize,
    height: usize,
    cells: Vec<bool>,
}

impl BinaryGrid {
    /// An all-closed grid.
    pub fn new(width: usize, height: usize) -> Self {
        BinaryGrid {
            width,
            height,
            cells: vec![false; width * height],
        }
    }

    /// A grid from rows of equal length (missing entries of short rows count as closed).
    pub fn from_rows(rows: &[Vec<bool>]) -> Self {
        let width = rows.iter().map(Vec::len).max().unwrap_or(0);
        let mut g = BinaryGrid::new(width, rows.len());
        for (r, row) in rows.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                g.set(c, r, v);
            }
        }
        g
    }

    /// Width in cells (columns).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in cells (rows).
    pub fn height(&self) -> usize {
        self.height
    }

    /// Whether cell `(col, row)` is open; outside the grid everything is closed.
    #[inline]
    pub fn get(&self, col: usize, row: usize) -> bool {
        col < self.width && row < self.height && self.cells[row * self.width + col]
    }

    /// Opens or closes cell `(col, row)`; writes outside the grid are ignored.
    #[inline]
    pub fn set(&mut self, col: usize, row: usize, open: bool) {
        if col < self.width && row < self.height {
            self.cells[row * self.width + col] = open;
        }
    }

    /// Number of open cells.
    pub fn count_open(&self) -> usize {
        self.cells.iter().filter(|v| **v).count()
    }

    /// The complement (open ↔ closed).
    pub fn inverted(&self) -> Self {
        BinaryGrid {
            width: self.width,
            height: self.height,
            cells: self.cells.iter().map(|v| !v).collect(),
        }
    }
}

/// A closed polygon on the half-cell lattice (see the module docs); the first point is not
/// repeated at the end. Outer boundaries run counter-clockwise.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ring {
    /// Vertices `[x, y]` in half cells (see the module docs).
    pub points: Vec<[i64; 2]>,
}

impl Ring {
    /// Signed area in cells (positive for counter-clockwise rings).
    pub fn area_cells(&self) -> f64 {
        let n = self.points.len();
        let twice: i64 = (0..n)
            .map(|i| {
                let [x0, y0] = self.points[i];
                let [x1, y1] = self.points[(i + 1) % n];
                x0 * y1 - x1 * y0
            })
            .sum();
        // Half-cell units: one cell is 4 lattice units².
        twice as f64 / 8.0
    }

    /// Moves the ring by a whole number of cells.
    fn shifted(mut self, dcol: i64, drow: i64) -> Self {
        for p in &mut self.points {
            p[0] += 2 * dcol;
            p[1] -= 2 * drow;
        }
        self
    }
}

/// Directions of unit edges, counter-clockwise order (y up).
const EAST: u8 = 0;
const NORTH: u8 = 1;
const WEST: u8 = 2;
const SOUTH: u8 = 3;

/// The lattice of cell corners: vertex `(vx, vy)` is `vx` cells right of and `vy` cells below
/// the grid's top-left corner.
struct Lattice {
    w1: usize,
}

impl Lattice {
    #[inline]
    fn index(&self, vx: usize, vy: usize) -> usize {
        vy * self.w1 + vx
    }

    #[inline]
    fn xy(&self, v: usize) -> (usize, usize) {
        (v % self.w1, v / self.w1)
    }

    /// The vertex one step from `v` in direction `d` (callers only step along existing edges).
    #[inline]
    fn step(&self, v: usize, d: u8) -> usize {
        match d {
            EAST => v + 1,
            NORTH => v - self.w1,
            WEST => v - 1,
            _ => v + self.w1,
        }
    }

    /// Half-cell lattice coordinates of vertex `v`.
    #[inline]
    fn point(&self, v: usize) -> [i64; 2] {
        let (vx, vy) = self.xy(v);
        [2 * vx as i64, -2 * vy as i64]
    }

    /// The midpoint of the unit edge leaving `v` in direction `d`.
    #[inline]
    fn midpoint(&self, v: usize, d: u8) -> [i64; 2] {
        let [x, y] = self.point(v);
        match d {
            EAST => [x + 1, y],
            NORTH => [x, y + 1],
            WEST => [x - 1, y],
            _ => [x, y - 1],
        }
    }

    /// The open cell `(col, row)` on the left of the unit edge leaving `v` in direction `d`.
    #[inline]
    fn left_cell(&self, v: usize, d: u8) -> (usize, usize) {
        let (vx, vy) = self.xy(v);
        match d {
            EAST => (vx, vy - 1),
            NORTH => (vx - 1, vy - 1),
            WEST => (vx - 1, vy),
            _ => (vx, vy),
        }
    }
}

/// One traced loop: its unit edges in order, as (start vertex, direction).
struct Loop {
    edges: Vec<(usize, u8)>,
    /// Twice the signed area in cells.
    area2: i64,
    component: u32,
}

/// Outgoing unit edges of every vertex, as a bit set of directions.
fn outgoing_edges(grid: &BinaryGrid, lat: &Lattice) -> Vec<u8> {
    let mut out = vec![0u8; lat.w1 * (grid.height + 1)];
    for r in 0..grid.height {
        for c in 0..grid.width {
            if !grid.get(c, r) {
                continue;
            }
            // Counter-clockwise around the cell: bottom east, right north, top west, left south.
            if r + 1 >= grid.height || !grid.get(c, r + 1) {
                out[lat.index(c, r + 1)] |= 1 << EAST;
            }
            if !grid.get(c + 1, r) {
                out[lat.index(c + 1, r + 1)] |= 1 << NORTH;
            }
            if r == 0 || !grid.get(c, r - 1) {
                out[lat.index(c + 1, r)] |= 1 << WEST;
            }
            if c == 0 || !grid.get(c - 1, r) {
                out[lat.index(c, r)] |= 1 << SOUTH;
            }
        }
    }
    out
}

/// Labels of the 4-connected open regions (`u32::MAX` for closed cells).
fn label_components(grid: &BinaryGrid) -> Vec<u32> {
    let (w, h) = (grid.width, grid.height);
    let mut labels = vec![u32::MAX; w * h];
    let mut next = 0u32;
    let mut stack = Vec::new();
    for start in 0..w * h {
        if !grid.cells[start] || labels[start] != u32::MAX {
            continue;
        }
        labels[start] = next;
        stack.push(start);
        while let Some(i) = stack.pop() {
            let (c, r) = (i % w, i / w);
            let mut visit = |j: usize| {
                if grid.cells[j] && labels[j] == u32::MAX {
                    labels[j] = next;
                    stack.push(j);
                }
            };
            if c > 0 {
                visit(i - 1);
            }
            if c + 1 < w {
                visit(i + 1);
            }
            if r > 0 {
                visit(i - w);
            }
            if r + 1 < h {
                visit(i + w);
            }
        }
        next += 1;
    }
    labels
}

/// Chains the unit edges into loops (left turns first, hugging the open side).
fn trace_loops(grid: &BinaryGrid, lat: &Lattice, labels: &[u32]) -> Vec<Loop> {
    let out = outgoing_edges(grid, lat);
    let mut used = vec![0u8; out.len()];
    let mut loops = Vec::new();
    for v0 in 0..out.len() {
        for d0 in 0..4u8 {
            if out[v0] & (1 << d0) == 0 || used[v0] & (1 << d0) != 0 {
                continue;
            }
            let mut edges = Vec::new();
            let mut area2 = 0i64;
            let (mut v, mut d) = (v0, d0);
            loop {
                used[v] |= 1 << d;
                edges.push((v, d));
                let next = lat.step(v, d);
                let [x0, y0] = lat.point(v);
                let [x1, y1] = lat.point(next);
                area2 += (x0 * y1 - x1 * y0) / 4;
                v = next;
                // Left turn, straight on, right turn: the first that exists.
                d = [(d + 1) % 4, d, (d + 3) % 4]
                    .into_iter()
                    .find(|nd| out[v] & (1 << nd) != 0)
                    .unwrap_or(d);
                if v == v0 && d == d0 {
                    break;
                }
            }
            let (c, r) = lat.left_cell(v0, d0);
            loops.push(Loop {
                edges,
                area2,
                component: labels[r * grid.width + c],
            });
        }
    }
    loops
}

/// For every hole, the (loop, edge index) its bridge lands on and the index of its own
/// departure edge.
struct Bridge {
    hole: usize,
    departure: usize,
    target: (usize, usize),
}

/// Finds each hole's bridge: from its rightmost south-going edge, east along the middle of that
/// cell row, to the first north-going boundary edge.
fn find_bridges(grid: &BinaryGrid, lat: &Lattice, loops: &[Loop]) -> Vec<Bridge> {
    let mut owner: std::collections::HashMap<(usize, u8), (usize, usize)> =
        std::collections::HashMap::new();
    for (li, l) in loops.iter().enumerate() {
        for (k, &(v, d)) in l.edges.iter().enumerate() {
            if d == NORTH {
                owner.insert((v, d), (li, k));
            }
        }
    }
    let mut bridges = Vec::new();
    for (li, l) in loops.iter().enumerate() {
        if l.area2 >= 0 {
            continue;
        }
        let Some((k, &(v, _))) = l
            .edges
            .iter()
            .enumerate()
            .filter(|(_, (_, d))| *d == SOUTH)
            .max_by_key(|(_, (v, _))| lat.xy(*v).0)
        else {
            continue;
        };
        let (vx, row) = lat.xy(v);
        // The cell east of the departure edge is open; walk to the first closed one.
        let mut col = vx;
        while grid.get(col, row) {
            col += 1;
        }
        // The boundary there is the north-going right side of cell (col - 1, row).
        let target_v = lat.index(col, row + 1);
        if let Some(&target) = owner.get(&(target_v, NORTH)) {
            bridges.push(Bridge {
                hole: li,
                departure: k,
                target,
            });
        }
    }
    bridges
}

/// Walks one region's outer loop and, through the bridges, every hole, into one point list.
fn splice(
    lat: &Lattice,
    loops: &[Loop],
    outer: usize,
    attached: &std::collections::HashMap<(usize, usize), (usize, usize)>,
) -> Vec<[i64; 2]> {
    let mut points = Vec::new();
    // Explicit stack (holes chain onto holes, so recursion depth is unbounded): each frame is
    // (loop, next edge offset, first edge index, bridge point to return through).
    let mut stack: Vec<(usize, usize, usize, Option<[i64; 2]>)> = vec![(outer, 0, 0, None)];
    while let Some(frame) = stack.last_mut() {
        let (li, offset, first, _) = *frame;
        let l = &loops[li];
        if offset >= l.edges.len() {
            if let Some((_, _, _, Some(back))) = stack.pop() {
                // Close the hole: along its departure edge to the bridge, then back across.
                let (v, d) = loops[li].edges[first];
                points.push(lat.point(v));
                points.push(lat.midpoint(v, d));
                points.push(back);
            }
            continue;
        }
        frame.1 += 1;
        let idx = (first + offset) % l.edges.len();
        let (v, d) = l.edges[idx];
        // A hole is entered at its departure edge's midpoint; its edges follow from the next one.
        if !(offset == 0 && stack.len() > 1) {
            points.push(lat.point(v));
        }
        if let Some(&(hole, departure)) = attached.get(&(li, idx)) {
            let here = lat.midpoint(v, d);
            points.push(here);
            let (hv, hd) = loops[hole].edges[departure];
            points.push(lat.midpoint(hv, hd));
            let n = loops[hole].edges.len();
            stack.push((hole, 1, departure % n, Some(here)));
        }
    }
    points
}

/// Removes repeated points and the middle points of straight runs.
fn simplify(points: Vec<[i64; 2]>) -> Vec<[i64; 2]> {
    let mut out: Vec<[i64; 2]> = Vec::with_capacity(points.len());
    let same_dir = |a: [i64; 2], b: [i64; 2], c: [i64; 2]| {
        let (d1, d2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
        d1[0] * d2[1] - d1[1] * d2[0] == 0 && d1[0] * d2[0] + d1[1] * d2[1] > 0
    };
    for p in points {
        if out.last() == Some(&p) {
            continue;
        }
        while out.len() >= 2 && same_dir(out[out.len() - 2], out[out.len() - 1], p) {
            out.pop();
        }
        out.push(p);
    }
    // The seam where the ring closes.
    loop {
        let n = out.len();
        if n < 3 {
            break;
        }
        if out[n - 1] == out[0] || same_dir(out[n - 2], out[n - 1], out[0]) {
            out.pop();
        } else if same_dir(out[n - 1], out[0], out[1]) {
            out.remove(0);
        } else {
            break;
        }
    }
    out
}

/// One polygon per 4-connected open region, holes keyholed, ignoring the vertex limit. Returns
/// each polygon with its region label.
fn region_polygons(grid: &BinaryGrid) -> (Vec<(u32, Ring)>, Vec<u32>) {
    let lat = Lattice { w1: grid.width + 1 };
    let labels = label_components(grid);
    let loops = trace_loops(grid, &lat, &labels);
    let attached: std::collections::HashMap<(usize, usize), (usize, usize)> =
        find_bridges(grid, &lat, &loops)
            .into_iter()
            .map(|b| (b.target, (b.hole, b.departure)))
            .collect();
    let rings = loops
        .iter()
        .enumerate()
        .filter(|(_, l)| l.area2 > 0)
        .map(|(li, l)| {
            let points = simplify(splice(&lat, &loops, li, &attached));
            (l.component, Ring { points })
        })
        .collect();
    (rings, labels)
}

/// The open cells of `grid` as rectilinear polygons without holes (holes are keyholed), none
/// with more than `max_vertices` vertices (at least 4 are always allowed).
///
/// The union of the polygons is exactly the set of open cells and they do not overlap.
pub fn trace_polygons(grid: &BinaryGrid, max_vertices: usize) -> Vec<Ring> {
    let max_vertices = max_vertices.max(4);
    let (rings, labels) = region_polygons(grid);
    let mut out = Vec::with_capacity(rings.len());
    for (label, ring) in rings {
        if ring.points.len() <= max_vertices {
            out.push(ring);
            continue;
        }
        // Too many vertices: cut the region's bounding box in two and trace each half.
        let (mut c0, mut r0, mut c1, mut r1) = (usize::MAX, usize::MAX, 0, 0);
        for (i, _) in labels.iter().enumerate().filter(|(_, l)| **l == label) {
            let (c, r) = (i % grid.width, i / grid.width);
            (c0, r0, c1, r1) = (c0.min(c), r0.min(r), c1.max(c), r1.max(r));
        }
        let (w, h) = (c1 - c0 + 1, r1 - r0 + 1);
        let halves = if w >= h {
            [(c0, r0, w / 2, h), (c0 + w / 2, r0, w - w / 2, h)]
        } else {
            [(c0, r0, w, h / 2), (c0, r0 + h / 2, w, h - h / 2)]
        };
        for (hc, hr, hw, hh) in halves {
            let mut sub = BinaryGrid::new(hw, hh);
            for r in 0..hh {
                for c in 0..hw {
                    let i = (hr + r) * grid.width + hc + c;
                    sub.set(c, r, labels[i] == label);
                }
            }
            out.extend(
                trace_polygons(&sub, max_vertices)
                    .into_iter()
                    .map(|ring| ring.shifted(hc as i64, hr as i64)),
            );
        }
    }
    out
}

/// Whether the point `(x, y)` (half-cell lattice units, possibly fractional) lies inside the
/// ring (even-odd rule; keyhole bridges cancel out).
pub fn ring_contains(ring: &Ring, x: f64, y: f64) -> bool {
    let n = ring.points.len();
    let mut inside = false;
    for i in 0..n {
        let [x0, y0] = ring.points[i].map(|v| v as f64);
        let [x1, y1] = ring.points[(i + 1) % n].map(|v| v as f64);
        if (y0 <= y) != (y1 <= y) {
            let xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0);
            if xc > x {
                inside = !inside;
            }
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(rows: &[&str]) -> BinaryGrid {
        BinaryGrid::from_rows(
            &rows
                .iter()
                .map(|r| r.chars().map(|c| c == '#').collect())
                .collect::<Vec<_>>(),
        )
    }

    /// Rasterises rings back onto the grid by sampling cell centres.
    fn raster(rings: &[Ring], w: usize, h: usize) -> BinaryGrid {
        let mut g = BinaryGrid::new(w, h);
        for r in 0..h {
            for c in 0..w {
                let (x, y) = (2.0 * c as f64 + 1.0, -2.0 * r as f64 - 1.0);
                let hits = rings.iter().filter(|p| ring_contains(p, x, y)).count();
                assert!(hits <= 1, "polygons overlap at cell ({c}, {r})");
                g.set(c, r, hits == 1);
            }
        }
        g
    }

    #[test]
    fn a_rectangle_is_one_four_vertex_polygon() {
        let g = grid(&["....", ".##.", ".##.", "...."]);
        let rings = trace_polygons(&g, 8190);
        assert_eq!(rings.len(), 1);
        assert_eq!(rings[0].points.len(), 4);
        assert_eq!(rings[0].area_cells(), 4.0);
    }

    #[test]
    fn diagonal_neighbours_are_separate_polygons() {
        let g = grid(&["#.", ".#"]);
        let rings = trace_polygons(&g, 8190);
        assert_eq!(rings.len(), 2);
        assert_eq!(raster(&rings, 2, 2), g);
    }

    #[test]
    fn a_ring_is_one_keyholed_polygon() {
        let g = grid(&["#####", "#...#", "#.#.#", "#...#", "#####"]);
        let rings = trace_polygons(&g, 8190);
        // The outer ring with its hole, and the island in the hole.
        assert_eq!(rings.len(), 2);
        let ring = rings.iter().find(|r| r.points.len() > 4).expect("the ring");
        // 4 outer corners, 4 hole corners, and each end of the bridge visited twice.
        assert_eq!(ring.points.len(), 4 + 4 + 4);
        assert_eq!(ring.area_cells(), 16.0);
        assert_eq!(raster(&rings, 5, 5), g);
    }
}
