//! Slurm scripts for a sharded sweep: a job array with one task per shard, a merge job that
//! waits for the whole array (`afterok`), and `submit.sh`, which submits both with `sbatch`.

use std::path::Path;

/// What the scripts run and ask Slurm for.
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmSettings {
    /// Shards, one array task each.
    pub shards: u64,
    /// The `udc-studio` binary as the compute nodes see it (absolute).
    pub binary: String,
    /// The results folder as the compute nodes see it (absolute; shared storage).
    pub out_dir: String,
    /// `--partition`, when given.
    pub partition: Option<String>,
    /// `--time` of each task, `HH:MM:SS`.
    pub time: String,
    /// CPUs per task (the shard's worker threads).
    pub cpus_per_task: u32,
    /// Memory per task, MB.
    pub mem_mb: u64,
    /// Name prefix of the jobs.
    pub job_name: String,
}

/// Single quotes for the shell: `'it'\''s'`.
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn header(s: &SlurmSettings, name: &str, log: &str) -> String {
    let mut h = String::from("#!/bin/bash\n");
    h.push_str(&format!("#SBATCH --job-name={}-{name}\n", s.job_name));
    h.push_str(&format!("#SBATCH --output={}\n", log));
    if let Some(p) = &s.partition {
        h.push_str(&format!("#SBATCH --partition={p}\n"));
    }
    h.push_str(&format!("#SBATCH --time={}\n", s.time));
    h
}

/// The job array: task `i` runs shard `i/N` into `OUT/shards/i`.
pub fn array_script(s: &SlurmSettings) -> String {
    let out = Path::new(&s.out_dir);
    let mut t = header(s, "shard", &format!("{}/slurm/shard-%a.log", s.out_dir));
    t.push_str(&format!(
        "#SBATCH --array=0-{}\n",
        s.shards.saturating_sub(1)
    ));
    t.push_str(&format!("#SBATCH --cpus-per-task={}\n", s.cpus_per_task));
    t.push_str(&format!("#SBATCH --mem={}M\n", s.mem_mb));
    t.push_str("set -euo pipefail\n");
    t.push_str("# One shard per array task; a re-submitted task resumes its shard by hash.\n");
    t.push_str(&format!(
        "exec {} sweep {} --out {}/shards/\"$SLURM_ARRAY_TASK_ID\" --shard \"$SLURM_ARRAY_TASK_ID\"/{} --threads \"${{SLURM_CPUS_PER_TASK:-{}}}\" --quiet\n",
        shell_quote(&s.binary),
        shell_quote(&out.join("spec.toml").to_string_lossy()),
        shell_quote(&s.out_dir),
        s.shards,
        s.cpus_per_task
    ));
    t
}

/// The merge job: runs once every array task succeeded.
pub fn merge_script(s: &SlurmSettings) -> String {
    let mut t = header(s, "merge", &format!("{}/slurm/merge.log", s.out_dir));
    t.push_str("#SBATCH --cpus-per-task=1\n");
    t.push_str(&format!("#SBATCH --mem={}M\n", s.mem_mb.max(1024)));
    t.push_str("set -euo pipefail\n");
    t.push_str(&format!(
        "exec {} sweep merge {}/shards/* --out {} --quiet\n",
        shell_quote(&s.binary),
        shell_quote(&s.out_dir),
        shell_quote(&s.out_dir)
    ));
    t
}

/// Submits the array, then the merge with a dependency on it; prints both job ids.
pub fn submit_script(s: &SlurmSettings) -> String {
    let dir = shell_quote(&format!("{}/slurm", s.out_dir));
    format!(
        "#!/bin/bash\n\
         # Submit the sweep's {n} shards as a job array and the merge after them.\n\
         set -euo pipefail\n\
         cd {dir}\n\
         array=$(sbatch --parsable array.sbatch)\n\
         array=${{array%%;*}}\n\
         merge=$(sbatch --parsable --dependency=afterok:\"$array\" merge.sbatch)\n\
         merge=${{merge%%;*}}\n\
         echo \"array job $array ({n} tasks), merge job $merge\"\n\
         echo \"results: {out}/results.csv once job $merge finishes (squeue -j $array,$merge)\"\n",
        n = s.shards,
        out = s.out_dir,
    )
}
