//! The noise model of eq. 5.1: `i = Φ{g·(l + n_pre) + n_post} + i0`, `l ~ Poisson(l*)`, and its
//! inverse `l̂ = (i − i0)/g` (eq. 5.2).
//!
//! An exposure is drawn once as a [`Frame`]: per pixel the charge `min(l, l_wc) + n_pre` and a
//! post-amplifier noise sample `n_post`. Readouts are then deterministic: a pixel read at gain
//! `g` gives `Φ{g·charge + n_post}`, a bin read in an analog mode uses the `n_post` of its
//! top-left pixel. Every readout strategy of one run reads the same frame (common random
//! numbers: they differ only by what they do, not by luck). The ADC [`Adc`] maps
//! `[−i0, l_wc]` electrons (at base gain) onto codes `0 … 2^bits − 1` with the black level at
//! code `i0`; a pixel whose code is the top code is saturated.

use ndarray::{Array2, ArrayView2, Axis};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Poisson, StandardNormal};
use rayon::prelude::*;

use super::SensorSpec;

/// Noise streams of one run: each (stream, image row) pair has its own ChaCha8 stream, so
/// results do not depend on the number of threads.
pub mod stream {
    /// Photons and read noise of the capture that every strategy reads.
    pub const CAPTURE: u64 = 1;
    /// Photons and read noise of the two-shot strategies' snapshot.
    pub const SNAPSHOT: u64 = 2;
}

/// The ChaCha8 stream of one image row of one noise stream.
pub fn row_rng(seed: u64, stream: u64, row: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream((stream << 40) ^ row as u64);
    rng
}

/// The ADC and black level of a sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Adc {
    /// The top code, `2^bits − 1`.
    pub max_code: f64,
    /// The black level `i0`, codes.
    pub black_dn: f64,
    /// Electrons (at base gain) per code: the full well spans the codes above the black level.
    pub e_per_dn: f64,
}

impl Adc {
    /// The ADC of `sensor`: its bit depth, black level and full well.
    pub fn of(sensor: &SensorSpec) -> Adc {
        let max_code = ((1u64 << sensor.adc_bits.clamp(1, 52)) - 1) as f64;
        let black_dn = (sensor.black_level_fraction * max_code).round();
        Adc {
            max_code,
            black_dn,
            e_per_dn: sensor.full_well_e / (max_code - black_dn).max(1.0),
        }
    }

    /// `Φ{v} + i0`: the code of an amplified signal of `v_e` electrons (at base gain) and whether
    /// it is the top code (saturated).
    pub fn digitise(&self, v_e: f64) -> (f64, bool) {
        // Round half up by truncating `t + 0.5 ≥ 0` (one instruction, where `round` is a libm
        // call on the baseline x86-64 target); NaN lands on code 0.
        let t = (self.black_dn + v_e * (1.0 / self.e_per_dn)).clamp(-0.5, self.max_code);
        let dn = (t + 0.5) as i64 as f64;
        let dn = dn.min(self.max_code);
        (dn, dn >= self.max_code)
    }

    /// `Φ⁻¹(i − i0)`: electrons at base gain of a code.
    pub fn electrons(&self, dn: f64) -> f64 {
        (dn - self.black_dn) * self.e_per_dn
    }
}

/// One exposure's random draws, `[row, col]` per unit pixel, kept in `f32`: drawn in `f64`,
/// then rounded to about 7 significant digits (at most 0.004 e⁻ on a 60 000 e⁻ well, 0.0001 e⁻
/// at Table 5.4's 1 000 e⁻), far below the ADC's step and the read noise; readouts compute in
/// `f64`. Half the memory of `f64` draws, which every strategy reads to the end of a run.
#[derive(Debug, Clone)]
pub struct Frame {
    /// `min(Poisson(l*), l_wc) + n_pre`, electrons.
    pub charge_e: Array2<f32>,
    /// `n_post`, electrons at base gain.
    pub post_noise_e: Array2<f32>,
}

/// A Poisson draw of mean `mean_e` (≥ 0), clipped at the full well. Means far beyond the full
/// well skip the draw: the well is full either way.
pub(crate) fn photons(mean_e: f64, full_well_e: f64, rng: &mut ChaCha8Rng) -> f64 {
    if !(mean_e > 0.0) {
        return 0.0;
    }
    if mean_e > 2.0 * full_well_e + 100.0 || !mean_e.is_finite() {
        return full_well_e;
    }
    let l = match Poisson::new(mean_e) {
        Ok(p) => p.sample(rng),
        Err(_) => mean_e,
    };
    l.min(full_well_e)
}

/// Draws one exposure of the expected electrons `electrons` (per unit pixel): per pixel, in
/// row order, the photons, `n_pre` and `n_post`, from the row's stream of `stream`.
pub fn expose_frame(
    electrons: ArrayView2<'_, f64>,
    sensor: &SensorSpec,
    seed: u64,
    stream: u64,
) -> Frame {
    let dim = electrons.dim();
    let mut charge = Array2::<f32>::zeros(dim);
    let mut post = Array2::<f32>::zeros(dim);
    let (s_pre, s_post, well) = (sensor.sigma_pre_e, sensor.sigma_post_e, sensor.full_well_e);
    charge
        .axis_iter_mut(Axis(0))
        .into_par_iter()
        .zip(post.axis_iter_mut(Axis(0)).into_par_iter())
        .enumerate()
        .for_each(|(y, (mut c_row, mut p_row))| {
            let mut rng = row_rng(seed, stream, y);
            let e_row = electrons.row(y);
            for ((c, p), e) in c_row.iter_mut().zip(p_row.iter_mut()).zip(e_row.iter()) {
                let l = photons(*e, well, &mut rng);
                let n_pre: f64 = StandardNormal.sample(&mut rng);
                let n_post: f64 = StandardNormal.sample(&mut rng);
                #[allow(clippy::cast_possible_truncation)]
                {
                    *c = (l + s_pre * n_pre) as f32;
                    *p = (s_post * n_post) as f32;
                }
            }
        });
    Frame {
        charge_e: charge,
        post_noise_e: post,
    }
}

/// One bin's (or pixel's) readout.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BinRead {
    /// `l̂`: the estimated electrons per unit pixel.
    pub estimate_e: f64,
    /// Whether the bin's code (or one of its pixels' codes, digitally) hit the top.
    pub saturated: bool,
}

/// Reads one pixel at gain `gain`: `l̂ = Φ⁻¹(Φ{g·charge + n_post})/g`.
pub fn read_pixel(charge_e: f64, post_noise_e: f64, gain: f64, adc: &Adc) -> BinRead {
    let (dn, saturated) = adc.digitise(gain * charge_e + post_noise_e);
    BinRead {
        // `* (1 / g)`: loop-invariant in a row of equal gains, so it is hoisted.
        estimate_e: adc.electrons(dn) * (1.0 / gain),
        saturated,
    }
}

/// Reads the analog sum `charge_sum_e` of a bin of `pixels` pixels in an analog `mode` at
/// amplifier gain `amp_gain`, with one post-amplifier sample: average binning digitises
/// `g·sum/N + n_post`, additive binning `ĝ·sum + n_post`; both return the per-pixel estimate.
pub fn read_analog(
    mode: super::BinMode,
    amp_gain: f64,
    charge_sum_e: f64,
    pixels: usize,
    post_noise_e: f64,
    adc: &Adc,
) -> BinRead {
    let n = pixels.max(1) as f64;
    match mode {
        super::BinMode::AnalogAdditive => {
            let (dn, saturated) = adc.digitise(amp_gain * charge_sum_e + post_noise_e);
            BinRead {
                estimate_e: adc.electrons(dn) / (amp_gain * n),
                saturated,
            }
        }
        _ => read_pixel(charge_sum_e / n, post_noise_e, amp_gain, adc),
    }
}

/// Reads a bin of `charges.len()` pixels in `mode` at amplifier gain `amp_gain` (for
/// [`super::BinMode::AnalogAdditive`] this is `ĝ`; see [`super::BinMode::amplifier_gain`]).
/// Analog modes use `post_noise[0]` once; the digital mode reads every pixel with its own.
/// Returns the per-pixel estimate (Table 5.1's imaging models).
pub fn read_bin(
    mode: super::BinMode,
    amp_gain: f64,
    charges: &[f64],
    post_noise: &[f64],
    adc: &Adc,
) -> BinRead {
    let post0 = post_noise.first().copied().unwrap_or(0.0);
    match mode {
        _ if charges.len() == 1 => read_pixel(charges[0], post0, amp_gain, adc),
        super::BinMode::Digital => {
            let mut sum = 0.0;
            let mut saturated = false;
            for (c, p) in charges.iter().zip(post_noise) {
                let r = read_pixel(*c, *p, amp_gain, adc);
                sum += r.estimate_e;
                saturated |= r.saturated;
            }
            BinRead {
                estimate_e: sum / charges.len().max(1) as f64,
                saturated,
            }
        }
        _ => read_analog(
            mode,
            amp_gain,
            charges.iter().sum(),
            charges.len(),
            post0,
            adc,
        ),
    }
}
