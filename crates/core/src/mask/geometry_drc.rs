//! The design-rule check of drawn geometry: the polygons a mask file holds on one layer, after
//! the region is cut, the tone chosen and the border drawn. [`super::drc::check`] checks the
//! design (a pixel beside its tiled neighbours); this checks what the fab gets.
//!
//! **What is measured** is what KLayout's `width` and `space` checks measure with the
//! *projection* metric on the merged layer: two edges facing each other, the distance between
//! them across the span they share. A *width* is drawn between them, a *space* is undrawn between
//! them (inside one polygon or between two); the field around the drawing is neither.
//! Every such edge pair narrower than the rule is one violation. Openings or chrome that meet at
//! a corner only are *corner contacts* (KLayout sees them as zero-distance pairs of the
//! Euclidean metric).
//!
//! **The tone** decides which is which: with openings drawn, a width is an opening and a space a
//! chrome gap; with chrome drawn, the other way round.
//!
//! The geometry must be Manhattan (edges along x or y), as every display mask the studio writes
//! is; polygons are united by the non-zero rule, so keyholes and overlaps cost nothing.

use std::collections::{BTreeMap, HashMap, HashSet};

use super::Tone;
use super::drc::{DrcReport, Rules, Violation, ViolationKind};
use crate::Progress;

/// The most polygon vertices one check takes (16 M: about 300 MB of edges and their order at
/// its peak).
pub const MAX_CHECK_VERTICES: usize = 16_000_000;

/// Why drawn geometry cannot be checked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryDrcError {
    /// An edge neither along x nor along y.
    #[error(
        "an edge from ({:.3}, {:.3}) µm to ({:.3}, {:.3}) µm is neither horizontal nor vertical: \
         the check of written geometry takes Manhattan polygons only",
        .from_nm[0] as f64 * 1e-3, .from_nm[1] as f64 * 1e-3,
        .to_nm[0] as f64 * 1e-3, .to_nm[1] as f64 * 1e-3
    )]
    NotManhattan {
        /// Where the edge starts, nm.
        from_nm: [i64; 2],
        /// Where it ends, nm.
        to_nm: [i64; 2],
    },
    /// More vertices than [`MAX_CHECK_VERTICES`].
    #[error(
        "{vertices} vertices are more than the {MAX_CHECK_VERTICES} one check of written \
         geometry takes"
    )]
    TooLarge {
        /// Vertices offered.
        vertices: usize,
    },
    /// A coordinate beyond GDSII's 32-bit range.
    #[error("a coordinate of {nm} nm is beyond the 32-bit range of mask coordinates")]
    OutOfRange {
        /// The coordinate, nm.
        nm: i64,
    },
    /// The caller cancelled.
    #[error("cancelled")]
    Cancelled,
}

/// One edge across the sweep: at `at` along the sweep's cross axis, spanning `lo..hi` of the
/// sweep axis, `+1` or `−1` by its direction.
#[derive(Debug, Clone, Copy)]
struct Edge {
    at: i32,
    lo: i32,
    hi: i32,
    winding: i8,
}

/// A coordinate as the edges keep it: mask coordinates are GDSII's 32-bit integers.
fn narrow(v: i64) -> Result<i32, GeometryDrcError> {
    i32::try_from(v).map_err(|_| GeometryDrcError::OutOfRange { nm: v })
}

/// Drawn geometry ready to check: its edges, split by direction.
#[derive(Debug, Clone, Default)]
pub struct DrawnGeometry {
    /// Vertical edges (x, y-span): swept along y, they give the widths across x.
    vertical: Vec<Edge>,
    /// Horizontal edges (y, x-span): swept along x, they give the widths across y.
    horizontal: Vec<Edge>,
    vertices: usize,
}

impl DrawnGeometry {
    /// Nothing drawn yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one closed polygon (nm, first vertex not repeated; a repeated last vertex is fine).
    ///
    /// # Errors
    /// [`GeometryDrcError::NotManhattan`] for a slanted edge, [`GeometryDrcError::TooLarge`]
    /// past [`MAX_CHECK_VERTICES`].
    pub fn add(&mut self, points_nm: &[[i64; 2]]) -> Result<(), GeometryDrcError> {
        let k = points_nm.len();
        self.vertices += k;
        // Files carry no orientation: every polygon counts +1 inside, whichever way it runs.
        let twice_area: i128 = (0..k)
            .map(|i| {
                let (a, b) = (points_nm[i], points_nm[(i + 1) % k]);
                i128::from(a[0]) * i128::from(b[1]) - i128::from(b[0]) * i128::from(a[1])
            })
            .sum();
        let sense: i8 = if twice_area < 0 { -1 } else { 1 };
        if self.vertices > MAX_CHECK_VERTICES {
            return Err(GeometryDrcError::TooLarge {
                vertices: self.vertices,
            });
        }
        for i in 0..k {
            let (a, b) = (points_nm[i], points_nm[(i + 1) % k]);
            if a == b {
                continue;
            }
            if a[0] == b[0] {
                // Up counts +1: a counter-clockwise polygon winds +1 inside.
                let winding = if b[1] > a[1] { -sense } else { sense };
                self.vertical.push(Edge {
                    at: narrow(a[0])?,
                    lo: narrow(a[1].min(b[1]))?,
                    hi: narrow(a[1].max(b[1]))?,
                    winding,
                });
            } else if a[1] == b[1] {
                let winding = if b[0] > a[0] { sense } else { -sense };
                self.horizontal.push(Edge {
                    at: narrow(a[1])?,
                    lo: narrow(a[0].min(b[0]))?,
                    hi: narrow(a[0].max(b[0]))?,
                    winding,
                });
            } else {
                return Err(GeometryDrcError::NotManhattan {
                    from_nm: a,
                    to_nm: b,
                });
            }
        }
        Ok(())
    }

    /// Polygons added so far hold this many vertices.
    pub fn vertices(&self) -> usize {
        self.vertices
    }

    /// Checks the united drawing against `rules`, reading widths and spaces by `tone`.
    ///
    /// # Errors
    /// [`GeometryDrcError::Cancelled`] when `progress` is cancelled.
    pub fn check(
        &self,
        tone: Tone,
        rules: &Rules,
        progress: &Progress,
    ) -> Result<DrcReport, GeometryDrcError> {
        let mut report = DrcReport::new(*rules);
        let mut contacts = Vec::new();
        // Across x (vertical edges, bands along y), then across y.
        sweep(
            &self.vertical,
            Axis::AcrossX,
            tone,
            &mut report,
            &mut contacts,
            progress,
            0.0,
        )?;
        sweep(
            &self.horizontal,
            Axis::AcrossY,
            tone,
            &mut report,
            &mut Vec::new(),
            progress,
            0.5,
        )?;
        for at in contacts {
            report.corner_contacts += 1;
            if rules.no_corner_contact {
                report.push(Violation {
                    kind: ViolationKind::CornerContact,
                    value: 0.0,
                    at_um: at.map(|v| v as f64 * 1e-3),
                    place: format!(
                        "at ({:.3}, {:.3}) µm",
                        at[0] as f64 * 1e-3,
                        at[1] as f64 * 1e-3
                    ),
                });
            }
        }
        progress.set(1.0);
        Ok(report)
    }
}

/// Which distance a sweep measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Axis {
    /// Between vertical edges: bands along y, runs along x.
    AcrossX,
    /// Between horizontal edges: bands along x, runs along y.
    AcrossY,
}

/// A drawn run (`drawn`) or an undrawn one between two drawn runs, `from..to` across a band.
type RunKey = (bool, i64, i64);

/// Sweeps bands between consecutive edge ends; in each band the drawn intervals come from the
/// winding of the edges that span it. Runs equal in consecutive bands are one edge pair.
fn sweep(
    edges: &[Edge],
    axis: Axis,
    tone: Tone,
    report: &mut DrcReport,
    contacts: &mut Vec<[i64; 2]>,
    progress: &Progress,
    progress_from: f32,
) -> Result<(), GeometryDrcError> {
    let mut open: HashMap<RunKey, i64> = HashMap::new();
    let mut previous: Vec<[i64; 2]> = Vec::new();
    let total = 2 * edges.len().max(1);
    let mut k = 0usize;
    bands(edges, |at, intervals| {
        k += 1;
        if k.is_multiple_of(4096) {
            progress.check().map_err(|_| GeometryDrcError::Cancelled)?;
            progress.set(progress_from + 0.5 * (k as f32 / total as f32).min(1.0));
        }
        if axis == Axis::AcrossX {
            for x in checkerboard(&previous, intervals) {
                contacts.push([x, at]);
            }
        }
        let mut now: Vec<RunKey> = intervals.iter().map(|i| (true, i[0], i[1])).collect();
        now.extend(intervals.windows(2).map(|w| (false, w[0][1], w[1][0])));
        // Pairs that end here become findings; the rest carry on.
        let carried: HashSet<RunKey> = now.iter().copied().collect();
        let mut ended: Vec<(RunKey, i64)> = open
            .iter()
            .filter(|(key, _)| !carried.contains(key))
            .map(|(key, from)| (*key, *from))
            .collect();
        ended.sort_unstable();
        for (key, from) in ended {
            open.remove(&key);
            finding(key, [from, at], axis, tone, report);
        }
        for key in now {
            open.entry(key).or_insert(at);
        }
        previous = intervals.to_vec();
        Ok(())
    })
}

/// The union of Manhattan polygons (nm) as non-overlapping rectangles `[x0, y0, x1, y1]`, one
/// per band between vertex heights and drawn interval; slanted edges are ignored.
pub fn union_rectangles<'a>(polygons: impl IntoIterator<Item = &'a [[i64; 2]]>) -> Vec<[i64; 4]> {
    let mut g = DrawnGeometry::new();
    for p in polygons {
        // A slanted edge is reported by `add`; a rectangle list has no place for it.
        let _ = g.add(p);
    }
    let mut out = Vec::new();
    let mut previous: Option<i64> = None;
    let mut intervals: Vec<[i64; 2]> = Vec::new();
    bands(&g.vertical, |at, now| {
        if let Some(from) = previous {
            out.extend(intervals.iter().map(|i| [i[0], from, i[1], at]));
        }
        previous = Some(at);
        intervals = now.to_vec();
        Ok(())
    })
    .ok();
    out
}

/// Calls `f(at, intervals)` at every edge end along the sweep, in order, with the drawn
/// intervals of the band that starts there (the last band is empty).
fn bands(
    edges: &[Edge],
    mut f: impl FnMut(i64, &[[i64; 2]]) -> Result<(), GeometryDrcError>,
) -> Result<(), GeometryDrcError> {
    let mut cuts: Vec<i32> = edges.iter().flat_map(|e| [e.lo, e.hi]).collect();
    cuts.sort_unstable();
    cuts.dedup();
    // u32 indices: at most MAX_CHECK_VERTICES edges.
    let mut starts: Vec<u32> = (0..edges.len() as u32).collect();
    starts.sort_unstable_by_key(|&i| edges[i as usize].lo);
    let mut ends: Vec<u32> = starts.clone();
    ends.sort_unstable_by_key(|&i| edges[i as usize].hi);
    // Windings summed per position of the active edges.
    let mut active: BTreeMap<i64, i32> = BTreeMap::new();
    let (mut s, mut e) = (0, 0);
    for &at in &cuts {
        while e < ends.len() && edges[ends[e] as usize].hi == at {
            let edge = edges[ends[e] as usize];
            *active.entry(i64::from(edge.at)).or_insert(0) -= i32::from(edge.winding);
            e += 1;
        }
        while s < starts.len() && edges[starts[s] as usize].lo == at {
            let edge = edges[starts[s] as usize];
            *active.entry(i64::from(edge.at)).or_insert(0) += i32::from(edge.winding);
            s += 1;
        }
        active.retain(|_, w| *w != 0);
        f(i64::from(at), &drawn_intervals(&active))?;
    }
    Ok(())
}

/// The drawn intervals of one band from the windings of its edges (non-zero rule), touching
/// intervals joined.
fn drawn_intervals(active: &BTreeMap<i64, i32>) -> Vec<[i64; 2]> {
    let mut out: Vec<[i64; 2]> = Vec::new();
    let mut winding = 0;
    let mut from = 0;
    for (&x, &w) in active {
        let before = winding;
        winding += w;
        if before == 0 && winding != 0 {
            from = x;
        } else if before != 0 && winding == 0 {
            match out.last_mut() {
                Some(last) if last[1] == from => last[1] = x,
                _ => out.push([from, x]),
            }
        }
    }
    out
}

/// Where two bands, `below` then `above`, meet in a checkerboard: drawn on one diagonal only.
fn checkerboard(below: &[[i64; 2]], above: &[[i64; 2]]) -> Vec<i64> {
    let ends = |v: &[[i64; 2]]| -> Vec<(i64, bool)> {
        v.iter()
            .flat_map(|i| [(i[0], true), (i[1], false)])
            .collect()
    };
    let (b, a) = (ends(below), ends(above));
    // Positions where both bands change state: a starts where the other ends.
    let mut out = Vec::new();
    let (mut i, mut j) = (0, 0);
    while i < b.len() && j < a.len() {
        match b[i].0.cmp(&a[j].0) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                if b[i].1 != a[j].1 {
                    out.push(b[i].0);
                }
                i += 1;
                j += 1;
            }
        }
    }
    out
}

/// Records one edge pair: `key` across, `span` along.
fn finding(key: RunKey, span: [i64; 2], axis: Axis, tone: Tone, report: &mut DrcReport) {
    let (drawn, from, to) = key;
    let width_nm = to - from;
    let opening = drawn == (tone == Tone::Open);
    let value = width_nm as f64 * 1e-3;
    let (best, rule, kind) = if opening {
        (
            &mut report.min_feature_um,
            report.rules.min_feature_um,
            ViolationKind::MinFeature,
        )
    } else {
        (
            &mut report.min_gap_um,
            report.rules.min_gap_um,
            ViolationKind::MinGap,
        )
    };
    *best = Some(best.map_or(value, |b: f64| b.min(value)));
    if value < rule - 1e-9 {
        let um = |v: i64| v as f64 * 1e-3;
        let mid = |a: i64, b: i64| (a + b) as f64 * 0.5e-3;
        let (at_um, place) = match axis {
            Axis::AcrossX => (
                [mid(from, to), mid(span[0], span[1])],
                format!(
                    "x = {:.3} … {:.3} µm, y = {:.3} … {:.3} µm",
                    um(from),
                    um(to),
                    um(span[0]),
                    um(span[1])
                ),
            ),
            Axis::AcrossY => (
                [mid(span[0], span[1]), mid(from, to)],
                format!(
                    "y = {:.3} … {:.3} µm, x = {:.3} … {:.3} µm",
                    um(from),
                    um(to),
                    um(span[0]),
                    um(span[1])
                ),
            ),
        };
        report.push(Violation {
            kind,
            value,
            at_um,
            place,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: i64, y0: i64, x1: i64, y1: i64) -> Vec<[i64; 2]> {
        vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    }

    fn check(polys: &[Vec<[i64; 2]>], tone: Tone, rule_um: f64) -> DrcReport {
        let mut g = DrawnGeometry::new();
        for p in polys {
            g.add(p).unwrap();
        }
        let rules = Rules {
            min_feature_um: rule_um,
            min_gap_um: rule_um,
            ..Rules::default()
        };
        g.check(tone, &rules, &Progress::new()).unwrap()
    }

    #[test]
    fn a_bar_has_its_width_and_two_bars_their_space() {
        // Two 1.5 × 10 µm bars 1 µm apart.
        let r = check(
            &[rect(0, 0, 1500, 10_000), rect(2500, 0, 4000, 10_000)],
            Tone::Open,
            2.0,
        );
        assert_eq!(r.min_feature_um, Some(1.5));
        assert_eq!(r.min_gap_um, Some(1.0));
        assert_eq!(r.counts, [2, 1, 0, 0]);
        // Drawn chrome: the same bars are chrome widths, the space between them an opening.
        let r = check(
            &[rect(0, 0, 1500, 10_000), rect(2500, 0, 4000, 10_000)],
            Tone::Chrome,
            2.0,
        );
        assert_eq!(r.min_feature_um, Some(1.0));
        assert_eq!(r.min_gap_um, Some(1.5));
    }

    #[test]
    fn overlapping_and_abutting_polygons_are_one_shape() {
        // A 4-µm square drawn as two abutting halves and an overlapping copy of the left half,
        // in both windings: no 2-µm width at the seam.
        let mut cw = rect(0, 0, 2000, 4000);
        cw.reverse();
        let r = check(
            &[rect(0, 0, 2000, 4000), rect(2000, 0, 4000, 4000), cw],
            Tone::Open,
            3.0,
        );
        assert_eq!(r.min_feature_um, Some(4.0));
        assert!(r.is_clean(), "{r:?}");
    }

    #[test]
    fn squares_meeting_at_a_corner_are_a_contact() {
        let r = check(
            &[rect(0, 0, 5000, 5000), rect(5000, 5000, 10_000, 10_000)],
            Tone::Open,
            2.0,
        );
        assert_eq!(r.corner_contacts, 1);
        assert_eq!(r.counts[ViolationKind::CornerContact as usize], 1);
        assert_eq!(r.violations[0].at_um, [5.0, 5.0]);
    }

    #[test]
    fn a_notch_is_a_space_and_its_sides_are_widths() {
        // A U: 10 µm wide, a 1-µm notch down the middle 6 µm deep.
        let u = vec![
            [0, 0],
            [10_000, 0],
            [10_000, 10_000],
            [5500, 10_000],
            [5500, 4000],
            [4500, 4000],
            [4500, 10_000],
            [0, 10_000],
        ];
        let r = check(&[u], Tone::Open, 2.0);
        assert_eq!(r.min_gap_um, Some(1.0));
        assert_eq!(r.counts[ViolationKind::MinGap as usize], 1);
        assert_eq!(r.min_feature_um, Some(4.0));
    }

    #[test]
    fn slanted_edges_are_refused() {
        let mut g = DrawnGeometry::new();
        assert!(matches!(
            g.add(&[[0, 0], [1000, 0], [0, 1000]]),
            Err(GeometryDrcError::NotManhattan { .. })
        ));
    }
}
