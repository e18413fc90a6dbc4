//! `sweep slurm`: the scripts that run a spec's shards as a Slurm job array and merge them.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use udc_jobs::sweep::{SlurmJob, write_slurm};

/// Arguments of `udc-studio sweep slurm`.
#[derive(Debug, Args)]
pub struct SlurmArgs {
    /// The sweep spec.
    pub spec: PathBuf,
    /// Shards: array tasks, each running the points `i ≡ task (mod N)`.
    #[arg(long)]
    pub shards: u64,
    /// The results folder, on storage every node sees: the scripts, the spec and the shards
    /// go there, and the merged results.
    #[arg(long)]
    pub out: PathBuf,
    /// The `udc-studio` binary as the nodes see it (default: this one).
    #[arg(long)]
    pub binary: Option<PathBuf>,
    /// Slurm partition.
    #[arg(long)]
    pub partition: Option<String>,
    /// Time limit of each task, HH:MM:SS.
    #[arg(long, default_value = "01:00:00")]
    pub time: String,
    /// CPUs per task (worker threads per shard).
    #[arg(long, default_value_t = 2)]
    pub cpus_per_task: u32,
    /// Memory per task, MB.
    #[arg(long, default_value_t = 2048)]
    pub mem_mb: u64,
}

/// Runs `sweep slurm`.
///
/// # Errors
/// An invalid spec or settings, an unwritable folder.
pub fn slurm_cmd(a: &SlurmArgs) -> Result<()> {
    let spec = udc_io::sweep::load_spec(&a.spec)?;
    let here = std::env::current_dir().context("cannot read the working directory")?;
    let job = SlurmJob {
        shards: a.shards,
        out: a.out.clone(),
        binary: match &a.binary {
            Some(b) => b.clone(),
            None => std::env::current_exe().context("cannot find this program's path")?,
        },
        partition: a.partition.clone(),
        time: a.time.clone(),
        cpus_per_task: a.cpus_per_task,
        mem_mb: a.mem_mb,
    };
    let w = write_slurm(&spec, &here, &job)?;
    println!(
        "{} points in {} shards ({} to {} points each); submit with:\n  bash {}",
        w.points,
        a.shards,
        w.points / a.shards,
        w.points.div_ceil(a.shards),
        w.submit.display()
    );
    Ok(())
}
