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

use super::capture::THESIS_SNR_DB;
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
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sigma2 {
    /// The recipe's table at the light level, converted to the capture's scale.
    Thesis(Recipe),
    /// A σ² on the capture's own scale (white ≈ 1), as BM3D gets it.
    Fixed(f64),
}

impl Sigma2 {
    /// The σ² on the scale of a capture that reads ≈ 1 at white, for the light level `snr_db`
    /// (SNR of a white pixel behind the reference display) and a display passing
    /// `ltr_relative` times the reference's light (module docs).
    pub fn resolve(self, snr_db: f64, ltr_relative: f64) -> f64 {
        match self {
            Sigma2::Thesis(Recipe::Iccp21) => {
                Recipe::Iccp21.sigma2(snr_db) / (ltr_relative * ltr_relative)
            }
            Sigma2::Thesis(Recipe::Iccv23) => Recipe::Iccv23.sigma2(snr_db),
            Sigma2::Fixed(s) => s,
        }
    }
}

/// The denoising step between the capture and the deblurring: a closed set.
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

impl Denoise {
    /// The thesis's step for `recipe`: BM3D with the recipe's σ² table.
    pub fn thesis(recipe: Recipe) -> Self {
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
    /// [`SimError::InvalidField`] (`denoise.sigma2`) for a σ² that is not finite and > 0.
    pub fn validate(self) -> Result<(), SimError> {
        if let Denoise::Bm3d {
            sigma2: Sigma2::Fixed(s),
        } = self
            && !crate::denoise::sigma2_in_range(s)
        {
            return Err(SimError::field(
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

    /// What this setting does at a light level: `None`, or the σ² BM3D gets on a capture that
    /// reads ≈ 1 at white (see [`Sigma2::resolve`]).
    pub fn applied(self, snr_db: f64, ltr_relative: f64) -> DenoiseUsed {
        DenoiseUsed {
            setting: self,
            sigma2: match self {
                Denoise::None => None,
                Denoise::Bm3d { sigma2 } => Some(sigma2.resolve(snr_db, ltr_relative)),
            },
        }
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
    /// Where σ² came from: the recipe's name, `"override"`, or `None` when not denoised.
    pub fn source(&self) -> Option<&'static str> {
        match self.setting {
            Denoise::None => None,
            Denoise::Bm3d {
                sigma2: Sigma2::Thesis(r),
            } => Some(r.name()),
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

    #[test]
    fn chapter_3_sigma2_is_converted_to_our_scale_and_chapter_4_is_not() {
        let s = Sigma2::Thesis(Recipe::Iccp21).resolve(28.0, 2.0);
        assert!((s - 0.002 / 4.0).abs() < 1e-15, "{s}");
        let s = Sigma2::Thesis(Recipe::Iccv23).resolve(32.0, 2.0);
        assert_eq!(s, 0.0005);
        assert_eq!(Sigma2::Fixed(0.003).resolve(24.0, 3.0), 0.003);
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
        assert!(Denoise::thesis(Recipe::Iccp21).validate().is_ok());
    }
}
