//! A design chosen as the command line chooses it: a file or a preset, then overrides (pattern,
//! pitch, tiling, seed, optics recipe, spectral response). The CLI's flags and a sweep row's
//! parameters both resolve through here, so the studio opens exactly the design a sweep point
//! computed.

use std::path::PathBuf;

use crate::design::{file as design_file, pattern, presets, spectral};
use crate::error::{IoError, TableError};
use udc_core::ValueError;
use udc_core::design::{Design, OpticsRecipe, TilingMode};

/// The choice; `None` fields keep the design's own value.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignChoice {
    /// A design file; wins over `preset`.
    pub design: Option<PathBuf>,
    /// A built-in preset name; without either, the default preset.
    pub preset: Option<String>,
    /// A PNG opening that replaces the design's.
    pub pattern: Option<PathBuf>,
    /// Display pixel pitch, µm.
    pub pitch_um: Option<f64>,
    /// Tiling mode.
    pub tiling: Option<TilingMode>,
    /// Seed of the random tiling.
    pub seed: Option<u64>,
    /// Optics recipe.
    pub optics: Option<OpticsRecipe>,
    /// Spectral response CSV: channels become weighted sums of wavelengths.
    pub spectral: Option<PathBuf>,
    /// Wavelength step for `spectral`, nm.
    pub spectral_step_nm: f64,
}

impl Default for DesignChoice {
    fn default() -> Self {
        DesignChoice {
            design: None,
            preset: None,
            pattern: None,
            pitch_um: None,
            tiling: None,
            seed: None,
            optics: None,
            spectral: None,
            spectral_step_nm: 30.0,
        }
    }
}

impl DesignChoice {
    /// Resolves the choice into a validated design.
    ///
    /// # Errors
    /// Unreadable or invalid files, unknown presets, bad override values (the core's message
    /// naming the field).
    pub fn resolve(&self) -> Result<Design, IoError> {
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
        design.validate()?;
        Ok(design)
    }

    /// The choice a sweep row names: its design parameters by flag name (`preset`,
    /// `pitch-um`, …) with their values as the command line spells them. Parameters that do
    /// not choose the design (a light level, `preview`) are ignored.
    ///
    /// # Errors
    /// A value that does not parse, naming the parameter.
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ValueError> {
        let mut c = DesignChoice::default();
        let num = |name: &str, v: &str| -> Result<f64, ValueError> {
            v.parse::<f64>().map_err(|_| ValueError::Unusable {
                value: v.to_string(),
                problem: format!("{name} is not a number"),
            })
        };
        for (name, v) in params {
            match name {
                "design" => c.design = Some(PathBuf::from(v)),
                "preset" => c.preset = Some(v.to_string()),
                "pattern" => c.pattern = Some(PathBuf::from(v)),
                "pitch-um" => c.pitch_um = Some(num(name, v)?),
                "tiling" => c.tiling = Some(v.parse()?),
                "seed" => {
                    c.seed = Some(v.parse().map_err(|_| ValueError::Unusable {
                        value: v.to_string(),
                        problem: "the seed is not a whole number".into(),
                    })?);
                }
                "optics" => {
                    c.optics = Some(
                        OpticsRecipe::NAMED
                            .into_iter()
                            .find(|r| r.as_str() == v)
                            .ok_or_else(|| ValueError::UnknownName {
                                what: "optics recipe",
                                value: v.to_string(),
                                expected: "iccp21 or phone",
                            })?,
                    );
                }
                "spectral" => c.spectral = Some(PathBuf::from(v)),
                "spectral-step-nm" => c.spectral_step_nm = num(name, v)?,
                _ => {}
            }
        }
        Ok(c)
    }
}

/// The hash a sweep row records for its design (`design_hash`): of the design's file form.
pub fn design_hash(design: &Design) -> String {
    udc_core::sweep::hash::short_hash(serde_json::to_string(design).unwrap_or_default().as_bytes())
}
