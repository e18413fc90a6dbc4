//! Reading a sweep spec: TOML (`.toml`) or JSON (anything else), with errors that name the
//! field (and in TOML the line) and the file.

use std::path::Path;

use crate::error::{IoError, SpecError};
use crate::safe_file::read_text_bounded;
use udc_core::sweep::SweepSpec;

/// Specs are a few lines; anything larger is not one.
const MAX_SPEC_BYTES: u64 = 1_000_000;

/// Reads and validates a spec file.
///
/// # Errors
/// [`IoError::Spec`] naming the field and the file; [`IoError::File`] and friends when it
/// cannot be read.
pub fn load_spec(path: &Path) -> Result<SweepSpec, IoError> {
    let text = read_text_bounded(path, MAX_SPEC_BYTES, "sweep spec")?;
    let toml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    parse_spec(&text, toml).map_err(|error| IoError::Spec {
        path: path.to_path_buf(),
        error,
    })
}

/// Writes `spec` as the TOML `udc-studio sweep` reads, atomically.
///
/// # Errors
/// A spec TOML cannot hold (never for a valid one), or a file that cannot be written.
pub fn save_spec_toml(path: &Path, spec: &SweepSpec) -> Result<(), IoError> {
    let text = toml::to_string(spec).map_err(|e| {
        IoError::file(
            "write the spec as TOML",
            path,
            std::io::Error::other(e.to_string()),
        )
    })?;
    crate::safe_file::write_atomic(path, text.as_bytes())
}

/// Parses and validates spec text, TOML or JSON.
///
/// # Errors
/// A [`SpecError`]: what is wrong and where (the field's path; in TOML the line).
pub fn parse_spec(text: &str, toml: bool) -> Result<SweepSpec, SpecError> {
    let spec: SweepSpec = if toml {
        let de = toml::Deserializer::parse(text).map_err(|e| SpecError::Toml(Box::new(e)))?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            let error = Box::new(e.into_inner());
            if field == "." {
                SpecError::Toml(error)
            } else {
                SpecError::TomlField { field, error }
            }
        })?
    } else {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            let error = e.into_inner();
            if field == "." {
                SpecError::Json(error)
            } else {
                SpecError::JsonField { field, error }
            }
        })?
    };
    spec.validate()?;
    Ok(spec)
}
