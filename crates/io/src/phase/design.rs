//! The phase design file (`phase_design.json`): a [`PhaseDesign`] as JSON. Read by the studio's
//! autosave and by `phase export --design`, written by both and by `phase optimize --out`.
//!
//! Files written before the sampling convention existed have no `sampling` field: they load
//! with the thesis convention (the default) and a note saying so, since their numbers were
//! computed under the centred one.

use std::path::Path;

use crate::IoError;
use crate::design::file::read_design_text;
use crate::error::DesignFileError;
use crate::safe_file::write_atomic;
use udc_core::phase::PhaseDesign;

/// A design read from a file, with what the reader had to assume.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedPhaseDesign {
    /// The validated design.
    pub design: PhaseDesign,
    /// Said to the user once: e.g. that an older file got the thesis sampling convention.
    pub notes: Vec<String>,
}

/// Parses a phase design from JSON text and validates it.
///
/// # Errors
/// A [`DesignFileError`] naming the field that is missing, mistyped or out of range.
pub fn parse_phase_design(text: &str) -> Result<LoadedPhaseDesign, DesignFileError> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(DesignFileError::NotJson)?;
    let has_sampling = value.get("sampling").is_some();
    // Unlike the display design's, a whole-document error still names its path (`.`).
    let design: PhaseDesign =
        serde_path_to_error::deserialize(value).map_err(|e| DesignFileError::Field {
            field: e.path().to_string(),
            error: e.into_inner(),
        })?;
    design.validate()?;
    let mut notes = Vec::new();
    if !has_sampling {
        notes.push(
            "this phase design predates the sampling convention; it now uses the thesis's \
             (axis on the left edge of pixel 512, 2.03 µm effective pixels), so its PSFs and V \
             differ from those it was saved with"
                .to_string(),
        );
    }
    Ok(LoadedPhaseDesign { design, notes })
}

/// Reads a phase design file.
///
/// # Errors
/// [`IoError::File`] when it cannot be read, [`IoError::Design`] when it is not a valid design.
pub fn load_phase_design(path: &Path) -> Result<LoadedPhaseDesign, IoError> {
    let text = read_design_text(path)?;
    parse_phase_design(&text).map_err(|error| IoError::Design {
        path: path.to_path_buf(),
        error,
    })
}

/// The design as pretty JSON.
pub fn phase_design_json(design: &PhaseDesign) -> String {
    // Serialising plain data to a String cannot fail.
    serde_json::to_string_pretty(design).unwrap_or_default() + "\n"
}

/// Writes a design atomically.
///
/// # Errors
/// [`IoError::File`] when the file cannot be written.
pub fn save_phase_design(path: &Path, design: &PhaseDesign) -> Result<(), IoError> {
    write_atomic(path, phase_design_json(design).as_bytes())
}

/// True when `path` holds a phase design rather than a display design: a display design names
/// its `format`, a phase design has none and carries the folding wavelengths (`lambda0`). An
/// unreadable file is not one, so the display reader reports why it cannot be read.
pub fn is_phase_design_file(path: &Path) -> bool {
    read_design_text(path).is_ok_and(|text| is_phase_design_text(&text))
}

/// As [`is_phase_design_file`], on the file's text.
pub fn is_phase_design_text(text: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(text).is_ok_and(|v| {
        v.get("format").is_none() && v.get("lambda0").is_some() && v.get("fold").is_some()
    })
}
