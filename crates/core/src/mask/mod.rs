//! Photolithography masks of a design: pure geometry, no files (the writers live in
//! `io::mask`).
//!
//! **Frame.** Mask coordinates are integers in nanometres (the GDSII database unit), snapped to a
//! chosen grid, with **x to the right and y up** (GDSII's frame) and the **optical axis at the
//! origin**. A design's row 0 (the top row on screen) is the top of its tile on the mask, so the
//! mask looks like the studio's display when viewed in KLayout.
//!
//! **Grey cells** are thresholded: a cell with transmittance ≥ [`OPEN_THRESHOLD`] (0.5) is open
//! (clear), anything below is chrome. Masks are binary; the simulation of the exported mask is the
//! simulation of this thresholded design ([`binary_design`]).
//!
//! **Tone.** [`Tone::Open`] draws the clear openings; [`Tone::Chrome`] draws the dark chrome, i.e.
//! the complement of the openings within each pixel *including* the wiring gap around it.

pub mod drc;
pub mod frame;
pub mod geometry_drc;
pub mod layout;
pub mod polygons;
pub mod region;

use thiserror::Error;

use crate::design::Design;
use crate::display::aperture::{Display, Extent, effective_cells, pupil_sample_count, rasterise};
use crate::{SimError, ValueError};

pub use border::{BorderCounts, BorderEdit, BorderPolicy};
pub use frame::{
    FrameError, FrameGeometry, FrameLabel, FramePart, FrameSpec, frame_geometry, label_text,
};
pub use layout::border;
pub use layout::{MaskLayout, MaskRegion, MaskStats, Placement, Polygon, TileRow};
pub use polygons::{BinaryGrid, Ring, trace_polygons};

/// Transmittance at or above which a cell is open on the mask.
pub const OPEN_THRESHOLD: f64 = 0.5;

/// The most vertices one GDSII boundary may have (an XY record holds 8191 points, the first
/// repeated at the end).
pub const MAX_VERTICES: usize = 8190;

/// Which side of the mask the polygons describe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tone {
    /// Drawn = open (clear glass): the polygons are the openings.
    #[default]
    Open,
    /// Drawn = chrome (dark): the polygons are everything but the openings, gap included.
    Chrome,
}

impl Tone {
    /// Both tones, in the order the UI lists them.
    pub const ALL: [Tone; 2] = [Tone::Open, Tone::Chrome];

    /// The name used on the command line and in files.
    pub fn as_str(self) -> &'static str {
        match self {
            Tone::Open => "open",
            Tone::Chrome => "chrome",
        }
    }

    /// The explicit statement written into every file and report.
    pub fn meaning(self) -> &'static str {
        match self {
            Tone::Open => "drawn = open (clear)",
            Tone::Chrome => "drawn = chrome (dark)",
        }
    }
}

impl std::str::FromStr for Tone {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        match s {
            "open" => Ok(Tone::Open),
            "chrome" => Ok(Tone::Chrome),
            other => Err(ValueError::UnknownName {
                what: "tone",
                value: other.to_string(),
                expected: "open or chrome",
            }),
        }
    }
}

/// What to lay out: the region, the tone and the coordinate grid.
#[derive(Debug, Clone, PartialEq)]
pub struct MaskSpec {
    /// Which pixels the mask covers.
    pub region: MaskRegion,
    /// Whether the polygons are the openings or the chrome.
    pub tone: Tone,
    /// Coordinates are snapped to multiples of this many nanometres (the database unit is 1 nm).
    pub grid_nm: u32,
    /// Polygons with more vertices are split (GDSII allows [`MAX_VERTICES`]).
    pub max_vertices: usize,
    /// What happens to the openings the region's edge cuts.
    pub border: BorderPolicy,
    /// Width of the chrome frame [`BorderPolicy::Margin`] draws around a chrome-drawn region,
    /// µm.
    pub margin_um: f64,
}

impl Default for MaskSpec {
    fn default() -> Self {
        MaskSpec {
            region: MaskRegion::PIXEL,
            tone: Tone::Open,
            grid_nm: 1,
            max_vertices: MAX_VERTICES,
            border: BorderPolicy::default(),
            margin_um: border::DEFAULT_MARGIN_UM,
        }
    }
}

/// Why a mask cannot be laid out.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MaskError {
    /// The design itself is invalid.
    #[error(transparent)]
    Design(#[from] SimError),
    /// No cell is open, so there is nothing to draw.
    #[error(
        "the opening has no open cell (none reaches transmittance {OPEN_THRESHOLD}); there is nothing to draw"
    )]
    EmptyPattern,
    /// A bad setting (e.g. a zero grid or an empty region); the message says which.
    #[error("{0}")]
    Invalid(String),
    /// A die frame that cannot be drawn.
    #[error(transparent)]
    Frame(#[from] FrameError),
    /// Too many tiles, or coordinates beyond GDSII's 32-bit range.
    #[error("region too large: {0}")]
    TooLarge(String),
    /// The caller cancelled the job through its `Progress`.
    #[error("cancelled")]
    Cancelled,
}

/// The thresholded opening: `true` where the effective transmittance is ≥ [`OPEN_THRESHOLD`].
pub fn binary_pattern(design: &Design) -> BinaryGrid {
    let cells = effective_cells(&design.opening);
    BinaryGrid::from_rows(
        &cells
            .iter()
            .map(|row| row.iter().map(|v| *v >= OPEN_THRESHOLD).collect())
            .collect::<Vec<_>>(),
    )
}

/// The design the mask realises: cells thresholded to 0/1 and polygons folded into them.
pub fn binary_design(design: &Design) -> Design {
    let mut d = design.clone();
    let grid = binary_pattern(design);
    d.opening.cells = (0..grid.height())
        .map(|r| {
            (0..grid.width())
                .map(|c| f64::from(u8::from(grid.get(c, r))))
                .collect()
        })
        .collect();
    d.opening.polygons.clear();
    d
}

/// Light transmittance ratio of the mask in front of the design's lens: the fraction of the
/// pupil (sampled at `optics.pupil_sample_um`) that the thresholded display lets through.
pub fn mask_ltr(design: &Design) -> f64 {
    let d = binary_design(design);
    let display = Display::from_design(&d, &d.opening.cells);
    let diameter_um = d.optics.pupil_diameter_um();
    let delta_um = d.optics.pupil_sample_um;
    let field = rasterise(&display, Extent::Pupil { diameter_um }, delta_um);
    let pupil = pupil_sample_count(diameter_um, delta_um);
    if pupil > 0.0 {
        field.energy() / pupil
    } else {
        0.0
    }
}
