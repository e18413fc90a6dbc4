//! The built-in presets: the JSON files of `presets/`, compiled into the binary so the studio
//! and the CLI work from any directory.

use super::IoError;
use super::design_file::parse_design;
use crate::core::Design;

macro_rules! presets {
    ($($name:literal),* $(,)?) => {
        /// `(name, file text)` of every preset, in menu order.
        pub const PRESETS: &[(&str, &str)] = &[
            $(($name, include_str!(concat!("../../presets/", $name, ".json")))),*
        ];
    };
}

presets!(
    "toled-150dpi",
    "toled-300dpi",
    "toled-600dpi",
    "poled-336um",
    "disc-lattice",
    "open-aperture",
    "l2-repeat",
    "l2inv-repeat",
    "l2-random",
    "l2inv-random",
);

/// The preset the studio opens with on first run.
pub const DEFAULT_PRESET: &str = "toled-150dpi";

/// Loads a preset by name.
///
/// # Errors
/// [`IoError::UnknownPreset`] for a name not in [`PRESETS`]; [`IoError::Design`] if a preset
/// file is broken (a test guards against that).
pub fn load_preset(name: &str) -> Result<Design, IoError> {
    let (_, text) = PRESETS
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| IoError::UnknownPreset(name.to_string()))?;
    parse_design(text).map_err(|message| IoError::Design {
        path: format!("presets/{name}.json").into(),
        message,
    })
}

/// `(name, one-line description)` of every preset.
pub fn list() -> Vec<(&'static str, String)> {
    PRESETS
        .iter()
        .map(|(name, _)| {
            let d = load_preset(name)
                .map(|d| d.description)
                .unwrap_or_else(|e| e.to_string());
            let first = d.split(['\n', ';']).next().unwrap_or("").trim().to_string();
            (*name, first)
        })
        .collect()
}
