//! Design files: the display design (`udc-studio-design`) and the phase design.

use thiserror::Error;

use udc_core::SimError;

/// What is wrong with a design file's text (display or phase design). The JSON errors are
/// serde_json's own, with its line and column.
#[derive(Debug, Error)]
pub enum DesignFileError {
    /// A display design that is not JSON, or has no object with a header.
    #[error("not a design file: {0}")]
    NotADesignFile(serde_json::Error),
    /// A phase design that is not JSON.
    #[error("not JSON: {0}")]
    NotJson(serde_json::Error),
    /// A `format` field that names another format.
    #[error("field `format`: expected \"{expected}\", found \"{found}\"")]
    WrongFormat {
        /// The format this reader reads.
        expected: &'static str,
        /// The format the file names.
        found: String,
    },
    /// No `format` field.
    #[error("field `format` is missing (expected \"{expected}\")")]
    MissingFormat {
        /// The format this reader reads.
        expected: &'static str,
    },
    /// A `version` field other than the one this studio reads.
    #[error("field `version`: this studio reads version {supported}; the file is version {found}")]
    WrongVersion {
        /// The version this studio reads.
        supported: u32,
        /// The file's version.
        found: u32,
    },
    /// No `version` field.
    #[error("field `version` is missing")]
    MissingVersion,
    /// A field that is mistyped, unknown or missing, by its path (`optics.f_number`).
    #[error("field `{field}`: {error}")]
    Field {
        /// The field's path in the file.
        field: String,
        /// serde_json's message, with the line and column.
        error: serde_json::Error,
    },
    /// A display design whose document as a whole does not deserialize (no field to name).
    #[error("{0}")]
    Document(serde_json::Error),
    /// A well-formed design with a value out of range.
    #[error(transparent)]
    Invalid(#[from] SimError),
}
