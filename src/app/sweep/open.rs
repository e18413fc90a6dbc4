//! Reading a results folder, and rebuilding the design a row computed, both for jobs: the
//! folder may hold a large table, and a design may come from a file.

use std::path::Path;

use super::table::SweepTable;
use crate::app::error::StudioError;
use crate::app::job::JobError;
use crate::core::Design;
use crate::core::phase::PhaseDesign;
use crate::core::sweep::SweepJob;
use crate::core::sweep::{ParamValue, Points};
use crate::core::{Progress, SimError};
use crate::io::design::hash::design_hash;
use crate::io::error::IoError;
use crate::io::sweep::manifest::{CSV_FILE, read_manifest};
use crate::io::sweep::table::read_csv;
use crate::jobs::JobSpec;
use crate::jobs::sweep::{FILE_PARAMS, job_of, point_params};

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

/// The design a row computed: a display layout or a phase-mask design.
#[derive(Debug, Clone)]
pub enum RowDesign {
    /// A display design (an `analyze` or `restore` point), opened in Display layouts.
    Display(Design),
    /// A phase-mask design (a `phase psf` point), opened in Phase masks.
    Phase(PhaseDesign),
}

/// A row's design, rebuilt.
#[derive(Debug, Clone)]
pub struct OpenedDesign {
    /// The design, as the sweep's point resolved it (if nothing changed since).
    pub design: RowDesign,
    /// The row's point index.
    pub point: u64,
    /// Whether its hash is the one the row recorded; when not, the preset or a file changed
    /// since the sweep ran (a phase-mask design is made of its parameters alone).
    pub hash_matches: bool,
}

/// Rebuilds the design of row `index` as its point did: the point's parameters from the spec
/// (base, axes and linked values) built into the job, by the runner's own functions.
/// Relative file parameters (`design`, `pattern`) are looked up from the results folder's
/// parent first, where a spec beside its `--out` folder names them from, then from the working
/// directory. A phase point whose λ0 plan is `optimized` runs the allocation again (reporting
/// to `progress`).
///
/// # Errors
/// A sweep of a job with no design to open (`sensor`, the other phase commands), a row that is
/// not there, or the design's own error (an unknown preset, a file gone).
pub fn open_row(
    table: &SweepTable,
    index: usize,
    progress: &Progress,
) -> Result<OpenedDesign, StudioError> {
    let spec = &table.manifest.spec;
    if !matches!(
        spec.job,
        SweepJob::Analyze | SweepJob::Restore | SweepJob::PhasePsf
    ) {
        return Err(StudioError::NotDisplaySweep(spec.job));
    }
    let row = table.rows.get(index).ok_or(StudioError::NoRow(index))?;
    let points = Points::new(spec).map_err(anyhow::Error::from)?;
    let base = table.dir.parent().map(Path::to_path_buf);
    let params: Vec<(String, ParamValue)> = point_params(spec, &points, row.point)
        .into_iter()
        .map(|(k, v)| match (v, &base) {
            (ParamValue::Text(t), Some(b))
                if FILE_PARAMS.contains(&k.as_str())
                    && Path::new(t).is_relative()
                    && b.join(t).exists() =>
            {
                let joined = ParamValue::Text(b.join(t).to_string_lossy().into_owned());
                (k, joined)
            }
            (v, _) => (k, v.clone()),
        })
        .collect();
    let refs: Vec<(String, &ParamValue)> = params.iter().map(|(k, v)| (k.clone(), v)).collect();
    let display = |design: Design| {
        let hash_matches = design_hash(&design) == row.design_hash;
        OpenedDesign {
            design: RowDesign::Display(design),
            point: row.point,
            hash_matches,
        }
    };
    Ok(match job_of(spec.job, &refs)? {
        JobSpec::Analyze(j) => display(j.selection.resolve()?),
        JobSpec::Restore(j) => display(j.selection.resolve()?),
        JobSpec::PhasePsf(j) => OpenedDesign {
            design: RowDesign::Phase(crate::jobs::phase::psf_design(&j, progress)?),
            point: row.point,
            hash_matches: true,
        },
        other => return Err(StudioError::NotDisplaySweep(other.kind())),
    })
}
