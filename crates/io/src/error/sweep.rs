//! Sweeps: the spec, the manifest beside the results, the plots.

use thiserror::Error;

use udc_core::SimError;

/// What is wrong with a sweep spec (TOML or JSON), its metric patterns, or the manifest that
/// records it beside the results.
#[derive(Debug, Error)]
pub enum SpecError {
    /// TOML that does not parse or deserialize as a whole (toml's words, with the line).
    // Boxed, as in `TomlField`: toml's error is large, and every `IoError` would carry its size.
    #[error("{}", one_line(&.0.to_string()))]
    Toml(Box<toml::de::Error>),
    /// A TOML field that does not deserialize, by its path.
    #[error("{field}: {}", one_line(&.error.to_string()))]
    TomlField {
        /// The field's path (`axis[0].values`).
        field: String,
        /// toml's error.
        error: Box<toml::de::Error>,
    },
    /// JSON that does not parse or deserialize as a whole (serde_json's words).
    #[error("{0}")]
    Json(serde_json::Error),
    /// A JSON field that does not deserialize, by its path.
    #[error("{field}: {error}")]
    JsonField {
        /// The field's path.
        field: String,
        /// serde_json's error.
        error: serde_json::Error,
    },
    /// A well-formed spec that is not a valid sweep.
    #[error(transparent)]
    Invalid(#[from] SimError),
    /// A metric pattern that matches nothing in the job's output.
    #[error("metric `{pattern}` is not in the job's output; it has: {}", .available.join(", "))]
    UnknownMetric {
        /// The pattern as written.
        pattern: String,
        /// The metrics the output has.
        available: Vec<String>,
    },
    /// A manifest that is not the expected JSON.
    #[error("not a sweep manifest: {0}")]
    NotAManifest(serde_json::Error),
    /// A manifest of another format.
    #[error("format `{found}` is not `{expected}`")]
    ManifestFormat {
        /// The manifest's `format`.
        found: String,
        /// The format this studio writes.
        expected: &'static str,
    },
    /// A manifest that cannot be written as JSON (serde_json's words).
    #[error("{0}")]
    ManifestJson(serde_json::Error),
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

/// Why a sweep plot could not be drawn.
#[derive(Debug, Error)]
pub enum PlotError {
    /// plotters failed to draw or present (its words: its error type depends on the backend).
    #[error("cannot draw the plot: {0}")]
    Draw(String),
    /// The pixel buffer does not match the plot's size.
    #[error("cannot draw the plot: buffer size")]
    BufferSize,
    /// The PNG encoder failed (its own words).
    #[error("cannot draw the plot: {0}")]
    Encode(image::ImageError),
}
