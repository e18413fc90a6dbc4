//! Phase-plate height maps for fabrication (thesis §4.6): a CSV profile for plotting and
//! checking, a 16-bit PNG for grayscale lithography, a multi-level GDSII for layer-per-dose
//! mask writers, and a closed STL for two-photon printing.
//!
//! The plate of [`udc_core::phase`] varies along x only and is uniform along y, so every file
//! is the 1-D profile extruded (or repeated) along y. Conventions, stated once:
//! - x = 0 is the optical axis; the plate spans the lenslet array, `[−W/2, W/2]` with
//!   W = lenslets × pitch. y is the extrusion, `[−length/2, length/2]`. z (height) is up.
//! - Sampled files (CSV, PNG) put `N = ⌊W / sample⌋` samples at `x_i = (i − (N−1)/2)·sample`:
//!   centred on the axis, every sample inside the array.
//! - A height step quantises by `design.height_rounding`: floor (default, the authors' code)
//!   `h_q = floor(mod(sag, d0) / step)·step` with the unrounded fold height d0 = T λ0/(n−1), so
//!   levels 0 … floor(d0/step) stay below d0; or nearest (`round`, fold height rounded to the step).
//! - GDSII and STL do not sample the steps: the height jumps where the parabolic sag
//!   ([`geometry::sag_um`]) crosses a level boundary (`w·d0 + (j+1)·step` for floor,
//!   `(K + ½)·step` for nearest) or a fold `w·d0`, and those crossings are solved for exactly in
//!   integer level indices ([`geometry::bands`]), so every flat level and vertical wall sits where
//!   the model puts it. Only the curved parts of an unquantised STL are sampled (chords every
//!   `sample_um` at most).
//! - Every file writes the fabricated plate of [`plate::pieces`]: the model's profile, except
//!   that a part-ring at either outer edge of the array narrower than the ring inside it is
//!   drawn as that ring continued to the edge (no writer can make the sliver).
//! - Lengths are micrometres throughout; GDSII coordinates are whole nanometres.
//!
//! One file per format (`csv`, `png`, `gds`, `stl`); `pieces` cuts the profile at its exact jumps
//! for the two vector formats, and the sampled formats read their heights off the same pieces.

use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use ::png::{BitDepth, ColorType, Encoder, PixelDimensions, Unit};
use gds21::{GdsBoundary, GdsElement, GdsLibrary, GdsPoint, GdsStruct, GdsTextElem, GdsUnits};
use serde::Serialize;
use stl_io::{Normal, Triangle, Vertex};

use crate::IoError;
use crate::safe_file::{TempFile, write_atomic};
use udc_core::mask::MaskError;
use udc_core::phase::geometry::{self, Lenslets};
use udc_core::phase::{HeightRounding, PhaseDesign, Surface, plate};

/// Finest x sample of the CSV, PNG and STL: the GDSII database unit, 1 nm.
pub const MIN_SAMPLE_UM: f64 = 0.001;
/// Most CSV rows (about 100 MB of text).
pub const MAX_CSV_SAMPLES: usize = 2_000_000;
/// Widest PNG: many viewers and mask-writer converters stop at 16-bit sizes.
pub const MAX_PNG_WIDTH: usize = 65_535;
/// Most PNG rows.
pub const MAX_PNG_ROWS: usize = 65_535;
/// Largest PNG (pixels), so a decoder can hold it as 16-bit samples in 400 MB.
pub const MAX_PNG_PIXELS: u64 = 200_000_000;
/// Extrusion length limits: 10 nm to 10 cm (GDSII's 32-bit nanometres reach ±2.1 m).
pub const MIN_LENGTH_UM: f64 = 0.01;
/// Longest extrusion along y, in µm (10 cm).
pub const MAX_LENGTH_UM: f64 = 100_000.0;
/// STL base-slab thickness limits. A base keeps the solid one piece where the height is 0.
pub const MIN_BASE_UM: f64 = 0.01;
/// Thickest STL base slab, in µm (1 cm).
pub const MAX_BASE_UM: f64 = 10_000.0;
pub use udc_core::phase::plate::MAX_PIECES;
/// Most STL triangles (1 GB of binary STL).
pub const MAX_STL_TRIANGLES: usize = 20_000_000;

/// GDSII database unit in µm.
const DB_UNIT_UM: f64 = 0.001;
/// Layer of the GDSII notes: a documentation layer, text only. Not 0, which reads as height
/// level 0; level layers stop below it (see [`MAX_GDS_LEVEL`]).
pub const GDS_NOTE_LAYER: i16 = 255;
/// Highest level layer of the plate's GDSII: every level stays below [`GDS_NOTE_LAYER`] and in
/// the 0–255 layers every reader accepts.
pub const MAX_GDS_LEVEL: u64 = 254;
/// Name of the GDSII library the export writes.
pub const GDS_LIBRARY: &str = "UDCSTUDIO";
/// Prefix of the GDSII top cell that holds the plate's rectangles and notes; the cell is
/// `UDC_PHASE_<first 8 hex digits of the design's SHA-256>` so two plates merge without a clash.
pub const GDS_TOP_CELL: &str = "UDC_PHASE";

/// The phase plate's file formats (the CLI's `--format`, the studio's export menu, and which
/// file an export wrote).
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum HeightFormat {
    /// Profile as text: x_um, height_um, lenslet, lambda0_nm per sample.
    Csv,
    /// 16-bit grey height map for grayscale lithography.
    Png,
    /// One GDSII layer per height level, for layer-per-dose mask writers.
    Gds,
    /// Closed binary STL solid on a base slab, for two-photon printing.
    Stl,
}

impl HeightFormat {
    /// Every format, in menu order.
    pub const ALL: [HeightFormat; 4] = [
        HeightFormat::Csv,
        HeightFormat::Png,
        HeightFormat::Gds,
        HeightFormat::Stl,
    ];

    /// The menu entry.
    pub fn label(self) -> &'static str {
        match self {
            HeightFormat::Csv => "Heights (CSV)…",
            HeightFormat::Png => "Height map (16-bit PNG)…",
            HeightFormat::Gds => "Mask layers (GDSII)…",
            HeightFormat::Stl => "Plate (STL)…",
        }
    }

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            HeightFormat::Csv => "csv",
            HeightFormat::Png => "png",
            HeightFormat::Gds => "gds",
            HeightFormat::Stl => "stl",
        }
    }
}

/// One GDSII layer: the rectangles of one quantised height.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GdsLayer {
    /// GDSII layer number: the level index k ≥ 1.
    pub layer: i16,
    /// Height of the level, in µm.
    pub height_um: f64,
    /// Number of rectangles drawn on the layer.
    pub rectangles: usize,
    /// Summed x-width of the layer's rectangles (their area is this × the length).
    pub width_um: f64,
}

/// What an export wrote, in the numbers a user checks against the fabrication order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExportSummary {
    /// The file written.
    pub path: PathBuf,
    /// Its format.
    pub kind: HeightFormat,
    /// Array width W = lenslets × pitch.
    pub width_um: f64,
    /// Tallest height written (above the base for STL).
    pub max_height_um: f64,
    /// x samples (CSV rows, PNG columns) or STL profile vertices.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
    /// Sample spacing along x, in µm (CSV, PNG; for STL the longest chord of a curved part).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample_um: Option<f64>,
    /// PNG pixel size, in x and y.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pixel_um: Option<f64>,
    /// PNG rows (identical: the plate is uniform along y).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rows: Option<usize>,
    /// Quantised heights, 0 included.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub levels: Option<usize>,
    /// Height of one level, in µm: a PNG pixel value or GDSII layer number times this is the
    /// height.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um_per_level: Option<f64>,
    /// GDSII rectangles over all layers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rectangles: Option<usize>,
    /// GDSII layers, one per height level above 0, lowest first.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub layers: Vec<GdsLayer>,
    /// STL triangles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangles: Option<usize>,
    /// Extrusion length along y as written, in µm (GDSII, STL).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length_um: Option<f64>,
    /// STL base-slab thickness under the plate, in µm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base_um: Option<f64>,
    /// The x grid coordinates were snapped to.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grid_um: Option<f64>,
    /// Part-level rings joined to the next fold under the writer's rule, and the phase error
    /// this costs (`plate::ring_merge`); absent when none were joined.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ring_merge: Option<plate::RingMerge>,
}

impl ExportSummary {
    fn new(path: &Path, kind: HeightFormat, width_um: f64, max_height_um: f64) -> Self {
        ExportSummary {
            path: path.to_path_buf(),
            kind,
            width_um,
            max_height_um,
            samples: None,
            sample_um: None,
            pixel_um: None,
            rows: None,
            levels: None,
            um_per_level: None,
            rectangles: None,
            layers: Vec::new(),
            triangles: None,
            length_um: None,
            base_um: None,
            grid_um: None,
            ring_merge: None,
        }
    }
}

fn invalid(message: String) -> IoError {
    IoError::MaskLayout(MaskError::Invalid(message))
}

/// Rejects NaN, infinities and values outside `lo..=hi`, naming the parameter.
fn check_um(name: &str, v: f64, lo: f64, hi: f64, why: &str) -> Result<(), IoError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(invalid(format!(
            "{name} = {v}: must be a finite number within {lo}–{hi} µm{why}"
        )))
    }
}

/// A sample coarser than half a lenslet would not show the lenslets at all.
fn check_sample(design: &PhaseDesign, sample_um: f64) -> Result<(), IoError> {
    check_um(
        "sample_um",
        sample_um,
        MIN_SAMPLE_UM,
        design.pitch_um / 2.0,
        " (at least two samples per lenslet)",
    )
}

fn check_length(length_um: f64) -> Result<(), IoError> {
    check_um("length_um", length_um, MIN_LENGTH_UM, MAX_LENGTH_UM, "")
}

/// The design checked and its lenslets built, so no file is touched for a bad design.
fn lenslets_of(design: &PhaseDesign) -> Result<Lenslets, IoError> {
    design.validate()?;
    Ok(Lenslets::new(design)?)
}

/// The profile at the sampled files' x positions.
struct Samples {
    x_um: Vec<f64>,
    height_um: Vec<f64>,
}

/// Samples the fabricated plate, refusing more than `max` samples before allocating them.
fn sample_profile(
    design: &PhaseDesign,
    lenslets: &Lenslets,
    sample_um: f64,
    (max, what): (usize, &str),
    min_feature_um: f64,
) -> Result<Samples, IoError> {
    let span = lenslets.span_um();
    // The relative nudge keeps W / sample = 5712 from flooring to 5711 after rounding.
    let n = (span / sample_um * (1.0 + 1e-12)).floor();
    if !(n >= 1.0 && n <= max as f64) {
        return Err(invalid(format!(
            "sample_um = {sample_um}: gives {n} samples across the {span} µm array, \
             more than the {max} {what} allows; use a coarser sample"
        )));
    }
    let n = n as usize;
    // Snapped to 1e-9 µm so the files carry the decimal the grid means (1.05, not
    // 1.0500000000000003); the heights are computed at the snapped positions.
    let x_um: Vec<f64> = (0..n)
        .map(|i| {
            crate::numbers::snap_decimals(
                (2.0 * i as f64 + 1.0 - n as f64) * sample_um / 2.0,
                CSV_DECIMALS,
            )
        })
        .collect();
    // The fabricated plate, as the vector exports draw it (its outer edges differ from the
    // model's profile: `plate::pieces`).
    let pieces = plate::pieces(design, lenslets, min_feature_um)?;
    let height_um = x_um
        .iter()
        .map(|&x| plate::height_on(design, &pieces, x))
        .collect();
    Ok(Samples { x_um, height_um })
}

/// Decimal places of positions and heights in µm in the CSV (1e-9 µm = 1 fm, far below any
/// fabrication tolerance, far above float noise).
pub const CSV_DECIMALS: i32 = 9;

fn max_of(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, f64::max)
}

/// The design in plain ASCII, for file headers and notes that outlive the design file.
fn header_lines(design: &PhaseDesign, lenslets: &Lenslets) -> Vec<String> {
    let step = match (design.height_step_um, design.height_rounding) {
        (Some(s), HeightRounding::Floor) => format!(
            "{s} um, floor rounding (every height is floor(h / step) x step, below the fold height)"
        ),
        (Some(s), HeightRounding::Nearest) => format!(
            "{s} um, nearest rounding (every height is round(h / step) x step; fold height rounded \
             to the step)"
        ),
        (None, _) => "none (continuous heights)".into(),
    };
    let surface = match design.surface {
        Surface::Folded => "folded",
        Surface::Unfolded => "unfolded (thick reference lens)",
    };
    let lambdas = &lenslets.lambda0_nm;
    let (lo, hi) = (
        lambdas.iter().copied().fold(f64::INFINITY, f64::min),
        lambdas.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    vec![
        "UDC Studio phase-plate height profile (thesis 4.6); the plate is uniform along y".into(),
        "units: x and heights in micrometres (um), lambda0 in nanometres; \
         x = 0 on the optical axis; lenslet = index from the left, from 0"
            .into(),
        format!(
            "pitch {} um, f_mla {} um, refractive index {}, fold T {}, surface {surface}",
            design.pitch_um, design.f_mla_um, design.refractive_index, design.fold
        ),
        format!("height step: {step}"),
        format!(
            "{} lenslets, array width {} um, lambda0 {lo}-{hi} nm, max fold height {} um",
            lenslets.count(),
            lenslets.span_um(),
            max_of(lenslets.fold_height_um.iter().copied())
        ),
    ]
}

mod csv;
mod gds;
mod pieces;
mod png;
mod stl;

pub use csv::{height_csv_text, write_height_csv, write_kernels_csv};
pub use gds::write_height_gds;
pub use png::write_height_png;
pub use stl::write_height_stl;

/// The per-format sizes of a height export (each format reads the ones it needs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeightParams {
    /// Sample along x, in µm (CSV, PNG pixel size, STL chord length).
    pub sample_um: f64,
    /// Rows of the PNG (the plate is uniform along y).
    pub rows: usize,
    /// Length of the plate along y, in µm (GDSII, STL).
    pub length_um: f64,
    /// Thickness of the STL's base under the profile, in µm.
    pub base_um: f64,
    /// Fixed GDSII timestamps, so identical exports are byte-identical.
    pub deterministic: bool,
    /// The writer's narrowest feature, µm (`Rules::phase_min_feature_um`): part-level rings
    /// narrower join the next fold (`plate::pieces`); 0 keeps every ring.
    pub phase_min_feature_um: f64,
}

/// Writes `design`'s plate to `path` in `format`: the one entry point of the studio and the CLI.
///
/// # Errors
/// What the format's writer refuses (sizes, steps, piece counts) or cannot write.
pub fn write_height(
    format: HeightFormat,
    design: &PhaseDesign,
    path: &Path,
    p: &HeightParams,
) -> Result<ExportSummary, IoError> {
    let rule = p.phase_min_feature_um;
    let (mut summary, layers) = match format {
        HeightFormat::Csv => (write_height_csv(design, path, p.sample_um, rule)?, None),
        HeightFormat::Png => (
            write_height_png(design, path, p.sample_um, p.rows, rule)?,
            None,
        ),
        HeightFormat::Gds => {
            let s = gds::write_height_gds_with(design, path, p.length_um, p.deterministic, rule)?;
            let map = gds::layer_map(&s);
            (s, Some(map))
        }
        HeightFormat::Stl => (
            write_height_stl(design, path, p.sample_um, p.length_um, p.base_um, rule)?,
            None,
        ),
    };
    let merge = plate::ring_merge(design, &lenslets_of(design)?, rule)?;
    summary.ring_merge = (merge.merged_rings > 0).then_some(merge);
    let json = crate::phase::design::phase_design_json(design);
    let mut m = serde_json::Map::new();
    m.insert("format".into(), format.extension().into());
    m.insert(
        "design".into(),
        serde_json::json!({"name": "phase plate", "sha256": crate::fab::sha256_hex(json.as_bytes())}),
    );
    m.insert(
        "parameters".into(),
        serde_json::json!({
            "sample_um": p.sample_um,
            "rows": p.rows,
            "length_um": p.length_um,
            "base_um": p.base_um,
            "deterministic": p.deterministic,
            "phase_min_feature_um": p.phase_min_feature_um,
        }),
    );
    let header = vec![
        "layer map of a phase plate: level_k = height k x height_step_um; notes = text only".into(),
    ];
    let layers = layers.as_ref().map(|m| (m, header.as_slice()));
    crate::fab::write_sidecars(path, m, layers)?;
    Ok(summary)
}
