//! The built-in presets: the JSON files of `presets/`, compiled into the binary so the studio
//! and the CLI work from any directory.

use crate::IoError;
use crate::design::file::parse_design;
use udc_core::Design;

/// Which shelf of the Presets menu a preset sits on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PresetGroup {
    /// The designs of the thesis (chapter 3), whose numbers the tests reproduce.
    Thesis,
    /// Textbook apertures and gratings with their analytic patterns, for teaching.
    FourierOptics,
}

impl PresetGroup {
    /// Every group, in menu order.
    pub const ALL: [PresetGroup; 2] = [PresetGroup::Thesis, PresetGroup::FourierOptics];

    /// The group's heading in menus and listings.
    pub fn label(self) -> &'static str {
        match self {
            PresetGroup::Thesis => "Thesis designs",
            PresetGroup::FourierOptics => "Fourier optics (teaching)",
        }
    }
}

/// One built-in design.
#[derive(Debug, Clone, Copy)]
pub struct Preset {
    /// The name menus and `--preset` use.
    pub name: &'static str,
    /// Its shelf.
    pub group: PresetGroup,
    /// The design file's text.
    pub text: &'static str,
}

macro_rules! presets {
    ($($group:ident: $name:literal),* $(,)?) => {
        /// Every preset, in menu order.
        pub const PRESETS: &[Preset] = &[
            $(Preset {
                name: $name,
                group: PresetGroup::$group,
                text: include_str!(concat!("../../../../presets/", $name, ".json")),
            }),*
        ];
    };
}

presets!(
    Thesis: "toled-150dpi",
    Thesis: "toled-300dpi",
    Thesis: "toled-600dpi",
    Thesis: "poled-336um",
    Thesis: "disc-lattice",
    Thesis: "open-aperture",
    Thesis: "l2-repeat",
    Thesis: "l2inv-repeat",
    Thesis: "l2-random",
    Thesis: "l2inv-random",
    Thesis: "l2inv-random-wiring8",
    FourierOptics: "fourier-slit",
    FourierOptics: "fourier-double-slit",
    FourierOptics: "fourier-square",
    FourierOptics: "fourier-circle",
    FourierOptics: "fourier-grating",
    FourierOptics: "fourier-periodic",
    FourierOptics: "fourier-random",
);

/// The preset the studio opens with on first run.
pub const DEFAULT_PRESET: &str = "toled-150dpi";

/// Loads a preset by name.
///
/// # Errors
/// [`IoError::UnknownPreset`] for a name not in [`PRESETS`]; [`IoError::Design`] if a preset
/// file is broken (a test guards against that).
pub fn load_preset(name: &str) -> Result<Design, IoError> {
    let preset = PRESETS
        .iter()
        .find(|p| p.name == name)
        .ok_or_else(|| IoError::UnknownPreset(name.to_string()))?;
    parse_design(preset.text).map_err(|error| IoError::Design {
        path: format!("presets/{name}.json").into(),
        error,
    })
}

/// `(name, group, one-line description)` of every preset, parsed once (menus ask every frame).
pub fn list() -> Vec<(&'static str, PresetGroup, String)> {
    static LIST: std::sync::OnceLock<Vec<(&'static str, PresetGroup, String)>> =
        std::sync::OnceLock::new();
    LIST.get_or_init(|| {
        PRESETS
            .iter()
            .map(|p| {
                let d = load_preset(p.name)
                    .map(|d| d.description)
                    .unwrap_or_else(|e| e.to_string());
                let first = d.split(['\n', ';']).next().unwrap_or("").trim().to_string();
                (p.name, p.group, first)
            })
            .collect()
    })
    .clone()
}
