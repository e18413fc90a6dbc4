//! `sweep.json` beside the results: the spec, the shard, the columns, the tool version and
//! how the run went. `sweep merge` reads it to check that shards belong to one sweep.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::table::TableSchema;
use crate::error::{IoError, SpecError};
use crate::safe_file::{read_text_bounded, write_atomic};
use udc_core::sweep::SweepSpec;
use udc_core::sweep::hash::short_hash;

/// The file's name in a results folder.
pub const MANIFEST_FILE: &str = "sweep.json";
/// The results tables' names.
pub const CSV_FILE: &str = "results.csv";

/// The results folder a path names: the folder itself, or the folder of its `sweep.json` or
/// `results.csv`; `None` for any other file.
pub fn results_dir(path: &Path) -> Option<PathBuf> {
    if path.is_dir() {
        return Some(path.to_path_buf());
    }
    let name = path.file_name()?.to_string_lossy();
    if name == MANIFEST_FILE || name == CSV_FILE {
        return path.parent().map(Path::to_path_buf);
    }
    None
}
/// See [`CSV_FILE`].
pub const PARQUET_FILE: &str = "results.parquet";
/// Format tag of the manifest.
pub const FORMAT: &str = "udc-studio-sweep";

/// What a results folder holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Always [`FORMAT`].
    pub format: String,
    /// Manifest version (1).
    pub version: u32,
    /// The spec the points came from.
    pub spec: SweepSpec,
    /// Hash of what defines the points (job, base, axes, metrics): shards of one sweep share it.
    pub spec_hash: String,
    /// Points in the whole sweep.
    pub points: u64,
    /// This folder's shard `[index, count]`; `[0, 1]` for a whole sweep or a merge.
    pub shard: [u64; 2],
    /// The table's columns.
    pub schema: TableSchema,
    /// The `udc-studio` version that wrote the folder.
    pub tool_version: String,
    /// Rows in the table (finished points, failed ones included).
    pub rows: u64,
    /// Rows whose point failed.
    pub failed: u64,
    /// Whether every point of the shard is in the table.
    pub complete: bool,
    /// Wall time of the last run, s.
    pub elapsed_s: f64,
    /// Points computed per second in the last run (skipped ones not counted).
    pub points_per_s: f64,
    /// Worker threads of the last run.
    pub threads: usize,
}

/// The hash that identifies a sweep's points.
pub fn spec_hash(spec: &SweepSpec) -> String {
    let key = serde_json::json!({
        "job": spec.job, "base": spec.base, "axes": spec.axes, "metrics": spec.metric_patterns()
    });
    short_hash(key.to_string().as_bytes())
}

/// Writes `dir/sweep.json`.
///
/// # Errors
/// [`IoError::File`].
pub fn write_manifest(dir: &Path, m: &Manifest) -> Result<(), IoError> {
    let text = serde_json::to_string_pretty(m).map_err(|e| IoError::Spec {
        path: dir.join(MANIFEST_FILE),
        error: SpecError::ManifestJson(e),
    })?;
    write_atomic(&dir.join(MANIFEST_FILE), text.as_bytes())
}

/// Reads `dir/sweep.json`.
///
/// # Errors
/// [`IoError::Spec`] naming the file when it is not a sweep manifest.
pub fn read_manifest(dir: &Path) -> Result<Manifest, IoError> {
    let path = dir.join(MANIFEST_FILE);
    let text = read_text_bounded(&path, 10_000_000, "sweep manifest")?;
    let m: Manifest = serde_json::from_str(&text).map_err(|e| IoError::Spec {
        path: path.clone(),
        error: SpecError::NotAManifest(e),
    })?;
    if m.format != FORMAT {
        return Err(IoError::Spec {
            path,
            error: SpecError::ManifestFormat {
                found: m.format,
                expected: FORMAT,
            },
        });
    }
    Ok(m)
}
