//! Display-layout jobs (thesis chapter 3): `analyze` and `restore`, and how they pick their
//! design.

mod analysis_cache;
mod analyze;
mod figure;
mod restore;
mod restore_measured;

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use serde::{Deserialize, Serialize};

use udc_core::design::{OpticsRecipe, TilingMode};
use udc_core::sweep::one_axis::SweepParameter;
use udc_core::{Design, Setting, SettingPath, SimError};
use udc_io::design::{file as design_file, pattern, presets, spectral};
use udc_io::error::{IoError, TableError};

pub use analysis_cache::analyze_shared;
pub use analyze::{AnalyzeJob, analyze};
pub use figure::{FigureJob, figure, figure_of};
pub use restore::{RestoreJob, RestoreMethod, restore};
pub use restore_measured::{Capture, load_capture, negative_note};

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
    /// Display pixel density in dots per inch, instead of `--pitch-um` (the pitch becomes
    /// 25 400 µm / DPI; the opening's cells scale with it, and the pupil sample becomes an odd
    /// fraction of the cell, no coarser than the design's, so that samples do not straddle cell
    /// edges, as in the thesis's 150-, 300- and 600-DPI presets).
    #[arg(long, conflicts_with = "pitch_um")]
    #[serde(default)]
    pub dpi: Option<f64>,
    /// Tiling: repeat, random-d4 or random-4.
    #[arg(long)]
    pub tiling: Option<TilingMode>,
    /// Seed of the random tiling.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Opaque wiring gap around every display pixel, µm.
    #[arg(long)]
    pub wiring_gap_um: Option<f64>,
    /// Lens f-number (makes the optics a custom recipe).
    #[arg(long)]
    pub f_number: Option<f64>,
    /// Lens focal length in mm (makes the optics a custom recipe).
    #[arg(long)]
    pub focal_length_mm: Option<f64>,
    /// Sensor pixel pitch in µm (makes the optics a custom recipe).
    #[arg(long)]
    pub sensor_pixel_um: Option<f64>,
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
            dpi: None,
            tiling: None,
            seed: None,
            wiring_gap_um: None,
            f_number: None,
            focal_length_mm: None,
            sensor_pixel_um: None,
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

    /// Resolves the selection into a validated design: the file or preset, then each override
    /// (the lens and sensor numbers after the optics recipe, as the studio sets them).
    ///
    /// # Errors
    /// Unreadable or invalid files, unknown presets or recipes, bad override values (a core
    /// error stays one, so `name_flags` can name the flag behind its field).
    pub fn resolve(&self) -> Result<Design> {
        let mut design = match (&self.design, &self.preset) {
            (Some(path), _) => design_file::load_design(path)?,
            (None, Some(name)) => presets::load_preset(name)?,
            (None, None) => presets::load_preset(presets::DEFAULT_PRESET)?,
        };
        if let Some(path) = &self.pattern {
            design.opening.cells = pattern::load_pattern_png(path)?;
            design.opening.polygons.clear();
            design.reconcile_subpixels();
        }
        if let Some(p) = self.pitch_um {
            design.opening.pitch_um = p;
        }
        if let Some(t) = self.tiling {
            design.tiling.mode = t;
        }
        if let Some(s) = self.seed {
            design.tiling.seed = s;
        }
        if let Some(o) = self.optics.and_then(OpticsRecipe::optics) {
            design.optics = o;
        }
        for (parameter, value) in [
            (SweepParameter::WiringGapUm, self.wiring_gap_um),
            (SweepParameter::FNumber, self.f_number),
            (SweepParameter::FocalLengthMm, self.focal_length_mm),
            (SweepParameter::SensorPixelUm, self.sensor_pixel_um),
        ] {
            if let Some(v) = value {
                design = parameter.apply(&design, v)?;
            }
        }
        // After the optics: the DPI refines whichever pupil sampling the design ends with.
        if let Some(d) = self.dpi {
            if !(d.is_finite() && d > 0.0) {
                anyhow::bail!("--dpi {d}: give a positive number of dots per inch");
            }
            design = design.at_dpi(d)?;
        }
        if let Some(path) = &self.spectral {
            let table_err = |error: TableError| IoError::Table {
                path: path.clone(),
                error,
            };
            let resp = spectral::load_response_csv(path)?;
            let lo = resp.wavelengths_nm.first().copied().unwrap_or(0.0);
            let hi = resp.wavelengths_nm.last().copied().unwrap_or(0.0);
            let samples = spectral::sample_grid(lo, hi, self.spectral_step_nm)
                .map_err(|e| table_err(TableError::SpectralStep(e)))?;
            design.channels = spectral::channels_from_response(&resp, &samples)
                .map_err(|e| table_err(TableError::Spectral(e)))?;
        }
        design.validate().map_err(|e| self.by_flag(e))?;
        Ok(design)
    }

    /// A refused design value that a flag of this selection set is named by that flag (`--f-number:
    /// must be …`); one from the design file or preset keeps its field's path.
    fn by_flag(&self, e: SimError) -> anyhow::Error {
        let SimError::InvalidSetting {
            path: SettingPath::Setting(setting),
            message,
        } = &e
        else {
            return e.into();
        };
        let flag = match setting {
            Setting::OpeningPitchUm if self.pitch_um.is_some() => "--pitch-um",
            Setting::TilingWiringGapUm if self.wiring_gap_um.is_some() => "--wiring-gap-um",
            Setting::OpticsFNumber if self.f_number.is_some() => "--f-number",
            Setting::OpticsFocalLengthMm if self.focal_length_mm.is_some() => "--focal-length-mm",
            Setting::OpticsSensorPixelUm if self.sensor_pixel_um.is_some() => "--sensor-pixel-um",
            _ => return e.into(),
        };
        anyhow::anyhow!("{flag}: {message}")
    }
}
