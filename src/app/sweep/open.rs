//! Reading a results folder, and rebuilding the design a row computed, both for jobs: the
//! folder may hold a large table, and a design may come from a file.

use std::path::Path;

use super::table::SweepTable;
use crate::app::error::StudioError;
use crate::app::job::JobError;
use crate::core::Design;
use crate::core::sweep::SweepJob;
use crate::core::{Progress, SimError};
use crate::io::design::choice::{DesignChoice, design_hash};
use crate::io::error::IoError;
use crate::io::sweep::manifest::{CSV_FILE, read_manifest};
use crate::io::sweep::table::read_csv;

pub use crate::io::sweep::manifest::results_dir;

/// Reads `dir`'s manifest and table, reporting the fraction of the manifest's rows read.
///
/// # Errors
/// An unreadable or foreign manifest or table (the io error naming the file), or
/// [`JobError::Cancelled`].
pub fn read_folder(dir: &Path, progress: &Progress) -> Result<SweepTable, JobError> {
    let manifest = read_manifest(dir)?;
    let expected = manifest.rows.max(1) as f32;
    let mut rows = Vec::with_capacity(usize::try_from(manifest.rows).unwrap_or(0).min(1 << 20));
    let path = dir.join(CSV_FILE);
    let read = read_csv(&path, &manifest.schema, false, |row| {
        rows.push(row);
        if rows.len() % 1024 == 0 {
            progress.set((rows.len() as f32 / expected).min(1.0));
            if progress.is_cancelled() {
                // Any error stops the reader; the check below reports it as a cancellation.
                return Err(IoError::Invalid(SimError::Cancelled));
            }
        }
        Ok(())
    });
    if progress.is_cancelled() {
        return Err(JobError::Cancelled);
    }
    read?;
    Ok(SweepTable {
        dir: dir.to_path_buf(),
        manifest,
        rows,
    })
}

/// A row's design, rebuilt.
#[derive(Debug, Clone)]
pub struct OpenedDesign {
    /// The design, as the sweep's point resolved it (if nothing changed since).
    pub design: Design,
    /// The row's point index.
    pub point: u64,
    /// Whether its hash is the one the row recorded; when not, the preset or a file changed
    /// since the sweep ran.
    pub hash_matches: bool,
}

/// The parameters of row `index` as the command line spells them: the spec's base, then the
/// row's axis values (an axis wins over the base, as in the sweep).
pub fn row_params(table: &SweepTable, index: usize) -> Vec<(String, String)> {
    let mut params: Vec<(String, String)> = table
        .manifest
        .spec
        .base
        .iter()
        .map(|(k, v)| (k.clone(), v.to_arg()))
        .collect();
    if let Some(row) = table.rows.get(index) {
        for ((name, _), value) in table.manifest.schema.params.iter().zip(&row.params) {
            params.retain(|(k, _)| k != name);
            params.push((name.clone(), value.clone()));
        }
    }
    params
}

/// Rebuilds the display design of row `index`. Relative file parameters (`design`,
/// `pattern`) are looked up from the results folder's parent first, where a spec beside its
/// `--out` folder names them from, then from the working directory.
///
/// # Errors
/// A sweep of another job (only display designs open), a row that is not there, or the
/// design's own error (an unknown preset, a file gone).
pub fn open_row(table: &SweepTable, index: usize) -> Result<OpenedDesign, StudioError> {
    let job = table.manifest.spec.job;
    if !matches!(job, SweepJob::Analyze | SweepJob::Restore) {
        return Err(StudioError::NotDisplaySweep(job));
    }
    let row = table.rows.get(index).ok_or(StudioError::NoRow(index))?;
    let base = table.dir.parent().map(Path::to_path_buf);
    let params: Vec<(String, String)> = row_params(table, index)
        .into_iter()
        .map(|(k, v)| {
            let is_file = matches!(k.as_str(), "design" | "pattern" | "spectral");
            match &base {
                Some(b) if is_file && Path::new(&v).is_relative() && b.join(&v).exists() => {
                    (k, b.join(&v).to_string_lossy().into_owned())
                }
                _ => (k, v),
            }
        })
        .collect();
    let choice = DesignChoice::from_params(params.iter().map(|(k, v)| (k.as_str(), v.as_str())))?;
    let design = choice.resolve()?;
    let hash_matches = design_hash(&design) == row.design_hash;
    Ok(OpenedDesign {
        design,
        point: row.point,
        hash_matches,
    })
}
