//! The design-rule check of what a mask file holds: the polygons on its drawn layer after the
//! region is cut, the tone chosen, the border redrawn and the frame added (when a layer map puts
//! the frame or marks on the drawn layer, they are checked with it). The export runs it before
//! writing; `udc-studio drc FILE` runs it on a file read back; both with
//! [`udc_core::mask::geometry_drc`].

use std::path::Path;

use super::{ChecksumCheck, ExportOptions, FrameDrawing, MaskFormat, for_each_flat_polygon};
use crate::IoError;
use udc_core::Progress;
use udc_core::design::Design;
use udc_core::mask::drc::{DrcReport, Rules, check};
use udc_core::mask::geometry_drc::{DrawnGeometry, GeometryDrcError, MAX_CHECK_VERTICES};
use udc_core::mask::{MaskError, MaskLayout, Tone};

/// The most flattened vertices an export checks as written (about a second); a larger region
/// (a whole display) is checked as a design, so the export stays as fast as its writer.
/// `udc-studio drc FILE` takes up to [`MAX_CHECK_VERTICES`].
pub const MAX_EXPORT_CHECK_VERTICES: u64 = 2_000_000;

/// What a check covered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CheckScope {
    /// The written geometry, every polygon of the drawn layer.
    Written,
    /// The design only (a pixel beside its tiled neighbours): the written geometry has more
    /// vertices than an export checks flat ([`MAX_EXPORT_CHECK_VERTICES`]).
    DesignOnly {
        /// Vertices of the written geometry, flattened.
        vertices: u64,
    },
}

/// A design-rule check and what it covered.
#[derive(Debug, Clone, PartialEq)]
pub struct RulesCheck {
    /// The findings.
    pub report: DrcReport,
    /// What was checked.
    pub scope: CheckScope,
}

impl RulesCheck {
    /// One line on what was checked.
    pub fn scope_line(&self) -> String {
        match self.scope {
            CheckScope::Written => "design rules checked on the written geometry".into(),
            CheckScope::DesignOnly { vertices } => format!(
                "design rules checked on the design only: the written geometry ({vertices} \
                 vertices flattened) is more than the {MAX_EXPORT_CHECK_VERTICES} an export \
                 checks flat (`udc-studio drc FILE` takes {MAX_CHECK_VERTICES})"
            ),
        }
    }
}

fn geometry_error(e: GeometryDrcError) -> IoError {
    match e {
        GeometryDrcError::Cancelled => MaskError::Cancelled.into(),
        other => MaskError::Invalid(other.to_string()).into(),
    }
}

/// Checks the geometry `layout` and `frame` put on the drawn layer against `o.rules`.
///
/// # Errors
/// [`MaskError::Cancelled`] when `progress` is cancelled.
pub fn check_written(
    design: &Design,
    layout: &MaskLayout,
    o: &ExportOptions,
    frame: &FrameDrawing,
    progress: &Progress,
) -> Result<RulesCheck, IoError> {
    let flat = layout.stats().flat_vertices;
    if flat > MAX_EXPORT_CHECK_VERTICES {
        return Ok(RulesCheck {
            report: check(design, &o.rules),
            scope: CheckScope::DesignOnly { vertices: flat },
        });
    }
    let layers = o
        .mask_layers()
        .map_err(|e| MaskError::Invalid(e.to_string()))?;
    let mut g = DrawnGeometry::new();
    let walk = Progress::new();
    for_each_flat_polygon(layout, &walk, |poly| g.add(poly).map_err(geometry_error))?;
    for (role, poly) in &frame.polygons {
        if o.format != MaskFormat::Png && layers.of(*role) == layers.openings {
            g.add(&poly.points_nm).map_err(geometry_error)?;
        }
    }
    let report = g
        .check(layout.spec.tone, &o.rules, progress)
        .map_err(geometry_error)?;
    Ok(RulesCheck {
        report,
        scope: CheckScope::Written,
    })
}

/// Checks the polygons of a GDSII, OASIS or DXF file on `layer`/`datatype` against `rules`;
/// the tone is the file's note unless `tone` says.
///
/// # Errors
/// An unreadable or damaged file (its checksum is verified unless `checksum` says not), an
/// extension that names no mask format, nothing on the layer, or a slanted edge.
pub fn check_file(
    path: &Path,
    (layer, datatype): (i16, i16),
    tone: Option<Tone>,
    rules: &Rules,
    checksum: ChecksumCheck,
    progress: &Progress,
) -> Result<(DrcReport, Tone), IoError> {
    super::import::vector_format(path)?;
    if checksum == ChecksumCheck::Verify {
        super::integrity::verify_checksum(path)?;
    }
    let (polygons, texts) = super::import::read_drawn(path, layer, datatype, None, None)?;
    if polygons.is_empty() {
        return Err(IoError::MaskImport {
            path: path.to_path_buf(),
            error: crate::error::MaskImportError::NoPolygon { layer, datatype },
        });
    }
    let tone = tone
        .or_else(|| super::tone_of_notes(texts.iter().map(String::as_str)))
        .unwrap_or(Tone::Open);
    let mask_err = |message: String| IoError::Mask {
        path: path.to_path_buf(),
        message,
    };
    let mut g = DrawnGeometry::new();
    let mut nm = Vec::new();
    for poly in &polygons {
        nm.clear();
        for p in poly {
            if !(p[0].is_finite() && p[1].is_finite() && p[0].abs() < 1e7 && p[1].abs() < 1e7) {
                return Err(mask_err(format!(
                    "a vertex at ({}, {}) µm is beyond any mask",
                    p[0], p[1]
                )));
            }
            nm.push([(p[0] * 1e3).round() as i64, (p[1] * 1e3).round() as i64]);
        }
        g.add(&nm).map_err(|e| match e {
            GeometryDrcError::Cancelled => IoError::from(MaskError::Cancelled),
            other => mask_err(format!("layer {layer}/{datatype}: {other}")),
        })?;
    }
    let report = g.check(tone, rules, progress).map_err(|e| match e {
        GeometryDrcError::Cancelled => IoError::from(MaskError::Cancelled),
        other => mask_err(other.to_string()),
    })?;
    Ok((report, tone))
}
