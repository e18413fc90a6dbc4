//! Reading a sweep spec: TOML (`.toml`) or JSON (anything else), with errors that name the
//! field (and in TOML the line) and the file.

use std::path::Path;

use crate::error::IoError;
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
    parse_spec(&text, toml).map_err(|message| IoError::Spec {
        path: path.to_path_buf(),
        message,
    })
}

/// Parses and validates spec text, TOML or JSON.
///
/// # Errors
/// One line saying what is wrong and where.
pub fn parse_spec(text: &str, toml: bool) -> Result<SweepSpec, String> {
    let spec: SweepSpec = if toml {
        let de = toml::Deserializer::parse(text).map_err(|e| one_line(&e.to_string()))?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = one_line(&e.into_inner().to_string());
            if path == "." {
                inner
            } else {
                format!("{path}: {inner}")
            }
        })?
    } else {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner().to_string();
            if path == "." {
                inner
            } else {
                format!("{path}: {inner}")
            }
        })?
    };
    spec.validate().map_err(|e| e.to_string())?;
    Ok(spec)
}

/// TOML's errors draw the offending line with a caret over several lines: keep the headline
/// and the line number.
fn one_line(text: &str) -> String {
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('|') && !l.chars().all(|c| c == '^'))
        .collect();
    lines.join(" ")
}
