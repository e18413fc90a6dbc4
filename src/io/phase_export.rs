//! Phase-plate height maps for fabrication (thesis §4.6): a CSV profile for plotting and
//! checking, a 16-bit PNG for grayscale lithography, a multi-level GDSII for layer-per-dose
//! mask writers, and a closed STL for two-photon printing.
//!
//! The plate of [`crate::core::phase`] varies along x only and is uniform along y, so every file
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
//! - Lengths are micrometres throughout; GDSII coordinates are whole nanometres.

use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use gds21::{
    GdsBoundary, GdsDateTime, GdsElement, GdsLibrary, GdsPoint, GdsStruct, GdsTextElem, GdsUnits,
};
use png::{BitDepth, ColorType, Encoder, PixelDimensions, Unit};
use serde::Serialize;
use stl_io::{Normal, Triangle, Vertex};

use super::IoError;
use super::safe_file::{TempFile, write_atomic};
use crate::core::mask::MaskError;
use crate::core::phase::geometry::{self, Lenslets};
use crate::core::phase::{HeightRounding, PhaseDesign, Surface};

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
pub const MAX_LENGTH_UM: f64 = 100_000.0;
/// STL base-slab thickness limits. A base keeps the solid one piece where the height is 0.
pub const MIN_BASE_UM: f64 = 0.01;
pub const MAX_BASE_UM: f64 = 10_000.0;
/// Most flat or curved stretches between height jumps the profile may have (a design with a
/// tiny step or fold under wide lenslets has billions).
pub const MAX_PIECES: usize = 4_000_000;
/// Most STL triangles (1 GB of binary STL).
pub const MAX_STL_TRIANGLES: usize = 20_000_000;

/// GDSII database unit in µm.
const DB_UNIT_UM: f64 = 0.001;
/// Layer of the GDSII notes: text only, no geometry (height 0 is bare substrate, never drawn).
pub const GDS_NOTE_LAYER: i16 = 0;
pub const GDS_LIBRARY: &str = "UDCSTUDIO";
pub const GDS_TOP_CELL: &str = "UDC_PHASE";

/// Which file an export wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ExportKind {
    Csv,
    Png,
    Gds,
    Stl,
}

/// One GDSII layer: the rectangles of one quantised height.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GdsLayer {
    pub layer: i16,
    pub height_um: f64,
    pub rectangles: usize,
    /// Summed x-width of the layer's rectangles (their area is this × the length).
    pub width_um: f64,
}

/// What an export wrote, in the numbers a user checks against the fabrication order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExportSummary {
    pub path: PathBuf,
    pub kind: ExportKind,
    /// Array width W = lenslets × pitch.
    pub width_um: f64,
    /// Tallest height written (above the base for STL).
    pub max_height_um: f64,
    /// x samples (CSV rows, PNG columns) or STL profile vertices.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample_um: Option<f64>,
    /// PNG pixel size, in x and y.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pixel_um: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rows: Option<usize>,
    /// Quantised heights, 0 included.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub levels: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um_per_level: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rectangles: Option<usize>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub layers: Vec<GdsLayer>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangles: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length_um: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base_um: Option<f64>,
    /// The x grid coordinates were snapped to.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grid_um: Option<f64>,
}

impl ExportSummary {
    fn new(path: &Path, kind: ExportKind, width_um: f64, max_height_um: f64) -> Self {
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

/// Samples the profile, refusing more than `max` samples before allocating them.
fn sample_profile(
    design: &PhaseDesign,
    lenslets: &Lenslets,
    sample_um: f64,
    max: usize,
    what: &str,
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
    let x_um: Vec<f64> = (0..n)
        .map(|i| (2.0 * i as f64 + 1.0 - n as f64) * sample_um / 2.0)
        .collect();
    let height_um = x_um
        .iter()
        .map(|&x| lenslets.height_at(design, x))
        .collect();
    Ok(Samples { x_um, height_um })
}

fn max_of(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, f64::max)
}

/// The CSV text of [`write_height_csv`]: a `#` header stating units and design, then
/// `x_um,height_um,lenslet,lambda0_nm` rows. Numbers are written in full (shortest round-trip)
/// precision so a reader recovers exactly the heights the model computed.
///
/// # Errors
/// A message naming `sample_um` when it is out of range or gives too many rows, or the design's
/// own validation error.
pub fn height_csv_text(design: &PhaseDesign, sample_um: f64) -> Result<String, IoError> {
    Ok(csv_text(design, sample_um)?.0)
}

fn csv_text(design: &PhaseDesign, sample_um: f64) -> Result<(String, Samples), IoError> {
    let lenslets = lenslets_of(design)?;
    check_sample(design, sample_um)?;
    let s = sample_profile(design, &lenslets, sample_um, MAX_CSV_SAMPLES, "CSV export")?;
    let mut out = String::with_capacity(64 * s.x_um.len() + 1024);
    for line in header_lines(design, &lenslets) {
        out.push_str("# ");
        out.push_str(&line);
        out.push('\n');
    }
    out.push_str(&format!(
        "# samples: {} every {sample_um} um, x_i = (i - (N-1)/2) * sample_um\n",
        s.x_um.len()
    ));
    out.push_str("x_um,height_um,lenslet,lambda0_nm\n");
    for (&x, &h) in s.x_um.iter().zip(&s.height_um) {
        match lenslets.locate(x) {
            Some((l, _)) => {
                let lambda = lenslets.lambda0_nm.get(l).copied().unwrap_or(f64::NAN);
                out.push_str(&format!("{x},{h},{l},{lambda}\n"));
            }
            None => out.push_str(&format!("{x},{h},,\n")),
        }
    }
    Ok((out, s))
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

/// Writes the height profile as CSV (see [`height_csv_text`]), for plotting and for checking
/// a fabricated plate against the design with a profilometer.
///
/// # Errors
/// As [`height_csv_text`], or when the file cannot be written.
pub fn write_height_csv(
    design: &PhaseDesign,
    path: &Path,
    sample_um: f64,
) -> Result<ExportSummary, IoError> {
    let (text, s) = csv_text(design, sample_um)?;
    write_atomic(path, text.as_bytes())?;
    let width = geometry::lenslet_count(design) as f64 * design.pitch_um;
    let mut summary = ExportSummary::new(
        path,
        ExportKind::Csv,
        width,
        max_of(s.height_um.iter().copied()),
    );
    summary.samples = Some(s.x_um.len());
    summary.sample_um = Some(sample_um);
    Ok(summary)
}

/// Writes a 16-bit grayscale height map for grayscale lithography: one column per x sample,
/// `rows` identical rows (the plate is uniform along y). A pixel value times `um_per_level`
/// (tEXt chunk) is the height: `um_per_level` is the fabrication step when there is one, so
/// values are level numbers, else the tallest height over 65535. The pixel size is in the
/// `pixel_um` tEXt chunk and in `pHYs` (rounded to whole pixels per metre).
///
/// # Errors
/// Names `sample_um` or `rows` when out of range or the image would be too large, and
/// `height_step_um` when the levels do not fit 16 bits; [`IoError::Image`] when encoding fails.
pub fn write_height_png(
    design: &PhaseDesign,
    path: &Path,
    sample_um: f64,
    rows: usize,
) -> Result<ExportSummary, IoError> {
    let lenslets = lenslets_of(design)?;
    check_sample(design, sample_um)?;
    if rows == 0 || rows > MAX_PNG_ROWS {
        return Err(invalid(format!(
            "rows = {rows}: must be within 1–{MAX_PNG_ROWS}"
        )));
    }
    let s = sample_profile(design, &lenslets, sample_um, MAX_PNG_WIDTH, "PNG width")?;
    let width = s.x_um.len();
    let pixels = width as u64 * rows as u64;
    if pixels > MAX_PNG_PIXELS {
        return Err(invalid(format!(
            "rows = {rows}: {width} × {rows} is {pixels} pixels, more than {MAX_PNG_PIXELS}; \
             use fewer rows or a coarser sample_um"
        )));
    }
    let max_height = max_of(s.height_um.iter().copied());
    let um_per_level = match design.height_step_um {
        Some(step) => {
            let top = (max_height / step).round();
            if top > 65535.0 {
                return Err(invalid(format!(
                    "height_step_um = {step}: the plate has {top} levels above 0, more than a \
                     16-bit PNG holds (65535); use a coarser step"
                )));
            }
            step
        }
        None => {
            let tallest = lenslets.max_height_um(design);
            if tallest > 0.0 {
                tallest / 65535.0
            } else {
                1.0
            }
        }
    };
    let row: Vec<u8> = s
        .height_um
        .iter()
        .flat_map(|&h| {
            let level = (h / um_per_level).round().clamp(0.0, 65535.0) as u16;
            level.to_be_bytes()
        })
        .collect();
    let levels = design
        .height_step_um
        .map(|_| (max_height / um_per_level).round() as usize + 1);
    let description = format!(
        "UDC Studio phase-plate height map (thesis 4.6). height_um = pixel value x um_per_level. \
         Columns: x across the lenslets, pixel_um apart, centred on the optical axis; rows are \
         identical (the plate is uniform along y). {}",
        header_lines(design, &lenslets)[2..].join("; ")
    );
    let bytes = encode_png(
        path,
        (width, rows),
        &row,
        &[
            ("um_per_level", format!("{um_per_level}")),
            ("pixel_um", format!("{sample_um}")),
            ("description", description),
            ("Software", "UDC Studio".into()),
        ],
        sample_um,
    )?;
    write_atomic(path, &bytes)?;
    let mut summary = ExportSummary::new(path, ExportKind::Png, lenslets.span_um(), max_height);
    summary.samples = Some(width);
    summary.sample_um = Some(sample_um);
    summary.pixel_um = Some(sample_um);
    summary.rows = Some(rows);
    summary.levels = levels;
    summary.um_per_level = Some(um_per_level);
    Ok(summary)
}

/// The PNG bytes. Identical rows are streamed, so memory stays at one row plus the (tiny)
/// compressed image.
fn encode_png(
    path: &Path,
    (width, rows): (usize, usize),
    row: &[u8],
    texts: &[(&str, String)],
    pixel_um: f64,
) -> Result<Vec<u8>, IoError> {
    let err = |e: String| IoError::Image {
        path: path.to_path_buf(),
        message: format!("cannot encode the PNG: {e}"),
    };
    let to_u32 = |v: usize| u32::try_from(v).map_err(|e| err(e.to_string()));
    let mut bytes = Vec::new();
    let mut enc = Encoder::new(&mut bytes, to_u32(width)?, to_u32(rows)?);
    enc.set_color(ColorType::Grayscale);
    enc.set_depth(BitDepth::Sixteen);
    let ppm = (1e6 / pixel_um).round().clamp(1.0, f64::from(u32::MAX)) as u32;
    enc.set_pixel_dims(Some(PixelDimensions {
        xppu: ppm,
        yppu: ppm,
        unit: Unit::Meter,
    }));
    for (key, text) in texts {
        enc.add_text_chunk((*key).into(), text.clone())
            .map_err(|e| err(e.to_string()))?;
    }
    let mut writer = enc.write_header().map_err(|e| err(e.to_string()))?;
    {
        let mut stream = writer.stream_writer().map_err(|e| err(e.to_string()))?;
        for _ in 0..rows {
            stream.write_all(row).map_err(|e| err(e.to_string()))?;
        }
        stream.finish().map_err(|e| err(e.to_string()))?;
    }
    writer.finish().map_err(|e| err(e.to_string()))?;
    Ok(bytes)
}

/// How the height varies over one stretch between consecutive jumps.
#[derive(Debug, Clone, Copy)]
enum Shape {
    /// A quantised level: height `level × step`.
    Flat { level: u64, height_um: f64 },
    /// The sag about `centre_um`, less the folds below it (`offset_um`), at most `cap_um`.
    Curved {
        centre_um: f64,
        offset_um: f64,
        cap_um: f64,
    },
}

/// One stretch of the profile between consecutive height jumps (or lenslet edges).
#[derive(Debug, Clone, Copy)]
struct Piece {
    x0_um: f64,
    x1_um: f64,
    shape: Shape,
}

impl Piece {
    /// The height on this piece, continued to its ends (a jump's two sides are two pieces).
    fn height_um(&self, design: &PhaseDesign, x_um: f64) -> f64 {
        match self.shape {
            Shape::Flat { height_um, .. } => height_um,
            Shape::Curved {
                centre_um,
                offset_um,
                cap_um,
            } => (geometry::sag_um(design, x_um - centre_um) - offset_um).clamp(0.0, cap_um),
        }
    }
}

/// The profile cut at every height jump, left to right.
///
/// The jumps are the analytic crossings of [`geometry::bands`]: in integer level indices, a
/// floored level j of wrap w ends where the sag reaches `w·d0 + (j+1)·step` and a wrap where it
/// reaches `(w+1)·d0` (d0 the unrounded fold height); rounding to the nearest level jumps at
/// `(K + ½)·step`. The radius is `sqrt(2(n−1)f·sag)`, so every level's ring has exactly the
/// model's width, and each piece's level is the integer index of its ring, not a sampled height.
fn pieces(design: &PhaseDesign, lenslets: &Lenslets) -> Result<Vec<Piece>, IoError> {
    let pitch = lenslets.pitch_um;
    let count = lenslets.count();
    let half = pitch / 2.0;
    let edge_sag = geometry::sag_um(design, half);
    if !(geometry::sag_um(design, 1.0) > 0.0 && edge_sag.is_finite()) {
        return Err(invalid(format!(
            "the lens sag {edge_sag} µm at the lenslet edge cannot be cut into levels"
        )));
    }
    let estimate: f64 = lenslets
        .fold_height_um
        .iter()
        .map(|&f| 2.0 * geometry::band_count_bound(design, f, half) + 1.0)
        .sum();
    if !(estimate <= MAX_PIECES as f64) {
        let cause = match design.height_step_um {
            Some(step) => format!("height_step_um = {step} µm"),
            None => "the fold height".into(),
        };
        return Err(invalid(format!(
            "the profile would have about {estimate:.0} separate levels or folds ({cause} under \
             {edge_sag:.1} µm of lens sag), more than {MAX_PIECES}; use a coarser step"
        )));
    }
    let mut out = Vec::with_capacity(estimate as usize);
    let mut cached: Option<(f64, Vec<geometry::Band>)> = None;
    for (l, &fold_um) in lenslets.fold_height_um.iter().enumerate() {
        let c = lenslets.centre_um(l);
        // Edges from one formula, so neighbouring lenslets share them bit for bit.
        let left = (l as f64 - count as f64 / 2.0) * pitch;
        let right = (l as f64 + 1.0 - count as f64 / 2.0) * pitch;
        let bands = match &cached {
            Some((f, b)) if *f == fold_um => b,
            _ => {
                &cached
                    .insert((fold_um, geometry::bands(design, fold_um, half)))
                    .1
            }
        };
        let shape = |b: &geometry::Band| match (b.level, design.height_step_um) {
            (Some(level), Some(step)) => Shape::Flat {
                level,
                height_um: level as f64 * step,
            },
            _ => Shape::Curved {
                centre_um: c,
                offset_um: b.wraps as f64 * fold_um,
                cap_um: match design.surface {
                    Surface::Folded => fold_um,
                    Surface::Unfolded => f64::INFINITY,
                },
            },
        };
        // Left half outside in, the central ring across the centre, right half inside out.
        let last = bands.len() - 1;
        let mut spans: Vec<(f64, f64, &geometry::Band)> = Vec::with_capacity(2 * bands.len());
        for (k, b) in bands.iter().enumerate().skip(1).rev() {
            let x0 = if k == last { left } else { c - b.u1_um };
            spans.push((x0, c - b.u0_um, b));
        }
        let (x0, x1) = if last == 0 {
            (left, right)
        } else {
            (c - bands[0].u1_um, c + bands[0].u1_um)
        };
        spans.push((x0, x1, &bands[0]));
        for (k, b) in bands.iter().enumerate().skip(1) {
            let x1 = if k == last { right } else { c + b.u1_um };
            spans.push((c + b.u0_um, x1, b));
        }
        for (x0, x1, b) in spans {
            // Rounding could put a crossing on or past an edge; such a piece has no width.
            let (x0, x1) = (x0.max(left), x1.min(right));
            if x1 > x0 {
                out.push(Piece {
                    x0_um: x0,
                    x1_um: x1,
                    shape: shape(b),
                });
            }
        }
    }
    Ok(out)
}

/// Height of level `k` for tables: `k·step` without the binary noise (0.6, not
/// 0.6000000000000001), which would otherwise read as a different height in a layer map.
fn level_height_um(k: u64, step_um: f64) -> f64 {
    (k as f64 * step_um * 1e9).round() / 1e9
}

/// Runs of one quantised level `[x0_nm, x1_nm, level]`, merged across pieces and lenslets and
/// snapped to the 1 nm grid. The level is each piece's integer index.
fn level_runs(pieces: &[Piece]) -> Vec<(i64, i64, u64)> {
    let mut runs: Vec<(i64, i64, u64)> = Vec::new();
    for p in pieces {
        let Shape::Flat { level, .. } = p.shape else {
            continue;
        };
        let x0 = (p.x0_um / DB_UNIT_UM).round() as i64;
        let x1 = (p.x1_um / DB_UNIT_UM).round() as i64;
        if x1 <= x0 {
            continue;
        }
        match runs.last_mut() {
            Some(last) if last.2 == level && last.1 == x0 => last.1 = x1,
            _ => runs.push((x0, x1, level)),
        }
    }
    runs
}

/// Writes a multi-level GDSII: layer k holds the rectangles where the height is k·step (k ≥ 1;
/// height 0 is bare substrate and is not drawn), each spanning `length_um` along y. Mask writers
/// and grayscale processes assign one dose or one etch per layer. Coordinates are whole
/// nanometres (database unit 1 nm, user unit 1 µm); the length is rounded to 2 nm so the plate
/// stays centred. Equal neighbouring levels are one rectangle, also across lenslet edges. The
/// top cell [`GDS_TOP_CELL`] carries ASCII notes (units, layer table, design) on
/// [`GDS_NOTE_LAYER`].
///
/// # Errors
/// A message naming `height_step_um` when the design has no step (GDSII needs discrete levels)
/// or too many levels, naming `length_um` when out of range; [`IoError::Mask`] when encoding
/// fails.
pub fn write_height_gds(
    design: &PhaseDesign,
    path: &Path,
    length_um: f64,
) -> Result<ExportSummary, IoError> {
    let lenslets = lenslets_of(design)?;
    check_length(length_um)?;
    let Some(step) = design.height_step_um else {
        return Err(invalid(
            "GDSII export needs a fabrication step: set height_step_um (e.g. 0.2 µm) so every \
             height is one of a few levels, one layer each"
                .into(),
        ));
    };
    let pieces = pieces(design, &lenslets)?;
    let runs = level_runs(&pieces);
    let top_level = runs.iter().map(|r| r.2).max().unwrap_or(0);
    if top_level > i16::MAX as u64 {
        return Err(invalid(format!(
            "height_step_um = {step}: {top_level} levels above 0 need more than GDSII's {} \
             layers; use a coarser step",
            i16::MAX
        )));
    }
    let half_nm = (length_um / DB_UNIT_UM / 2.0).round().max(1.0) as i64;
    let to_i32 = |v: i64| {
        i32::try_from(v)
            .map_err(|_| invalid(format!("coordinate {v} nm is outside GDSII's 32-bit range")))
    };
    let (y0, y1) = (to_i32(-half_nm)?, to_i32(half_nm)?);
    let mut layers: Vec<GdsLayer> = (1..=top_level)
        .map(|k| GdsLayer {
            layer: k as i16,
            height_um: level_height_um(k, step),
            rectangles: 0,
            width_um: 0.0,
        })
        .collect();
    let mut cell = GdsStruct::new(GDS_TOP_CELL);
    let mut width_nm = vec![0i64; layers.len()];
    for &(x0, x1, level) in &runs {
        if level == 0 {
            continue;
        }
        let (a, b) = (to_i32(x0)?, to_i32(x1)?);
        let k = level as usize - 1;
        layers[k].rectangles += 1;
        width_nm[k] += x1 - x0;
        cell.elems.push(GdsElement::GdsBoundary(GdsBoundary {
            layer: level as i16,
            datatype: 0,
            xy: vec![
                GdsPoint::new(a, y0),
                GdsPoint::new(b, y0),
                GdsPoint::new(b, y1),
                GdsPoint::new(a, y1),
                GdsPoint::new(a, y0),
            ],
            ..Default::default()
        }));
    }
    for (layer, w) in layers.iter_mut().zip(&width_nm) {
        layer.width_um = *w as f64 * DB_UNIT_UM;
    }
    let length_written = 2.0 * half_nm as f64 * DB_UNIT_UM;
    let mut notes = vec![
        format!(
            "UDC STUDIO PHASE PLATE: layer k = height k x {step} um (k = 1..{top_level}); \
             height 0 = bare substrate, not drawn"
        ),
        format!(
            "units: user unit 1 um, database unit 1 nm; x across lenslets (x = 0 on the axis), \
             plate uniform along y over {length_written} um"
        ),
    ];
    notes.extend(header_lines(design, &lenslets).into_iter().skip(2));
    let x_note = to_i32(-(lenslets.span_um() / 2.0 / DB_UNIT_UM).round() as i64)?;
    for (k, note) in notes.iter().enumerate() {
        // One line per note, 10 µm apart, above the plate's top-left corner.
        let y = half_nm + 10_000 * (notes.len() - k) as i64;
        cell.elems.push(GdsElement::GdsTextElem(GdsTextElem {
            string: note.clone(),
            layer: GDS_NOTE_LAYER,
            texttype: 0,
            xy: GdsPoint::new(x_note, to_i32(y)?),
            ..Default::default()
        }));
    }
    let mut lib = GdsLibrary::new(GDS_LIBRARY);
    // Database unit 1 nm = 1e-3 user units (1 µm), 1e-9 m.
    lib.units = GdsUnits::new(1e-3, 1e-9);
    lib.structs.push(cell);
    lib.set_all_dates(GdsDateTime::now());
    let mut bytes = Vec::new();
    lib.write(&mut bytes).map_err(|e| IoError::Mask {
        path: path.to_path_buf(),
        message: format!("cannot encode the GDSII library: {e}"),
    })?;
    write_atomic(path, &bytes)?;
    let mut summary = ExportSummary::new(
        path,
        ExportKind::Gds,
        lenslets.span_um(),
        level_height_um(top_level, step),
    );
    summary.levels = Some(top_level as usize + 1);
    summary.um_per_level = Some(step);
    summary.rectangles = Some(layers.iter().map(|l| l.rectangles).sum());
    summary.layers = layers;
    summary.length_um = Some(length_written);
    summary.grid_um = Some(DB_UNIT_UM);
    Ok(summary)
}

/// One vertex of the STL's top profile: x in grid units, z (base + height) in µm.
#[derive(Debug, Clone, Copy)]
struct TopPoint {
    x: i64,
    z_um: f64,
}

/// The x grid of the STL: 1 nm, coarsened by tens while single precision could not tell
/// neighbouring grid points apart (f32 spacing near v is at most v·2⁻²³; four per grid step).
fn stl_grid_um(extent_um: f64) -> f64 {
    let mut grid = DB_UNIT_UM;
    while 4.0 * extent_um * 2f64.powi(-23) > grid && grid < 1e6 {
        grid *= 10.0;
    }
    grid
}

/// The top of the plate's cross-section, left to right: both sides of every jump at the same
/// x (so walls are vertical), curved pieces as chords at most `sample_um` long, flat runs as
/// their two ends.
fn top_profile(
    design: &PhaseDesign,
    pieces: &[Piece],
    sample_um: f64,
    base_um: f64,
    grid_um: f64,
) -> Result<Vec<TopPoint>, IoError> {
    let snap = |x: f64| (x / grid_um).round() as i64;
    let divisions = |p: &Piece, cells: i64| match p.shape {
        Shape::Flat { .. } => 1,
        Shape::Curved { .. } => {
            ((cells as f64 * grid_um / sample_um).ceil() as i64).clamp(1, cells)
        }
    };
    let estimate: f64 = pieces
        .iter()
        .map(|p| divisions(p, (snap(p.x1_um) - snap(p.x0_um)).max(1)) as f64 + 1.0)
        .sum();
    // Each profile vertex costs about eight triangles (top, bottom, two caps).
    if !(8.0 * estimate <= MAX_STL_TRIANGLES as f64) {
        return Err(invalid(format!(
            "sample_um = {sample_um}: the plate would need about {:.0} triangles, more than \
             {MAX_STL_TRIANGLES}; use a coarser sample (or a height step)",
            8.0 * estimate
        )));
    }
    let mut pts: Vec<TopPoint> = Vec::with_capacity(estimate as usize);
    // Jumps smaller than half a grid step are not walls: single precision could not draw them.
    let push = |pts: &mut Vec<TopPoint>, p: TopPoint| match pts.last() {
        Some(last) if last.x == p.x && (last.z_um - p.z_um).abs() < grid_um / 2.0 => {}
        _ => pts.push(p),
    };
    for p in pieces {
        let (x0, x1) = (snap(p.x0_um), snap(p.x1_um));
        if x1 <= x0 {
            continue;
        }
        let n = divisions(p, x1 - x0);
        for i in 0..=n {
            let x = x0 + ((x1 - x0) as f64 * i as f64 / n as f64).round() as i64;
            let z_um = base_um + p.height_um(design, x as f64 * grid_um);
            push(&mut pts, TopPoint { x, z_um });
        }
    }
    // Flat runs keep only their ends.
    let flat = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(1.0);
    let mut out: Vec<TopPoint> = Vec::with_capacity(pts.len());
    for p in pts {
        if let [.., a, b] = out.as_slice()
            && a.x < b.x
            && b.x < p.x
            && flat(a.z_um, b.z_um)
            && flat(b.z_um, p.z_um)
        {
            out.pop();
        }
        out.push(p);
    }
    Ok(out)
}

/// Triangles in the x–z plane, counter-clockwise, filling the column between the vertical
/// chains `a` (at `xa`) and `b` (at `xb > xa`), each listed bottom to top. Every triangle has two
/// vertices on one chain and one on the other, so none is degenerate.
fn zipper(xa: f64, a: &[f64], xb: f64, b: &[f64], out: &mut Vec<[[f64; 2]; 3]>) {
    let (mut i, mut j) = (0, 0);
    while i + 1 < a.len() || j + 1 < b.len() {
        let advance_b = i + 1 >= a.len() || (j + 1 < b.len() && b[j + 1] <= a[i + 1]);
        if advance_b {
            out.push([[xa, a[i]], [xb, b[j]], [xb, b[j + 1]]]);
            j += 1;
        } else {
            out.push([[xa, a[i]], [xb, b[j]], [xa, a[i + 1]]]);
            i += 1;
        }
    }
}

fn triangle(p: [[f64; 3]; 3]) -> Triangle {
    let d1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
    let d2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
    let n = [
        d1[1] * d2[2] - d1[2] * d2[1],
        d1[2] * d2[0] - d1[0] * d2[2],
        d1[0] * d2[1] - d1[1] * d2[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let unit = |v: f64| if len > 0.0 { (v / len) as f32 } else { 0.0 };
    Triangle {
        normal: Normal::new([unit(n[0]), unit(n[1]), unit(n[2])]),
        vertices: p.map(|v| Vertex::new([v[0] as f32, v[1] as f32, v[2] as f32])),
    }
}

/// The closed surface of the extruded cross-section. The cross-section's boundary (top left to
/// right, down the right end, back along the bottom through every column edge, up the left end)
/// runs clockwise in x–z, so extruding each boundary edge `p → q` as `(p0, q0, q1), (p0, q1, p1)`
/// points every side face outward; the end caps are counter-clockwise column strips at y = −L/2
/// (normal −y) and reversed at +L/2. Every edge is then shared by exactly two triangles, once
/// in each direction.
fn plate_triangles(
    top: &[TopPoint],
    grid_um: f64,
    length_um: f64,
) -> Result<Vec<Triangle>, IoError> {
    // Each distinct x with the heights just left and right of it (equal without a jump).
    let mut columns: Vec<(f64, f64, f64)> = Vec::new();
    for p in top {
        let x = p.x as f64 * grid_um;
        match columns.last_mut() {
            Some(c) if c.0 == x => c.2 = p.z_um,
            _ => columns.push((x, p.z_um, p.z_um)),
        }
    }
    if columns.len() < 2 {
        return Err(invalid(
            "the plate has no width to triangulate; check the design".into(),
        ));
    }
    let mut boundary: Vec<[f64; 2]> = top.iter().map(|p| [p.x as f64 * grid_um, p.z_um]).collect();
    boundary.extend(columns.iter().rev().map(|c| [c.0, 0.0]));
    let mut cap = Vec::new();
    for w in columns.windows(2) {
        let (xa, la, ra) = w[0];
        let (xb, lb, rb) = w[1];
        // A jump at an edge splits that side where the lower of its two heights meets it.
        let a: Vec<f64> = if la < ra {
            vec![0.0, la, ra]
        } else {
            vec![0.0, ra]
        };
        let b: Vec<f64> = if rb < lb {
            vec![0.0, rb, lb]
        } else {
            vec![0.0, lb]
        };
        zipper(xa, &a, xb, &b, &mut cap);
    }
    let total = 2 * boundary.len() + 2 * cap.len();
    if total > MAX_STL_TRIANGLES {
        return Err(invalid(format!(
            "the plate needs {total} triangles, more than {MAX_STL_TRIANGLES}; \
             use a coarser sample_um"
        )));
    }
    let (y0, y1) = (-length_um / 2.0, length_um / 2.0);
    let at = |p: [f64; 2], y: f64| [p[0], y, p[1]];
    let mut tris = Vec::with_capacity(total);
    for (k, &p) in boundary.iter().enumerate() {
        let q = boundary[(k + 1) % boundary.len()];
        tris.push(triangle([at(p, y0), at(q, y0), at(q, y1)]));
        tris.push(triangle([at(p, y0), at(q, y1), at(p, y1)]));
    }
    for t in &cap {
        tris.push(triangle([at(t[0], y0), at(t[1], y0), at(t[2], y0)]));
        tris.push(triangle([at(t[0], y1), at(t[2], y1), at(t[1], y1)]));
    }
    Ok(tris)
}

/// Binary STL header text: units first, since STL itself has none. Must not begin with
/// `solid`, which readers take for ASCII STL.
const STL_HEADER: &str = "UDC Studio phase plate; units: micrometres (um); x lenslets, z up";

/// Writes a closed, watertight binary STL of the plate for two-photon printing: the
/// cross-section `{0 ≤ z ≤ base + h(x)}` over the array extruded along y over `length_um`,
/// centred on the origin, in µm. Steps and fold wraps are vertical walls; flat runs are single
/// strips; curved parts are chords at most `sample_um` long (a quantised plate is exact and
/// `sample_um` then does not matter). x is snapped to a 1 nm grid (coarser only when the plate
/// is too wide for single precision to keep 1 nm apart; the summary states it).
///
/// # Errors
/// Names `sample_um`, `length_um` or `base_um` when out of range or the mesh would be too
/// large; [`IoError::File`] when the file cannot be written.
pub fn write_height_stl(
    design: &PhaseDesign,
    path: &Path,
    sample_um: f64,
    length_um: f64,
    base_um: f64,
) -> Result<ExportSummary, IoError> {
    let lenslets = lenslets_of(design)?;
    check_sample(design, sample_um)?;
    check_length(length_um)?;
    check_um("base_um", base_um, MIN_BASE_UM, MAX_BASE_UM, "")?;
    let pieces = pieces(design, &lenslets)?;
    let tallest = lenslets.max_height_um(design);
    let grid_um = stl_grid_um((lenslets.span_um() / 2.0).max(base_um + tallest));
    let top = top_profile(design, &pieces, sample_um, base_um, grid_um)?;
    let tris = plate_triangles(&top, grid_um, length_um)?;
    write_stl_file(path, &tris)?;
    let max_z = max_of(top.iter().map(|p| p.z_um));
    let mut summary = ExportSummary::new(
        path,
        ExportKind::Stl,
        lenslets.span_um(),
        (max_z - base_um).max(0.0),
    );
    summary.samples = Some(top.len());
    summary.sample_um = Some(sample_um);
    summary.triangles = Some(tris.len());
    summary.length_um = Some(length_um);
    summary.base_um = Some(base_um);
    summary.grid_um = Some(grid_um);
    Ok(summary)
}

/// Writes beside the target and renames, so a failed export leaves no half file behind.
fn write_stl_file(path: &Path, tris: &[Triangle]) -> Result<(), IoError> {
    let temp = TempFile::beside(path)?;
    let io = |e| IoError::file("write", path, e);
    let mut file = File::create(temp.path()).map_err(io)?;
    stl_io::write_stl(&mut file, tris.iter()).map_err(io)?;
    // stl_io writes a blank header; the units go in it afterwards.
    let mut header = [0u8; 80];
    let text = STL_HEADER.as_bytes();
    let n = text.len().min(header.len());
    header[..n].copy_from_slice(&text[..n]);
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    file.write_all(&header).map_err(io)?;
    file.flush().map_err(io)?;
    drop(file);
    temp.persist()
}
