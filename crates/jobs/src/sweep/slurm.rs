//! Slurm scripts for a sweep (`udc-studio sweep slurm`, the studio's Run on a cluster…): the
//! spec saved in the results folder as TOML, an array job of shards, a merge job and a submit
//! script, every path absolute so the nodes find them.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use udc_core::sweep::SweepSpec;
use udc_io::sweep::slurm::{SlurmSettings, array_script, merge_script, submit_script};

/// How the cluster runs the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmJob {
    /// Shards: array tasks, each running the points `i ≡ task (mod N)`.
    pub shards: u64,
    /// The results folder, on storage every node sees.
    pub out: PathBuf,
    /// The `udc-studio` binary as the nodes see it: a path, or a name on the nodes' `PATH`.
    pub binary: PathBuf,
    /// Slurm partition.
    pub partition: Option<String>,
    /// Time limit of each task, HH:MM:SS.
    pub time: String,
    /// CPUs per task (worker threads per shard).
    pub cpus_per_task: u32,
    /// Memory per task, MB.
    pub mem_mb: u64,
}

/// What [`write_slurm`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmWritten {
    /// The sweep's points.
    pub points: u64,
    /// The script that submits the array and the merge: `bash` it on the cluster.
    pub submit: PathBuf,
}

/// Checks `spec` and the settings, then writes the spec (inputs named relative to `here`
/// made absolute) and the scripts into `a.out`.
///
/// # Errors
/// A spec with a refused value, settings out of range, files that cannot be written.
pub fn write_slurm(spec: &SweepSpec, here: &Path, a: &SlurmJob) -> Result<SlurmWritten> {
    let points = super::check_points(spec)?;
    if a.shards == 0 || a.shards > 100_000 {
        bail!("--shards {}: between 1 and 100000 array tasks", a.shards);
    }
    if a.cpus_per_task == 0 || a.mem_mb == 0 {
        bail!("--cpus-per-task and --mem-mb must be at least 1");
    }
    let time_ok = {
        let parts: Vec<&str> = a.time.split(':').collect();
        parts.len() == 3
            && parts
                .iter()
                .all(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()))
    };
    if !time_ok {
        bail!("--time {}: give HH:MM:SS", a.time);
    }
    if let Some(p) = &a.partition
        && (p.is_empty()
            || !p
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c)))
    {
        bail!("--partition {p}: a partition name is letters, digits, - _ .");
    }
    let slurm_dir = a.out.join("slurm");
    std::fs::create_dir_all(&slurm_dir)
        .with_context(|| format!("cannot create {}", slurm_dir.display()))?;
    let out = std::fs::canonicalize(&a.out)
        .with_context(|| format!("cannot resolve {}", a.out.display()))?;
    // A bare name is looked up on the nodes' PATH; a path is made absolute.
    let binary = if a.binary.components().count() > 1 {
        std::path::absolute(&a.binary).unwrap_or_else(|_| a.binary.clone())
    } else {
        a.binary.clone()
    };
    // The nodes read the spec from the results folder, as TOML, and run in the slurm folder:
    // input files named relative to here must be named absolutely there.
    let spec = super::inputs_under(spec, here);
    udc_io::sweep::save_spec_toml(&out.join("spec.toml"), &spec)?;
    let settings = SlurmSettings {
        shards: a.shards,
        binary: binary.to_string_lossy().into_owned(),
        out_dir: out.to_string_lossy().into_owned(),
        partition: a.partition.clone(),
        time: a.time.clone(),
        cpus_per_task: a.cpus_per_task,
        mem_mb: a.mem_mb,
        job_name: if spec.name.is_empty() {
            "udc-sweep".into()
        } else {
            spec.name
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
                .collect()
        },
    };
    let files = [
        ("array.sbatch", array_script(&settings)),
        ("merge.sbatch", merge_script(&settings)),
        ("submit.sh", submit_script(&settings)),
    ];
    for (name, text) in files {
        let path = out.join("slurm").join(name);
        udc_io::safe_file::write_atomic(&path, text.as_bytes())?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let _ = std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755));
        }
    }
    Ok(SlurmWritten {
        points,
        submit: out.join("slurm").join("submit.sh"),
    })
}
