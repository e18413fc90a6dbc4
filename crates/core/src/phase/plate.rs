//! The fabricated plate's profile as pieces: the stretches between consecutive height jumps,
//! cut at the analytic level crossings of [`geometry::bands`], with no sliver at the array's
//! outer edges and no part-level ring narrower than the writer's rule. What every export draws
//! (GDSII and STL the pieces, CSV and PNG sampled on them) and what the plate's design-rule
//! check measures.
//!
//! **Part-level rings.** With floor rounding the fold height d0 is rarely a whole number of
//! steps: the top level J = [`geometry::top_level`] spans only `d0 − J·step` of sag, less than
//! a step, and far out on a lenslet, where the sag is steep, its ring is a sliver (34 nm at
//! r ≈ 15.8 µm for T = 5 at 0.2-µm steps and λ0 = 600 nm). Where that ring is narrower than the
//! writer's narrowest feature, the next fold's level 0 starts where it starts: the fold wraps
//! at `J·step` instead of d0 there. Against the continuous folded lens the phase error at λ0 of
//! such a ring stays under one step's (its height is off by at most `d0 − J·step`, as the
//! floored level's is), and [`ring_merge`] reports what it costs. Full-step rings are never
//! merged: one narrower than the rule is the lens's slope at that step, and the check refuses it.

use super::geometry::{self, Lenslets};
use super::{HeightRounding, PhaseDesign, Surface};
use crate::SimError;

/// Most flat or curved stretches between height jumps the profile may have (a design with a
/// tiny step or fold under wide lenslets has billions).
pub const MAX_PIECES: usize = 4_000_000;

/// How the height varies over one stretch between consecutive jumps.
#[derive(Debug, Clone, Copy)]
pub enum Shape {
    /// A quantised level: height `level × step`.
    Flat {
        /// Level index (0 = the plate's base).
        level: u64,
        /// Height of the level, µm.
        height_um: f64,
    },
    /// The sag about `centre_um`, less the folds below it (`offset_um`), at most `cap_um`.
    Curved {
        /// Centre of the lenslet, µm in the plate's frame.
        centre_um: f64,
        /// Height removed by the folds below, µm.
        offset_um: f64,
        /// Largest height on the piece, µm.
        cap_um: f64,
    },
}

/// One stretch of the profile between consecutive height jumps (or lenslet edges).
#[derive(Debug, Clone, Copy)]
pub struct Piece {
    /// Left end, µm in the plate's frame (array centred on x = 0).
    pub x0_um: f64,
    /// Right end, µm in the plate's frame.
    pub x1_um: f64,
    /// How the height varies between the ends.
    pub shape: Shape,
}

impl Piece {
    /// The height on this piece, continued to its ends (a jump's two sides are two pieces).
    pub fn height_um(&self, design: &PhaseDesign, x_um: f64) -> f64 {
        match self.shape {
            Shape::Flat { height_um, .. } => height_um,
            Shape::Curved {
                centre_um,
                offset_um,
                cap_um,
            } => (geometry::sag_um(design, x_um - centre_um) - offset_um).clamp(0.0, cap_um),
        }
    }
}

/// The profile cut at every height jump, left to right.
///
/// The jumps are the analytic crossings of [`geometry::bands`]: in integer level indices, a
/// floored level j of wrap w ends where the sag reaches `w·d0 + (j+1)·step` and a wrap where it
/// reaches `(w+1)·d0` (d0 the unrounded fold height); rounding to the nearest level jumps at
/// `(K + ½)·step`. The radius is `sqrt(2(n−1)f·sag)`, so every level's ring has exactly the
/// model's width, and each piece's level is the integer index of its ring, not a sampled height.
/// Part-level rings narrower than `min_feature_um` (the writer's rule; 0 keeps every ring) join
/// the next fold (see the module docs).
pub fn pieces(
    design: &PhaseDesign,
    lenslets: &Lenslets,
    min_feature_um: f64,
) -> Result<Vec<Piece>, SimError> {
    let pitch = lenslets.pitch_um;
    let count = lenslets.count();
    let half = pitch / 2.0;
    let edge_sag = geometry::sag_um(design, half);
    if !(geometry::sag_um(design, 1.0) > 0.0 && edge_sag.is_finite()) {
        return Err(SimError::invalid(
            "f_mla_um",
            format!("the lens sag {edge_sag:?} µm at the lenslet edge cannot be cut into levels"),
        ));
    }
    let estimate: f64 = lenslets
        .fold_height_um
        .iter()
        .map(|&f| 2.0 * geometry::band_count_bound(design, f, half) + 1.0)
        .sum();
    if !(estimate <= MAX_PIECES as f64) {
        let cause = match design.height_step_um {
            Some(step) => format!("height_step_um = {step} µm"),
            None => "the fold height".into(),
        };
        return Err(SimError::TooLarge(format!(
            "the profile would have about {estimate:.0} separate levels or folds ({cause} under \
             {edge_sag:.1} µm of lens sag), more than {MAX_PIECES}; use a coarser step"
        )));
    }
    let mut out = Vec::with_capacity(estimate as usize);
    let mut cached: Option<(f64, Vec<geometry::Band>)> = None;
    for (l, &fold_um) in lenslets.fold_height_um.iter().enumerate() {
        let c = lenslets.centre_um(l);
        // Edges from one formula, so neighbouring lenslets share them bit for bit.
        let left = (l as f64 - count as f64 / 2.0) * pitch;
        let right = (l as f64 + 1.0 - count as f64 / 2.0) * pitch;
        let bands = match &cached {
            Some((f, b)) if *f == fold_um => b,
            _ => {
                let bands = geometry::bands(design, fold_um, half);
                let (bands, _) = merge_part_rings(design, fold_um, bands, min_feature_um);
                &cached.insert((fold_um, bands)).1
            }
        };
        let shape = |b: &geometry::Band| match (b.level, design.height_step_um) {
            (Some(level), Some(step)) => Shape::Flat {
                level,
                height_um: level as f64 * step,
            },
            _ => Shape::Curved {
                centre_um: c,
                offset_um: b.wraps as f64 * fold_um,
                cap_um: match design.surface {
                    Surface::Folded => fold_um,
                    Surface::Unfolded => f64::INFINITY,
                },
            },
        };
        // Left half outside in, the central ring across the centre, right half inside out.
        let last = bands.len() - 1;
        let mut spans: Vec<(f64, f64, &geometry::Band)> = Vec::with_capacity(2 * bands.len());
        for (k, b) in bands.iter().enumerate().skip(1).rev() {
            let x0 = if k == last { left } else { c - b.u1_um };
            spans.push((x0, c - b.u0_um, b));
        }
        let (x0, x1) = if last == 0 {
            (left, right)
        } else {
            (c - bands[0].u1_um, c + bands[0].u1_um)
        };
        spans.push((x0, x1, &bands[0]));
        for (k, b) in bands.iter().enumerate().skip(1) {
            let x1 = if k == last { right } else { c + b.u1_um };
            spans.push((c + b.u0_um, x1, b));
        }
        for (x0, x1, b) in spans {
            // Rounding could put a crossing on or past an edge; such a piece has no width.
            let (x0, x1) = (x0.max(left), x1.min(right));
            if x1 > x0 {
                out.push(Piece {
                    x0_um: x0,
                    x1_um: x1,
                    shape: shape(b),
                });
            }
        }
    }
    merge_edge_slivers(design, &mut out, pitch);
    Ok(out)
}

/// `bands` of one lenslet (fold height `fold_um`) with each part-level ring narrower than
/// `min_feature_um` joined to the next fold's level 0 (see the module docs), and how many were.
/// Only a floored, folded, stepped plate whose fold is not a whole number of steps has them;
/// the last ring, cut by the lenslet's edge, stays.
fn merge_part_rings(
    design: &PhaseDesign,
    fold_um: f64,
    bands: Vec<geometry::Band>,
    min_feature_um: f64,
) -> (Vec<geometry::Band>, usize) {
    let Some(step) = design.height_step_um else {
        return (bands, 0);
    };
    let top = geometry::top_level(fold_um, step);
    let part = fold_um - top as f64 * step < step * (1.0 - 1e-9);
    if !(min_feature_um > 0.0
        && part
        && top > 0
        && design.surface == Surface::Folded
        && design.height_rounding == HeightRounding::Floor)
    {
        return (bands, 0);
    }
    let mut out = Vec::with_capacity(bands.len());
    let mut merged = 0;
    let mut iter = bands.into_iter().peekable();
    while let Some(b) = iter.next() {
        match iter.peek_mut() {
            Some(next) if b.level == Some(top) && b.u1_um - b.u0_um < min_feature_um => {
                next.u0_um = b.u0_um;
                merged += 1;
            }
            _ => out.push(b),
        }
    }
    (out, merged)
}

/// What joining part-level rings costs ([`ring_merge`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RingMerge {
    /// Part-level rings joined to the next fold, over the whole array (each side of a
    /// lenslet's centre counted).
    pub merged_rings: usize,
    /// RMS phase error at each lenslet's λ0 of the quantised model against the continuous
    /// folded lens, radians, over the array's width.
    pub model_rms_phase_error_rad: f64,
    /// The same for the fabricated plate, with the rings joined.
    pub fabricated_rms_phase_error_rad: f64,
}

/// Samples per lenslet of [`ring_merge`]'s phase error.
const MERGE_ERROR_SAMPLES: usize = 4096;

/// How many part-level rings the plate of `design` joins to the next fold under a writer's
/// `min_feature_um`, and the phase error at λ0 before and after (see the module docs). A fold
/// of T waves at λ0 is `fold_um` of height, so a height error `e` is `2π T e / fold` radians,
/// wrapped to ±π.
///
/// # Errors
/// As [`Lenslets::new`].
pub fn ring_merge(
    design: &PhaseDesign,
    lenslets: &Lenslets,
    min_feature_um: f64,
) -> Result<RingMerge, SimError> {
    let half = lenslets.pitch_um / 2.0;
    let (mut merged, mut model_sq, mut fab_sq, mut n) = (0usize, 0.0, 0.0, 0usize);
    let mut cached: Option<(f64, usize, f64, f64)> = None;
    for &fold_um in &lenslets.fold_height_um {
        let (m, a, b) = match cached {
            Some((f, m, a, b)) if f == fold_um => (m, a, b),
            _ => {
                let model = geometry::bands(design, fold_um, half);
                let (fab, m) = merge_part_rings(design, fold_um, model.clone(), min_feature_um);
                let a = band_error_sq(design, fold_um, &model, half);
                let b = band_error_sq(design, fold_um, &fab, half);
                cached = Some((fold_um, m, a, b));
                (m, a, b)
            }
        };
        merged += 2 * m;
        model_sq += a;
        fab_sq += b;
        n += MERGE_ERROR_SAMPLES;
    }
    let rms = |sq: f64| if n == 0 { 0.0 } else { (sq / n as f64).sqrt() };
    Ok(RingMerge {
        merged_rings: merged,
        model_rms_phase_error_rad: rms(model_sq),
        fabricated_rms_phase_error_rad: rms(fab_sq),
    })
}

/// The summed squared phase error of one lenslet's `bands` against the continuous folded lens
/// over [`MERGE_ERROR_SAMPLES`] samples across `[−half, half)` (the profile is even in u).
fn band_error_sq(design: &PhaseDesign, fold_um: f64, bands: &[geometry::Band], half: f64) -> f64 {
    let step = design.height_step_um.unwrap_or(0.0);
    let waves_per_um = design.fold / fold_um;
    (0..MERGE_ERROR_SAMPLES)
        .map(|i| {
            let u = ((i as f64 + 0.5) / MERGE_ERROR_SAMPLES as f64 - 0.5) * 2.0 * half;
            let r = u.abs();
            let k = bands.partition_point(|b| b.u1_um <= r).min(bands.len() - 1);
            let sag = geometry::sag_um(design, r);
            let height = match bands[k].level {
                Some(level) => level as f64 * step,
                None => sag - bands[k].wraps as f64 * fold_um,
            };
            let waves = (height - sag) * waves_per_um;
            let wrapped = waves - waves.round();
            (std::f64::consts::TAU * wrapped).powi(2)
        })
        .sum()
}

/// A height difference below this (µm) is no jump: the surface runs on.
const CONTINUOUS_UM: f64 = 1e-9;

/// At the plate's two outer edges the array's outermost lenslet is cut wherever its last ring
/// happens to be: that part-ring can be a sliver far narrower than any feature inside (76 nm
/// against 152 nm for a 600-DPI plate at 0.2-µm steps), which no writer can make. A part-ring
/// narrower than the ring inside it is drawn as that ring, continued to the edge (a level stays
/// flat; a curved ring rises until it meets the fold height, where it is capped), so the edge
/// feature is always wider than the ring next to it. The simulations keep the thesis's profile;
/// the difference is the width of that part-ring at each outer edge.
fn merge_edge_slivers(design: &PhaseDesign, out: &mut Vec<Piece>, pitch_um: f64) {
    let jump = |a: &Piece, b: &Piece| {
        (a.height_um(design, a.x1_um) - b.height_um(design, b.x0_um)).abs() >= CONTINUOUS_UM
    };
    let width = |p: &Piece| p.x1_um - p.x0_um;
    if let [edge, inner, ..] = out.as_slice()
        && inner.x1_um <= edge.x0_um + pitch_um
        && width(edge) < width(inner)
        && jump(edge, inner)
    {
        let x0 = edge.x0_um;
        out.remove(0);
        out[0].x0_um = x0;
    }
    if let [.., inner, edge] = out.as_slice()
        && inner.x0_um >= edge.x1_um - pitch_um
        && width(edge) < width(inner)
        && jump(inner, edge)
    {
        let x1 = edge.x1_um;
        out.pop();
        if let Some(last) = out.last_mut() {
            last.x1_um = x1;
        }
    }
}

/// The plate as it is fabricated (what every export writes), sampled at `x_um` (µm, the
/// plate's frame; 0 outside the array): the model's profile
/// ([`geometry::profile_um`]) but for the part-rings at the two outer edges that
/// [`pieces`] draws as the ring inside them.
///
/// # Errors
/// As [`pieces`].
pub fn profile_um(
    design: &PhaseDesign,
    x_um: &[f64],
    min_feature_um: f64,
) -> Result<Vec<f64>, SimError> {
    let lenslets = Lenslets::new(design)?;
    let pieces = pieces(design, &lenslets, min_feature_um)?;
    Ok(x_um
        .iter()
        .map(|&x| height_on(design, &pieces, x))
        .collect())
}

/// The height of `pieces` (left to right, as [`pieces`] returns them) at `x_um`; a point on a
/// jump belongs to the piece on its right, as [`Lenslets::locate`] gives an edge to the
/// lenslet on its right.
pub fn height_on(design: &PhaseDesign, pieces: &[Piece], x_um: f64) -> f64 {
    let k = pieces.partition_point(|p| p.x1_um <= x_um);
    match pieces.get(k) {
        Some(p) if p.x0_um <= x_um => p.height_um(design, x_um),
        _ => 0.0,
    }
}

/// One feature a writer makes: a stretch of the plate between two height jumps. The pieces
/// are cut at lenslet edges too; where the height runs on across an edge without a jump, the
/// two pieces are one feature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Feature {
    /// Left end, µm in the plate's frame.
    pub x0_um: f64,
    /// Right end, µm in the plate's frame.
    pub x1_um: f64,
}

impl Feature {
    /// Its width, µm.
    pub fn width_um(&self) -> f64 {
        self.x1_um - self.x0_um
    }
}

/// `pieces` joined where the height has no jump between them, left to right.
pub fn features(design: &PhaseDesign, pieces: &[Piece]) -> Vec<Feature> {
    let mut out: Vec<Feature> = Vec::with_capacity(pieces.len());
    let mut last: Option<&Piece> = None;
    for p in pieces.iter().filter(|p| p.x1_um > p.x0_um) {
        let runs_on = last.is_some_and(|q| {
            (q.x1_um - p.x0_um).abs() < 1e-9
                && (q.height_um(design, p.x0_um) - p.height_um(design, p.x0_um)).abs()
                    < CONTINUOUS_UM
        });
        match out.last_mut() {
            Some(f) if runs_on => f.x1_um = p.x1_um,
            _ => out.push(Feature {
                x0_um: p.x0_um,
                x1_um: p.x1_um,
            }),
        }
        last = Some(p);
    }
    out
}

/// The narrowest feature of the plate of `design`: the smallest a fab must write (the fold
/// rings narrow towards each lenslet's edge, as `1/u`).
///
/// # Errors
/// As [`pieces`].
pub fn narrowest_feature(
    design: &PhaseDesign,
    lenslets: &Lenslets,
    min_feature_um: f64,
) -> Result<Option<Feature>, SimError> {
    Ok(features(design, &pieces(design, lenslets, min_feature_um)?)
        .into_iter()
        .min_by(|a, b| a.width_um().total_cmp(&b.width_um())))
}
