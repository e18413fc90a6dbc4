//! Denoise, then deblur (conventions.md §5): what every simulated number of thesis chapters 3 and
//! 4 did. The denoiser is BM3D ([`crate::denoise::bm3d`], CBM3D for a colour capture) given
//! a noise variance σ²; the thesis tabulates σ² per light level, one table per chapter
//! ([`Recipe`]).
//!
//! **Scale.** σ² is a variance, so it lives on the scale of the image it describes. The thesis
//! states its tables on its own scales:
//! - chapter 3 ([`Recipe::Iccp21`]): the capture is gain-normalised at the *reference* display,
//!   `y₃ = electrons / L`, so a display passing `r = ltr_relative` times the reference's light
//!   reads `≈ r` at white;
//! - chapter 4 ([`Recipe::Iccv23`]): the gain is `1/(L·LTR)` of each setup, so every capture reads
//!   `≈ 1` at white.
//!
//! Our display capture is `y = electrons / (L·r)` (white reads ≈ 1: chapter 4's scale), so
//! `y₃ = r·y` and a variance `σ₃²` on the chapter-3 scale is `σ₃² / r²` on ours; chapter 4's σ²
//! applies as it stands. [`Sigma2::resolve`] does this conversion; a σ² given by the user
//! ([`Sigma2::Fixed`]) is on our scale, the one BM3D sees and the captured images are written on.
//! Handing chapter 3's σ² to a capture on our scale unconverted would make BM3D over- or
//! under-smooth by `r²` (a display passing twice the reference's light: 4×).
//!
//! **Matched σ², the default.** [`Sigma2::Matched`] gives BM3D the variance this capture really
//! has at a white pixel, `1/e + σ_read²/e² + q²/12` for `e` electrons at white and an ADC step
//! `q` (Poisson, read noise and quantisation, on the scale where white reads 1; chapter 4's
//! 12-bit capture has `q = 1/4095`, so `e = L·LTR` gives conventions.md §5's
//! `1/(L·LTR) + σ_read²/(L·LTR)² + 1/(12·4095²)`). The authors' tables ([`Sigma2::Thesis`],
//! "the authors' table" in the CLI and the studio) stay for comparisons with their code:
//! chapter 4's is that variance for a display that passes all the light (`e = L`: 0.0040,
//! 0.0016, 0.00063, 0.00025, 0.00010 at 24 … 40 dB against the table's 0.005, 0.002, 0.0005,
//! 0.00025, 0.0001), so it understates the noise of a display passing `LTR` of the light by
//! `1/LTR`: 2× for the double MLA, 4× for the T-OLED, 12× for the P-OLED, and BM3D told the
//! table leaves most of that noise in.

use super::capture::{CaptureSettings, THESIS_SNR_DB};
use crate::SimError;

/// Chapter 3's σ² (ICCP 2021) at SNR 24 / 28 / 32 / 36 / 40 dB ([`THESIS_SNR_DB`]), on the
/// capture gain-normalised at the reference display; restored there by Wiener, nsr 0.00371.
pub const ICCP21_SIGMA2: [f64; 5] = [0.005, 0.002, 0.002, 0.001, 0.0002];
/// Chapter 4's σ² (ICCV 2023) at SNR 24 … 40 dB, on a capture that reads ≈ 1 at white in every
/// setup; restored there by least squares with a gradient prior ([`ICCV23_LAMBDA`]).
pub const ICCV23_SIGMA2: [f64; 5] = [0.005, 0.002, 0.0005, 0.00025, 0.0001];
/// Chapter 4's gradient weight λ at SNR 24 … 40 dB, used after its BM3D.
pub const ICCV23_LAMBDA: [f64; 5] = [0.01, 0.005, 0.005, 0.005, 0.001];
/// Chapter 4's conjugate-gradient iterations after BM3D.
pub const ICCV23_CG_ITERATIONS: usize = 150;
/// Chapter 4's conjugate-gradient tolerance after BM3D.
pub const ICCV23_CG_TOLERANCE: f64 = 1e-6;

/// Whose σ² table: a closed set, one per thesis chapter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recipe {
    /// Chapter 3, the display openings (ICCP 2021): [`ICCP21_SIGMA2`].
    Iccp21,
    /// Chapter 4, the phase masks (ICCV 2023): [`ICCV23_SIGMA2`].
    Iccv23,
}

impl Recipe {
    /// The name used in JSON and docs: `iccp21` or `iccv23`.
    pub fn name(self) -> &'static str {
        match self {
            Recipe::Iccp21 => "iccp21",
            Recipe::Iccv23 => "iccv23",
        }
    }

    /// The σ² per row of [`THESIS_SNR_DB`], on the recipe's own scale (module docs).
    pub fn table(self) -> &'static [f64; 5] {
        match self {
            Recipe::Iccp21 => &ICCP21_SIGMA2,
            Recipe::Iccv23 => &ICCV23_SIGMA2,
        }
    }

    /// The σ² of the row nearest `snr_db`, on the recipe's own scale.
    pub fn sigma2(self, snr_db: f64) -> f64 {
        self.table()[nearest_row(snr_db)]
    }
}

/// The row of [`THESIS_SNR_DB`] nearest `snr_db` (the thesis tabulates five light levels; any
/// other takes the nearest). Halfway between two rows the darker one is taken: it assumes more
/// noise, and BM3D given too little σ² leaves noise the deblurring then amplifies. Below 24 dB
/// (and for NaN) the 24 dB row, above 40 dB the 40 dB row.
pub fn nearest_row(snr_db: f64) -> usize {
    let mut best = 0;
    for (i, row) in THESIS_SNR_DB.iter().enumerate() {
        if (snr_db - row).abs() < (snr_db - THESIS_SNR_DB[best]).abs() {
            best = i;
        }
    }
    best
}

/// Where the σ² handed to BM3D comes from.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Sigma2 {
    /// The authors' table of the recipe at the light level, converted to the capture's scale.
    Thesis(Recipe),
    /// The capture's own noise variance at a white pixel (module docs), whatever the light
    /// level and the display: the default.
    #[default]
    Matched,
    /// A σ² on the capture's own scale (white ≈ 1), as BM3D gets it.
    Fixed(f64),
}

/// What BM3D's σ² can depend on: the light level and the noise of the capture it is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureNoise {
    /// SNR in dB of a white pixel behind the reference display: picks the thesis table's row.
    pub snr_db: f64,
    /// Light through this display relative to the reference display's (chapter 3's scale).
    pub ltr_relative: f64,
    /// Electrons a white pixel of this capture collects, e⁻.
    pub white_e: f64,
    /// Read noise, e⁻ rms.
    pub read_noise_e: f64,
    /// The ADC's step on the capture's scale (white reads 1); 0 for an unquantised capture.
    pub adc_step: f64,
}

impl CaptureNoise {
    /// The light level and noise of a display capture taken with `cap`.
    pub fn of(cap: &CaptureSettings) -> Self {
        let white_e = cap.electrons_per_unit();
        CaptureNoise {
            snr_db: cap.light.snr_db(cap.read_noise_e),
            ltr_relative: cap.ltr_relative,
            white_e,
            read_noise_e: cap.read_noise_e,
            adc_step: if cap.noise {
                cap.adc_step_e() / white_e
            } else {
                0.0
            },
        }
    }

    /// The capture's noise variance at a white pixel, on the scale where white reads 1:
    /// `1/e + σ_read²/e² + q²/12` (Poisson, read noise and the ADC's step `q`). `NaN` for a
    /// capture that collects no light.
    pub fn white_variance(&self) -> f64 {
        let e = self.white_e;
        if !(e > 0.0) {
            return f64::NAN;
        }
        (e + self.read_noise_e * self.read_noise_e) / (e * e) + self.adc_step * self.adc_step / 12.0
    }
}

impl Sigma2 {
    /// The σ² on the scale of a capture that reads ≈ 1 at white, for the capture `at` (module
    /// docs): chapter 3's table is divided by `ltr_relative²`, chapter 4's applies as it stands.
    pub fn resolve(self, at: &CaptureNoise) -> f64 {
        match self {
            Sigma2::Thesis(Recipe::Iccp21) => {
                Recipe::Iccp21.sigma2(at.snr_db) / (at.ltr_relative * at.ltr_relative)
            }
            Sigma2::Thesis(Recipe::Iccv23) => Recipe::Iccv23.sigma2(at.snr_db),
            Sigma2::Matched => at.white_variance(),
            Sigma2::Fixed(s) => s,
        }
    }
}

/// The denoising step between the capture and the deblurring: a closed set. The default is
/// BM3D told the capture's own noise ([`Sigma2::Matched`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Denoise {
    /// Deblur the capture as it is.
    None,
    /// BM3D (CBM3D for three channels) with a noise variance.
    Bm3d {
        /// Where the noise variance comes from.
        sigma2: Sigma2,
    },
}

impl Default for Denoise {
    fn default() -> Self {
        Denoise::Bm3d {
            sigma2: Sigma2::Matched,
        }
    }
}

impl Denoise {
    /// BM3D with the authors' σ² table of `recipe`, for comparisons with their code.
    pub fn authors_table(recipe: Recipe) -> Self {
        Denoise::Bm3d {
            sigma2: Sigma2::Thesis(recipe),
        }
    }

    /// `"bm3d"` or `"none"`, as the CLI flag and the JSON spell it.
    pub fn method_name(self) -> &'static str {
        match self {
            Denoise::None => "none",
            Denoise::Bm3d { .. } => "bm3d",
        }
    }

    /// Checks a fixed σ².
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] (`denoise.sigma2`) for a σ² that is not finite and > 0.
    pub fn validate(self) -> Result<(), SimError> {
        if let Denoise::Bm3d {
            sigma2: Sigma2::Fixed(s),
        } = self
            && !crate::denoise::sigma2_in_range(s)
        {
            return Err(SimError::invalid(
                "denoise.sigma2",
                format!(
                    "must be a finite number > 0, at least {:e} and at most {} (got {s:?})",
                    crate::denoise::MIN_SIGMA2,
                    crate::denoise::MAX_SIGMA2
                ),
            ));
        }
        Ok(())
    }

    /// What this setting does for the capture `at`: `None`, or the σ² BM3D gets on a capture
    /// that reads ≈ 1 at white (see [`Sigma2::resolve`]).
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] (`denoise.sigma2`) when the σ² is not a usable variance: a
    /// matched σ² for a capture that collects no light, or one outside BM3D's range.
    pub fn applied(self, at: &CaptureNoise) -> Result<DenoiseUsed, SimError> {
        let sigma2 = match self {
            Denoise::None => None,
            Denoise::Bm3d { sigma2 } => {
                let mut s = sigma2.resolve(at);
                // Below about 25 electrons at white a capture's own variance passes 1, the top
                // of BM3D's range (images in [0, 1]): the capture is noise, and the largest σ²
                // BM3D takes is the matched one's nearest. The run reports the σ² it got.
                if sigma2 == Sigma2::Matched && s > crate::denoise::MAX_SIGMA2 {
                    s = crate::denoise::MAX_SIGMA2;
                }
                if !crate::denoise::sigma2_in_range(s) {
                    return Err(SimError::invalid(
                        "denoise.sigma2",
                        format!(
                            "{s:.4} for this capture ({:.3} e⁻ at white) is outside {:e} … {}: \
                             give more light or a σ² of your own",
                            at.white_e,
                            crate::denoise::MIN_SIGMA2,
                            crate::denoise::MAX_SIGMA2
                        ),
                    ));
                }
                Some(s)
            }
        };
        Ok(DenoiseUsed {
            setting: self,
            sigma2,
        })
    }
}

/// The denoising one run did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenoiseUsed {
    /// The setting asked for.
    pub setting: Denoise,
    /// The σ² BM3D got, on the capture's scale; `None` when not denoised.
    pub sigma2: Option<f64>,
}

impl DenoiseUsed {
    /// Where σ² came from: the recipe's name, `"matched"`, `"override"`, or `None` when not
    /// denoised.
    pub fn source(&self) -> Option<&'static str> {
        match self.setting {
            Denoise::None => None,
            Denoise::Bm3d {
                sigma2: Sigma2::Thesis(r),
            } => Some(r.name()),
            Denoise::Bm3d {
                sigma2: Sigma2::Matched,
            } => Some("matched"),
            Denoise::Bm3d {
                sigma2: Sigma2::Fixed(_),
            } => Some("override"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_tabulated_level_takes_its_own_row() {
        for (i, db) in THESIS_SNR_DB.iter().enumerate() {
            assert_eq!(nearest_row(*db), i);
            assert_eq!(Recipe::Iccp21.sigma2(*db), ICCP21_SIGMA2[i]);
            assert_eq!(Recipe::Iccv23.sigma2(*db), ICCV23_SIGMA2[i]);
        }
    }

    #[test]
    fn levels_between_rows_take_the_nearest_and_ties_the_darker() {
        assert_eq!(nearest_row(25.9), 0);
        assert_eq!(nearest_row(26.0), 0);
        assert_eq!(nearest_row(26.1), 1);
        assert_eq!(nearest_row(33.9), 2);
        assert_eq!(nearest_row(34.1), 3);
        assert_eq!(nearest_row(10.0), 0);
        assert_eq!(nearest_row(60.0), 4);
        assert_eq!(nearest_row(f64::NAN), 0);
    }

    fn at(snr_db: f64, ltr_relative: f64) -> CaptureNoise {
        CaptureNoise {
            snr_db,
            ltr_relative,
            white_e: 100.0,
            read_noise_e: 4.87,
            adc_step: 0.0,
        }
    }

    #[test]
    fn chapter_3_sigma2_is_converted_to_our_scale_and_chapter_4_is_not() {
        let s = Sigma2::Thesis(Recipe::Iccp21).resolve(&at(28.0, 2.0));
        assert!((s - 0.002 / 4.0).abs() < 1e-15, "{s}");
        let s = Sigma2::Thesis(Recipe::Iccv23).resolve(&at(32.0, 2.0));
        assert_eq!(s, 0.0005);
        assert_eq!(Sigma2::Fixed(0.003).resolve(&at(24.0, 3.0)), 0.003);
    }

    /// The matched σ² is the variance of Poisson(e) + N(0, σ_read²) divided by e², whatever the
    /// table says; chapter 4's table is that variance with all the light (e = L at each level).
    #[test]
    fn matched_sigma2_is_the_captures_white_variance() {
        let mut a = at(24.0, 1.0);
        for e in [20.0, 273.0, 10_024.0] {
            a.white_e = e;
            let want = (e + 4.87 * 4.87) / (e * e);
            let got = Sigma2::Matched.resolve(&a);
            assert!((got - want).abs() <= 1e-15 * want, "{e}: {got} vs {want}");
        }
        // Halving the light doubles the photon part: the table cannot follow a display's LTR.
        a.white_e = 200.0;
        let bright = Sigma2::Matched.resolve(&a);
        a.white_e = 100.0;
        assert!(Sigma2::Matched.resolve(&a) > 1.9 * bright);
        for (row, table) in ICCV23_SIGMA2.iter().enumerate() {
            let l = super::super::capture::Light::SnrDb(THESIS_SNR_DB[row]).electrons(4.87);
            let open = CaptureNoise {
                white_e: l,
                ..at(THESIS_SNR_DB[row], 1.0)
            };
            let ratio = Sigma2::Matched.resolve(&open) / table;
            assert!((0.75..=1.3).contains(&ratio), "row {row}: {ratio}");
        }
        // A capture darker than about 25 e⁻ at white has a variance above BM3D's range: BM3D
        // gets the range's top, not a refusal.
        a.white_e = 3.0;
        assert!(Sigma2::Matched.resolve(&a) > crate::denoise::MAX_SIGMA2);
        let used = Denoise::default().applied(&a).unwrap();
        assert_eq!(used.sigma2, Some(crate::denoise::MAX_SIGMA2));
        a.white_e = 0.0;
        let dark = Denoise::Bm3d {
            sigma2: Sigma2::Matched,
        }
        .applied(&a);
        assert!(
            dark.is_err_and(|e| e.to_string().contains("denoise.sigma2")),
            "a capture without light has no matched σ²"
        );
    }

    #[test]
    fn a_bad_fixed_sigma2_names_its_field() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let d = Denoise::Bm3d {
                sigma2: Sigma2::Fixed(bad),
            };
            let msg = d
                .validate()
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default();
            assert!(msg.contains("denoise.sigma2"), "{bad}: {msg}");
        }
        assert!(Denoise::None.validate().is_ok());
        assert!(Denoise::authors_table(Recipe::Iccp21).validate().is_ok());
    }
}
