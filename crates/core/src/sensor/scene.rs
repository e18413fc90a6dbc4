//! HDR scenes and their exposure: linear relative radiance in, electrons per unit pixel out.

use ndarray::{Array2, Axis};
use rayon::prelude::*;

use super::SensorSpec;
use crate::SimError;

/// Rec. 709 / sRGB luminance weights of linear R, G, B (OpenEXR's default primaries).
pub const LUMINANCE_WEIGHTS: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// An HDR scene: linear relative radiance, one `[row, col]` plane per channel (R, G, B, or a
/// single luminance plane), every value finite and ≥ 0 (the loader guarantees it; [`run`]
/// checks it).
///
/// [`run`]: super::run
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scene {
    /// The planes, all of the same size.
    pub planes: Vec<Array2<f64>>,
}

/// A scene a run borrows ([`super::run`]).
impl<'a> From<&'a Scene> for std::borrow::Cow<'a, Scene> {
    fn from(scene: &'a Scene) -> Self {
        std::borrow::Cow::Borrowed(scene)
    }
}

/// A scene a run takes over ([`super::run_with`]).
impl From<Scene> for std::borrow::Cow<'_, Scene> {
    fn from(scene: Scene) -> Self {
        std::borrow::Cow::Owned(scene)
    }
}

impl Scene {
    /// `(rows, cols)` of the first plane, `(0, 0)` without planes.
    pub fn dim(&self) -> (usize, usize) {
        self.planes.first().map_or((0, 0), Array2::dim)
    }

    /// The luminance the simulation runs on: `0.2126 R + 0.7152 G + 0.0722 B` for three planes,
    /// the plane itself for one (see the module docs). Planes of another count are averaged.
    pub fn luminance(&self) -> Array2<f64> {
        match self.planes.as_slice() {
            [] => Array2::zeros((0, 0)),
            [y] => y.clone(),
            [r, g, b] if r.dim() == g.dim() && r.dim() == b.dim() => {
                let mut out = Array2::zeros(r.dim());
                let [wr, wg, wb] = LUMINANCE_WEIGHTS;
                out.axis_iter_mut(Axis(0))
                    .into_par_iter()
                    .enumerate()
                    .for_each(|(y, mut row)| {
                        let (r, g, b) = (r.row(y), g.row(y), b.row(y));
                        for (((o, r), g), b) in row.iter_mut().zip(r).zip(g).zip(b) {
                            *o = wr * r + wg * g + wb * b;
                        }
                    });
                out
            }
            planes => {
                let n = planes.len() as f64;
                let mut out = planes[0].clone();
                for p in &planes[1..] {
                    if p.dim() == out.dim() {
                        out += p;
                    }
                }
                out / n
            }
        }
    }

    /// [`Scene::luminance`], taking over the plane of a one-plane scene instead of copying it.
    pub fn into_luminance(mut self) -> Array2<f64> {
        if self.planes.len() == 1
            && let Some(plane) = self.planes.pop()
        {
            return plane;
        }
        self.luminance()
    }

    /// The scene scaled down so that its longer side is at most `max_side_px` (at least 1),
    /// by area averaging: every output pixel is the mean radiance of the input area it covers,
    /// so the mean radiance (and an exposure set from it) is kept. A scene that already fits is
    /// returned as it is. The preview path of the studio runs [`run`] on such a scene.
    ///
    /// [`run`]: super::run
    pub fn downscaled(&self, max_side_px: usize) -> Scene {
        let (h, w) = self.dim();
        let max_side = max_side_px.max(1);
        if h.max(w) <= max_side || h == 0 || w == 0 {
            return self.clone();
        }
        let scale = max_side as f64 / h.max(w) as f64;
        let oh = ((h as f64 * scale).round() as usize).clamp(1, max_side);
        let ow = ((w as f64 * scale).round() as usize).clamp(1, max_side);
        let rows = area_weights(h, oh);
        let cols = area_weights(w, ow);
        let planes = self
            .planes
            .par_iter()
            .map(|p| resample(p, &rows, &cols))
            .collect();
        Scene { planes }
    }

    /// Checks that the scene can be simulated: at least one plane, equal non-empty sizes of at
    /// least `min_side_px`, every value finite and ≥ 0.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] naming `scene` or `scene.planes[c]`.
    pub fn validate(&self, min_side_px: usize) -> Result<(), SimError> {
        let Some(first) = self.planes.first() else {
            return Err(SimError::invalid("scene", "has no planes"));
        };
        let (h, w) = first.dim();
        if h < min_side_px || w < min_side_px {
            return Err(SimError::invalid(
                "scene",
                format!(
                    "is {w}×{h} pixels; at least {min_side_px}×{min_side_px} are needed (the SSIM \
                     window)"
                ),
            ));
        }
        for (c, p) in self.planes.iter().enumerate() {
            if p.dim() != (h, w) {
                return Err(SimError::invalid(
                    format!("scene.planes[{c}]"),
                    format!("is {:?}, plane 0 is {:?}", p.dim(), (h, w)),
                ));
            }
            let bad = p
                .axis_iter(Axis(0))
                .into_par_iter()
                .find_map_first(|row| row.iter().copied().find(|v| !(v.is_finite() && *v >= 0.0)));
            if let Some(v) = bad {
                return Err(SimError::invalid(
                    format!("scene.planes[{c}]"),
                    format!("holds {v}; radiance must be finite and ≥ 0"),
                ));
            }
        }
        Ok(())
    }
}

/// For each output sample, the first input sample it covers and the weights of the input samples
/// it covers (overlap length / output length; they sum to 1).
fn area_weights(n_in: usize, n_out: usize) -> Vec<(usize, Vec<f64>)> {
    let step = n_in as f64 / n_out as f64;
    (0..n_out)
        .map(|i| {
            let (a, b) = (i as f64 * step, ((i + 1) as f64 * step).min(n_in as f64));
            let first = a.floor() as usize;
            let last = (b.ceil() as usize).clamp(first + 1, n_in);
            let weights = (first..last)
                .map(|j| {
                    let overlap = (b.min((j + 1) as f64) - a.max(j as f64)).max(0.0);
                    overlap / step
                })
                .collect();
            (first, weights)
        })
        .collect()
}

/// Separable area resampling: along rows, then along columns.
fn resample(
    p: &Array2<f64>,
    rows: &[(usize, Vec<f64>)],
    cols: &[(usize, Vec<f64>)],
) -> Array2<f64> {
    let (h, _) = p.dim();
    let ow = cols.len();
    let mut across = Array2::<f64>::zeros((h, ow));
    across
        .axis_iter_mut(Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(y, mut out)| {
            let row = p.row(y);
            for (o, (first, ws)) in out.iter_mut().zip(cols) {
                *o = ws.iter().enumerate().map(|(k, w)| w * row[first + k]).sum();
            }
        });
    let mut out = Array2::<f64>::zeros((rows.len(), ow));
    out.axis_iter_mut(Axis(0))
        .into_par_iter()
        .zip(rows.par_iter())
        .for_each(|(mut o, (first, ws))| {
            for (k, w) in ws.iter().enumerate() {
                o.scaled_add(*w, &across.row(first + k));
            }
        });
    out
}

/// How the scene's relative radiance becomes electrons per unit pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Exposure {
    /// The image mean is this fraction of the full well (Table 5.4: 0.05).
    MeanFraction(f64),
    /// The `percentile`-th percentile (0–100, nearest rank) of the luminance fills `fill` of the
    /// full well (e.g. 99.9 and 0.8).
    PercentileFill {
        /// Percentile of the luminance, 0–100.
        percentile: f64,
        /// Fraction of the full well it fills.
        fill: f64,
    },
    /// Absolute: radiance 1 gives this many electrons per µm² (a unit pixel collects that times
    /// its area).
    ElectronsPerUm2(f64),
}

impl Default for Exposure {
    /// Table 5.4's: the mean at 5 % of the full well.
    fn default() -> Self {
        Exposure::MeanFraction(0.05)
    }
}

impl Exposure {
    /// Checks the numbers; errors name `exposure.<field>`.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`].
    pub fn validate(&self) -> Result<(), SimError> {
        // Below the lower bounds a capture is under a millionth of an electron (black); above
        // the upper ones every pixel clips: refused rather than scored.
        let positive = |field: &str, v: f64| {
            let (lo, hi) = if field == "electrons_per_um2" {
                (1e-6, 1e9)
            } else {
                (1e-6, 1e3)
            };
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(SimError::invalid(
                    format!("exposure.{field}"),
                    format!("must be {lo:e} … {hi:e} (got {v:?})"),
                ))
            }
        };
        match *self {
            Exposure::MeanFraction(f) => positive("mean_fraction", f),
            Exposure::PercentileFill { percentile, fill } => {
                if !(percentile.is_finite() && percentile > 0.0 && percentile <= 100.0) {
                    return Err(SimError::invalid(
                        "exposure.percentile",
                        format!("must be in (0, 100] (got {percentile:?})"),
                    ));
                }
                positive("fill", fill)
            }
            Exposure::ElectronsPerUm2(e) => positive("electrons_per_um2", e),
        }
    }

    /// Electrons per unit pixel per unit of luminance.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] (`exposure…`) for bad numbers, or `scene` when the statistic
    /// the exposure is set from is zero (a black scene cannot be normalised).
    pub fn electrons_per_radiance(
        &self,
        luminance: &Array2<f64>,
        sensor: &SensorSpec,
    ) -> Result<f64, SimError> {
        self.validate()?;
        let black = |what: &str| {
            SimError::invalid(
                "scene",
                format!("its {what} is 0; a black scene cannot be exposed by a relative rule"),
            )
        };
        match *self {
            Exposure::MeanFraction(f) => {
                let mean = luminance.mean().unwrap_or(0.0);
                if !(mean > 0.0) {
                    return Err(black("mean"));
                }
                Ok(f * sensor.full_well_e / mean)
            }
            Exposure::PercentileFill { percentile, fill } => {
                let p = percentile_of(luminance, percentile);
                if !(p > 0.0) {
                    return Err(black(&format!("{percentile}th percentile")));
                }
                Ok(fill * sensor.full_well_e / p)
            }
            Exposure::ElectronsPerUm2(e) => Ok(e * sensor.unit_pixel_area_um2()),
        }
    }
}

/// The `percentile`-th percentile (nearest rank, 0–100) of the values; 0 when empty.
pub fn percentile_of(values: &Array2<f64>, percentile: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().collect();
    if v.is_empty() {
        return 0.0;
    }
    let rank = ((percentile / 100.0) * v.len() as f64).ceil() as usize;
    let k = rank.clamp(1, v.len()) - 1;
    let (_, x, _) = v.select_nth_unstable_by(k, f64::total_cmp);
    *x
}
