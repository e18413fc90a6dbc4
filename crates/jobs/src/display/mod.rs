//! Display-layout jobs (thesis chapter 3): `analyze` and `restore`, and how they pick their
//! design.

mod analysis_cache;
mod analyze;
mod restore;

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use serde::{Deserialize, Serialize};

use udc_core::Design;
use udc_core::design::{OpticsRecipe, TilingMode};

pub use analysis_cache::analyze_shared;
pub use analyze::{AnalyzeJob, analyze};
pub use restore::{RestoreJob, RestoreMethod, restore};

/// The wavelength step of `--spectral` unless given, nm.
pub const SPECTRAL_STEP_NM: f64 = 30.0;

/// How a command picks its design: a file, or a preset, then overrides.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct DesignSelection {
    /// Design file (JSON). Without it, `--preset` or the default T-OLED preset is used.
    pub design: Option<PathBuf>,
    /// Built-in preset name (see `udc-studio presets`).
    #[arg(long, conflicts_with = "design")]
    pub preset: Option<String>,
    /// PNG opening that replaces the design's (grey > 127 = open; one pixel = one cell).
    #[arg(long)]
    pub pattern: Option<PathBuf>,
    /// Display pixel pitch in µm.
    #[arg(long)]
    pub pitch_um: Option<f64>,
    /// Tiling: repeat, random-d4 or random-4.
    #[arg(long)]
    pub tiling: Option<TilingMode>,
    /// Seed of the random tiling.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Optics recipe: iccp21 (the thesis) or phone.
    #[arg(long, value_parser = crate::choice::choice_of(&OpticsRecipe::NAMED))]
    pub optics: Option<OpticsRecipe>,
    /// Spectral response CSV (wavelength_nm, r, g, b): channels become weighted sums of
    /// wavelengths sampled every `--spectral-step-nm`.
    #[arg(long)]
    pub spectral: Option<PathBuf>,
    /// Wavelength step for `--spectral`, in nm.
    #[arg(long, default_value_t = SPECTRAL_STEP_NM, requires = "spectral")]
    pub spectral_step_nm: f64,
}

impl Default for DesignSelection {
    fn default() -> Self {
        DesignSelection {
            design: None,
            preset: None,
            pattern: None,
            pitch_um: None,
            tiling: None,
            seed: None,
            optics: None,
            spectral: None,
            spectral_step_nm: SPECTRAL_STEP_NM,
        }
    }
}

impl DesignSelection {
    /// The files this selection reads (design, pattern, spectral response).
    pub fn input_files(&self) -> Vec<&std::path::Path> {
        [&self.design, &self.pattern, &self.spectral]
            .into_iter()
            .flatten()
            .map(PathBuf::as_path)
            .collect()
    }

    /// Resolves the selection into a validated design.
    ///
    /// # Errors
    /// Unreadable or invalid files, unknown presets or recipes, bad override values.
    pub fn resolve(&self) -> Result<Design> {
        // A core error stays one, so `name_flags` can name the flag behind its field.
        self.choice().resolve().map_err(|e| match e {
            udc_io::error::IoError::Invalid(sim) => anyhow::Error::from(sim),
            other => other.into(),
        })
    }

    /// The selection as the io layer's [`DesignChoice`](udc_io::design::choice::DesignChoice).
    pub fn choice(&self) -> udc_io::design::choice::DesignChoice {
        udc_io::design::choice::DesignChoice {
            design: self.design.clone(),
            preset: self.preset.clone(),
            pattern: self.pattern.clone(),
            pitch_um: self.pitch_um,
            tiling: self.tiling,
            seed: self.seed,
            optics: self.optics,
            spectral: self.spectral.clone(),
            spectral_step_nm: self.spectral_step_nm,
        }
    }
}
