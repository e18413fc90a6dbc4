//! A study run from the studio: the design and the spec saved in a results folder (the spec as
//! the TOML `udc-studio sweep` runs), the one sweep runner on a job, and the folder re-read as
//! rows land so the table and plots fill while it runs. Cancel stops after the points in
//! flight; Resume (also after a restart: the folder keeps the spec) runs what is left.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crate::app::job::{Job, JobError};
use crate::app::widgets::photo::Photo;
use crate::core::psf::route::Backend;
use crate::core::sweep::study::{Study, StudyFiles, StudySubject};
use crate::core::sweep::{Shard, SweepSpec};
use crate::jobs::sweep::{RunOptions, RunSummary, run_sweep};

/// The spec's file in a study's folder.
pub const SPEC_FILE: &str = "spec.toml";
/// The design's file in a study's folder.
pub const DESIGN_FILE: &str = "design.json";

/// How often the folder is re-read while rows land.
pub const REREAD_EVERY: Duration = Duration::from_millis(400);

/// A study running: its folder, the job, and how many rows have landed.
pub struct StudyRun {
    /// The results folder.
    pub dir: PathBuf,
    job: Job<RunSummary>,
    landed: Arc<AtomicU64>,
    /// Rows landed when the folder was last read.
    read_at: u64,
    last_read: Instant,
}

/// The photo's file in a restoring study's folder.
pub const PHOTO_FILE: &str = "photo.png";
/// A phase-mask design's file in a study's folder (for the record: the spec carries its
/// values as `phase psf` flags).
pub const PHASE_DESIGN_FILE: &str = "phase-design.json";

/// Writes the study's inputs and spec into `dir` (created): a display design as
/// [`DESIGN_FILE`], a phase-mask design as [`PHASE_DESIGN_FILE`], the photo a restoring study
/// captures as [`PHOTO_FILE`] (16 bits a channel; the built-in photo's own file when `photo` is
/// `None`), an opening axis's variants as `design-opening-<i>.json`, and the spec naming them by absolute paths as [`SPEC_FILE`], so that
/// `udc-studio sweep dir/spec.toml --out …` runs the same points from any folder. The spec
/// computes its points' PSFs on `backend` (the studio's choice; the CPU leaves it as the study
/// made it), so that a resume, in the studio or from the command line, runs where the study
/// started and finds its finished points by their hashes.
///
/// # Errors
/// A folder or file that cannot be written.
pub fn write_study(
    dir: &Path,
    study: &Study,
    photo: Option<&Photo>,
    backend: Backend,
) -> Result<SweepSpec, JobError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| JobError::Failed(format!("cannot create {}: {e}", dir.display())))?;
    let dir = std::fs::canonicalize(dir)
        .map_err(|e| JobError::Failed(format!("cannot resolve {}: {e}", dir.display())))?;
    let design_path = dir.join(DESIGN_FILE);
    match &study.subject {
        StudySubject::Display(d) => crate::io::design::file::save_design(&design_path, d)?,
        StudySubject::Phase(d) => {
            crate::io::phase::design::save_phase_design(&dir.join(PHASE_DESIGN_FILE), d)?;
        }
    }
    let photo_path = study.needs_photo().then(|| dir.join(PHOTO_FILE));
    if let Some(path) = &photo_path {
        match photo {
            Some(p) => {
                let planes: Vec<&ndarray::Array2<f64>> = p.planes.iter().collect();
                crate::io::photo::write_photo_png16(path, &planes)?;
            }
            None => std::fs::write(path, crate::io::photo::BUILT_IN_PHOTO_PNG)
                .map_err(|e| JobError::Failed(format!("cannot write {}: {e}", path.display())))?,
        }
    }
    let mut opening_designs = Vec::new();
    for (i, d) in study.opening_designs().iter().enumerate() {
        let path = dir.join(format!("design-opening-{i}.json"));
        crate::io::design::file::save_design(&path, d)?;
        opening_designs.push(path.to_string_lossy().into_owned());
    }
    let files = StudyFiles {
        design: design_path.to_string_lossy().into_owned(),
        photo: photo_path.map(|p| p.to_string_lossy().into_owned()),
        opening_designs,
    };
    let spec = study.spec(&files).computed_on(backend);
    crate::io::sweep::save_spec_toml(&dir.join(SPEC_FILE), &spec)?;
    Ok(spec)
}

/// Shards a study is cut into for a cluster: one per point up to this many.
pub const CLUSTER_SHARDS: u64 = 16;

/// Writes the Slurm scripts for `spec` into its study folder `dir` (as `udc-studio sweep
/// slurm SPEC --shards 16 --out DIR`): the notice says how to submit them, or why not.
pub fn write_cluster(dir: &Path, spec: &SweepSpec) -> crate::app::notice::Notice {
    use crate::app::notice::Notice;
    let points = crate::core::sweep::Points::new(spec).map_or(1, |p| p.count());
    let job = crate::jobs::sweep::SlurmJob {
        shards: points.clamp(1, CLUSTER_SHARDS),
        out: dir.to_path_buf(),
        // The cluster runs its own install (the package puts udc-studio on the PATH): this
        // machine's binary is rarely where the nodes can run it.
        binary: "udc-studio".into(),
        partition: None,
        time: "01:00:00".into(),
        cpus_per_task: 2,
        mem_mb: 2048,
    };
    match crate::jobs::sweep::write_slurm(spec, dir, &job) {
        Ok(w) => Notice::info(format!(
            "wrote the Slurm scripts for {} points in {} shards: on the cluster, bash {} (the \
             folder must be on storage the nodes see; edit the partition and time in its \
             .sbatch files)",
            w.points,
            job.shards,
            w.submit.display()
        )),
        Err(e) => Notice::error(format!("cannot write the Slurm scripts: {e:#}")),
    }
}

/// The spec saved in a study's folder, if it holds one.
///
/// # Errors
/// A spec file that does not parse.
pub fn saved_spec(dir: &Path) -> Result<Option<SweepSpec>, JobError> {
    let path = dir.join(SPEC_FILE);
    if !path.exists() {
        return Ok(None);
    }
    Ok(Some(crate::io::sweep::load_spec(&path)?))
}

impl StudyRun {
    /// Runs `spec` into `dir` on a job (resuming what the folder holds); `hold_after_points`
    /// holds the workers after that many new points until cancelled (the interruption tests).
    pub fn start(
        dir: PathBuf,
        spec: SweepSpec,
        hold_after_points: Option<u64>,
        wake: impl Fn() + Send + Sync + 'static,
    ) -> StudyRun {
        let landed = Arc::new(AtomicU64::new(0));
        let (count, out) = (landed.clone(), dir.clone());
        let wake = Arc::new(wake);
        let on_row = wake.clone();
        let job = Job::spawn(
            "study",
            move || wake(),
            move |progress| -> Result<RunSummary, JobError> {
                let options = RunOptions {
                    shard: Shard::WHOLE,
                    threads: None,
                    plots: false,
                    check_values: true,
                    hold_after_points,
                };
                let ran = run_sweep(&spec, &out, &options, progress, &mut |_| {
                    count.fetch_add(1, Ordering::Relaxed);
                    on_row();
                });
                match ran {
                    Ok(s) => Ok(s),
                    Err(_) if progress.is_cancelled() => Err(JobError::Cancelled),
                    Err(e) => Err(JobError::Failed(format!("{e:#}"))),
                }
            },
        );
        StudyRun {
            dir,
            job,
            landed,
            read_at: 0,
            last_read: Instant::now(),
        }
    }

    /// The share of the points in the table, 0 … 1.
    pub fn fraction(&self) -> f32 {
        self.job.fraction()
    }

    /// Seconds since it started.
    pub fn elapsed(&self) -> Duration {
        self.job.elapsed()
    }

    /// Stops it after the points in flight; the folder keeps every finished point.
    pub fn cancel(&self) {
        self.job.cancel();
    }

    /// How it ended, once it has.
    pub fn poll(&self) -> Option<Result<RunSummary, JobError>> {
        self.job.poll()
    }

    /// Whether new rows have landed since the folder was last read and it is time to read it
    /// again; marks them read.
    pub fn take_new_rows(&mut self) -> bool {
        let landed = self.landed.load(Ordering::Relaxed);
        if landed > self.read_at && self.last_read.elapsed() >= REREAD_EVERY {
            self.read_at = landed;
            self.last_read = Instant::now();
            true
        } else {
            false
        }
    }

    /// Rows landed when the folder was last read.
    pub fn read_rows(&self) -> u64 {
        self.read_at
    }

    /// Rows landed in this run.
    pub fn landed(&self) -> u64 {
        self.landed.load(Ordering::Relaxed)
    }
}
