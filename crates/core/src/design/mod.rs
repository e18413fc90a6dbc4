//! The design document: one pixel's opening, how it is tiled, the camera optics and the colour
//! channels. It is small, serialisable (see `io::design::file` for the versioned file format) and
//! validated here, so every front end rejects the same bad values with the same message.

use serde::{Deserialize, Serialize};

use crate::{SimError, ValueError};

mod dpi;
mod subpixels;
mod theory;
mod validate;

pub use dpi::UM_PER_INCH;
pub use subpixels::{Subpixel, SubpixelChecks, Subpixels};
pub use theory::Theory;

/// Largest opening grid the studio accepts (cells per side).
pub const MAX_CELLS: usize = 512;
/// Largest FFT size per side the studio accepts. The PSF routes hold the pupil's nonzero rows
/// and half the columns, never the whole grid: the 300-DPI design of Fig. 3.9 (two pupil
/// samples per 2-µm cell, a 12 102-sample grid at 610 nm) peaks at 1.3 GB; a whole 16k² complex
/// grid would be 4 GB.
pub const MAX_FFT_SIZE: usize = 12288;
/// Display pixels the lens pupil may span: the rasteriser's time and memory grow with them
/// (2.5 × 10⁵ take a few seconds; a real display at ≥ 20 µm pitch behind a 4 mm pupil has
/// 3 × 10⁴). Finer pitches are refused before anything is allocated.
pub const MAX_PUPIL_PIXELS: f64 = 250_000.0;
/// Wavelengths per channel (the thesis's spectral grid has 30).
pub const MAX_WAVELENGTHS: usize = 128;
/// Largest sensor window per side, in sensor pixels.
pub const MAX_WINDOW_PX: usize = 4096;

/// A complete design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Design {
    /// Short human name shown in the title bar.
    #[serde(default)]
    pub name: String,
    /// Free text: what the design is and where it comes from (e.g. a thesis figure).
    #[serde(default)]
    pub description: String,
    /// The pixel's opening pattern and pitch.
    pub opening: Opening,
    /// How the opening is tiled over the display.
    pub tiling: Tiling,
    /// Camera optics and sampling.
    pub optics: Optics,
    /// Colour channels, each analysed separately (the thesis uses R, G, B).
    pub channels: Vec<Channel>,
    /// The analytic pattern a teaching design is compared with (the Theory view); designs
    /// without one compare with their own diffraction orders.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theory: Option<Theory>,
    /// The emitter layer: where the R, G, B subpixels sit in the opaque area (thesis §3.7).
    /// Designs without one get an automatic placement where one is needed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subpixels: Option<Subpixels>,
}

/// One display pixel's opening: an `N×N` grid of amplitude transmittance in `[0, 1]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Opening {
    /// Display pixel pitch `T` in µm; the cell size is `pitch_um / N`. DPI = 25400 / pitch_um.
    pub pitch_um: f64,
    /// Rows of amplitude transmittance, row 0 at the top; every row has `N` entries.
    /// In files a binary row may be written as text, `#` open and `.` closed.
    #[serde(with = "cell_rows")]
    pub cells: Vec<Vec<f64>>,
    /// Optional openings described as polygons (µm, tile frame: origin at the tile's top-left
    /// corner, x to the right, y down). They are rasterised onto the cell grid with area coverage
    /// and united with `cells` (the larger transmittance wins).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub polygons: Vec<Polygon>,
}

/// A polygonal opening drawn in the tile frame, rasterised with area-weighted coverage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Polygon {
    /// Vertices in µm in the tile frame; the polygon closes itself.
    pub vertices_um: Vec<[f64; 2]>,
}

/// How the pixel pattern is laid out over the display.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TilingMode {
    /// Periodic: every pixel identical.
    #[default]
    Repeat,
    /// Each pixel takes one of the 8 rotations/reflections of the dihedral group D4
    /// (three fair coins: rotate 90° counter-clockwise, flip left-right, flip up-down).
    RandomD4,
    /// Each pixel takes one of {P, Pᵀ, fliplr P, flipud Pᵀ} (the thesis's optimization set).
    #[serde(rename = "random-4")]
    Random4,
}

impl TilingMode {
    /// Every mode, in the order the UI lists them.
    pub const ALL: [TilingMode; 3] = [
        TilingMode::Repeat,
        TilingMode::RandomD4,
        TilingMode::Random4,
    ];

    /// The name used in design files and on the command line (e.g. `random-d4`).
    pub fn as_str(self) -> &'static str {
        match self {
            TilingMode::Repeat => "repeat",
            TilingMode::RandomD4 => "random-d4",
            TilingMode::Random4 => "random-4",
        }
    }

    /// Whether pixels take random orientations (anything but `repeat`).
    pub fn is_random(self) -> bool {
        self != TilingMode::Repeat
    }
}

impl std::str::FromStr for TilingMode {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        TilingMode::ALL
            .into_iter()
            .find(|m| m.as_str() == s)
            .ok_or_else(|| ValueError::UnknownName {
                what: "tiling",
                value: s.to_string(),
                expected: "repeat, random-d4 or random-4",
            })
    }
}

/// How the display tiles the pixel pattern (conventions.md §1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tiling {
    /// Periodic or random orientations.
    pub mode: TilingMode,
    /// Seed of the random orientations (ignored by `repeat`).
    #[serde(default)]
    pub seed: u64,
    /// Registration of the tile grid: the optical axis sits on the centre of cell `[x, y]` of its
    /// tile (cells counted from the tile's top-left corner; fractions shift the grid
    /// continuously). The thesis recipe puts the axis 6 cells into a tile: `[6, 6]`.
    #[serde(default)]
    pub origin_offset_cells: [f64; 2],
    /// Opaque wiring gap added around every pixel, in µm; the display period becomes
    /// `pitch_um + wiring_gap_um` (thesis §3.7).
    #[serde(default)]
    pub wiring_gap_um: f64,
}

/// Camera optics and sampling.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Optics {
    /// Which named recipe these values came from (`custom` once edited).
    #[serde(default)]
    pub recipe: OpticsRecipe,
    /// Lens focal length `f`, mm.
    pub focal_length_mm: f64,
    /// Pupil diameter D = f / F#.
    pub f_number: f64,
    /// Pupil (and display) sample spacing δ1.
    pub pupil_sample_um: f64,
    /// Target fine output spacing δ2 at the sensor; the FFT size per wavelength is
    /// `M = 2·floor(λ f / (2 δ1 δ2))`, so the real spacing `λ f / (M δ1)` is a hair above δ2.
    pub fine_sample_um: f64,
    /// Sensor pixel pitch, µm.
    pub sensor_pixel_um: f64,
    /// Side of the square sensor window, in sensor pixels.
    pub window_px: usize,
    /// Sampling phase: where the optical axis lies inside its sensor pixel, from the pixel's
    /// lower edge, in µm (`[x, y]`); snapped to a fine sample. iccp21: `[0.25, 0.25]`.
    pub axis_in_pixel_um: [f64; 2],
}

/// Where a design's optics came from: a named recipe, or edited values.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OpticsRecipe {
    /// The thesis recipe: f = 10 mm, f/2.5, δ1 = 8 µm, δ2 = 0.5 µm, 2-µm pixels, 294-px window.
    Iccp21,
    /// A phone main camera: f = 5.56 mm, f/1.6, 1.0-µm pixels.
    Phone,
    /// Values edited away from any recipe.
    #[default]
    Custom,
}

impl OpticsRecipe {
    /// The recipes a design can switch to.
    pub const NAMED: [OpticsRecipe; 2] = [OpticsRecipe::Iccp21, OpticsRecipe::Phone];

    /// The name used in design files and on the command line.
    pub fn as_str(self) -> &'static str {
        self.into()
    }

    /// One line for a tooltip.
    pub fn describe(self) -> &'static str {
        match self {
            OpticsRecipe::Iccp21 => {
                "The thesis recipe: f = 10 mm, f/2.5, δ1 = 8 µm, δ2 = 0.5 µm, 2-µm pixels, 294-px window"
            }
            OpticsRecipe::Phone => "A phone main camera: f = 5.56 mm, f/1.6, 1.0-µm pixels",
            OpticsRecipe::Custom => "Values edited away from a named recipe",
        }
    }

    /// The recipe's optics; `None` for [`OpticsRecipe::Custom`].
    pub fn optics(self) -> Option<Optics> {
        match self {
            OpticsRecipe::Iccp21 => Some(Optics::iccp21()),
            OpticsRecipe::Phone => Some(Optics::phone()),
            OpticsRecipe::Custom => None,
        }
    }
}

impl Optics {
    /// Pupil diameter `D = f / F#`, µm.
    pub fn pupil_diameter_um(&self) -> f64 {
        self.focal_length_mm * 1000.0 / self.f_number
    }

    /// The thesis display recipe (conventions.md §4).
    pub fn iccp21() -> Self {
        Optics {
            recipe: OpticsRecipe::Iccp21,
            focal_length_mm: 10.0,
            f_number: 2.5,
            pupil_sample_um: 8.0,
            fine_sample_um: 0.5,
            sensor_pixel_um: 2.0,
            window_px: 294,
            axis_in_pixel_um: [0.25, 0.25],
        }
    }

    /// A realistic phone main camera: f = 5.56 mm, f/1.6, 1.0 µm pixels.
    /// The window (400 px = 400 µm) holds the first diffraction orders of a 150-DPI display.
    pub fn phone() -> Self {
        Optics {
            recipe: OpticsRecipe::Phone,
            focal_length_mm: 5.56,
            f_number: 1.6,
            pupil_sample_um: 8.0,
            fine_sample_um: 0.25,
            sensor_pixel_um: 1.0,
            window_px: 400,
            axis_in_pixel_um: [0.125, 0.125],
        }
    }
}

/// One colour channel: the wavelengths sampled and their weights (normalised when used).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Channel {
    /// Label shown in the UI and reports (e.g. "R").
    pub name: String,
    /// Wavelengths sampled for this channel, nm.
    pub wavelengths_nm: Vec<f64>,
    /// Spectral weight of each wavelength (same length as `wavelengths_nm`).
    pub weights: Vec<f64>,
}

impl Channel {
    /// A single-wavelength channel at `wavelength_nm` with weight 1.
    pub fn peak(name: &str, wavelength_nm: f64) -> Self {
        Channel {
            name: name.into(),
            wavelengths_nm: vec![wavelength_nm],
            weights: vec![1.0],
        }
    }

    /// The thesis's peak wavelengths: R 610, G 530, B 470 nm.
    pub fn rgb_peaks() -> Vec<Channel> {
        vec![
            Channel::peak("R", 610.0),
            Channel::peak("G", 530.0),
            Channel::peak("B", 470.0),
        ]
    }

    /// The weight-averaged wavelength, for labels.
    pub fn mean_wavelength_nm(&self) -> f64 {
        let wsum: f64 = self.weights.iter().sum();
        if wsum <= 0.0 {
            return self.wavelengths_nm.first().copied().unwrap_or(0.0);
        }
        self.wavelengths_nm
            .iter()
            .zip(&self.weights)
            .map(|(l, w)| l * w)
            .sum::<f64>()
            / wsum
    }
}

impl Opening {
    /// Cells per side `N`.
    pub fn n(&self) -> usize {
        self.cells.len()
    }

    /// Cell size `T / N`, µm.
    pub fn cell_um(&self) -> f64 {
        self.pitch_um / self.n().max(1) as f64
    }

    /// Display resolution in dots per inch, `25400 / pitch_um`.
    pub fn dpi(&self) -> f64 {
        25400.0 / self.pitch_um
    }

    /// An all-open `n×n` opening.
    pub fn open(n: usize, pitch_um: f64) -> Self {
        Opening {
            pitch_um,
            cells: vec![vec![1.0; n]; n],
            polygons: Vec::new(),
        }
    }

    /// A full-height vertical slit `width_cells` wide, centred (the T-OLED pixel).
    pub fn slit(n: usize, width_cells: usize, pitch_um: f64) -> Self {
        let start = (n - width_cells.min(n)) / 2;
        let row: Vec<f64> = (0..n)
            .map(|c| f64::from(u8::from(c >= start && c < start + width_cells)))
            .collect();
        Opening {
            pitch_um,
            cells: vec![row; n],
            polygons: Vec::new(),
        }
    }
}

impl Design {
    /// The default design: the T-OLED pixel at 150 DPI, periodic, with the thesis recipe.
    pub fn default_toled() -> Self {
        Design {
            name: "T-OLED 150 DPI".into(),
            description: "T-OLED pixel: a full-height slit 5 of 21 cells wide (40 µm of 168 µm); \
                          thesis §3.3.2, Fig. 3.4a"
                .into(),
            opening: Opening::slit(21, 5, 168.0),
            tiling: Tiling {
                mode: TilingMode::Repeat,
                seed: 0,
                origin_offset_cells: [6.0, 6.0],
                wiring_gap_um: 0.0,
            },
            optics: Optics::iccp21(),
            channels: Channel::rgb_peaks(),
            theory: None,
            subpixels: None,
        }
    }
}

impl Design {
    /// Keeps the emitter layer consistent after the opening changed: a grid of another size is
    /// dropped, emitters on cells that are now open are removed.
    pub fn reconcile_subpixels(&mut self) {
        let n = self.opening.n();
        if let Some(sp) = &mut self.subpixels {
            if sp.cells.len() != n || sp.cells.iter().any(|r| r.len() != n) {
                self.subpixels = None;
            } else {
                sp.clear_open(&self.opening.cells);
            }
        }
    }
}

impl Default for Design {
    fn default() -> Self {
        Self::default_toled()
    }
}

/// Cell rows in design files: binary rows as `"..##.."` text (readable, diffable), others as
/// arrays of numbers. Both forms are accepted on input.
mod cell_rows {
    use serde::de::Error as _;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    #[serde(untagged)]
    enum Row {
        Text(String),
        Numbers(Vec<f64>),
    }

    pub fn serialize<S: Serializer>(cells: &[Vec<f64>], s: S) -> Result<S::Ok, S::Error> {
        let binary = cells.iter().flatten().all(|v| *v == 0.0 || *v == 1.0);
        let rows: Vec<Row> = cells
            .iter()
            .map(|r| {
                if binary {
                    Row::Text(
                        r.iter()
                            .map(|v| if *v == 1.0 { '#' } else { '.' })
                            .collect(),
                    )
                } else {
                    Row::Numbers(r.clone())
                }
            })
            .collect();
        rows.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
        let rows = Vec::<Row>::deserialize(d)?;
        rows.into_iter()
            .enumerate()
            .map(|(i, r)| match r {
                Row::Numbers(v) => Ok(v),
                Row::Text(t) => t
                    .chars()
                    .map(|c| match c {
                        '#' | '1' => Ok(1.0),
                        '.' | '0' => Ok(0.0),
                        other => Err(D::Error::custom(format!(
                            "row {i}: unexpected character {other:?} (use '#' for open and '.' for closed)"
                        ))),
                    })
                    .collect(),
            })
            .collect()
    }
}
