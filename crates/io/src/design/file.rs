//! The design file: versioned JSON.
//!
//! ```json
//! { "format": "udc-studio-design", "version": 1,
//!   "name": "…", "description": "…",
//!   "opening": { "pitch_um": 168, "cells": ["....", "…"], "polygons": [] },
//!   "tiling":  { "mode": "repeat", "seed": 0, "origin_offset_cells": [6, 6], "wiring_gap_um": 0 },
//!   "optics":  { "recipe": "iccp21", "focal_length_mm": 10, "f_number": 2.5, … },
//!   "channels": [ { "name": "R", "wavelengths_nm": [610], "weights": [1] }, … ],
//!   "subpixels": { "cells": ["RR..GG", "…"] } }
//! ```
//! `subpixels` (optional) is the emitter layer: `R`, `G`, `B` or `.` per cell of the opening.
//! Unknown fields are rejected and every error names the field's path (`optics.f_number`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::IoError;
use crate::error::DesignFileError;
use crate::safe_file::read_text_bounded;
use crate::safe_file::write_atomic;
use udc_core::design::Theory;
use udc_core::design::{Channel, Design, Opening, Optics, Subpixels, Tiling};

/// The `format` field every design file carries.
pub const FORMAT: &str = "udc-studio-design";
/// The file-format version this studio reads and writes (the `version` field).
pub const VERSION: u32 = 1;
/// Design files larger than this are refused before parsing (a 512² grid is ~1.5 MB).
pub const MAX_FILE_BYTES: u64 = 32 * 1024 * 1024;

#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u32>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileV1 {
    format: String,
    version: u32,
    #[serde(default)]
    name: String,
    #[serde(default)]
    description: String,
    opening: Opening,
    tiling: Tiling,
    optics: Optics,
    channels: Vec<Channel>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    theory: Option<Theory>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    subpixels: Option<Subpixels>,
}

/// Parses and validates a design file's text.
///
/// # Errors
/// A [`DesignFileError`] naming the field (its path) and the line for syntax, type,
/// unknown-field and range errors. The caller adds the file path.
pub fn parse_design(text: &str) -> Result<Design, DesignFileError> {
    let header: Header = serde_json::from_str(text).map_err(DesignFileError::NotADesignFile)?;
    match header.format {
        Some(f) if f == FORMAT => {}
        Some(found) => {
            return Err(DesignFileError::WrongFormat {
                expected: FORMAT,
                found,
            });
        }
        None => return Err(DesignFileError::MissingFormat { expected: FORMAT }),
    }
    match header.version {
        Some(VERSION) => {}
        Some(found) => {
            return Err(DesignFileError::WrongVersion {
                supported: VERSION,
                found,
            });
        }
        None => return Err(DesignFileError::MissingVersion),
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    let file: FileV1 = serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        let error = e.into_inner();
        if field == "." || field.is_empty() {
            DesignFileError::Document(error)
        } else {
            DesignFileError::Field { field, error }
        }
    })?;
    let design = Design {
        name: file.name,
        description: file.description,
        opening: file.opening,
        tiling: file.tiling,
        optics: file.optics,
        channels: file.channels,
        theory: file.theory,
        subpixels: file.subpixels,
    };
    design.validate()?;
    Ok(design)
}

/// Reads a design file.
///
/// # Errors
/// [`IoError::File`] when it cannot be read, [`IoError::Design`] when it is not a valid design.
pub fn load_design(path: &Path) -> Result<Design, IoError> {
    let text = read_design_text(path)?;
    parse_design(&text).map_err(|error| IoError::Design {
        path: path.to_path_buf(),
        error,
    })
}

/// The text of a design file (display or phase) of at most [`MAX_FILE_BYTES`].
///
/// # Errors
/// As [`read_text_bounded`]: not a regular file, too large, or not UTF-8.
pub fn read_design_text(path: &Path) -> Result<String, IoError> {
    read_text_bounded(path, MAX_FILE_BYTES, "read the design")
}

/// The design as pretty JSON in the file format.
pub fn to_json(design: &Design) -> String {
    let file = FileV1 {
        format: FORMAT.into(),
        version: VERSION,
        name: design.name.clone(),
        description: design.description.clone(),
        opening: design.opening.clone(),
        tiling: design.tiling.clone(),
        optics: design.optics.clone(),
        channels: design.channels.clone(),
        theory: design.theory,
        subpixels: design.subpixels.clone(),
    };
    // Serialising plain data to a String cannot fail.
    serde_json::to_string_pretty(&file).unwrap_or_default() + "\n"
}

/// Writes a design atomically (temp file, then rename), so a crash never leaves half a file.
///
/// # Errors
/// [`IoError::File`] when the file cannot be written.
pub fn save_design(path: &Path, design: &Design) -> Result<(), IoError> {
    write_atomic(path, to_json(design).as_bytes())
}
