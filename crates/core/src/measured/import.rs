//! A measured PSF from raw frames: a bracket of exposures of a point source with dark frames,
//! merged into one linear PSF in the core's conventions. The steps, each switchable and each
//! reported:
//!
//! 1. **Dark subtraction**: the mean of the dark frames off every frame.
//! 2. **Hot pixels**: pixels far above all their neighbours (in the dark mean when there are
//!    darks, else in every frame) take their neighbours' median.
//! 3. **Saturation mask**: a frame's samples at or above 98 % of its full scale carry no
//!    information and are left out of the merge.
//! 4. **HDR merge**: per pixel, the counts of its unsaturated frames over the sum of their
//!    exposure times, the maximum-likelihood rate under photon noise; a pixel saturated in every
//!    frame keeps the shortest exposure's rate (and is counted as clipped).
//! 5. **Background**: the median of a border band, subtracted (its MAD gives the noise).
//! 6. **Centring**: on the centroid (of the light above 1 % of the peak and 5σ) or the peak (with a parabolic
//!    sub-pixel refinement); the PSF is then moved there by a Fourier phase ramp, so that the
//!    optical axis sits at `[N/2, N/2]` without blurring it.
//! 7. **Crop** to a square around the centre (a given side, or the largest that fits, at most
//!    [`DEFAULT_MAX_SIDE_PX`]), then **normalisation** to unit sum.

use ndarray::{Array2, Zip};
use serde::{Deserialize, Serialize};

use super::shift::shifted;
use crate::SimError;
use crate::progress::Progress;

/// The exposure times a bracket may hold, s: 1 ns to about 11.6 days. Outside, the number is a
/// slip of unit (µs given as s) and the merge's weights would be meaningless.
pub const EXPOSURE_S_RANGE: std::ops::RangeInclusive<f64> = 1e-9..=1e6;

/// A frame's share of its full scale at and above which a sample counts as saturated.
pub const SATURATION_SHARE: f64 = 0.98;
/// A frame saturated over more than this share of its pixels is refused (a far too long
/// exposure, not a PSF).
pub const MOSTLY_SATURATED: f64 = 0.5;
/// The side a crop takes when none is given, at most (pixels): a 20-megapixel frame otherwise
/// makes a PSF of 13 M samples that every comparison must transform.
pub const DEFAULT_MAX_SIDE_PX: usize = 1024;
/// Light more than this many background σ above the background counts as signal (centroid,
/// the "no light" check).
pub const SIGNAL_SIGMAS: f64 = 5.0;
/// The centroid weighs the light above this share of the peak (and above 5σ).
pub const CORE_SHARE: f64 = 0.01;
/// A hot pixel stands this many times above the largest of its eight neighbours…
const HOT_RATIO: f64 = 4.0;
/// …and this many noise σ above their median.
const HOT_SIGMAS: f64 = 10.0;

/// One exposure of the point source.
#[derive(Debug, Clone)]
pub struct Exposure {
    /// The raw frame, `[row, col]`, in the file's units (counts).
    pub frame: Array2<f64>,
    /// Its exposure time, s.
    pub exposure_s: f64,
}

/// The frames of one measurement.
#[derive(Debug, Clone, Default)]
pub struct Bracket {
    /// The exposures, in any order.
    pub exposures: Vec<Exposure>,
    /// Dark frames (the source covered), averaged and subtracted; none: no dark subtraction.
    pub darks: Vec<Array2<f64>>,
    /// The value a sample reaches when the pixel saturates (65535 for 16-bit files); `None`
    /// for float data, which has no full scale.
    pub full_scale: Option<f64>,
}

/// Where the PSF is centred.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Centring {
    /// On the centroid of the PSF's bright core (the light above 1 % of the peak and 5σ of the
    /// background): sub-pixel, and not pulled about by noise in faint wings.
    #[default]
    Centroid,
    /// On the brightest sample, refined to a sub-pixel position by a parabola through it and
    /// its neighbours.
    Peak,
    /// Not moved: the frame's middle is taken as the axis.
    None,
}

/// Which steps run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImportSteps {
    /// Subtract the mean dark frame (when there are darks).
    pub dark: bool,
    /// Replace hot pixels by their neighbours' median.
    pub hot_pixels: bool,
    /// Leave saturated samples out of the merge.
    pub saturation: bool,
    /// Subtract the background of the border band.
    pub background: bool,
    /// Where the PSF is centred.
    pub centring: Centring,
    /// A centre already found, `[row, col]` in the frame (the other colour channels of a
    /// frame take the first's, so that lateral colour is kept); overrides `centring`'s search.
    pub centre_px: Option<[f64; 2]>,
    /// The side of the square crop, pixels; `None`: the largest that fits, at most
    /// [`DEFAULT_MAX_SIDE_PX`].
    pub crop_px: Option<usize>,
    /// Scale to unit sum.
    pub normalise: bool,
}

impl Default for ImportSteps {
    fn default() -> Self {
        ImportSteps {
            dark: true,
            hot_pixels: true,
            saturation: true,
            background: true,
            centring: Centring::Centroid,
            centre_px: None,
            crop_px: None,
            normalise: true,
        }
    }
}

/// What the import did, step by step.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ImportReport {
    /// Exposures merged.
    pub exposures: usize,
    /// Dark frames averaged (0: no dark subtraction).
    pub darks: usize,
    /// Mean of the dark frame subtracted, counts.
    pub dark_mean: Option<f64>,
    /// Whether hot pixels were looked for (they are not in one frame without dark frames).
    pub hot_pixels_checked: bool,
    /// Hot pixels replaced.
    pub hot_pixels: usize,
    /// Samples left out as saturated, over all exposures.
    pub saturated_samples: usize,
    /// Pixels saturated in every exposure: their rate is a lower bound (clipped).
    pub clipped_pixels: usize,
    /// The background subtracted, in the merged units (counts per second).
    pub background: Option<f64>,
    /// The background's noise (1.4826 · MAD), same units.
    pub background_sigma: f64,
    /// The peak over the background noise.
    pub peak_snr: f64,
    /// Where the centre was found in the input frame, `[row, col]` pixels.
    pub centre_px: [f64; 2],
    /// Side of the cropped PSF, pixels.
    pub side_px: usize,
    /// Share of the light (above the background) the crop kept.
    pub light_kept: f64,
    /// One line each: what the user should know (clipping, a crop that cut light).
    pub warnings: Vec<String>,
}

impl ImportReport {
    /// One line naming what was done.
    pub fn summary(&self) -> String {
        let mut parts = vec![format!(
            "{} exposure{} merged",
            self.exposures,
            if self.exposures == 1 { "" } else { "s" }
        )];
        if self.darks > 0 {
            parts.push(format!(
                "{} dark frame{} subtracted (mean {:.4})",
                self.darks,
                if self.darks == 1 { "" } else { "s" },
                self.dark_mean.unwrap_or(0.0)
            ));
        }
        parts.push(if self.hot_pixels_checked {
            format!("{} hot pixels replaced", self.hot_pixels)
        } else {
            "hot pixels not looked for (one frame, no dark frame)".to_owned()
        });
        parts.push(format!(
            "{} saturated samples masked ({} pixels clipped in every exposure)",
            self.saturated_samples, self.clipped_pixels
        ));
        if let Some(b) = self.background {
            parts.push(format!(
                "background {} ± {} subtracted",
                crate::figure::short_value(b),
                crate::figure::short_value(self.background_sigma)
            ));
        }
        parts.push(format!(
            "centred at row {:.2}, col {:.2}",
            self.centre_px[0], self.centre_px[1]
        ));
        parts.push(format!(
            "cropped to {0}×{0} px ({1:.1} % of the light)",
            self.side_px,
            100.0 * self.light_kept
        ));
        parts.push(format!("peak SNR {:.0}", self.peak_snr));
        parts.join("; ")
    }
}

/// The merged, centred, cropped PSF of `bracket` and what was done; sums to 1 when
/// `steps.normalise`.
///
/// # Errors
/// No exposure; frames or darks of different sizes; a non-positive exposure time; a
/// non-finite sample; a frame mostly saturated or holding no light above its dark level; a
/// PSF with no light above the background; a crop larger than the frame; cancellation.
pub fn merge(
    bracket: &Bracket,
    steps: &ImportSteps,
    progress: &Progress,
) -> Result<(Array2<f64>, ImportReport), SimError> {
    check(bracket)?;
    let mut report = ImportReport {
        exposures: bracket.exposures.len(),
        ..ImportReport::default()
    };
    let dim = bracket.exposures[0].frame.dim();
    // 1. The dark frame.
    let dark = if steps.dark && !bracket.darks.is_empty() {
        let mut mean = Array2::<f64>::zeros(dim);
        for d in &bracket.darks {
            mean += d;
        }
        mean /= bracket.darks.len() as f64;
        report.darks = bracket.darks.len();
        report.dark_mean = Some(mean.mean().unwrap_or(0.0));
        Some(mean)
    } else {
        None
    };
    progress.check()?;
    // 2. Hot pixels, found once and replaced in every frame.
    // One frame and no dark frame: a hot pixel cannot be told from a point of light (a sparse
    // PSF is made of them), so nothing is replaced, and the report says so.
    let can_tell = dark.is_some() || bracket.exposures.len() > 1;
    report.hot_pixels_checked = steps.hot_pixels && can_tell;
    let hot = if report.hot_pixels_checked {
        match &dark {
            Some(d) => hot_pixels(d),
            _ => {
                // Without darks a hot pixel is hot in every exposure; light is not.
                let mut common: Option<Vec<[usize; 2]>> = None;
                for e in &bracket.exposures {
                    let found = hot_pixels(&e.frame);
                    common = Some(match common {
                        None => found,
                        Some(c) => c.into_iter().filter(|p| found.contains(p)).collect(),
                    });
                }
                common.unwrap_or_default()
            }
        }
    } else {
        Vec::new()
    };
    report.hot_pixels = hot.len();
    // 3 and 4. Saturation masks and the merge, one exposure at a time.
    let level = bracket
        .full_scale
        .filter(|_| steps.saturation)
        .map(|f| SATURATION_SHARE * f);
    let mut counts = Array2::<f64>::zeros(dim);
    let mut time_s = Array2::<f64>::zeros(dim);
    // The shortest exposure's rate, for pixels saturated in every exposure.
    let shortest = bracket
        .exposures
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.exposure_s.total_cmp(&b.1.exposure_s))
        .map_or(0, |(i, _)| i);
    let mut fallback = Array2::<f64>::zeros(dim);
    for (i, e) in bracket.exposures.iter().enumerate() {
        progress.check()?;
        let mut frame = match &dark {
            Some(d) => &e.frame - d,
            None => e.frame.clone(),
        };
        replace_hot(&mut frame, &hot);
        let saturated = level.map_or(0, |l| e.frame.iter().filter(|v| **v >= l).count());
        let share = saturated as f64 / e.frame.len().max(1) as f64;
        if share > MOSTLY_SATURATED {
            return Err(SimError::invalid(
                format!("exposure {} ({} s)", i + 1, e.exposure_s),
                format!(
                    "{:.0} % of its pixels are saturated: take a shorter exposure",
                    100.0 * share
                ),
            ));
        }
        report.saturated_samples += saturated;
        if i == shortest {
            fallback = frame.mapv(|v| v / e.exposure_s);
        }
        Zip::from(&mut counts)
            .and(&mut time_s)
            .and(&frame)
            .and(&e.frame)
            .for_each(|c, t, v, raw| {
                if level.is_none_or(|l| *raw < l) {
                    *c += v;
                    *t += e.exposure_s;
                }
            });
    }
    let mut rate = Array2::<f64>::zeros(dim);
    Zip::from(&mut rate)
        .and(&counts)
        .and(&time_s)
        .and(&fallback)
        .for_each(|r, c, t, f| *r = if *t > 0.0 { c / t } else { *f });
    report.clipped_pixels = time_s.iter().filter(|t| **t == 0.0).count();
    if report.clipped_pixels > 0 {
        report.warnings.push(format!(
            "{} pixels are saturated in every exposure: their light is a lower bound; add a \
             shorter exposure",
            report.clipped_pixels
        ));
    }
    for (i, e) in bracket.exposures.iter().enumerate() {
        // A frame with no light above its dark level cannot have been of the source.
        let noise = border_stats(&e.frame).1.max(1e-12);
        let base = dark
            .as_ref()
            .map_or(border_stats(&e.frame).0, |d| d.mean().unwrap_or(0.0));
        let top = e.frame.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if top - base <= SIGNAL_SIGMAS * noise && bracket.exposures.len() > 1 {
            return Err(SimError::invalid(
                format!("exposure {} ({} s)", i + 1, e.exposure_s),
                "holds no light above its dark level: was the source on?",
            ));
        }
    }
    progress.check()?;
    // 5. The background.
    let (median, sigma) = border_stats(&rate);
    report.background_sigma = sigma;
    if steps.background {
        rate.mapv_inplace(|v| v - median);
        report.background = Some(median);
    }
    let floor = if steps.background { 0.0 } else { median };
    let peak = rate.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    report.peak_snr = if sigma > 0.0 {
        (peak - floor) / sigma
    } else {
        f64::INFINITY
    };
    if !(peak - floor > SIGNAL_SIGMAS * sigma && peak - floor > 0.0) {
        return Err(SimError::invalid(
            "psf",
            format!(
                "no light above the background: the peak is {} over a background of {} ± {}",
                crate::figure::short_value(peak),
                crate::figure::short_value(median),
                crate::figure::short_value(sigma)
            ),
        ));
    }
    // 6. The centre: the bright core's centroid; faint wings far out would give the noise a
    // long lever arm.
    let threshold = floor + (SIGNAL_SIGMAS * sigma).max(CORE_SHARE * (peak - floor));
    let centre = match (steps.centre_px, steps.centring) {
        (Some(at), _) => at,
        (None, Centring::Centroid) => centroid(&rate, threshold, floor),
        (None, Centring::Peak) => peak_position(&rate),
        (None, Centring::None) => [(dim.0 / 2) as f64, (dim.1 / 2) as f64],
    };
    report.centre_px = centre;
    // 7. The crop, the sub-pixel move and the normalisation.
    let [cy, cx] = [centre[0].round() as i64, centre[1].round() as i64];
    let fits = [cy, dim.0 as i64 - cy, cx, dim.1 as i64 - cx]
        .into_iter()
        .min()
        .unwrap_or(0)
        .max(1) as usize;
    let side = match steps.crop_px {
        Some(s) if s == 0 || s > dim.0.max(dim.1) => {
            return Err(SimError::invalid(
                "crop_px",
                format!(
                    "must be 1 … {} px (the frame's side), got {s}",
                    dim.0.max(dim.1)
                ),
            ));
        }
        Some(s) => s,
        None => (2 * fits).min(DEFAULT_MAX_SIDE_PX).min(dim.0).min(dim.1),
    };
    // Signed sums: the background's noise cancels out instead of counting as light.
    let total_light: f64 = rate.iter().map(|v| v - floor).sum();
    // The square whose middle sample [side/2, side/2] is the rounded centre; outside the frame
    // it is background (0 once subtracted).
    let (y0, x0) = (cy - (side / 2) as i64, cx - (side / 2) as i64);
    let mut psf = Array2::from_shape_fn((side, side), |(y, x)| {
        let (sy, sx) = (y0 + y as i64, x0 + x as i64);
        if sy >= 0 && sx >= 0 && (sy as usize) < dim.0 && (sx as usize) < dim.1 {
            rate[[sy as usize, sx as usize]]
        } else {
            0.0
        }
    });
    let kept: f64 = psf.iter().map(|v| v - floor).sum();
    report.side_px = side;
    report.light_kept = if total_light > 0.0 {
        (kept / total_light).min(1.0)
    } else {
        0.0
    };
    if report.light_kept < 0.97 {
        report.warnings.push(format!(
            "the {side}-px crop keeps {:.1} % of the light: give a larger --crop-px",
            100.0 * report.light_kept
        ));
    }
    progress.check()?;
    if steps.centring != Centring::None || steps.centre_px.is_some() {
        // The rounded centre sits at [side/2, side/2]; move the rest of the way.
        let (fy, fx) = (centre[0] - cy as f64, centre[1] - cx as f64);
        psf = shifted(&psf, -fy, -fx);
    }
    if steps.normalise {
        let sum = psf.sum();
        if !(sum > 0.0) {
            return Err(SimError::invalid(
                "psf",
                "the cropped PSF holds no light above the background",
            ));
        }
        psf /= sum;
    }
    Ok((psf, report))
}

/// The bracket's frames agree in size, have positive exposure times and finite samples.
fn check(bracket: &Bracket) -> Result<(), SimError> {
    let Some(first) = bracket.exposures.first() else {
        return Err(SimError::invalid("exposures", "no frame to import"));
    };
    let dim = first.frame.dim();
    if dim.0 == 0 || dim.1 == 0 {
        return Err(SimError::invalid("exposure 1", "the frame is empty"));
    }
    let frames = bracket
        .exposures
        .iter()
        .map(|e| &e.frame)
        .enumerate()
        .map(|(i, f)| (format!("exposure {}", i + 1), f))
        .chain(
            bracket
                .darks
                .iter()
                .enumerate()
                .map(|(i, f)| (format!("dark frame {}", i + 1), f)),
        );
    for (name, f) in frames {
        if f.dim() != dim {
            return Err(SimError::invalid(
                name,
                format!(
                    "is {}×{} px but exposure 1 is {}×{} (columns × rows): a bracket's frames \
                     must be of one size",
                    f.ncols(),
                    f.nrows(),
                    dim.1,
                    dim.0
                ),
            ));
        }
        if let Some(((r, c), v)) = f.indexed_iter().find(|(_, v)| !v.is_finite()) {
            return Err(SimError::invalid(
                name,
                format!("holds {v} at row {r}, column {c}"),
            ));
        }
    }
    for (i, e) in bracket.exposures.iter().enumerate() {
        if !EXPOSURE_S_RANGE.contains(&e.exposure_s) {
            return Err(SimError::invalid(
                format!("exposure {}", i + 1),
                format!(
                    "its exposure time must be {} … {} s, got {}",
                    EXPOSURE_S_RANGE.start(),
                    EXPOSURE_S_RANGE.end(),
                    e.exposure_s
                ),
            ));
        }
    }
    Ok(())
}

/// The median and the noise (1.4826 · MAD) of the band `max(4, side/16)` pixels wide along the
/// frame's border, where a centred PSF has least light.
pub fn border_stats(a: &Array2<f64>) -> (f64, f64) {
    let (h, w) = a.dim();
    let band = (h.min(w) / 16).max(4).min(h / 2).min(w / 2).max(1);
    let mut v: Vec<f64> = a
        .indexed_iter()
        .filter(|((y, x), _)| *y < band || *x < band || *y >= h - band || *x >= w - band)
        .map(|(_, v)| *v)
        .collect();
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let median = median_of(&mut v);
    let mut dev: Vec<f64> = v.iter().map(|x| (x - median).abs()).collect();
    (median, 1.4826 * median_of(&mut dev))
}

fn median_of(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    *m
}

/// The eight neighbours of `[y, x]` inside `a`.
fn neighbours(a: &Array2<f64>, y: usize, x: usize) -> Vec<f64> {
    let (h, w) = a.dim();
    let mut out = Vec::with_capacity(8);
    for dy in -1i64..=1 {
        for dx in -1i64..=1 {
            if dy == 0 && dx == 0 {
                continue;
            }
            let (ny, nx) = (y as i64 + dy, x as i64 + dx);
            if ny >= 0 && nx >= 0 && (ny as usize) < h && (nx as usize) < w {
                out.push(a[[ny as usize, nx as usize]]);
            }
        }
    }
    out
}

/// Pixels far above every neighbour: more than [`HOT_RATIO`] times the largest of them (above
/// the frame's median) and [`HOT_SIGMAS`] noise σ above their median. A diffraction-limited PSF
/// sampled by a camera spreads its peak over neighbours; a hot pixel does not.
fn hot_pixels(a: &Array2<f64>) -> Vec<[usize; 2]> {
    let (base, sigma) = border_stats(a);
    let sigma = sigma.max(1e-12);
    let (h, w) = a.dim();
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let v = a[[y, x]] - base;
            if v <= HOT_SIGMAS * sigma {
                continue;
            }
            let mut n = neighbours(a, y, x);
            let top = n.iter().copied().fold(f64::NEG_INFINITY, f64::max) - base;
            let med = median_of(&mut n) - base;
            if v > HOT_RATIO * top.max(0.0) && v - med > HOT_SIGMAS * sigma {
                out.push([y, x]);
            }
        }
    }
    out
}

/// Each listed pixel takes its neighbours' median.
fn replace_hot(a: &mut Array2<f64>, hot: &[[usize; 2]]) {
    let values: Vec<f64> = hot
        .iter()
        .map(|[y, x]| median_of(&mut neighbours(a, *y, *x)))
        .collect();
    for ([y, x], v) in hot.iter().zip(values) {
        a[[*y, *x]] = v;
    }
}

/// The centroid `[row, col]` of the light above `threshold`, weighted by its height above
/// `floor`; the pixel centres are at whole coordinates.
fn centroid(a: &Array2<f64>, threshold: f64, floor: f64) -> [f64; 2] {
    let (mut sy, mut sx, mut s) = (0.0, 0.0, 0.0);
    for ((y, x), v) in a.indexed_iter() {
        if *v > threshold {
            let wgt = v - floor;
            sy += y as f64 * wgt;
            sx += x as f64 * wgt;
            s += wgt;
        }
    }
    if s > 0.0 {
        [sy / s, sx / s]
    } else {
        peak_position(a)
    }
}

/// The brightest sample, refined by a parabola through it and its two neighbours along each
/// axis.
fn peak_position(a: &Array2<f64>) -> [f64; 2] {
    let (h, w) = a.dim();
    let ((py, px), _) = a
        .indexed_iter()
        .fold(((0, 0), f64::NEG_INFINITY), |best, (i, v)| {
            if *v > best.1 { (i, *v) } else { best }
        });
    let refine = super::parabola_peak;
    let dy = if py > 0 && py + 1 < h {
        refine(a[[py - 1, px]], a[[py, px]], a[[py + 1, px]])
    } else {
        0.0
    };
    let dx = if px > 0 && px + 1 < w {
        refine(a[[py, px - 1]], a[[py, px]], a[[py, px + 1]])
    } else {
        0.0
    };
    [py as f64 + dy, px as f64 + dx]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(n: usize, cy: f64, cx: f64, width: f64, amplitude: f64) -> Array2<f64> {
        Array2::from_shape_fn((n, n), |(y, x)| {
            let (dy, dx) = (y as f64 - cy, x as f64 - cx);
            amplitude * (-(dy * dy + dx * dx) / (2.0 * width * width)).exp()
        })
    }

    #[test]
    fn the_merge_recovers_the_rate_and_centres_the_spot() {
        // A spot at (30.3, 33.6) on a 64² frame, 0.01 and 0.1 s; the long one saturates its peak.
        let rate = spot(64, 30.3, 33.6, 2.0, 1e6);
        let full = 60_000.0;
        let expose = |t: f64| Exposure {
            frame: rate.mapv(|r| (r * t + 100.0).min(full)),
            exposure_s: t,
        };
        let bracket = Bracket {
            exposures: vec![expose(0.01), expose(0.1)],
            darks: vec![Array2::from_elem((64, 64), 100.0)],
            full_scale: Some(full),
        };
        let (psf, report) =
            merge(&bracket, &ImportSteps::default(), &Progress::new()).expect("merged");
        assert!(report.saturated_samples > 0, "the long exposure saturated");
        assert_eq!(report.clipped_pixels, 0, "the short one covers the peak");
        assert!(
            (report.centre_px[0] - 30.3).abs() < 0.02,
            "{:?}",
            report.centre_px
        );
        assert!(
            (report.centre_px[1] - 33.6).abs() < 0.02,
            "{:?}",
            report.centre_px
        );
        assert!((psf.sum() - 1.0).abs() < 1e-9);
        // Centred at [N/2, N/2]: the spot's own shape, normalised.
        let n = psf.nrows();
        let clean = spot(n, (n / 2) as f64, (n / 2) as f64, 2.0, 1.0);
        let clean = &clean / clean.sum();
        let err = (&psf - &clean).mapv(f64::abs).sum();
        assert!(err < 3e-3, "L1 error {err}");
    }

    #[test]
    fn hot_pixels_are_replaced_and_light_is_not() {
        let mut frame = spot(48, 24.0, 24.0, 1.5, 5000.0);
        frame += 10.0;
        frame[[5, 7]] = 4000.0;
        frame[[40, 30]] = 9000.0;
        // Two exposures, no dark frame: what is bright in both and alone is a hot pixel.
        let mut bracket = Bracket {
            exposures: vec![
                Exposure {
                    frame: frame.clone(),
                    exposure_s: 1.0,
                },
                Exposure {
                    frame,
                    exposure_s: 1.0,
                },
            ],
            darks: Vec::new(),
            full_scale: None,
        };
        let (psf, report) =
            merge(&bracket, &ImportSteps::default(), &Progress::new()).expect("merged");
        assert_eq!(report.hot_pixels, 2);
        // One frame alone: not looked for, and said so.
        bracket.exposures.truncate(1);
        let (_, one) = merge(&bracket, &ImportSteps::default(), &Progress::new()).expect("one");
        assert!(!one.hot_pixels_checked && one.hot_pixels == 0);
        assert!(one.summary().contains("hot pixels not looked for"));
        // The spot's peak (far above its neighbours' median, but not four times the largest)
        // stays.
        let n = psf.nrows();
        assert!(psf[[n / 2, n / 2]] > 0.05);
    }

    #[test]
    fn bad_brackets_are_refused_naming_the_frame() {
        let ok = Exposure {
            frame: spot(32, 16.0, 16.0, 2.0, 100.0),
            exposure_s: 1.0,
        };
        let steps = ImportSteps::default();
        let p = Progress::new();
        let msg = |b: Bracket| merge(&b, &steps, &p).map(|_| ()).unwrap_err().to_string();
        let mismatched = Bracket {
            exposures: vec![
                ok.clone(),
                Exposure {
                    frame: Array2::zeros((16, 32)),
                    exposure_s: 2.0,
                },
            ],
            ..Bracket::default()
        };
        assert!(msg(mismatched).contains("exposure 2"));
        let saturated = Bracket {
            exposures: vec![Exposure {
                frame: Array2::from_elem((32, 32), 65535.0),
                exposure_s: 1.0,
            }],
            full_scale: Some(65535.0),
            ..Bracket::default()
        };
        assert!(msg(saturated).contains("saturated"));
        let dark = Bracket {
            exposures: vec![
                ok.clone(),
                Exposure {
                    frame: Array2::from_elem((32, 32), 3.0),
                    exposure_s: 0.5,
                },
            ],
            ..Bracket::default()
        };
        assert!(msg(dark).contains("no light above its dark level"));
        let flat = Bracket {
            exposures: vec![Exposure {
                frame: Array2::from_elem((32, 32), 7.0),
                exposure_s: 1.0,
            }],
            ..Bracket::default()
        };
        assert!(msg(flat).contains("no light above the background"));
        let mut nan = ok.clone();
        nan.frame[[3, 4]] = f64::NAN;
        assert!(
            msg(Bracket {
                exposures: vec![nan],
                ..Bracket::default()
            })
            .contains("row 3, column 4")
        );
        let zero_time = Exposure {
            exposure_s: 0.0,
            ..ok
        };
        assert!(
            msg(Bracket {
                exposures: vec![zero_time],
                ..Bracket::default()
            })
            .contains("exposure time")
        );
    }
}
