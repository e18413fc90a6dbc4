//! Lenslet layout and height profiles (PHYSICS.md §7, eq. 4.8).

use serde::{Deserialize, Serialize};

use super::{
    DISPLAY_APERTURE_HALF_ANGLE_DEG, GRID_LEN, Lambda0, PhaseDesign, SimError, wavelength_grid_nm,
};

/// The plate as folded (eq. 4.8) or the thick lens it comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Surface {
    #[default]
    Folded,
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

/// Fold height `T λ0 / (n − 1)` in µm, rounded to the fabrication step (at least one step).
pub fn fold_height_um(d: &PhaseDesign, lambda0_nm: f64) -> f64 {
    let h = d.fold * lambda0_nm * 1e-3 / (d.refractive_index - 1.0);
    match d.height_step_um {
        Some(step) => (h / step).round().max(1.0) * step,
        None => h,
    }
}

/// Height of a lenslet's surface at `u_um` from its centre, given its fold height.
pub fn height_um(d: &PhaseDesign, u_um: f64, fold_height_um: f64) -> f64 {
    let sag = sag_um(d, u_um);
    match (d.surface, d.height_step_um) {
        (Surface::Unfolded, None) => sag,
        (Surface::Unfolded, Some(step)) => (sag / step).round() * step,
        (Surface::Folded, None) => sag.rem_euclid(fold_height_um),
        // Rounding to the nearest level (not flooring) keeps the mean phase error at zero; the
        // top level wraps to 0 like the continuous profile does.
        (Surface::Folded, Some(step)) => ((sag / step).round() * step).rem_euclid(fold_height_um),
    }
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
                return Err(SimError::field(
                    "lambda0.counts",
                    format!("need {GRID_LEN} counts summing to the {n} lenslets"),
                ));
            }
            Ok(expand_counts(counts, &grid))
        }
        Lambda0::PerLenslet { nm } => {
            if nm.len() != n {
                return Err(SimError::field(
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
    super::allocate::round_to_total(&share, lenslets)
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
    pub pitch_um: f64,
    pub lambda0_nm: Vec<f64>,
    pub fold_height_um: Vec<f64>,
}

impl Lenslets {
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
        match d.surface {
            Surface::Folded => self.fold_height_um.iter().copied().fold(0.0, f64::max),
            Surface::Unfolded => height_um(d, self.pitch_um / 2.0, 0.0),
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
