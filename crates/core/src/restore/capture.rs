//! The camera behind the display (conventions.md §5): blur, photon noise, read noise, full well and
//! ADC, with the light level given as electrons or as an SNR.

use crate::{Setting, SettingPath};
use ndarray::{Array2, ArrayView2};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};
use rayon::prelude::*;

use super::spectrum::{PadGrid, Spectrum};
use crate::{Sample, SimError};

/// Read noise of the thesis's phone camera, electrons RMS (§3.5).
pub const READ_NOISE_E: f64 = 4.87;
/// Full-well capacity of the thesis's phone camera, electrons (§3.5).
pub const FULL_WELL_E: f64 = 15506.0;
/// LTR of the reference display that `ltr_relative = 1` stands for: the T-OLED 150-DPI preset,
/// a slit 5 of 21 cells wide. Its open fraction is used rather than its pupil LTR (0.237886 with
/// the iccp21 optics, 0.09 % lower): a constant does not move with the sampling or the optics, so
/// the same light level means the same photon budget in every run.
pub const REFERENCE_LTR: f64 = 5.0 / 21.0;
/// The five light levels of thesis Fig. 3.8, SNR in dB (24 … 40 dB ↔ 273 … 10024 e⁻).
pub const THESIS_SNR_DB: [f64; 5] = [24.0, 28.0, 32.0, 36.0, 40.0];

/// How bright the scene is: the electrons a sharp pixel of value 1 collects behind the reference
/// display, or the equivalent SNR `20 log10(L / sqrt(L + σ_read²))` at that pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// `L` given directly: electrons at a sharp pixel of value 1.
    ElectronsAtPeak(f64),
    /// `L` given as the SNR at that pixel, dB.
    SnrDb(f64),
}

impl Light {
    /// Electrons at the brightest pixel, solving `SNR = 20 log10(L / sqrt(L + σ²))` for `L`
    /// when given an SNR: `L² − s²L − s²σ² = 0` with `s = 10^(SNR/20)`, positive root.
    pub fn electrons(self, read_noise_e: f64) -> f64 {
        match self {
            Light::ElectronsAtPeak(l) => l,
            Light::SnrDb(db) => {
                let s2 = 10f64.powf(db / 10.0);
                0.5 * (s2 + (s2 * s2 + 4.0 * s2 * read_noise_e * read_noise_e).sqrt())
            }
        }
    }

    /// The SNR in dB at the brightest pixel.
    pub fn snr_db(self, read_noise_e: f64) -> f64 {
        match self {
            Light::SnrDb(db) => db,
            Light::ElectronsAtPeak(l) => snr_db_of(l, read_noise_e),
        }
    }
}

/// `20 log10(L / sqrt(L + σ²))`.
pub fn snr_db_of(electrons: f64, read_noise_e: f64) -> f64 {
    20.0 * (electrons / (electrons + read_noise_e * read_noise_e).sqrt()).log10()
}

/// The sensor and the light of one capture.
#[derive(Debug, Clone, PartialEq)]
pub struct CaptureSettings {
    /// How bright the scene is: electrons or SNR at the brightest pixel.
    pub light: Light,
    /// Read noise σ, electrons (the thesis: 4.87).
    pub read_noise_e: f64,
    /// Full-well capacity, electrons (the thesis: 15506); brighter pixels clip.
    pub full_well_e: f64,
    /// ADC resolution over the full well (`Some(12)`: 4095 steps from 0 to the full well);
    /// `None` rounds to whole electrons.
    pub adc_bits: Option<u32>,
    /// The display's LTR over [`REFERENCE_LTR`]: a display that passes more light collects
    /// proportionally more electrons from the same scene (and may saturate).
    pub ltr_relative: f64,
    /// Seed of the photon and read noise.
    pub seed: u64,
    /// `false` gives an ideal sensor: no photon or read noise and no quantisation, only the blur
    /// and the full-well clip. For testing the optics alone.
    pub noise: bool,
}

impl Default for CaptureSettings {
    /// The thesis camera at 28 dB behind the reference display, without ADC quantisation (the
    /// thesis states none).
    fn default() -> Self {
        CaptureSettings {
            light: Light::SnrDb(28.0),
            read_noise_e: READ_NOISE_E,
            full_well_e: FULL_WELL_E,
            adc_bits: None,
            ltr_relative: 1.0,
            seed: 0,
            noise: true,
        }
    }
}

fn positive(field: impl Into<SettingPath>, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SimError::invalid(
            field,
            format!("must be a positive number (got {v:?})"),
        ))
    }
}

impl CaptureSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] naming the first bad field (`capture.light`, …).
    pub fn validate(&self) -> Result<(), SimError> {
        match self.light {
            Light::ElectronsAtPeak(l) => positive(Setting::CaptureElectronsAtPeak, l)?,
            Light::SnrDb(db) => {
                if !db.is_finite() {
                    return Err(SimError::invalid(
                        Setting::CaptureSnrDb,
                        format!("must be a finite number of dB (got {db:?})"),
                    ));
                }
            }
        }
        if !(self.read_noise_e.is_finite() && self.read_noise_e >= 0.0) {
            return Err(SimError::invalid(
                "capture.read_noise_e",
                format!("must be ≥ 0 electrons (got {:?})", self.read_noise_e),
            ));
        }
        positive("capture.full_well_e", self.full_well_e)?;
        positive("capture.ltr_relative", self.ltr_relative)?;
        if let Some(bits) = self.adc_bits
            && !(1..=24).contains(&bits)
        {
            return Err(SimError::invalid(
                Setting::CaptureAdcBits,
                format!("must be 1 … 24 bits (got {bits})"),
            ));
        }
        // Fewer than one electron at white is darkness (no PSNR to speak of); more than 100 full
        // wells is every pixel clipped: both are refused rather than scored.
        let l = self.light.electrons(self.read_noise_e);
        let (lo, hi) = (1.0, 100.0 * self.full_well_e);
        if !(l.is_finite() && (lo..=hi).contains(&l)) {
            let field = match self.light {
                Light::ElectronsAtPeak(_) => Setting::CaptureElectronsAtPeak,
                Light::SnrDb(_) => Setting::CaptureSnrDb,
            };
            return Err(SimError::invalid(
                field,
                format!(
                    "gives {l:.3e} electrons at white; the light must give {lo} … {hi:.0} \
                     electrons (SNR {:.1} … {:.1} dB)",
                    snr_db_of(lo, self.read_noise_e),
                    snr_db_of(hi, self.read_noise_e)
                ),
            ));
        }
        Ok(())
    }

    /// Electrons that a sharp pixel of value 1 collects behind this display: `L · ltr_relative`.
    pub fn electrons_per_unit(&self) -> f64 {
        self.light.electrons(self.read_noise_e) * self.ltr_relative
    }

    /// The step a noisy capture is rounded to, in electrons: the ADC's (full well over
    /// `2^bits − 1` levels), or one electron without an ADC.
    pub fn adc_step_e(&self) -> f64 {
        self.adc_bits
            .map_or(1.0, |bits| self.full_well_e / f64::from((1u32 << bits) - 1))
    }
}

/// The ChaCha8 stream of one image row of one channel: rows draw independently, so the noise is
/// the same whatever the number of threads and whatever order rows are processed in.
fn row_rng(seed: u64, channel: usize, row: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(((channel as u64) << 40) ^ row as u64);
    rng
}

/// The sharp plane blurred by the kernel whose spectrum is `kernel` (linear 'same' convolution,
/// kernel centre on the pixel it blurs; see [`super::spectrum`]).
pub fn blur(grid: &PadGrid, sharp: ArrayView2<'_, f64>, kernel: &Spectrum) -> Array2<f64> {
    grid.filter(sharp, |i, v| v * kernel.data[i])
}

/// One captured channel.
#[derive(Debug, Clone)]
pub struct Captured<T = f64> {
    /// The capture on the ground truth's scale (electrons / `L·ltr_relative`).
    pub image: Array2<T>,
    /// Fraction of pixels at the full well.
    pub saturated_fraction: f64,
}

/// Turns a blurred plane (sharp value 1 ↦ 1) into a capture: electrons `Poisson(e·x)` plus read
/// noise `N(0, σ²)`, clipped to `[0, full well]`, quantised, divided by `e = L·ltr_relative`.
/// Channel `channel` selects the noise streams.
///
/// # Errors
/// [`SimError::InvalidSetting`] for bad settings.
pub fn expose<T: Sample>(
    blurred: ArrayView2<'_, T>,
    settings: &CaptureSettings,
    channel: usize,
) -> Result<Captured<T>, SimError> {
    settings.validate()?;
    let e = settings.electrons_per_unit();
    let full = settings.full_well_e;
    let (h, w) = blurred.dim();
    let read = Normal::new(0.0, settings.read_noise_e)
        .map_err(|err| SimError::invalid("capture.read_noise_e", err.to_string()))?;
    let step_e = settings.adc_step_e();
    let mut out = Array2::<T>::default((h, w));
    let saturated: usize = out
        .axis_iter_mut(ndarray::Axis(0))
        .into_par_iter()
        .zip(blurred.axis_iter(ndarray::Axis(0)).into_par_iter())
        .enumerate()
        .map(|(y, (mut out_row, in_row))| {
            let mut rng = row_rng(settings.seed, channel, y);
            let mut saturated = 0usize;
            for (o, x) in out_row.iter_mut().zip(in_row.iter()) {
                // Round-off of the FFT blur can leave tiny negatives where the scene is black.
                let mean_e = ((*x).into() * e).max(0.0);
                let electrons = if settings.noise {
                    let photons = match Poisson::new(mean_e) {
                        Ok(p) => p.sample(&mut rng),
                        // λ = 0 (black) or a λ beyond the sampler's range (far past the full
                        // well, clipped below anyway).
                        Err(_) => mean_e,
                    };
                    let raw = (photons + read.sample(&mut rng)).clamp(0.0, full);
                    (raw / step_e).round() * step_e
                } else {
                    mean_e.min(full)
                };
                if electrons >= full {
                    saturated += 1;
                }
                *o = T::from_f64(electrons / e);
            }
            saturated
        })
        .sum();
    Ok(Captured {
        image: out,
        saturated_fraction: saturated as f64 / (h * w).max(1) as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thesis_light_levels_match_their_snr() {
        let pairs = [
            (273.0, 24.0),
            (654.0, 28.0),
            (1608.0, 32.0),
            (4005.0, 36.0),
            (10024.0, 40.0),
        ];
        for (e, db) in pairs {
            let l = Light::SnrDb(db).electrons(READ_NOISE_E);
            assert!((l - e).abs() < 0.5, "{db} dB → {l} e⁻, thesis {e}");
            let back = Light::ElectronsAtPeak(e).snr_db(READ_NOISE_E);
            assert!((back - db).abs() < 0.01, "{e} e⁻ → {back} dB");
        }
    }

    #[test]
    fn bad_settings_name_their_field() {
        let mut s = CaptureSettings {
            light: Light::ElectronsAtPeak(f64::NAN),
            ..CaptureSettings::default()
        };
        let msg = s
            .validate()
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(msg.contains("capture.light.electrons_at_peak"), "{msg}");
        s.light = Light::SnrDb(30.0);
        s.ltr_relative = 0.0;
        let msg = s
            .validate()
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(msg.contains("capture.ltr_relative"), "{msg}");
        s.ltr_relative = 1.0;
        s.full_well_e = -1.0;
        let msg = s
            .validate()
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(msg.contains("capture.full_well_e"), "{msg}");
    }

    #[test]
    fn adc_quantises_over_the_full_well() {
        let s = CaptureSettings {
            light: Light::ElectronsAtPeak(1000.0),
            adc_bits: Some(4),
            read_noise_e: 0.0,
            ..CaptureSettings::default()
        };
        let flat = Array2::from_elem((4, 50), 0.8);
        let c = expose(flat.view(), &s, 0).expect("valid");
        let step = FULL_WELL_E / 15.0;
        for v in &c.image {
            let dn = v * 1000.0 / step;
            assert!((dn - dn.round()).abs() < 1e-9, "{dn} is not a whole DN");
        }
    }
}
