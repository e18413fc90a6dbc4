//! Lenslet layout and height profiles (conventions.md §7, eq. 4.8).

use serde::{Deserialize, Serialize};

use super::{
    DISPLAY_APERTURE_HALF_ANGLE_DEG, GRID_LEN, HeightRounding, Lambda0, PhaseDesign, SimError,
    wavelength_grid_nm,
};

/// The plate as folded (eq. 4.8) or the thick lens it comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Surface {
    /// The folded plate: heights wrap every fold height `T λ0 / (n − 1)` (the design).
    #[default]
    Folded,
    /// The unfolded thick lens with the same focal length (the reference).
    Unfolded,
}

/// Display aperture in µm: the main-lens opening widened by `2 z tan 50°` (z = f_MLA).
pub fn display_aperture_um(d: &PhaseDesign) -> f64 {
    d.camera.aperture_um() + 2.0 * d.f_mla_um * DISPLAY_APERTURE_HALF_ANGLE_DEG.to_radians().tan()
}

/// Lenslets per array: `ceil(display aperture / pitch)` (58/45/31/17 for 42/56/84/168 µm).
pub fn lenslet_count(d: &PhaseDesign) -> usize {
    let n = display_aperture_um(d) / d.pitch_um;
    if n.is_finite() && n > 0.0 {
        // A ratio that is an integer up to rounding must not gain a lenslet.
        (n - 1e-9).ceil().max(1.0) as usize
    } else {
        1
    }
}

/// Sag of the thick lens at distance `u_um` from a lenslet's centre: `u² / (2 (n−1) f)`.
pub fn sag_um(d: &PhaseDesign, u_um: f64) -> f64 {
    u_um * u_um / (2.0 * (d.refractive_index - 1.0) * d.f_mla_um)
}

/// Fold height in µm: the sag at which a lenslet wraps back to 0.
///
/// It is `d0 = T λ0 / (n − 1)` itself, unless the design rounds to the nearest step
/// ([`HeightRounding::Nearest`] with a `height_step_um`): then `d0` is rounded to the step (at
/// least one step), as before the floor rule. With [`HeightRounding::Floor`] the wrap stays at the
/// unrounded `d0` and the tallest level is [`top_level`]`(d0, step) · step`, below `d0`.
pub fn fold_height_um(d: &PhaseDesign, lambda0_nm: f64) -> f64 {
    let h = d.fold * lambda0_nm * 1e-3 / (d.refractive_index - 1.0);
    match (d.height_step_um, d.height_rounding) {
        (Some(step), HeightRounding::Nearest) => (h / step).round().max(1.0) * step,
        _ => h,
    }
}

/// The highest level index of a floored plate within one fold: the largest `j` with
/// `j · step < fold_um`, i.e. `floor(fold/step)` unless the fold is a whole number of steps (then
/// the level at `fold` would have no width: the sag reaches it exactly where the next wrap starts).
/// A ratio within 1e-9 of a whole number counts as whole, so no sliver level appears from binary
/// noise.
pub fn top_level(fold_um: f64, step_um: f64) -> u64 {
    let ratio = fold_um / step_um;
    let levels = (ratio * (1.0 - 1e-9)).ceil();
    if levels.is_finite() && levels >= 1.0 {
        levels as u64 - 1
    } else {
        0
    }
}

/// Levels per fold of a plate rounded to the nearest step: `round(fold/step)`, at least 1 (the
/// fold of [`fold_height_um`] is that many steps; level `m` wraps to 0).
fn nearest_levels_per_fold(fold_um: f64, step_um: f64) -> u64 {
    let m = (fold_um / step_um).round();
    if m.is_finite() && m >= 1.0 {
        m as u64
    } else {
        1
    }
}

/// The quantised level index of a lenslet's surface at `u_um` from its centre (height =
/// level × `height_step_um`), or `None` when the design has no step. `fold_um` is the lenslet's
/// [`fold_height_um`].
///
/// - Floor, folded: `j = floor(mod(sag, d0) / step)`, at most [`top_level`]`(d0, step)`.
/// - Floor, unfolded: `floor(sag / step)`.
/// - Nearest, folded: `round(sag / step) mod m`, m = `round(fold / step)` (the fold is whole steps).
/// - Nearest, unfolded: `round(sag / step)`.
pub fn level_index(d: &PhaseDesign, u_um: f64, fold_um: f64) -> Option<u64> {
    let step = d.height_step_um?;
    let sag = sag_um(d, u_um);
    let k = |v: f64| if v > 0.0 { v as u64 } else { 0 };
    Some(match (d.surface, d.height_rounding) {
        (Surface::Unfolded, HeightRounding::Floor) => k((sag / step).floor()),
        (Surface::Unfolded, HeightRounding::Nearest) => k((sag / step).round()),
        (Surface::Folded, HeightRounding::Floor) => {
            k((sag.rem_euclid(fold_um) / step).floor()).min(top_level(fold_um, step))
        }
        (Surface::Folded, HeightRounding::Nearest) => {
            k((sag / step).round()) % nearest_levels_per_fold(fold_um, step)
        }
    })
}

/// Height of a lenslet's surface at `u_um` from its centre, given its fold height
/// ([`fold_height_um`]). Without a step: the sag, folded by `mod(sag, fold)` unless unfolded. With
/// a step: [`level_index`] × step, so every height is exactly a whole number of steps.
/// [`HeightRounding::Floor`] (the authors' rule) keeps every height below the unrounded fold d0
/// and wraps exactly at d0; [`HeightRounding::Nearest`] rounds the sag (zero mean error against
/// it) and wraps at the fold rounded to whole steps, so its period differs from d0 (1.2 µm for
/// d0 = 1.165 µm at a 0.2 µm step).
pub fn height_um(d: &PhaseDesign, u_um: f64, fold_height_um: f64) -> f64 {
    match (level_index(d, u_um, fold_height_um), d.height_step_um) {
        (Some(level), Some(step)) => level as f64 * step,
        _ => {
            let sag = sag_um(d, u_um);
            match d.surface {
                Surface::Unfolded => sag,
                Surface::Folded => sag.rem_euclid(fold_height_um),
            }
        }
    }
}

/// Distance from a lenslet's centre at which the sag reaches `sag_um`:
/// `sqrt(2 (n−1) f · sag)` (the inverse of [`sag_um`]).
pub fn radius_at_sag_um(d: &PhaseDesign, sag_um: f64) -> f64 {
    (2.0 * (d.refractive_index - 1.0) * d.f_mla_um * sag_um).sqrt()
}

/// One ring of a lenslet between consecutive height jumps, on one side of its centre:
/// `u0_um ≤ |u| < u1_um`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    /// Inner radius of the ring, µm from the lenslet centre.
    pub u0_um: f64,
    /// Outer radius of the ring, µm (exclusive).
    pub u1_um: f64,
    /// Folds below the ring: the continuous height there is `sag − wraps · fold` (0 unfolded).
    pub wraps: u64,
    /// The quantised level (height = level × step), `None` without a step.
    pub level: Option<u64>,
}

/// Upper bound on the number of [`bands`] out to `u_max_um`, without building them (so a design
/// with billions of levels can be refused first).
pub fn band_count_bound(d: &PhaseDesign, fold_um: f64, u_max_um: f64) -> f64 {
    let edge = sag_um(d, u_max_um);
    match (d.height_step_um, d.surface, d.height_rounding) {
        (None, Surface::Unfolded, _) => 1.0,
        (None, Surface::Folded, _) => edge / fold_um + 1.0,
        (Some(step), Surface::Folded, HeightRounding::Floor) => match top_level(fold_um, step) {
            0 => 1.0,
            top => (edge / fold_um + 1.0) * (top as f64 + 1.0),
        },
        (Some(step), Surface::Folded, HeightRounding::Nearest)
            if nearest_levels_per_fold(fold_um, step) == 1 =>
        {
            1.0
        }
        (Some(step), _, _) => edge / step + 2.0,
    }
}

/// The rings of one lenslet from its centre out to `u_max_um` (half the pitch), each where the
/// height is one level (or one continuous piece of one fold), from the analytic crossings of the
/// sag `u² / (2(n−1)f)` in integer level indices:
///
/// - Floor, folded (fold d0, step s, top level J = [`top_level`]): ring (w, j) spans
///   `w·d0 + j·s ≤ sag < w·d0 + (j+1)·s` for j < J and `w·d0 + J·s ≤ sag < (w+1)·d0` for j = J.
/// - Floor, unfolded: `k·s ≤ sag < (k+1)·s`, level k.
/// - Nearest: `(K−½)·s ≤ sag < (K+½)·s` (from 0 for K = 0), level K (mod the levels per fold).
/// - No step: one ring per fold `w·d0 ≤ sag < (w+1)·d0`, or one ring when unfolded.
///
/// The radius of a crossing is [`radius_at_sag_um`]. Neighbouring rings of equal level are merged
/// (a fold under one step is one flat level 0). The last ring ends at `u_max_um`.
pub fn bands(d: &PhaseDesign, fold_um: f64, u_max_um: f64) -> Vec<Band> {
    let edge = sag_um(d, u_max_um);
    // (sag at the ring's inner edge, wraps, level), in order; each ring ends where the next begins.
    let mut starts: Vec<(f64, u64, Option<u64>)> = Vec::new();
    let mut push = |sag: f64, wraps: u64, level: Option<u64>| -> bool {
        if sag >= edge && !starts.is_empty() {
            return false;
        }
        match starts.last() {
            Some(&(_, _, Some(prev))) if level == Some(prev) => {}
            _ => starts.push((sag, wraps, level)),
        }
        true
    };
    match (d.height_step_um, d.surface, d.height_rounding) {
        (None, Surface::Unfolded, _) => {
            push(0.0, 0, None);
        }
        (None, Surface::Folded, _) => {
            let mut w = 0u64;
            while push(w as f64 * fold_um, w, None) {
                w += 1;
            }
        }
        (Some(step), Surface::Folded, HeightRounding::Floor) => {
            let top = top_level(fold_um, step);
            let mut w = 0u64;
            'wraps: loop {
                let base = w as f64 * fold_um;
                for j in 0..=top {
                    if !push(base + j as f64 * step, w, Some(j)) {
                        break 'wraps;
                    }
                }
                if top == 0 {
                    break;
                }
                w += 1;
            }
        }
        (Some(step), Surface::Unfolded, HeightRounding::Floor) => {
            let mut k = 0u64;
            while push(k as f64 * step, 0, Some(k)) {
                k += 1;
            }
        }
        (Some(step), surface, HeightRounding::Nearest) => {
            let m = match surface {
                Surface::Folded => nearest_levels_per_fold(fold_um, step),
                Surface::Unfolded => u64::MAX,
            };
            let mut k = 0u64;
            loop {
                let sag = if k == 0 { 0.0 } else { (k as f64 - 0.5) * step };
                if !push(sag, k / m, Some(k % m)) || m == 1 {
                    break;
                }
                k += 1;
            }
        }
    }
    let mut out: Vec<Band> = starts
        .iter()
        .map(|&(sag, wraps, level)| Band {
            u0_um: radius_at_sag_um(d, sag),
            u1_um: u_max_um,
            wraps,
            level,
        })
        .collect();
    for k in 1..out.len() {
        out[k - 1].u1_um = out[k].u0_um;
    }
    out
}

/// λ0 of every lenslet, left to right.
///
/// # Errors
/// When counts or a per-lenslet list do not match the lenslet count.
pub fn lambda0_per_lenslet(d: &PhaseDesign) -> Result<Vec<f64>, SimError> {
    let n = lenslet_count(d);
    let grid = wavelength_grid_nm();
    match &d.lambda0 {
        Lambda0::Fixed { nm } => Ok(vec![*nm; n]),
        Lambda0::Uniform => Ok(expand_counts(&uniform_counts(n), &grid)),
        Lambda0::Counts { counts } => {
            if counts.len() != GRID_LEN || counts.iter().sum::<usize>() != n {
                return Err(SimError::invalid(
                    "lambda0.counts",
                    format!("need {GRID_LEN} counts summing to the {n} lenslets"),
                ));
            }
            Ok(expand_counts(counts, &grid))
        }
        Lambda0::PerLenslet { nm } => {
            if nm.len() != n {
                return Err(SimError::invalid(
                    "lambda0.nm",
                    format!("has {} entries for {n} lenslets", nm.len()),
                ));
            }
            Ok(nm.clone())
        }
    }
}

/// Equal counts over the 30 grid wavelengths, rounded to the lenslet count by largest remainder
/// (ties go to the shorter wavelengths).
pub fn uniform_counts(lenslets: usize) -> Vec<usize> {
    let share = vec![lenslets as f64 / GRID_LEN as f64; GRID_LEN];
    round_to_total(&share, lenslets)
}

/// Grid wavelengths repeated by their counts, ascending.
pub fn expand_counts(counts: &[usize], grid_nm: &[f64]) -> Vec<f64> {
    counts
        .iter()
        .zip(grid_nm)
        .flat_map(|(&c, &l)| std::iter::repeat_n(l, c))
        .collect()
}

/// The lenslets of one design: centres, λ0 and fold heights.
#[derive(Debug, Clone, PartialEq)]
pub struct Lenslets {
    /// Lenslet pitch (= display pixel pitch), µm.
    pub pitch_um: f64,
    /// Folding wavelength λ0 of each lenslet, nm, left to right.
    pub lambda0_nm: Vec<f64>,
    /// Fold height of each lenslet, µm: `T λ0 / (n − 1)`, rounded as `fold_height_um` says.
    pub fold_height_um: Vec<f64>,
}

impl Lenslets {
    /// The lenslets of `d`, with their λ0 and fold heights.
    ///
    /// # Errors
    /// When the λ0 plan does not fit the lenslet count.
    pub fn new(d: &PhaseDesign) -> Result<Self, SimError> {
        let lambda0_nm = lambda0_per_lenslet(d)?;
        let fold_height_um = lambda0_nm.iter().map(|&l| fold_height_um(d, l)).collect();
        Ok(Lenslets {
            pitch_um: d.pitch_um,
            lambda0_nm,
            fold_height_um,
        })
    }

    /// Number of lenslets.
    pub fn count(&self) -> usize {
        self.lambda0_nm.len()
    }

    /// Centre of lenslet `l` in µm from the axis.
    pub fn centre_um(&self, l: usize) -> f64 {
        (l as f64 - (self.count() as f64 - 1.0) / 2.0) * self.pitch_um
    }

    /// Width covered by the array, in µm.
    pub fn span_um(&self) -> f64 {
        self.count() as f64 * self.pitch_um
    }

    /// The lenslet under `x_um` and the distance from its centre, or `None` outside the array.
    pub fn locate(&self, x_um: f64) -> Option<(usize, f64)> {
        let rel = (x_um - self.centre_um(0)) / self.pitch_um + 0.5;
        let l = rel.floor();
        if l >= 0.0 && (l as usize) < self.count() {
            let l = l as usize;
            Some((l, x_um - self.centre_um(l)))
        } else {
            None
        }
    }

    /// Surface height at `x_um` (0 outside the array).
    pub fn height_at(&self, d: &PhaseDesign, x_um: f64) -> f64 {
        match self.locate(x_um) {
            Some((l, u)) => height_um(d, u, self.fold_height_um[l]),
            None => 0.0,
        }
    }

    /// Tallest point of the plate in µm (fold height, or the thick lens's edge sag).
    pub fn max_height_um(&self, d: &PhaseDesign) -> f64 {
        let fold = self.fold_height_um.iter().copied().fold(0.0, f64::max);
        match (d.surface, d.height_step_um, d.height_rounding) {
            // Floored levels stop at the top level below the fold.
            (Surface::Folded, Some(step), HeightRounding::Floor) => {
                top_level(fold, step) as f64 * step
            }
            (Surface::Folded, _, _) => fold,
            (Surface::Unfolded, _, _) => height_um(d, self.pitch_um / 2.0, 0.0),
        }
    }
}

/// The height profile sampled at `x_um` (µm), for plots and exports.
///
/// # Errors
/// When the λ0 plan does not fit the lenslet count.
pub fn profile_um(d: &PhaseDesign, x_um: &[f64]) -> Result<Vec<f64>, SimError> {
    let lenslets = Lenslets::new(d)?;
    Ok(x_um.iter().map(|&x| lenslets.height_at(d, x)).collect())
}

/// Rounds `shares` (summing to about `total`) to integers summing to exactly `total`: round each,
/// then add to the largest remainders or take from the smallest (largest-remainder method).
pub fn round_to_total(shares: &[f64], total: usize) -> Vec<usize> {
    let mut counts: Vec<usize> = shares.iter().map(|s| s.max(0.0).round() as usize).collect();
    let remainder = |i: usize, counts: &[usize]| shares[i] - counts[i] as f64;
    let mut order: Vec<usize> = (0..shares.len()).collect();
    let mut sum: usize = counts.iter().sum();
    while sum < total {
        order.sort_by(|&i, &j| remainder(j, &counts).total_cmp(&remainder(i, &counts)));
        counts[order[0]] += 1;
        sum += 1;
    }
    while sum > total {
        order.sort_by(|&i, &j| remainder(i, &counts).total_cmp(&remainder(j, &counts)));
        match order.iter().find(|&&i| counts[i] > 0) {
            Some(&i) => counts[i] -= 1,
            None => break,
        }
        sum -= 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_keeps_the_total_and_follows_the_remainders() {
        assert_eq!(round_to_total(&[1.4, 1.4, 1.2], 4), vec![2, 1, 1]);
        assert_eq!(round_to_total(&[1.6, 1.6, 1.8], 5), vec![1, 2, 2]);
        let even = round_to_total(&[58.0 / 30.0; 30], 58);
        assert_eq!(even.iter().sum::<usize>(), 58);
        assert!(even.iter().all(|&c| c == 1 || c == 2));
    }
}
