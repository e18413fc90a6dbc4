//! `sweep slurm`: the scripts that run a spec's shards as a Slurm job array and merge them.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use udc_io::sweep::slurm::{SlurmSettings, array_script, merge_script, submit_script};

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
    let points = super::check_points(&spec)?;
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
    let binary = match &a.binary {
        Some(b) => b.clone(),
        None => std::env::current_exe().context("cannot find this program's path")?,
    };
    let binary = std::path::absolute(&binary).unwrap_or(binary);
    // The nodes read the spec from the results folder, as TOML, and run in the slurm folder:
    // input files named relative to here must be named absolutely there.
    let here = std::env::current_dir().context("cannot read the working directory")?;
    let spec = super::inputs_under(&spec, &here);
    let text = toml::to_string(&spec).context("cannot write the spec as TOML")?;
    udc_io::safe_file::write_atomic(&out.join("spec.toml"), text.as_bytes())?;
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
    println!(
        "{points} points in {} shards ({} to {} points each); submit with:\n  bash {}",
        a.shards,
        points / a.shards,
        points.div_ceil(a.shards),
        out.join("slurm").join("submit.sh").display()
    );
    Ok(())
}
