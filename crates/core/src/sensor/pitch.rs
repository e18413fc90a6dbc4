//! The optimal pixel pitch (§5.5.1, conventions.md §8), with `l0` in e⁻/µm², `p` in µm and `f0` in
//! cycles/µm.
//!
//! A sinusoid of peak `l0` and mean `l0/2` seen through pixels of pitch `p` has the contrast
//! `c(f0) = |l0 p sin(π p f0) / (π f0)|` (= `l0 p² sinc(p f0)`; the thesis's eqs. 5.4 and 5.7
//! print `p²` in front of the `sin/(π f0)` form, a typo) and the noise
//! `σ² = σ_pre² + σ_post²/g² + l0 p²/2`, independent of `f0`. The cutoff is the lowest `f0`
//! where `c/σ` falls to `SNR_t`; the optimal pitch maximises it. The thesis does not clamp the
//! cutoff at Nyquist `1/(2p)`: neither does this module, which gives [`nyquist_cyc_per_um`] for
//! the plot.

use super::{BIN_SIZES, SensorSpec};

/// `c(f0)` for each frequency (`f0 = 0` gives `l0 p²`).
fn contrast(light_e_per_um2: f64, pitch_um: f64, f: f64) -> f64 {
    let x = std::f64::consts::PI * pitch_um * f;
    let sinc = if x.abs() < 1e-12 { 1.0 } else { x.sin() / x };
    (light_e_per_um2 * pitch_um * pitch_um * sinc).abs()
}

/// `σ = √(σ_pre² + σ_post²/g² + l0 p²/2)`, electrons.
pub fn noise_sigma_e(light_e_per_um2: f64, pitch_um: f64, sensor: &SensorSpec, gain: f64) -> f64 {
    (sensor.sigma_pre_e.powi(2)
        + (sensor.sigma_post_e / gain).powi(2)
        + light_e_per_um2 * pitch_um * pitch_um / 2.0)
        .sqrt()
}

/// Fig. 5.3(a): the contrast and the noise σ (electrons) at each frequency.
pub fn contrast_noise(
    light_e_per_um2: f64,
    pitch_um: f64,
    sensor: &SensorSpec,
    gain: f64,
    freqs_cyc_per_um: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let sigma = noise_sigma_e(light_e_per_um2, pitch_um, sensor, gain);
    (
        freqs_cyc_per_um
            .iter()
            .map(|f| contrast(light_e_per_um2, pitch_um, *f))
            .collect(),
        vec![sigma; freqs_cyc_per_um.len()],
    )
}

/// Nyquist frequency of pitch `p`: `1/(2p)` cycles/µm.
pub fn nyquist_cyc_per_um(pitch_um: f64) -> f64 {
    0.5 / pitch_um
}

/// The lowest frequency where `c/σ` falls to `snr_t` (on the main lobe, `0 < f0 < 1/p`, where
/// `c` decreases); 0 when even the mean level (`f0 = 0`) is below the threshold.
pub fn cutoff_cyc_per_um(
    light_e_per_um2: f64,
    pitch_um: f64,
    sensor: &SensorSpec,
    gain: f64,
    snr_t: f64,
) -> f64 {
    if !(light_e_per_um2 > 0.0 && pitch_um > 0.0) {
        return 0.0;
    }
    let sigma = noise_sigma_e(light_e_per_um2, pitch_um, sensor, gain);
    let snr = |f: f64| contrast(light_e_per_um2, pitch_um, f) / sigma;
    if !(snr(0.0) > snr_t) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0 / pitch_um);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if snr(mid) > snr_t {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The candidate pitch with the highest cutoff (the first of equal ones); when nothing is
/// resolved at any pitch (every cutoff 0), the largest candidate. NaN without candidates.
pub fn optimal_pitch_um(
    light_e_per_um2: f64,
    candidate_pitches_um: &[f64],
    sensor: &SensorSpec,
    gain: f64,
    snr_t: f64,
) -> f64 {
    let mut best = (f64::NAN, 0.0);
    for &p in candidate_pitches_um {
        let f = cutoff_cyc_per_um(light_e_per_um2, p, sensor, gain, snr_t);
        if best.0.is_nan() || f > best.1 {
            best = (p, f);
        }
    }
    if best.1 > 0.0 {
        best.0
    } else {
        candidate_pitches_um
            .iter()
            .copied()
            .fold(f64::NAN, f64::max)
    }
}

/// Fig. 5.3(b): the optimal pitch at each light level.
pub fn optimal_pitch_curve(
    lights_e_per_um2: &[f64],
    candidate_pitches_um: &[f64],
    sensor: &SensorSpec,
    gain: f64,
    snr_t: f64,
) -> Vec<f64> {
    lights_e_per_um2
        .iter()
        .map(|l| optimal_pitch_um(*l, candidate_pitches_um, sensor, gain, snr_t))
        .collect()
}

/// The bin side (one of [`BIN_SIZES`]) whose pitch `n · unit pixel` is optimal at this light.
pub fn optimal_bin(light_e_per_um2: f64, sensor: &SensorSpec, gain: f64, snr_t: f64) -> usize {
    let pitches: Vec<f64> = BIN_SIZES
        .iter()
        .map(|n| *n as f64 * sensor.unit_pixel_um)
        .collect();
    let p = optimal_pitch_um(light_e_per_um2, &pitches, sensor, gain, snr_t);
    BIN_SIZES
        .iter()
        .zip(&pitches)
        .find(|(_, q)| **q == p)
        .map_or(1, |(n, _)| *n)
}
