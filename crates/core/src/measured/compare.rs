//! A measured PSF beside the design's simulated one (computed at the measurement's pixel pitch):
//! aligned to a sub-pixel by the peak of their cross-correlation, the residual, and both MTFs
//! with their radially-minimum curves and AUC.

use ndarray::Array2;
use rustfft::num_complex::Complex64;

use super::shift::{shifted, transform};
use crate::SimError;
use crate::analysis::mtf::{Mtf, mtf_of};

/// One channel's comparison.
#[derive(Debug, Clone)]
pub struct ChannelComparison {
    /// The measured PSF, cropped to the common side, unit sum.
    pub measured: Array2<f64>,
    /// The simulated PSF on the same grid, moved onto the measured one, unit sum.
    pub simulated: Array2<f64>,
    /// How far the simulated PSF was moved to match, `[rows, cols]` pixels.
    pub shift_px: [f64; 2],
    /// `measured − simulated`.
    pub residual: Array2<f64>,
    /// The residual's energy over the measured PSF's: `Σ r² / Σ m²` (0: identical).
    pub residual_energy_share: f64,
    /// Pearson correlation of the two PSFs.
    pub correlation: f64,
    /// The measured PSF's MTF.
    pub mtf_measured: Mtf,
    /// The simulated PSF's MTF.
    pub mtf_simulated: Mtf,
}

/// A measured channel beside the design channel it was compared with.
#[derive(Debug, Clone)]
pub struct ComparedChannel {
    /// The measured channel's name.
    pub name: String,
    /// The design channel's name.
    pub design_channel: String,
    /// The comparison.
    pub comparison: ChannelComparison,
}

/// Every channel of `set` compared with `design` simulated on the set's grid
/// ([`super::design_on_grid`], full quality): each measured channel with the design channel
/// nearest in wavelength when it has one, else the one of its name (R, G, B), else the one at
/// its index. The design's PSFs take their Fraunhofer step on `route`.
///
/// # Errors
/// A set that fails its check, a design that does not simulate on the set's grid, a cancel.
pub fn compare_set(
    design: &crate::design::Design,
    set: &super::PsfSet,
    route: &dyn crate::psf::route::Fraunhofer,
    progress: &crate::progress::Progress,
) -> Result<Vec<ComparedChannel>, SimError> {
    use crate::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
    set.check()?;
    let on_grid = super::design_on_grid(design, set);
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let analysis = analyze_with_route(&on_grid, &options, route, progress)?;
    set.channels
        .iter()
        .enumerate()
        .map(|(i, channel)| {
            let k = match channel.wavelength_nm {
                Some(w) => analysis
                    .channels
                    .iter()
                    .enumerate()
                    .min_by(|a, b| {
                        (a.1.wavelength_nm - w)
                            .abs()
                            .total_cmp(&(b.1.wavelength_nm - w).abs())
                    })
                    .map_or(0, |(i, _)| i),
                None => analysis
                    .channels
                    .iter()
                    .position(|c| c.name.eq_ignore_ascii_case(&channel.name))
                    .unwrap_or(i.min(analysis.channels.len().saturating_sub(1))),
            };
            let sim = &analysis.channels[k];
            let comparison = compare(&channel.psf, &sim.psf).map_err(|e| match e {
                SimError::InvalidSetting { message, .. } => {
                    SimError::invalid(format!("channel {}", channel.name), message)
                }
                e => e,
            })?;
            Ok(ComparedChannel {
                name: channel.name.clone(),
                design_channel: sim.name.clone(),
                comparison,
            })
        })
        .collect()
}

/// `a` cropped (or padded with zeros) to `side × side` about its axis sample `[N/2, N/2]`.
pub fn centred_to(a: &Array2<f64>, side: usize) -> Array2<f64> {
    let n = a.nrows() as i64;
    let (c_in, c_out) = (n / 2, (side / 2) as i64);
    Array2::from_shape_fn((side, side), |(y, x)| {
        let (sy, sx) = (y as i64 - c_out + c_in, x as i64 - c_out + c_in);
        if sy >= 0 && sx >= 0 && sy < n && sx < a.ncols() as i64 {
            a[[sy as usize, sx as usize]]
        } else {
            0.0
        }
    })
}

/// The shift `[dy, dx]` that moves `b` onto `a` (both `n × n`): the peak of their circular
/// cross-correlation, refined by a parabola through it and its neighbours.
pub fn alignment(a: &Array2<f64>, b: &Array2<f64>) -> [f64; 2] {
    let n = a.nrows();
    let mut fa: Vec<Complex64> = a.iter().map(|v| Complex64::new(*v, 0.0)).collect();
    let mut fb: Vec<Complex64> = b.iter().map(|v| Complex64::new(*v, 0.0)).collect();
    transform(&mut fa, n, false);
    transform(&mut fb, n, false);
    let mut xc: Vec<Complex64> = fa.iter().zip(&fb).map(|(x, y)| x * y.conj()).collect();
    transform(&mut xc, n, true);
    let at = |y: usize, x: usize| xc[(y % n) * n + (x % n)].re;
    let (mut py, mut px, mut best) = (0, 0, f64::NEG_INFINITY);
    for y in 0..n {
        for x in 0..n {
            if at(y, x) > best {
                (py, px, best) = (y, x, at(y, x));
            }
        }
    }
    let refine = super::parabola_peak;
    let dy = refine(at(py + n - 1, px), best, at(py + 1, px));
    let dx = refine(at(py, px + n - 1), best, at(py, px + 1));
    // Lags past the middle are negative.
    let signed = |k: usize| {
        if 2 * k > n {
            k as f64 - n as f64
        } else {
            k as f64
        }
    };
    [signed(py) + dy, signed(px) + dx]
}

/// Compares `measured` with `simulated` (both square, axis at `[N/2, N/2]`, on one pixel
/// pitch): both cropped to the smaller side, the simulated one moved onto the measured one.
///
/// # Errors
/// A PSF that is not square, is empty or holds no light.
pub fn compare(
    measured: &Array2<f64>,
    simulated: &Array2<f64>,
) -> Result<ChannelComparison, SimError> {
    for (name, a) in [("measured", measured), ("simulated", simulated)] {
        if a.nrows() != a.ncols() || a.is_empty() {
            return Err(SimError::invalid(
                name,
                format!("the PSF must be square, got {}×{}", a.nrows(), a.ncols()),
            ));
        }
        if !(a.sum() > 0.0) || a.iter().any(|v| !v.is_finite()) {
            return Err(SimError::invalid(name, "the PSF holds no finite light"));
        }
    }
    let side = measured.nrows().min(simulated.nrows());
    let m = centred_to(measured, side);
    let m = &m / m.sum();
    let s = centred_to(simulated, side);
    let s = &s / s.sum();
    let shift_px = alignment(&m, &s);
    let s = shifted(&s, shift_px[0], shift_px[1]);
    let s = &s / s.sum();
    let residual = &m - &s;
    let m_energy: f64 = m.iter().map(|v| v * v).sum();
    let residual_energy_share = residual.iter().map(|v| v * v).sum::<f64>() / m_energy.max(1e-300);
    let n = (side * side) as f64;
    let (mm, sm) = (1.0 / n, 1.0 / n);
    let (mut cov, mut vm, mut vs) = (0.0, 0.0, 0.0);
    for (a, b) in m.iter().zip(s.iter()) {
        cov += (a - mm) * (b - sm);
        vm += (a - mm) * (a - mm);
        vs += (b - sm) * (b - sm);
    }
    let correlation = cov / (vm * vs).sqrt().max(1e-300);
    Ok(ChannelComparison {
        mtf_measured: mtf_of(&m),
        mtf_simulated: mtf_of(&s),
        measured: m,
        simulated: s,
        shift_px,
        residual,
        residual_energy_share,
        correlation,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(n: usize, cy: f64, cx: f64, w: f64) -> Array2<f64> {
        Array2::from_shape_fn((n, n), |(y, x)| {
            let (dy, dx) = (y as f64 - cy, x as f64 - cx);
            (-(dy * dy + dx * dx) / (2.0 * w * w)).exp()
        })
    }

    #[test]
    fn a_moved_copy_aligns_back_and_leaves_no_residual() {
        let n = 64;
        let a = spot(n, 32.0, 32.0, 2.5);
        let b = shifted(&a, -1.3, 0.6);
        let c = compare(&a, &b).expect("compared");
        assert!((c.shift_px[0] - 1.3).abs() < 0.05, "{:?}", c.shift_px);
        assert!((c.shift_px[1] + 0.6).abs() < 0.05, "{:?}", c.shift_px);
        assert!(
            c.residual_energy_share < 1e-3,
            "{}",
            c.residual_energy_share
        );
        assert!(c.correlation > 0.999);
    }

    #[test]
    fn a_wider_simulation_shows_in_the_residual_and_the_mtf() {
        let (a, b) = (spot(64, 32.0, 32.0, 2.0), spot(96, 48.0, 48.0, 3.0));
        let c = compare(&a, &b).expect("compared");
        assert_eq!(c.measured.dim(), (64, 64), "the smaller side");
        assert!(c.residual_energy_share > 0.05);
        // The narrower measured PSF passes more contrast at every frequency past DC.
        let (m, s) = (&c.mtf_measured.radial_mean, &c.mtf_simulated.radial_mean);
        assert!(m.iter().zip(s).skip(1).take(20).all(|(x, y)| x > y));
        assert!(c.mtf_measured.auc_radial_min > c.mtf_simulated.auc_radial_min);
    }

    #[test]
    fn a_psf_that_is_not_square_is_refused() {
        let e = compare(&Array2::ones((4, 5)), &Array2::ones((4, 4))).unwrap_err();
        assert!(e.to_string().contains("square"));
    }
}
