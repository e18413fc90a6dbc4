//! `--denoise` and `--denoise-sigma2`, shared by `restore` and `phase restore`: the thesis's
//! denoise-then-deblur step (conventions.md §5) and its JSON.

use anyhow::{Result, bail};
use clap::Args;
use serde::{Deserialize, Serialize};

use udc_core::restore::{Denoise, DenoiseUsed, Recipe, Sigma2};

/// The denoiser before the deblurring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DenoiseMethod {
    /// BM3D (CBM3D on colour photos), told the capture's own noise (the default).
    #[default]
    Bm3d,
    /// No denoiser: deblur the raw capture.
    None,
}

/// A `--denoise-sigma2` value: `matched`, `table` or a number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sigma2Arg {
    /// The capture's own noise variance at white (`matched`, the default).
    Matched,
    /// The authors' table at the light level (`table`), for comparisons with their code.
    Table,
    /// A σ² on the capture's scale.
    Value(f64),
}

impl std::str::FromStr for Sigma2Arg {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.trim().eq_ignore_ascii_case("matched") {
            return Ok(Sigma2Arg::Matched);
        }
        if s.trim().eq_ignore_ascii_case("table") {
            return Ok(Sigma2Arg::Table);
        }
        s.trim().parse::<f64>().map(Sigma2Arg::Value).map_err(|_| {
            format!(
                "{s:?} is neither `matched`, `table` nor a number (a noise variance such as 0.002)"
            )
        })
    }
}

impl std::fmt::Display for Sigma2Arg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Sigma2Arg::Matched => f.write_str("matched"),
            Sigma2Arg::Table => f.write_str("table"),
            Sigma2Arg::Value(v) => write!(f, "{v}"),
        }
    }
}

/// The denoising flags of a restoration command.
#[derive(Debug, Clone, Default, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct DenoiseFlags {
    /// Denoise the capture before deblurring: `bm3d` (the thesis, CBM3D for colour) or `none`.
    #[arg(long, value_enum, default_value_t = DenoiseMethod::Bm3d)]
    pub denoise: DenoiseMethod,
    /// BM3D's noise variance σ² on the capture's scale (white ≈ 1). By default (`matched`) the
    /// capture's own variance at white, 1/e + σ_read²/e² + q²/12 with e the electrons a white
    /// pixel collects through this display and q the ADC step; `table` for the authors' table at
    /// each light level (that variance with no display in front), or a number (finite, > 0).
    #[arg(long, value_name = "matched|table|S", allow_negative_numbers = true)]
    #[serde(with = "crate::params::optional_text")]
    pub denoise_sigma2: Option<Sigma2Arg>,
}

/// Who gave the settings, so that a refusal names them as that caller spells them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Caller {
    /// The command line: `--denoise-sigma2 0.002`, `--denoise none`.
    Cli,
    /// The Python package's keyword arguments: `denoise_sigma2=0.002`, `denoise="none"`.
    Python,
}

impl Caller {
    fn sigma2(self, s: impl std::fmt::Display) -> String {
        match self {
            Caller::Cli => format!("--denoise-sigma2 {s}"),
            Caller::Python => format!("denoise_sigma2={s}"),
        }
    }

    fn no_denoiser(self) -> &'static str {
        match self {
            Caller::Cli => "--denoise none",
            Caller::Python => "denoise=\"none\"",
        }
    }
}

impl DenoiseFlags {
    /// The setting: BM3D told the capture's own noise unless `--denoise-sigma2` says otherwise
    /// (`table` is `recipe`'s).
    ///
    /// # Errors
    /// A σ² that is not finite and > 0, or one given with `--denoise none`.
    pub fn resolve(&self, recipe: Recipe) -> Result<Denoise> {
        self.resolve_for(recipe, Caller::Cli)
    }

    /// [`DenoiseFlags::resolve`], with refusals naming the settings as `caller` spells them.
    ///
    /// # Errors
    /// As [`DenoiseFlags::resolve`].
    pub fn resolve_for(&self, recipe: Recipe, caller: Caller) -> Result<Denoise> {
        match (self.denoise, self.denoise_sigma2) {
            (DenoiseMethod::None, Some(s)) => bail!(
                "{}: there is no denoiser to give it to with {}",
                caller.sigma2(s),
                caller.no_denoiser()
            ),
            (DenoiseMethod::None, None) => Ok(Denoise::None),
            (DenoiseMethod::Bm3d, Some(Sigma2Arg::Matched) | None) => Ok(Denoise::Bm3d {
                sigma2: Sigma2::Matched,
            }),
            (DenoiseMethod::Bm3d, Some(Sigma2Arg::Table)) => Ok(Denoise::authors_table(recipe)),
            (DenoiseMethod::Bm3d, Some(Sigma2Arg::Value(s)))
                if !udc_core::denoise::sigma2_in_range(s) =>
            {
                bail!(
                    "{}: the noise variance must be a finite number > 0, \
                     at least {:e} and at most {} (images are in [0, 1])",
                    caller.sigma2(format!("{s:?}")),
                    udc_core::denoise::MIN_SIGMA2,
                    udc_core::denoise::MAX_SIGMA2
                )
            }
            (DenoiseMethod::Bm3d, Some(Sigma2Arg::Value(s))) => Ok(Denoise::Bm3d {
                sigma2: Sigma2::Fixed(s),
            }),
        }
    }
}

/// The run's denoising as a short text for tables: `BM3D σ² 2.000e-3 (matched)`, `… (iccp21)`
/// for the authors' table, or `no denoiser`.
pub fn denoise_text(used: &DenoiseUsed) -> String {
    match (used.sigma2, used.source()) {
        (Some(s), Some(source)) => format!("BM3D σ² {s:.3e} ({source})"),
        _ => "no denoiser".to_string(),
    }
}
