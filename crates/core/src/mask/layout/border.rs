//! What a mask does with the openings its region's border cuts.
//!
//! A region is whole pixels, but an opening of the tiled display may run across pixels (the
//! disc-lattice's discs sit on the pixel corners, four quarters to a disc). Where the region
//! ends, such an opening is cut, and the piece left inside can be far narrower than the opening
//! (a 40-µm disc leaves a 16-µm sliver): the file breaks rules the design keeps.
//!
//! **Openings** here are the 4-connected open cells of the tiled display (cells meeting at a
//! corner only are two openings, as a fab's merge sees them). An opening is *cut* when it has
//! cells both inside the region and outside it. Only the pixels along the border and one ring of
//! pixels beyond it are looked at: an opening that runs on past them, into the region or out
//! beyond the ring (a slit across the display, a mesh), has no whole form within reach and stays
//! cut under every policy; such a cut runs along the opening and keeps its width.
//!
//! The policies ([`BorderPolicy`]):
//! - **cut**: the region's edge cuts every opening (the pixel as tiled, for a fab that arrays it);
//! - **drop**: a cut opening is left out;
//! - **extend**: a cut opening is drawn whole, past the region's edge (drawn openings only: with
//!   chrome drawn the field beyond the region is clear, so there is nothing to complete);
//! - **margin** (the default): a cut opening is left out and, with chrome drawn, a chrome frame
//!   `margin_um` wide is drawn around the region so no chrome ends in a sliver at the edge (with
//!   openings drawn the undrawn field is that chrome already).

use std::collections::HashMap;

use super::{MaskLayout, Polygon, TileRow};
use crate::ValueError;
use crate::display::tiling::D4;
use crate::mask::polygons::{BinaryGrid, trace_polygons};
use crate::mask::{MaskError, Tone};

/// What to do with the openings the region's border cuts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BorderPolicy {
    /// Cut at the region's edge.
    Cut,
    /// Leave a cut opening out.
    Drop,
    /// Draw a cut opening whole, past the edge.
    Extend,
    /// Leave a cut opening out; with chrome drawn, frame the region in chrome.
    #[default]
    Margin,
}

impl BorderPolicy {
    /// Every policy, in the order the UI lists them.
    pub const ALL: [BorderPolicy; 4] = [
        BorderPolicy::Margin,
        BorderPolicy::Drop,
        BorderPolicy::Extend,
        BorderPolicy::Cut,
    ];

    /// The name used on the command line and in files.
    pub fn as_str(self) -> &'static str {
        match self {
            BorderPolicy::Cut => "cut",
            BorderPolicy::Drop => "drop",
            BorderPolicy::Extend => "extend",
            BorderPolicy::Margin => "margin",
        }
    }

    /// What it does, in words for reports and the UI.
    pub fn meaning(self) -> &'static str {
        match self {
            BorderPolicy::Cut => "openings cut at the region's edge",
            BorderPolicy::Drop => "openings the edge would cut left out",
            BorderPolicy::Extend => "openings the edge would cut drawn whole past it",
            BorderPolicy::Margin => {
                "openings the edge would cut left out, the region framed in chrome"
            }
        }
    }
}

impl std::str::FromStr for BorderPolicy {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        BorderPolicy::ALL
            .into_iter()
            .find(|p| p.as_str() == s)
            .ok_or_else(|| ValueError::UnknownName {
                what: "border policy",
                value: s.to_string(),
                expected: "margin, drop, extend or cut",
            })
    }
}

/// The default chrome margin, µm: wider than any default rule.
pub const DEFAULT_MARGIN_UM: f64 = 20.0;

/// The most cells the border policy looks at (the pixels along the edge and the ring beyond:
/// 256 MB of labels).
pub const MAX_BORDER_CELLS: usize = 64 << 20;

/// How the border policy changed the drawing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BorderEdit {
    /// Pixels drawn flat instead of referenced, `(tx, ty)`, sorted by row then column.
    pub replaced: Vec<(i64, i64)>,
    /// The drawn polygons of the replaced pixels, mask frame.
    pub inside: Vec<Polygon>,
    /// Drawn polygons beyond the region (completed openings, the chrome margin), mask frame.
    pub outside: Vec<Polygon>,
    /// What became of the cut openings.
    pub counts: BorderCounts,
}

/// What became of the openings the region's edge cuts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BorderCounts {
    /// Openings the region's edge cuts.
    pub cut: usize,
    /// Of those, left out.
    pub dropped: usize,
    /// Of those, drawn whole.
    pub completed: usize,
    /// Of those, left cut because they run on beyond the pixels along the edge (or past the
    /// ring of pixels beyond it).
    pub kept_cut: usize,
}

impl BorderCounts {
    /// The report's line on them, naming `policy`.
    pub fn line(&self, policy: BorderPolicy) -> String {
        let mut s = format!("border: {} ({})", policy.as_str(), policy.meaning());
        if self.cut == 0 {
            s.push_str("; no opening crosses the region's edge");
            return s;
        }
        s.push_str(&format!("; {} cut by the edge", counted(self.cut)));
        for (n, what) in [
            (self.dropped, "left out"),
            (self.completed, "drawn whole"),
            (
                self.kept_cut,
                "left cut (they run on, a pixel or more past the edge)",
            ),
        ] {
            if n > 0 {
                s.push_str(&format!(", {n} {what}"));
            }
        }
        s
    }
}

fn counted(n: usize) -> String {
    if n == 1 {
        "1 opening".into()
    } else {
        format!("{n} openings")
    }
}

impl BorderEdit {
    /// Every polygon the edit draws, mask frame.
    pub fn polygons(&self) -> impl Iterator<Item = &Polygon> {
        self.inside.iter().chain(&self.outside)
    }

    /// How many polygons and vertices the edit draws.
    pub fn size(&self) -> (u64, u64) {
        self.polygons()
            .fold((0, 0), |(n, v), p| (n + 1, v + p.points_nm.len() as u64))
    }
}

/// A disjoint-set forest over cell indices.
struct Sets(Vec<u32>);

impl Sets {
    fn find(&mut self, mut i: u32) -> u32 {
        while self.0[i as usize] != i {
            let up = self.0[self.0[i as usize] as usize];
            self.0[i as usize] = up;
            i = up;
        }
        i
    }
    fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.0[a.max(b) as usize] = a.min(b);
        }
    }
}

/// Which tiles the region holds (its rows sorted by `ty`).
pub(super) fn holds(rows: &[TileRow], tx: i64, ty: i64) -> bool {
    rows.binary_search_by_key(&ty, |r| r.ty)
        .is_ok_and(|k| (rows[k].tx0..rows[k].tx0 + i64::from(rows[k].count)).contains(&tx))
}

/// The region's tiles with a neighbour (of eight) outside it.
fn border_tiles(rows: &[TileRow]) -> Vec<(i64, i64)> {
    let mut out = Vec::new();
    for (k, r) in rows.iter().enumerate() {
        let (a, b) = (r.tx0, r.tx0 + i64::from(r.count) - 1);
        // Tiles whose three neighbours in the row above (or below) are all in the region.
        let covered = |other: Option<&TileRow>| -> (i64, i64) {
            match other {
                Some(o) if (o.ty - r.ty).abs() == 1 => (o.tx0 + 1, o.tx0 + i64::from(o.count) - 2),
                _ => (1, 0),
            }
        };
        let up = covered(k.checked_sub(1).and_then(|i| rows.get(i)));
        let down = covered(rows.get(k + 1));
        let lo = (a + 1).max(up.0).max(down.0);
        let hi = (b - 1).min(up.1).min(down.1);
        if lo > hi {
            out.extend((a..=b).map(|tx| (tx, r.ty)));
        } else {
            out.extend((a..lo).map(|tx| (tx, r.ty)));
            out.extend((hi + 1..=b).map(|tx| (tx, r.ty)));
        }
    }
    out
}

/// What is known of an opening near the border.
#[derive(Debug, Clone, Copy, Default)]
struct Reach {
    inside: bool,
    outside: bool,
    /// Runs on into the region beyond the border pixels.
    deep: bool,
    /// Runs on beyond the ring of pixels past the edge.
    far: bool,
}

/// Works out `policy` for `layout` (its region rows, orientations and clear cells in place).
///
/// # Errors
/// [`MaskError::Invalid`] for `extend` with chrome drawn or a margin that is not a positive
/// width.
pub fn edit(
    layout: &MaskLayout,
    region: &[TileRow],
    clear: &BinaryGrid,
    policy: BorderPolicy,
    margin_um: f64,
) -> Result<BorderEdit, MaskError> {
    let tone = layout.spec.tone;
    if policy == BorderPolicy::Extend && tone == Tone::Chrome {
        return Err(MaskError::Invalid(
            "--border extend draws openings past the region, but with chrome drawn the field \
             beyond it is clear already: use margin (or drop) for the chrome tone"
                .into(),
        ));
    }
    let margin = margin_nm(policy, tone, margin_um, layout.grid_nm)?;
    let mut out = BorderEdit::default();
    if policy == BorderPolicy::Cut {
        return Ok(out);
    }
    let border = border_tiles(region);
    if layout.period_nm == layout.pitch_nm {
        // The edge pixels and about as many beyond them.
        let cells = (2 * border.len() + 8).saturating_mul(layout.n * layout.n);
        if cells > MAX_BORDER_CELLS {
            return Err(MaskError::TooLarge(format!(
                "the border policy `{}` would label {cells} cells along the region's edge, more \
                 than {MAX_BORDER_CELLS}; use --border cut, or a smaller region",
                policy.as_str()
            )));
        }
        cut_openings(layout, region, clear, &border, policy, &mut out);
    }
    if let Some(m) = margin {
        out.outside.extend(self::margin(layout, region, &border, m));
    }
    Ok(out)
}

/// The widest chrome margin, µm: a centimetre, wider than any die.
pub const MAX_MARGIN_UM: f64 = 10_000.0;

/// The chrome margin's width on the `grid_nm` grid, nm, when `policy` and `tone` draw one.
///
/// # Errors
/// [`MaskError::Invalid`] for a width that is not a number, not positive, wider than
/// [`MAX_MARGIN_UM`] or narrower than half a grid step (it would vanish on the grid).
pub fn margin_nm(
    policy: BorderPolicy,
    tone: Tone,
    margin_um: f64,
    grid_nm: i64,
) -> Result<Option<i64>, MaskError> {
    if policy != BorderPolicy::Margin {
        return Ok(None);
    }
    if !(margin_um.is_finite() && margin_um > 0.0 && margin_um <= MAX_MARGIN_UM) {
        return Err(MaskError::Invalid(format!(
            "the chrome margin must be a width of more than 0 and at most {MAX_MARGIN_UM} µm \
             (got {margin_um:?})"
        )));
    }
    let steps = (margin_um * 1e3 / grid_nm as f64).round();
    if steps < 1.0 {
        return Err(MaskError::Invalid(format!(
            "the chrome margin of {margin_um:?} µm is less than the {grid_nm}-nm grid; give at \
             least {} µm",
            grid_nm as f64 * 1e-3
        )));
    }
    Ok((tone == Tone::Chrome).then_some(steps as i64 * grid_nm))
}

/// Finds the openings the border cuts and drops or completes them.
fn cut_openings(
    layout: &MaskLayout,
    region: &[TileRow],
    clear: &BinaryGrid,
    border: &[(i64, i64)],
    policy: BorderPolicy,
    out: &mut BorderEdit,
) {
    let n = layout.n;
    let grids: HashMap<D4, Vec<Vec<bool>>> = D4::all()
        .into_iter()
        .map(|g| {
            let rows: Vec<Vec<bool>> = (0..n)
                .map(|r| (0..n).map(|c| clear.get(c, r)).collect())
                .collect();
            (g, g.apply(&rows))
        })
        .collect();
    let grid_of = |tx: i64, ty: i64| &grids[&layout.orientation(tx, ty)];
    // The border pixels, then the ring beyond them.
    let mut band: Vec<(i64, i64)> = border.to_vec();
    let mut index: HashMap<(i64, i64), usize> =
        band.iter().enumerate().map(|(i, t)| (*t, i)).collect();
    for &(tx, ty) in border {
        for dy in -1..=1 {
            for dx in -1..=1 {
                let t = (tx + dx, ty + dy);
                if !holds(region, t.0, t.1) && !index.contains_key(&t) {
                    index.insert(t, band.len());
                    band.push(t);
                }
            }
        }
    }
    let cells = n * n;
    let id = |tile: usize, r: usize, c: usize| (tile * cells + r * n + c) as u32;
    let mut sets = Sets((0..(band.len() * cells) as u32).collect());
    for (i, &(tx, ty)) in band.iter().enumerate() {
        let g = grid_of(tx, ty);
        let right = index.get(&(tx + 1, ty)).map(|&j| (j, grid_of(tx + 1, ty)));
        let below = index.get(&(tx, ty + 1)).map(|&j| (j, grid_of(tx, ty + 1)));
        for r in 0..n {
            for c in 0..n {
                if !g[r][c] {
                    continue;
                }
                if c + 1 < n && g[r][c + 1] {
                    sets.union(id(i, r, c), id(i, r, c + 1));
                }
                if r + 1 < n && g[r + 1][c] {
                    sets.union(id(i, r, c), id(i, r + 1, c));
                }
            }
            if let Some((j, h)) = right
                && g[r][n - 1]
                && h[r][0]
            {
                sets.union(id(i, r, n - 1), id(j, r, 0));
            }
        }
        if let Some((j, h)) = below {
            for c in 0..n {
                if g[n - 1][c] && h[0][c] {
                    sets.union(id(i, n - 1, c), id(j, 0, c));
                }
            }
        }
    }
    let mut reach: HashMap<u32, Reach> = HashMap::new();
    for (i, &(tx, ty)) in band.iter().enumerate() {
        let g = grid_of(tx, ty);
        let inside = holds(region, tx, ty);
        // Edge cells whose neighbour across the tile edge lies beyond the band and is open.
        let beyond = |dx: i64, dy: i64| -> Option<&Vec<Vec<bool>>> {
            let t = (tx + dx, ty + dy);
            (!index.contains_key(&t)).then(|| grid_of(t.0, t.1))
        };
        let sides = [
            (beyond(-1, 0), 0usize),
            (beyond(1, 0), 1),
            (beyond(0, -1), 2),
            (beyond(0, 1), 3),
        ];
        for r in 0..n {
            for c in 0..n {
                if !g[r][c] {
                    continue;
                }
                let root = sets.find(id(i, r, c));
                let e = reach.entry(root).or_default();
                if inside {
                    e.inside = true;
                } else {
                    e.outside = true;
                }
                for (other, side) in &sides {
                    let Some(h) = other else { continue };
                    let touches = match side {
                        0 => c == 0 && h[r][n - 1],
                        1 => c == n - 1 && h[r][0],
                        2 => r == 0 && h[n - 1][c],
                        _ => r == n - 1 && h[0][c],
                    };
                    if touches {
                        if inside {
                            e.deep = true;
                        } else {
                            e.far = true;
                        }
                    }
                }
            }
        }
    }
    // The decision per cut opening: drop (true) or complete (false).
    let mut decision: HashMap<u32, bool> = HashMap::new();
    for (&root, r) in &reach {
        if !(r.inside && r.outside) {
            continue;
        }
        out.counts.cut += 1;
        if r.deep || r.far {
            out.counts.kept_cut += 1;
        } else if policy == BorderPolicy::Extend {
            out.counts.completed += 1;
            decision.insert(root, false);
        } else {
            out.counts.dropped += 1;
            decision.insert(root, true);
        }
    }
    if decision.is_empty() {
        return;
    }
    let tone = layout.spec.tone;
    let mut replaced = Vec::new();
    for (i, &(tx, ty)) in band.iter().enumerate() {
        let g = grid_of(tx, ty);
        let inside = holds(region, tx, ty);
        let mut changed = false;
        let mut cells = BinaryGrid::new(n, n);
        for (r, row) in g.iter().enumerate() {
            for (c, &open) in row.iter().enumerate() {
                let verdict = open
                    .then(|| decision.get(&sets.find(id(i, r, c))).copied())
                    .flatten();
                let drawn = if inside {
                    // Inside: the opening stays unless dropped.
                    let stays = open && verdict != Some(true);
                    changed |= open && !stays;
                    stays != (tone == Tone::Chrome)
                } else {
                    // Beyond the edge: only the completed openings (drawn open).
                    verdict == Some(false)
                };
                cells.set(c, r, drawn);
            }
        }
        let corner = layout.tile_corner_nm(tx, ty);
        let place = |p: &Polygon| Polygon {
            points_nm: p
                .points_nm
                .iter()
                .map(|q| [q[0] + corner[0], q[1] + corner[1]])
                .collect(),
        };
        let traced = || -> Vec<Polygon> {
            trace_polygons(&cells, layout.spec.max_vertices)
                .iter()
                .map(|ring| place(&layout.ring_to_polygon(ring)))
                .collect()
        };
        if inside && changed {
            replaced.push((ty, tx));
            out.inside.extend(traced());
            out.inside.extend(layout.gap_polygon.iter().map(place));
        } else if !inside && cells.count_open() > 0 {
            out.outside.extend(traced());
        }
    }
    replaced.sort_unstable();
    out.replaced = replaced.into_iter().map(|(ty, tx)| (tx, ty)).collect();
}

/// The chrome frame `m` nm wide around the region: a strip beyond every outward side of a
/// border pixel, a square beyond every outward corner, strips along one line joined.
fn margin(layout: &MaskLayout, region: &[TileRow], border: &[(i64, i64)], m: i64) -> Vec<Polygon> {
    let q = layout.period_nm;
    let mut horizontal: Vec<[i64; 4]> = Vec::new();
    let mut vertical: Vec<[i64; 4]> = Vec::new();
    let mut squares: Vec<[i64; 4]> = Vec::new();
    for &(tx, ty) in border {
        let [x, y] = layout.tile_corner_nm(tx, ty);
        let out = |dx: i64, dy: i64| !holds(region, tx + dx, ty + dy);
        let (left, right, up, down) = (out(-1, 0), out(1, 0), out(0, -1), out(0, 1));
        if left {
            vertical.push([x - m, y - q, x, y]);
        }
        if right {
            vertical.push([x + q, y - q, x + q + m, y]);
        }
        if up {
            horizontal.push([x, y, x + q, y + m]);
        }
        if down {
            horizontal.push([x, y - q - m, x + q, y - q]);
        }
        for (a, b, sq) in [
            (left, up, [x - m, y, x, y + m]),
            (right, up, [x + q, y, x + q + m, y + m]),
            (left, down, [x - m, y - q - m, x, y - q]),
            (right, down, [x + q, y - q - m, x + q + m, y - q]),
        ] {
            if a && b {
                squares.push(sq);
            }
        }
    }
    let rect = |b: [i64; 4]| Polygon {
        points_nm: vec![[b[0], b[1]], [b[2], b[1]], [b[2], b[3]], [b[0], b[3]]],
    };
    let mut out: Vec<Polygon> = Vec::new();
    // Strips on one line that meet end to end become one.
    for (mut strips, along) in [(horizontal, 0usize), (vertical, 1)] {
        let across = 1 - along;
        strips.sort_unstable_by_key(|b| (b[across], b[across + 2], b[along]));
        let mut current: Option<[i64; 4]> = None;
        for b in strips {
            current = match current {
                Some(mut c)
                    if c[across] == b[across]
                        && c[across + 2] == b[across + 2]
                        && c[along + 2] >= b[along] =>
                {
                    c[along + 2] = c[along + 2].max(b[along + 2]);
                    Some(c)
                }
                Some(c) => {
                    out.push(rect(c));
                    Some(b)
                }
                None => Some(b),
            };
        }
        out.extend(current.map(rect));
    }
    out.extend(squares.into_iter().map(rect));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_margin_is_a_width_between_one_grid_step_and_a_centimetre() {
        let m = |policy, tone, um, grid| margin_nm(policy, tone, um, grid);
        let (margin, chrome) = (BorderPolicy::Margin, Tone::Chrome);
        assert_eq!(m(margin, chrome, 20.0, 1).ok(), Some(Some(20_000)));
        assert_eq!(m(margin, chrome, 0.0124, 5).ok(), Some(Some(10)));
        // Drawn with chrome only; other policies ignore the width.
        assert_eq!(m(margin, Tone::Open, 20.0, 1).ok(), Some(None));
        assert_eq!(m(BorderPolicy::Cut, chrome, f64::NAN, 1).ok(), Some(None));
        let text = |um: f64| match m(margin, chrome, um, 1) {
            Err(MaskError::Invalid(t)) => t,
            other => panic!("{um}: {other:?}"),
        };
        // Quoted as given, not as some clamped value.
        assert!(
            text(1e308).contains("at most 10000 µm (got 1e308)"),
            "{}",
            text(1e308)
        );
        assert!(text(-1.0).contains("(got -1.0)"));
        assert!(text(f64::NAN).contains("(got NaN)"));
        let tiny = text(1e-300);
        assert!(
            tiny.contains("less than the 1-nm grid") && tiny.contains("0.001 µm"),
            "{tiny}"
        );
    }

    #[test]
    fn border_tiles_of_a_block_are_its_outer_ring() {
        let rows: Vec<TileRow> = (-2..=2)
            .map(|ty| TileRow {
                ty,
                tx0: -2,
                count: 5,
            })
            .collect();
        let b = border_tiles(&rows);
        assert_eq!(b.len(), 16);
        assert!(!b.contains(&(0, 0)) && !b.contains(&(1, 1)));
        assert!(b.contains(&(-2, 0)) && b.contains(&(2, 2)) && b.contains(&(0, -2)));
    }

    #[test]
    fn border_tiles_of_a_staircase_include_the_steps() {
        // Rows of 3, 5, 5, 3 tiles: the second row's ends sit beside the first row's gaps.
        let rows = vec![
            TileRow {
                ty: 0,
                tx0: 1,
                count: 3,
            },
            TileRow {
                ty: 1,
                tx0: 0,
                count: 5,
            },
            TileRow {
                ty: 2,
                tx0: 0,
                count: 5,
            },
            TileRow {
                ty: 3,
                tx0: 1,
                count: 3,
            },
        ];
        let b = border_tiles(&rows);
        let brute: Vec<(i64, i64)> = rows
            .iter()
            .flat_map(|r| (r.tx0..r.tx0 + i64::from(r.count)).map(move |tx| (tx, r.ty)))
            .filter(|&(tx, ty)| {
                (-1..=1).any(|dy| (-1..=1).any(|dx| !holds(&rows, tx + dx, ty + dy)))
            })
            .collect();
        assert_eq!(b, brute);
    }

    #[test]
    fn policies_parse_and_name_themselves() {
        for p in BorderPolicy::ALL {
            assert_eq!(p.as_str().parse::<BorderPolicy>(), Ok(p));
        }
        assert!("keep".parse::<BorderPolicy>().is_err());
        assert_eq!(BorderPolicy::default(), BorderPolicy::Margin);
    }
}
