//! The design-rule check of a display mask: the smallest opening and the smallest chrome gap
//! anywhere on the tiled display, cells that touch only at a corner, and acute angles of drawn
//! polygons, against a fab's rules.
//!
//! **Where it looks.** Features cross tile boundaries, so every line of cells is checked across
//! every pair of neighbouring tiles the tiling can produce: for a periodic tiling the tile beside
//! itself, for a random one every ordered pair of orientations of its orbit (the wiring gap, if
//! any, sits between them as chrome). A run of open (or closed) cells that reaches the end of
//! such a pair is longer than a tile and is not a minimum. Corner contacts are checked inside a
//! tile, across each edge and where four tiles meet (every combination of orientations).
//!
//! Cells are binary at [`super::OPEN_THRESHOLD`], as on the mask.

use super::OPEN_THRESHOLD;
use crate::design::Design;
use crate::display::aperture::effective_cells;
use crate::display::tiling::{D4, orbit};

/// A fab's rules (µm). A rule of 0 is not checked.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rules {
    /// Smallest opening (clear feature) width, µm.
    pub min_feature_um: f64,
    /// Smallest chrome gap between two openings, µm.
    pub min_gap_um: f64,
    /// Openings that touch only at a corner (a zero-width neck) are violations.
    pub no_corner_contact: bool,
    /// Smallest interior angle of a drawn polygon, degrees (90 flags acute angles).
    pub min_angle_deg: f64,
    /// Narrowest ring or height step of a phase plate, µm. Its own rule because a plate goes to
    /// a grey-scale writer, not to the chrome-mask process `min_feature_um` describes; optional
    /// in a rules file so older files still read.
    #[serde(default = "default_phase_min_feature_um")]
    pub phase_min_feature_um: f64,
}

/// A laser writer's half micron, µm: the thesis plate's outer fold rings (under 200 nm) break
/// it. The default of [`Rules::phase_min_feature_um`].
pub const DEFAULT_PHASE_MIN_FEATURE_UM: f64 = 0.5;

fn default_phase_min_feature_um() -> f64 {
    DEFAULT_PHASE_MIN_FEATURE_UM
}

impl Default for Rules {
    /// A contact-lithography chrome mask: 2 µm features and gaps, no corner contacts, no
    /// acute angles.
    fn default() -> Self {
        Rules {
            min_feature_um: 2.0,
            min_gap_um: 2.0,
            no_corner_contact: true,
            min_angle_deg: 90.0,
            phase_min_feature_um: default_phase_min_feature_um(),
        }
    }
}

/// What a violation breaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ViolationKind {
    /// An opening narrower than [`Rules::min_feature_um`] (or a phase plate's ring or step
    /// narrower than [`Rules::phase_min_feature_um`]).
    MinFeature,
    /// A chrome gap narrower than [`Rules::min_gap_um`].
    MinGap,
    /// Two openings that meet at a corner only.
    CornerContact,
    /// A polygon angle sharper than [`Rules::min_angle_deg`].
    AcuteAngle,
}

/// One violation, located in the tile frame (µm from the tile's top-left corner, y down).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Violation {
    /// The rule broken.
    pub kind: ViolationKind,
    /// The width (or angle, in degrees) found.
    pub value: f64,
    /// Where, µm in the tile frame.
    pub at_um: [f64; 2],
    /// Where, in words ("row 3, columns 7-8, across the right edge").
    pub place: String,
}

/// The check's result.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DrcReport {
    /// The rules checked.
    pub rules: Rules,
    /// Smallest opening width anywhere, µm (`None`: no bounded opening); for a phase plate,
    /// its narrowest ring or height step.
    pub min_feature_um: Option<f64>,
    /// Smallest chrome gap anywhere, µm (`None`: no bounded gap).
    pub min_gap_um: Option<f64>,
    /// Places where openings meet at a corner only.
    pub corner_contacts: usize,
    /// Every violation, the first [`MAX_LISTED`] of each kind (the counts are complete).
    pub violations: Vec<Violation>,
    /// How many violations of each kind there are, in [`ViolationKind`] order.
    pub counts: [usize; 4],
}

/// Violations listed per kind (the rest are counted).
pub const MAX_LISTED: usize = 50;

impl DrcReport {
    /// A report with nothing found yet.
    pub fn new(rules: Rules) -> Self {
        DrcReport {
            rules,
            min_feature_um: None,
            min_gap_um: None,
            corner_contacts: 0,
            violations: Vec::new(),
            counts: [0; 4],
        }
    }

    /// How many violations there are in all.
    pub fn total(&self) -> usize {
        self.counts.iter().sum()
    }

    /// True when nothing breaks a rule.
    pub fn is_clean(&self) -> bool {
        self.counts.iter().all(|c| *c == 0)
    }

    /// Records `v` (listed while its kind has fewer than [`MAX_LISTED`]).
    pub fn push(&mut self, v: Violation) {
        let k = v.kind as usize;
        self.counts[k] += 1;
        if self.counts[k] <= MAX_LISTED {
            self.violations.push(v);
        }
    }
}

/// One stretch of a line of cells: open or not, its length and where it starts.
#[derive(Debug, Clone, Copy)]
struct Stretch {
    open: bool,
    length_um: f64,
    start_um: f64,
}

/// Checks `design`'s mask against `rules`.
pub fn check(design: &Design, rules: &Rules) -> DrcReport {
    let cells = effective_cells(&design.opening);
    let n = cells.len();
    let cell_um = design.opening.cell_um();
    let gap_um = design.tiling.wiring_gap_um.max(0.0);
    let open: Vec<Vec<bool>> = cells
        .iter()
        .map(|r| r.iter().map(|v| *v >= OPEN_THRESHOLD).collect())
        .collect();
    let tiles: Vec<(D4, Vec<Vec<bool>>)> = orbit(design.tiling.mode)
        .into_iter()
        .map(|g| (g, g.apply(&open)))
        .collect();
    let mut report = DrcReport::new(*rules);
    if n == 0 {
        return report;
    }
    // Lines across every ordered pair of neighbouring tiles, both directions.
    for (_, a) in &tiles {
        for (k, (_, b)) in tiles.iter().enumerate() {
            // A stretch inside `a` is the same beside every `b`: counted beside the first.
            let first_partner = k == 0;
            for i in 0..n {
                let across = |t: &Vec<Vec<bool>>, j: usize| t[i][j];
                let down = |t: &Vec<Vec<bool>>, j: usize| t[j][i];
                let row = line((0..n).map(|j| across(a, j)), (0..n).map(|j| across(b, j)));
                let col = line((0..n).map(|j| down(a, j)), (0..n).map(|j| down(b, j)));
                let stretch = |s: &[bool]| stretches(s, cell_um, gap_um, n);
                for (line, horizontal) in [(stretch(&row), true), (stretch(&col), false)] {
                    let at = Line {
                        horizontal,
                        index: i,
                        first_partner,
                    };
                    judge(&line, at, cell_um, n, rules, &mut report);
                }
            }
        }
    }
    if gap_um == 0.0 {
        corner_contacts(&tiles, n, cell_um, rules, &mut report);
    } else if let Some((_, t)) = tiles.first() {
        // The gap separates tiles: contacts can only be inside one (every orientation has the
        // same ones, turned, so the tile as drawn counts them).
        contacts_in(t, n, cell_um, rules, &mut report);
    }
    for p in &design.opening.polygons {
        acute_angles(&p.vertices_um, rules, &mut report);
    }
    report
}

/// The cells of two neighbouring tiles along one line, `a` then `b`.
fn line(a: impl Iterator<Item = bool>, b: impl Iterator<Item = bool>) -> Vec<bool> {
    a.chain(b).collect()
}

/// The stretches of a two-tile line of `2n` cells, the wiring gap (chrome) between the tiles.
fn stretches(cells: &[bool], cell_um: f64, gap_um: f64, n: usize) -> Vec<Stretch> {
    let mut out: Vec<Stretch> = Vec::new();
    let mut pos = 0.0;
    let mut add = |open: bool, length_um: f64, pos: &mut f64| {
        match out.last_mut() {
            Some(s) if s.open == open => s.length_um += length_um,
            _ => out.push(Stretch {
                open,
                length_um,
                start_um: *pos,
            }),
        }
        *pos += length_um;
    };
    for (j, o) in cells.iter().enumerate() {
        if j == n && gap_um > 0.0 {
            add(false, gap_um, &mut pos);
        }
        add(*o, cell_um, &mut pos);
    }
    out
}

/// Which line of a tile pair is judged.
#[derive(Debug, Clone, Copy)]
struct Line {
    /// Along a row (else down a column).
    horizontal: bool,
    /// The row or column.
    index: usize,
    /// The pair's second tile is the first of the orbit.
    first_partner: bool,
}

/// Records the bounded stretches of one line (the first and last run on into other tiles).
fn judge(
    line: &[Stretch],
    at: Line,
    cell_um: f64,
    n: usize,
    rules: &Rules,
    report: &mut DrcReport,
) {
    let Line {
        horizontal,
        index,
        first_partner,
    } = at;
    let tile_um = n as f64 * cell_um;
    for s in line.iter().skip(1).take(line.len().saturating_sub(2)) {
        // Counted from the tile it starts in, or, when it starts right at the seam (bounded on
        // the left by the first tile's last cell), from this pair. A stretch inside the first
        // tile is the same beside every partner: counted beside the first one only.
        let at_seam = (s.start_um - tile_um).abs() < 1e-9;
        let crosses = s.start_um + s.length_um > tile_um + 1e-9;
        if (s.start_um >= tile_um && !at_seam) || (!crosses && !at_seam && !first_partner) {
            continue;
        }
        let (best, rule, kind) = if s.open {
            (
                &mut report.min_feature_um,
                rules.min_feature_um,
                ViolationKind::MinFeature,
            )
        } else {
            (
                &mut report.min_gap_um,
                rules.min_gap_um,
                ViolationKind::MinGap,
            )
        };
        *best = Some(best.map_or(s.length_um, |b: f64| b.min(s.length_um)));
        if s.length_um < rule - 1e-9 {
            let along = s.start_um;
            let across = (index as f64 + 0.5) * cell_um;
            let (at_um, place) = if horizontal {
                (
                    [along, across],
                    format!(
                        "row {index}, from x = {along:.2} µm{}",
                        if crosses {
                            ", across the right edge"
                        } else {
                            ""
                        }
                    ),
                )
            } else {
                (
                    [across, along],
                    format!(
                        "column {index}, from y = {along:.2} µm{}",
                        if crosses {
                            ", across the bottom edge"
                        } else {
                            ""
                        }
                    ),
                )
            };
            report.push(Violation {
                kind,
                value: s.length_um,
                at_um,
                place,
            });
        }
    }
}

/// `[[a, b], [c, d]]` touches at a corner only: one diagonal open, the other closed.
fn is_contact(a: bool, b: bool, c: bool, d: bool) -> bool {
    (a && d && !b && !c) || (b && c && !a && !d)
}

fn record_contact(report: &mut DrcReport, rules: &Rules, at_um: [f64; 2], place: String) {
    report.corner_contacts += 1;
    if rules.no_corner_contact {
        report.push(Violation {
            kind: ViolationKind::CornerContact,
            value: 0.0,
            at_um,
            place,
        });
    }
}

/// Corner contacts inside one tile.
fn contacts_in(t: &[Vec<bool>], n: usize, cell_um: f64, rules: &Rules, report: &mut DrcReport) {
    for r in 0..n.saturating_sub(1) {
        for c in 0..n.saturating_sub(1) {
            if is_contact(t[r][c], t[r][c + 1], t[r + 1][c], t[r + 1][c + 1]) {
                let at = [(c + 1) as f64 * cell_um, (r + 1) as f64 * cell_um];
                record_contact(
                    report,
                    rules,
                    at,
                    format!("between rows {r}-{} and columns {c}-{}", r + 1, c + 1),
                );
            }
        }
    }
}

/// Corner contacts inside tiles, across their edges and where four tiles meet.
fn corner_contacts(
    tiles: &[(D4, Vec<Vec<bool>>)],
    n: usize,
    cell_um: f64,
    rules: &Rules,
    report: &mut DrcReport,
) {
    let edge = n as f64 * cell_um;
    // Every orientation holds the same contacts, turned: the tile as drawn counts them.
    if let Some((_, t)) = tiles.first() {
        contacts_in(t, n, cell_um, rules, report);
    }
    for (_, a) in tiles {
        for (_, b) in tiles {
            for i in 0..n.saturating_sub(1) {
                // a left of b, rows i and i+1.
                if is_contact(a[i][n - 1], b[i][0], a[i + 1][n - 1], b[i + 1][0]) {
                    let at = [edge, (i + 1) as f64 * cell_um];
                    record_contact(
                        report,
                        rules,
                        at,
                        format!("rows {i}-{} across the right edge", i + 1),
                    );
                }
                // a above b, columns i and i+1.
                if is_contact(a[n - 1][i], a[n - 1][i + 1], b[0][i], b[0][i + 1]) {
                    let at = [(i + 1) as f64 * cell_um, edge];
                    record_contact(
                        report,
                        rules,
                        at,
                        format!("columns {i}-{} across the bottom edge", i + 1),
                    );
                }
            }
        }
    }
    // Where four tiles meet: top-left a, top-right b, bottom-left c, bottom-right d.
    for (_, a) in tiles {
        for (_, b) in tiles {
            for (_, c) in tiles {
                for (_, d) in tiles {
                    if is_contact(a[n - 1][n - 1], b[n - 1][0], c[0][n - 1], d[0][0]) {
                        record_contact(report, rules, [edge, edge], "where four tiles meet".into());
                    }
                }
            }
        }
    }
}

/// Interior angles of a closed polygon below the rule.
fn acute_angles(vertices: &[[f64; 2]], rules: &Rules, report: &mut DrcReport) {
    let k = vertices.len();
    if k < 3 || rules.min_angle_deg <= 0.0 {
        return;
    }
    // The signed area tells the winding, so interior angles come out right for both.
    let area2: f64 = (0..k)
        .map(|i| {
            let (p, q) = (vertices[i], vertices[(i + 1) % k]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum();
    for i in 0..k {
        let (p, v, q) = (
            vertices[(i + k - 1) % k],
            vertices[i],
            vertices[(i + 1) % k],
        );
        let (a, b) = ([p[0] - v[0], p[1] - v[1]], [q[0] - v[0], q[1] - v[1]]);
        let cross = a[0] * b[1] - a[1] * b[0];
        let dot = a[0] * b[0] + a[1] * b[1];
        let mut angle = cross.atan2(dot).to_degrees();
        if area2 > 0.0 {
            angle = -angle;
        }
        let interior = angle.rem_euclid(360.0);
        if interior > 1e-9 && interior < rules.min_angle_deg - 1e-6 {
            report.push(Violation {
                kind: ViolationKind::AcuteAngle,
                value: interior,
                at_um: v,
                place: format!("polygon vertex {i}"),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::{Polygon, TilingMode};

    fn design(rows: &[&str], pitch_um: f64, mode: TilingMode, gap_um: f64) -> Design {
        let mut d = Design::default_toled();
        d.opening.pitch_um = pitch_um;
        d.opening.cells = rows
            .iter()
            .map(|r| r.chars().map(|c| f64::from(c == '#')).collect())
            .collect();
        d.tiling.mode = mode;
        d.tiling.wiring_gap_um = gap_um;
        d
    }

    #[test]
    fn a_slit_has_its_width_and_the_chrome_between_slits() {
        // 2 open of 6 cells of 1 µm, repeated: features 2 µm, gaps 4 µm across the edge.
        let d = design(
            &["..##..", "..##..", "..##..", "..##..", "..##..", "..##.."],
            6.0,
            TilingMode::Repeat,
            0.0,
        );
        let r = check(&d, &Rules::default());
        assert_eq!(r.min_feature_um, Some(2.0));
        assert_eq!(r.min_gap_um, Some(4.0));
        assert!(r.is_clean(), "{r:?}");
        // A wiring gap adds its chrome to the gap across the side edge (2 + 3 + 2 µm), and cuts
        // the full-height slit at the top edge: a 3-µm gap between a slit and the next one up.
        let r = check(
            &design(
                &["..##..", "..##..", "..##..", "..##..", "..##..", "..##.."],
                6.0,
                TilingMode::Repeat,
                3.0,
            ),
            &Rules::default(),
        );
        assert_eq!(r.min_gap_um, Some(3.0));
        let sideways = r
            .violations
            .iter()
            .chain(
                check(
                    &design(
                        &["..##..", "..##..", "..##..", "..##..", "..##..", "..##.."],
                        6.0,
                        TilingMode::Repeat,
                        3.0,
                    ),
                    &Rules {
                        min_gap_um: 7.5,
                        ..Rules::default()
                    },
                )
                .violations
                .iter(),
            )
            .filter(|v| v.kind == ViolationKind::MinGap && (v.value - 7.0).abs() < 1e-9)
            .count();
        assert_eq!(sideways, 6, "every row's 7-µm gap across the side edge");
        // Rules above the widths flag every row once.
        let strict = Rules {
            min_feature_um: 3.0,
            min_gap_um: 5.0,
            ..Rules::default()
        };
        let r = check(&d, &strict);
        assert_eq!(r.counts[ViolationKind::MinFeature as usize], 6);
        assert_eq!(r.counts[ViolationKind::MinGap as usize], 6);
    }

    #[test]
    fn corner_contacts_are_found_inside_and_across_tiles() {
        let inside = design(
            &["#...", ".#..", "....", "...."],
            4.0,
            TilingMode::Repeat,
            0.0,
        );
        assert_eq!(check(&inside, &Rules::default()).corner_contacts, 1);
        // The corner cell touches its own copy where four tiles meet.
        let across = design(
            &["#...", "....", "....", "...#"],
            4.0,
            TilingMode::Repeat,
            0.0,
        );
        let r = check(&across, &Rules::default());
        assert!(r.corner_contacts >= 1 && !r.is_clean(), "{r:?}");
        // A wiring gap separates the tiles.
        let apart = design(
            &["#...", "....", "....", "...#"],
            4.0,
            TilingMode::Repeat,
            1.0,
        );
        assert_eq!(check(&apart, &Rules::default()).corner_contacts, 0);
        // Allowed when the rule says so.
        let lenient = Rules {
            no_corner_contact: false,
            min_feature_um: 1.0,
            min_gap_um: 1.0,
            ..Rules::default()
        };
        assert!(check(&inside, &lenient).is_clean());
    }

    #[test]
    fn a_random_tiling_is_checked_for_every_neighbour_pair() {
        // One open cell in a corner: a periodic tiling keeps it apart from its copies; flipped
        // copies bring two corners together, diagonally where four tiles meet.
        let d = design(&["#..", "...", "..."], 3.0, TilingMode::Repeat, 0.0);
        let periodic = check(&d, &Rules::default());
        let random = check(
            &design(&["#..", "...", "..."], 3.0, TilingMode::RandomD4, 0.0),
            &Rules::default(),
        );
        assert_eq!(periodic.min_feature_um, Some(1.0));
        assert_eq!(random.min_feature_um, Some(1.0));
        // Random: a flip puts an open cell right after the edge of another: features of 2.
        assert!(random.corner_contacts > periodic.corner_contacts);
    }

    #[test]
    fn acute_polygon_angles_are_flagged() {
        let mut d = design(&["...", "...", "..."], 30.0, TilingMode::Repeat, 0.0);
        d.opening.polygons = vec![Polygon {
            vertices_um: vec![[0.0, 0.0], [10.0, 0.0], [0.0, 3.0]],
        }];
        let r = check(&d, &Rules::default());
        assert_eq!(r.counts[ViolationKind::AcuteAngle as usize], 2, "{r:?}");
        d.opening.polygons = vec![Polygon {
            vertices_um: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
        }];
        assert_eq!(
            check(&d, &Rules::default()).counts[ViolationKind::AcuteAngle as usize],
            0
        );
    }
}
