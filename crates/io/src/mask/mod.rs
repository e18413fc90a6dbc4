//! Mask files for photolithography: GDSII, DXF, SVG and PNG of one region of a design, and
//! reading GDSII/DXF masks back into a cell grid.
//!
//! The geometry comes from [`udc_core::mask::MaskLayout`] (nanometres, y up, optical axis at
//! the origin). Every file states its tone (`TONE=OPEN: DRAWN = OPEN (CLEAR)` or the chrome
//! equivalent) in a note, and the design is written beside it as `<file>.design.json`.

mod deck;
mod dxf;
mod fab;
mod flat_size;
mod frame;
mod gds;
pub use gds::{ArrayGrid, array_grid};
mod import;
mod integrity;
mod oasis;
mod png;
mod png_read;
mod rules;
mod sampling;
mod svg;
mod walk;

use std::path::{Path, PathBuf};
use std::time::Instant;

use udc_core::design::Design;
use udc_core::mask::BorderCounts;
use udc_core::mask::drc::Rules;
use udc_core::mask::{FrameSpec, MaskError, MaskLayout, MaskSpec, MaskStats, Tone, mask_ltr};
use udc_core::psf::warning::SamplingWarning;
use udc_core::{Progress, ValueError};

use super::IoError;
use super::error::ExportOptionsError;
use super::fab::{LayerMap, MAX_BOUNDARY_VERTICES, Sidecars};

/// Largest mask file read back (GDSII or DXF): masks of whole displays are tens of MB.
pub const MAX_MASK_BYTES: u64 = 1024 * 1024 * 1024;
use super::safe_file::{TempFile, write_atomic};
use crate::design::file::to_json;

pub use deck::drc_deck;
pub use fab::{FRAME_LAYER, LABEL_LAYER, LayerRole, MARKS_LAYER, MaskLayers, design_hash};
pub use frame::{FrameDrawing, frame_drawing, label_date};
pub use import::{
    ChecksumCheck, ImportOptions, ImportWindow, ImportedMask, drawn_bounds_um, foreign_window,
    import_mask, import_opening, import_opening_on, mask_notes, note_field,
};
pub use integrity::verify_checksum;
pub use rules::{CheckScope, MAX_EXPORT_CHECK_VERTICES, RulesCheck, check_file, check_written};
pub use walk::region_bbox_nm;
use walk::{cell_vertex_counts, for_each_flat_polygon};

/// Polygons (µm, y up) and text notes a mask reader found in a file.
pub(crate) type Drawn = (Vec<Vec<[f64; 2]>>, Vec<String>);

/// A mask file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MaskFormat {
    /// GDSII stream (`.gds`), with cell references for repeated pixels.
    #[default]
    Gds,
    /// OASIS (`.oas`, SEMI P39), the same cells as GDSII with compact repetitions: a random
    /// tiling's file is an order of magnitude smaller.
    Oas,
    /// AutoCAD DXF (`.dxf`), every polygon flattened.
    Dxf,
    /// SVG (`.svg`), every polygon flattened; for viewing.
    Svg,
    /// A raster image (`.png`) of the region, 1 or 8 bits per pixel.
    Png,
}

impl MaskFormat {
    /// Every format, in menu order.
    pub const ALL: [MaskFormat; 5] = [
        MaskFormat::Gds,
        MaskFormat::Oas,
        MaskFormat::Dxf,
        MaskFormat::Svg,
        MaskFormat::Png,
    ];

    /// The name on the command line (`--format`), lower case.
    pub fn as_str(self) -> &'static str {
        match self {
            MaskFormat::Gds => "gds",
            MaskFormat::Oas => "oas",
            MaskFormat::Dxf => "dxf",
            MaskFormat::Svg => "svg",
            MaskFormat::Png => "png",
        }
    }

    /// The name shown to users (e.g. "GDSII").
    pub fn label(self) -> &'static str {
        match self {
            MaskFormat::Gds => "GDSII",
            MaskFormat::Oas => "OASIS",
            MaskFormat::Dxf => "DXF",
            MaskFormat::Svg => "SVG",
            MaskFormat::Png => "PNG",
        }
    }

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        self.as_str()
    }

    /// The format a file's extension names (`gds`, `gdsii`, `gds2`, `oas`, `oasis`, `dxf`,
    /// `svg`, `png`, any case), the one spelling the readers and commands share.
    pub fn of_path(path: &Path) -> Option<MaskFormat> {
        let ext = path.extension()?.to_string_lossy().to_lowercase();
        match ext.as_str() {
            "gds2" => Some(MaskFormat::Gds),
            other => other.parse().ok(),
        }
    }
}

impl std::str::FromStr for MaskFormat {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        MaskFormat::ALL
            .into_iter()
            .find(|f| {
                f.as_str() == s
                    || (s == "gdsii" && *f == MaskFormat::Gds)
                    || (s == "oasis" && *f == MaskFormat::Oas)
            })
            .ok_or_else(|| ValueError::UnknownName {
                what: "mask format",
                value: s.to_string(),
                expected: "gds, oas, dxf, svg or png",
            })
    }
}

/// How a GDSII file realises the tile orientations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GdsCells {
    /// One cell holds the opening; each pixel is a reference with the STRANS reflection bit and
    /// angle of its D4 element.
    #[default]
    Strans,
    /// One cell per orientation used, each holding its own transformed polygons; references
    /// carry no STRANS (for tools that mishandle reflected references).
    PerOrientation,
}

impl std::str::FromStr for GdsCells {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        match s {
            "strans" => Ok(GdsCells::Strans),
            "per-orientation" => Ok(GdsCells::PerOrientation),
            other => Err(ValueError::UnknownName {
                what: "GDSII cell layout",
                value: other.to_string(),
                expected: "strans or per-orientation",
            }),
        }
    }
}

/// Bits per PNG pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PngBits {
    /// Black/white: a pixel is drawn when at least half of it is covered.
    One,
    /// Grey levels: the covered fraction of each pixel.
    #[default]
    Eight,
}

impl std::str::FromStr for PngBits {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        match s {
            "1" => Ok(PngBits::One),
            "8" => Ok(PngBits::Eight),
            other => Err(ValueError::UnknownName {
                what: "PNG bit depth",
                value: other.to_string(),
                expected: "1 or 8",
            }),
        }
    }
}

/// Everything an export needs besides the design.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportOptions {
    /// The file format.
    pub format: MaskFormat,
    /// The region, tone and coordinate grid to lay out.
    pub spec: MaskSpec,
    /// GDSII layer and datatype of the drawn polygons.
    pub layer: i16,
    /// GDSII datatype of the drawn polygons (0–255).
    pub datatype: i16,
    /// Layer of the pupil outline and the text notes.
    pub note_layer: i16,
    /// GDSII top cell name: 1 to 32 ASCII letters, digits, `_`, `-` or `$`; `None` derives it
    /// from the design's name and hash (see [`crate::fab::derived_cell_name`]).
    pub top_cell: Option<String>,
    /// How GDSII realises the pixels' orientations.
    pub gds_cells: GdsCells,
    /// PNG resolution.
    pub um_per_px: f64,
    /// Bits per PNG pixel.
    pub png_bits: PngBits,
    /// Layers by role (`--layer-map`), overriding `layer`, `datatype` and `note_layer`.
    pub layer_map: Option<LayerMap>,
    /// Fixed GDSII and DXF timestamps (and nil DXF GUIDs), so identical exports are
    /// byte-identical.
    pub deterministic: bool,
    /// Die frame, alignment marks and label outside the region (all off by default).
    pub frame: FrameSpec,
    /// Whether the design has a subpixel (emitter) layer to write on the emitter roles' layers
    /// (set by `ExportOptions::resolved` from the design).
    pub emitters: bool,
    /// The design rules the written geometry is checked against before it is written.
    pub rules: Rules,
    /// Write nothing when the written geometry breaks a rule.
    pub strict: bool,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            format: MaskFormat::Gds,
            spec: MaskSpec::default(),
            layer: 1,
            datatype: 0,
            note_layer: 2,
            top_cell: None,
            gds_cells: GdsCells::Strans,
            um_per_px: 1.0,
            png_bits: PngBits::Eight,
            layer_map: None,
            deterministic: false,
            frame: FrameSpec::default(),
            emitters: false,
            rules: Rules::default(),
            strict: false,
        }
    }
}

impl ExportOptions {
    /// Checks the options that do not depend on the design.
    ///
    /// # Errors
    /// An [`ExportOptionsError`] naming the bad option.
    pub fn validate(&self) -> Result<(), ExportOptionsError> {
        let name = self.top_cell.as_deref().unwrap_or("UDC_MASK");
        if name.is_empty()
            || name.len() > 32
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '$'))
        {
            return Err(ExportOptionsError::TopCellName {
                name: name.to_string(),
            });
        }
        for (option, value) in [
            ("layer", self.layer),
            ("datatype", self.datatype),
            ("note layer", self.note_layer),
        ] {
            if !(0..=255).contains(&value) {
                return Err(ExportOptionsError::OutOfRange { option, value });
            }
        }
        if self.note_layer == self.layer {
            return Err(ExportOptionsError::NoteLayerIsDrawingLayer {
                layer: self.note_layer,
            });
        }
        self.frame.validate().map_err(ExportOptionsError::Frame)?;
        self.mask_layers()?;
        if !(self.um_per_px.is_finite() && self.um_per_px > 0.0) {
            return Err(ExportOptionsError::UmPerPx {
                um_per_px: self.um_per_px,
            });
        }
        Ok(())
    }
}

/// What a file holds (or would hold), as the writers count it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FileCounts {
    /// Polygons written to the file (GDSII: in its cells, references not expanded).
    pub polygons: u64,
    /// Vertices of those polygons.
    pub vertices: u64,
    /// Single references (one per pixel of a random tiling).
    pub references: u64,
    /// Array references (periodic tilings).
    pub arrays: u64,
    /// File size in bytes (an estimate before writing).
    pub bytes: u64,
}

/// The export report: what was written, and the numbers a mask house asks about.
#[derive(Debug, Clone, PartialEq)]
pub struct MaskReport {
    /// The mask file written.
    pub path: PathBuf,
    /// The design written beside it (`<file>.design.json`).
    pub sidecar: PathBuf,
    /// Checksum, manifest and layer map written beside it.
    pub fab_files: Sidecars,
    /// The options it was written with.
    pub options: ExportOptions,
    /// Counts and areas of the laid-out region.
    pub stats: MaskStats,
    /// The design-rule check of the written geometry.
    pub drc: RulesCheck,
    /// What the border policy did with the openings the region's edge cuts.
    pub border: BorderCounts,
    /// What the file holds.
    pub counts: FileCounts,
    /// Light transmittance ratio of the thresholded display over the lens pupil (0–1).
    pub ltr: f64,
    /// Display pixel pitch on the grid, in nm.
    pub pitch_nm: i64,
    /// Tile period (pitch plus wiring gap) on the grid, in nm.
    pub period_nm: i64,
    /// Wall-clock time of the export, in seconds.
    pub seconds: f64,
    /// The design's sampling warnings and notes, as `udc-studio analyze` and the studio give
    /// them: the LTR and the design's numbers come with the same caveats.
    pub sampling: Vec<SamplingWarning>,
    /// Why the sampling could not be checked (the analysis failed), when it could not.
    pub sampling_unchecked: Option<String>,
}

/// `n` and its noun in the right number ("1 pixel", "2 pixels").
fn counted(n: u64, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

impl MaskReport {
    /// The report as lines of text (CLI output, studio status).
    pub fn lines(&self) -> Vec<String> {
        let o = &self.options;
        let s = &self.stats;
        let c = &self.counts;
        vec![
            format!(
                "wrote {} ({}, {}) in {:.2} s; design in {}",
                self.path.display(),
                o.format.label(),
                human_bytes(c.bytes),
                self.seconds,
                self.sidecar.display()
            ),
            format!(
                "tone: {} ({}); {}; top cell {}",
                o.spec.tone.as_str(),
                o.spec.tone.meaning(),
                o.layers_line(),
                o.top_cell_name()
            ),
            format!(
                "region: {}, {} in {}; pitch {:.3} µm, period {:.3} µm, grid {} nm",
                o.spec.region.label(),
                counted(s.tiles, "pixel", "pixels"),
                counted(s.orientations as u64, "orientation", "orientations"),
                self.pitch_nm as f64 * 1e-3,
                self.period_nm as f64 * 1e-3,
                o.spec.grid_nm
            ),
            format!(
                "polygons: {} written ({} vertices), {} per pixel, {} when flattened",
                c.polygons, c.vertices, s.polygons_per_tile, s.flat_polygons
            ),
            format!(
                "references: {} single, {}",
                c.references,
                counted(c.arrays, "array", "arrays")
            ),
            format!(
                "open area: {:.6e} µm² of {:.6e} µm² (open fraction {:.6}); LTR {:.4}",
                s.open_area_um2,
                s.region_area_um2,
                s.open_fraction(),
                self.ltr
            ),
            self.border.line(o.spec.border),
        ]
        .into_iter()
        .chain(frame::report_line(o))
        .chain(sampling::lines(
            &self.sampling,
            self.sampling_unchecked.as_deref(),
        ))
        .collect()
    }
}

/// `12.3 MB`-style sizes.
pub fn human_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.2} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.1} MB", b / 1e6)
    } else if b >= 1e3 {
        format!("{:.1} kB", b / 1e3)
    } else {
        format!("{bytes} B")
    }
}

/// The sidecar design file of a mask: `<file>.design.json`.
pub fn sidecar_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".design.json");
    path.with_file_name(name)
}

/// Lays out `design` for `options` (no file is touched).
///
/// # Errors
/// A message for bad options or a design that cannot be laid out.
pub fn plan(design: &Design, options: &ExportOptions) -> Result<MaskLayout, MaskError> {
    // The core's mask error holds the options' complaint as text.
    options
        .validate()
        .map_err(|e| MaskError::Invalid(e.to_string()))?;
    let mut spec = options.spec.clone();
    if options.format == MaskFormat::Gds {
        // Many GDSII readers keep records within 32 kB: split boundaries before they exceed it.
        spec.max_vertices = spec.max_vertices.min(MAX_BOUNDARY_VERTICES);
    }
    MaskLayout::new(design, &spec)
}

/// What the file would hold, without writing it (the dialog's preview).
pub fn estimate(layout: &MaskLayout, options: &ExportOptions) -> FileCounts {
    match options.format {
        MaskFormat::Gds => gds::estimate(layout, options),
        MaskFormat::Oas => oasis::estimate(layout, options),
        MaskFormat::Dxf => dxf::estimate(layout),
        MaskFormat::Svg => svg::estimate(layout),
        MaskFormat::Png => png::estimate(layout, options),
    }
}

/// Writes the mask of `design` to `path` (through a temporary file, so a failed or cancelled
/// export leaves nothing behind) and the design to `<path>.design.json`.
///
/// # Errors
/// [`IoError::MaskLayout`] for a design or options that cannot be laid out (or a cancelled
/// export), [`IoError::File`] when a file cannot be written.
pub fn export_mask(
    design: &Design,
    options: &ExportOptions,
    path: &Path,
    progress: &Progress,
) -> Result<MaskReport, IoError> {
    let start = Instant::now();
    let options = &options
        .resolved(design)
        .map_err(|e| MaskError::Invalid(e.to_string()))?;
    let layout = plan(design, options)?;
    let notes = notes(design, &layout, options, path);
    let frame = frame_drawing(&layout, options, &design.name)?;
    // Checked before anything is written: a strict export that fails leaves nothing behind.
    let drc = check_written(design, &layout, options, &frame, progress)?;
    if options.strict && !drc.report.is_clean() {
        return Err(IoError::RulesBroken {
            scope: drc.scope_line(),
            report: Box::new(drc.report),
        });
    }
    // Dropped on any error (or a cancel), the temp file goes with it.
    let temp = TempFile::beside(path)?;
    // After the temp file (an unwritable path fails before a second of analysis), before the
    // mask (a cancel during the analysis leaves nothing behind).
    let (sampling, sampling_unchecked) = sampling::check(design, progress)?;
    let tmp = temp.path();
    let counts = match options.format {
        MaskFormat::Gds => gds::write(&layout, options, &notes, &frame, tmp, progress),
        MaskFormat::Oas => oasis::write(&layout, options, &notes, &frame, tmp, progress),
        MaskFormat::Dxf => dxf::write(&layout, options, &notes, &frame, tmp, progress),
        MaskFormat::Svg => svg::write(&layout, &notes, &frame, tmp, progress),
        MaskFormat::Png => png::write(&layout, options, &notes, tmp, progress),
    }
    .map_err(|e| e.naming(tmp, path))?;
    temp.persist()?;
    let sidecar = sidecar_path(path);
    write_atomic(&sidecar, to_json(design).as_bytes())?;
    let fab_files = fab::write_mask_sidecars(design, options, path)?;
    progress.set(1.0);
    Ok(MaskReport {
        path: path.to_path_buf(),
        sidecar,
        fab_files,
        options: options.clone(),
        stats: layout.stats(),
        drc,
        border: layout.border.counts,
        counts,
        ltr: mask_ltr(design),
        pitch_nm: layout.pitch_nm,
        period_nm: layout.period_nm,
        seconds: start.elapsed().as_secs_f64(),
        sampling,
        sampling_unchecked,
    })
}

/// The text notes every file carries (ASCII: GDSII strings are ASCII).
fn notes(design: &Design, layout: &MaskLayout, o: &ExportOptions, path: &Path) -> Vec<String> {
    let ascii = |s: &str| -> String {
        s.chars()
            .map(|c| {
                if c.is_ascii_graphic() || c == ' ' {
                    c
                } else {
                    '?'
                }
            })
            .take(200)
            .collect()
    };
    let tone = o.spec.tone;
    vec![
        format!("UDC STUDIO MASK: {}", ascii(&design.name)),
        format!(
            "TONE={}: {}",
            tone.as_str().to_uppercase(),
            tone.meaning().to_uppercase()
        ),
        format!(
            "LAYER={} DATATYPE={} NOTES_LAYER={} UNITS: USER 1 UM, DATABASE 1 NM, GRID_NM={}",
            o.layer, o.datatype, o.note_layer, o.spec.grid_nm
        ),
        format!(
            "PITCH_NM={} PERIOD_NM={} CELLS={} REGION={} PIXELS={} TILING={} SEED={} \
             AXIS_CELL={},{}",
            layout.pitch_nm,
            layout.period_nm,
            layout.n,
            o.spec.region.label(),
            layout.tiles,
            design.tiling.mode.as_str(),
            design.tiling.seed,
            // The registration, so `udc-studio import` finds the axis pixel without the sidecar.
            design.tiling.origin_offset_cells[0],
            design.tiling.origin_offset_cells[1]
        ),
        format!(
            "DESIGN FILE: {}",
            ascii(
                &sidecar_path(path)
                    .file_name()
                    .unwrap_or_default()
                    .to_string_lossy()
            )
        ),
        format!(
            "BORDER={} MARGIN_UM={}: {}",
            o.spec.border.as_str().to_uppercase(),
            o.spec.margin_um,
            o.spec.border.meaning().to_uppercase()
        ),
    ]
}

/// The tone a file states in its notes (`None` when it states none).
pub fn tone_of_notes<'a>(notes: impl IntoIterator<Item = &'a str>) -> Option<Tone> {
    notes.into_iter().find_map(|n| {
        if n.starts_with("TONE=CHROME") {
            Some(Tone::Chrome)
        } else if n.starts_with("TONE=OPEN") {
            Some(Tone::Open)
        } else {
            None
        }
    })
}
