//! What a job computes: its JSON object and its text table. The front end picks one (`--json`
//! prints the object, a sweep keeps it as a row, Python returns it; the CLI prints the text).

use serde_json::Value;

/// A job's result, in its two renderings.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// The object `--json` prints: every number the job reports, with its unit in its name.
    pub json: Value,
    /// The text the CLI prints without `--json`: a table, notes and the files written, one
    /// line each.
    pub text: String,
}
