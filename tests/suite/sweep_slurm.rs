//! Issue 19: `sweep slurm` on a real single-node Slurm. `.ci/slurm/start` brings up munged,
//! slurmctld and slurmd on this machine; the generated job array (one task per shard) and its
//! dependent merge job must give the same table as the local run, every point in exactly one
//! shard. Without Slurm the test is skipped, unless UDC_REQUIRE_SLURM is set (`.ci/test` sets it
//! after installing slurm-wlm and munge), in which case it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_udc-studio");
/// How long the submitted jobs may take before the test gives up and shows their logs.
const JOB_TIMEOUT: Duration = Duration::from_secs(300);
const SHARDS: usize = 3;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs a command to completion: (success, stdout, stderr).
fn run(cmd: &mut Command) -> (bool, String, String) {
    let out = cmd.output().unwrap_or_else(|e| panic!("run {cmd:?}: {e}"));
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn on_path(name: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(name).is_file()))
}

/// Brings up the single-node cluster. False (after saying why) when Slurm is not installed and
/// not required; panics when it is required, or installed but does not start.
fn slurm_up() -> bool {
    if !on_path("sbatch") {
        let why = "sbatch is not on PATH: Slurm is not installed (.ci/slurm/install installs \
                   Debian's slurm-wlm and munge)";
        if std::env::var_os("UDC_REQUIRE_SLURM").is_some() {
            panic!("{why}, and UDC_REQUIRE_SLURM is set");
        }
        eprintln!("skipped: {why}");
        return false;
    }
    let t0 = Instant::now();
    let (ok, stdout, stderr) = run(&mut Command::new(repo().join(".ci/slurm/start")));
    assert!(ok, ".ci/slurm/start failed:\n{stdout}{stderr}");
    eprintln!("slurm up in {:.1} s", t0.elapsed().as_secs_f64());
    true
}

/// The job ids in what sbatch or a submit script printed: a bare `sbatch --parsable` id (`ID` or
/// `ID;cluster`), or else every number right after the word "job", in order, each once.
fn job_ids(stdout: &str) -> Vec<u64> {
    if let Ok(id) = stdout.trim().split(';').next().unwrap_or("").parse() {
        return vec![id];
    }
    let words: Vec<&str> = stdout.split_whitespace().collect();
    let mut ids = Vec::new();
    for pair in words.windows(2) {
        let digits: String = pair[1].chars().take_while(char::is_ascii_digit).collect();
        if pair[0] == "job"
            && let Ok(id) = digits.parse()
            && !ids.contains(&id)
        {
            ids.push(id);
        }
    }
    ids
}

/// Every `JobState=` and `Reason=` of a job (an array job lists each of its tasks); None once
/// slurmctld has forgotten the job (MinJobAge after it ended).
fn job_states(id: u64) -> Option<Vec<(String, String)>> {
    let (ok, stdout, _) =
        run(Command::new("scontrol").args(["-o", "show", "job", &id.to_string()]));
    if !ok {
        return None;
    }
    let field = |line: &str, key: &str| {
        line.split_whitespace()
            .find_map(|w| w.strip_prefix(key))
            .unwrap_or("")
            .to_string()
    };
    Some(
        stdout
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(|l| (field(l, "JobState="), field(l, "Reason=")))
            .collect(),
    )
}

const ENDED: [&str; 9] = [
    "COMPLETED",
    "FAILED",
    "CANCELLED",
    "TIMEOUT",
    "NODE_FAIL",
    "OUT_OF_MEMORY",
    "PREEMPTED",
    "BOOT_FAIL",
    "DEADLINE",
];

/// What went wrong, with everything that helps: the jobs as slurmctld sees them, the jobs'
/// output files under `dir`, and the daemons' log tails.
fn slurm_report(ids: &[u64], dir: &Path) -> String {
    let mut s = String::new();
    for id in ids {
        let (_, out, err) = run(Command::new("scontrol").args(["show", "job", &id.to_string()]));
        s += &format!("--- scontrol show job {id}\n{out}{err}");
    }
    let (_, out, _) = run(Command::new("squeue").arg("-a"));
    s += &format!("--- squeue\n{out}");
    let mut logs = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if matches!(
                p.extension().and_then(|x| x.to_str()),
                Some("out" | "err" | "log")
            ) {
                logs.push(p);
            }
        }
    }
    logs.sort();
    for p in logs {
        s += &format!(
            "--- {}\n{}",
            p.display(),
            std::fs::read_to_string(&p).unwrap_or_default()
        );
    }
    for log in [
        "/var/log/udc-slurm/slurmctld.log",
        "/var/log/udc-slurm/slurmd.log",
    ] {
        let text = std::fs::read_to_string(log).unwrap_or_default();
        let tail: Vec<&str> = text.lines().rev().take(25).collect();
        s += &format!("--- last lines of {log}\n");
        for l in tail.iter().rev() {
            s += l;
            s += "\n";
        }
    }
    s
}

/// Waits until every job (and every task of an array job) has ended, and asserts that each one
/// completed. On a timeout, or a dependency that can never be met, cancels them and panics with
/// the report.
fn wait_for_jobs(ids: &[u64], dir: &Path) {
    let t0 = Instant::now();
    loop {
        let mut pending = false;
        for &id in ids {
            let Some(states) = job_states(id) else {
                continue;
            };
            for (state, reason) in &states {
                if reason == "DependencyNeverSatisfied" {
                    let report = slurm_report(ids, dir);
                    cancel(ids);
                    panic!("job {id} can never start (a job it depends on failed)\n{report}");
                }
                if !ENDED.contains(&state.as_str()) {
                    pending = true;
                } else if state != "COMPLETED" {
                    // The merge job would wait for ever on its failed dependency.
                    let report = slurm_report(ids, dir);
                    cancel(ids);
                    panic!("job {id} ended {state} ({reason})\n{report}");
                }
            }
        }
        if !pending {
            return;
        }
        if t0.elapsed() > JOB_TIMEOUT {
            let report = slurm_report(ids, dir);
            cancel(ids);
            panic!("the jobs did not finish within {JOB_TIMEOUT:?}\n{report}");
        }
        std::thread::sleep(Duration::from_millis(500));
    }
}

fn cancel(ids: &[u64]) {
    let ids: Vec<String> = ids.iter().map(u64::to_string).collect();
    let _ = run(Command::new("scancel").args(&ids));
}

/// A results.csv as its header and its data rows keyed by `point`; panics on a repeated point.
fn table(path: &Path) -> (String, BTreeMap<u64, String>) {
    let text =
        std::fs::read_to_string(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap_or_else(|| panic!("{} is empty", path.display()));
    assert!(
        header.starts_with("point,hash"),
        "{}: the columns start with point,hash: {header}",
        path.display()
    );
    let mut rows = BTreeMap::new();
    for line in lines.filter(|l| !l.is_empty()) {
        let point: u64 = line
            .split(',')
            .next()
            .and_then(|p| p.parse().ok())
            .unwrap_or_else(|| panic!("{}: no point index in {line:?}", path.display()));
        let before = rows.insert(point, line.to_string());
        assert!(before.is_none(), "{}: point {point} twice", path.display());
    }
    (header.to_string(), rows)
}

#[test]
fn slurm_runs_a_job_array_and_a_dependent_job() {
    // The harness on its own (no udc-studio): if this fails, Slurm is the problem, not the sweep.
    if !slurm_up() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("array.sbatch"),
        format!(
            "#!/bin/bash\n#SBATCH --array=0-2\n#SBATCH --output={0}/task_%a.out\n\
             echo \"task $SLURM_ARRAY_TASK_ID\" > {0}/task_$SLURM_ARRAY_TASK_ID.txt\n",
            d.display()
        ),
    )
    .unwrap();
    std::fs::write(
        d.join("after.sbatch"),
        format!(
            "#!/bin/bash\n#SBATCH --output={0}/after.out\ncat {0}/task_*.txt > {0}/all.txt\n",
            d.display()
        ),
    )
    .unwrap();
    let (ok, array, err) = run(Command::new("sbatch")
        .args(["--parsable", "array.sbatch"])
        .current_dir(d));
    assert!(ok, "sbatch: {err}");
    let array = job_ids(&array);
    assert_eq!(array.len(), 1);
    let (ok, after, err) = run(Command::new("sbatch")
        .args([
            "--parsable",
            &format!("--dependency=afterok:{}", array[0]),
            "after.sbatch",
        ])
        .current_dir(d));
    assert!(ok, "sbatch: {err}");
    let ids = [array, job_ids(&after)].concat();
    wait_for_jobs(&ids, d);
    assert_eq!(
        std::fs::read_to_string(d.join("all.txt")).unwrap(),
        "task 0\ntask 1\ntask 2\n",
        "{}",
        slurm_report(&ids, d)
    );
}

#[test]
fn the_job_array_and_its_merge_give_the_local_table() {
    if !slurm_up() {
        return;
    }
    let spec = repo().join("tests/sweep/tiny.toml");
    let spec = spec.to_str().unwrap();

    // The reference: the whole sweep in this process's machine, no Slurm.
    let local = tempfile::tempdir().unwrap();
    let t0 = Instant::now();
    let (ok, _, err) = run(Command::new(BIN)
        .args(["sweep", spec, "--out"])
        .arg(local.path()));
    assert!(ok, "local sweep: {err}");
    eprintln!("local sweep in {:.1} s", t0.elapsed().as_secs_f64());
    let (header, rows) = table(&local.path().join("results.csv"));
    // Equal tables of failed points would prove nothing: every point computed its metrics.
    if let Some(col) = header.split(',').position(|c| c == "error") {
        for row in rows.values() {
            assert_eq!(row.split(',').nth(col), Some(""), "a point failed: {row}");
        }
    }
    let n = rows.len() as u64;
    assert!(
        n >= SHARDS as u64,
        "tiny.toml has {n} points, fewer than {SHARDS} shards"
    );
    assert!(
        rows.keys().copied().eq(0..n),
        "the local run numbers its points 0..{n}: {:?}",
        rows.keys().collect::<Vec<_>>()
    );

    // The scripts, then the array and the merge through sbatch. The test binary's udc-studio
    // is on this machine, so slurmd can run it where it is.
    let cluster = tempfile::tempdir().unwrap();
    let c = cluster.path();
    let (ok, stdout, err) = run(Command::new(BIN)
        .args([
            "sweep",
            "slurm",
            spec,
            "--shards",
            &SHARDS.to_string(),
            "--out",
        ])
        .arg(c)
        .args([
            "--binary",
            BIN,
            "--time",
            "00:10:00",
            "--cpus-per-task",
            "1",
        ])
        .args(["--mem-mb", "1024"]));
    assert!(ok, "sweep slurm: {err}");
    // The scripts name the folder as the nodes see it (resolved).
    let scripts = std::fs::canonicalize(c).unwrap().join("slurm");
    let submit = scripts.join("submit.sh");
    assert!(
        stdout.contains(&format!("bash {}", submit.display())),
        "sweep slurm prints the line to run: {stdout}"
    );
    let array = std::fs::read_to_string(scripts.join("array.sbatch")).unwrap();
    assert!(
        array
            .lines()
            .any(|l| l.trim() == format!("#SBATCH --array=0-{}", SHARDS - 1)),
        "array.sbatch:\n{array}"
    );
    assert!(
        !c.join("results.csv").exists(),
        "nothing is computed before submission"
    );

    let t0 = Instant::now();
    let (ok, stdout, err) = run(Command::new("bash").arg(&submit).current_dir(&scripts));
    assert!(ok, "submit.sh failed:\n{stdout}{err}");
    let ids = job_ids(&stdout);
    assert_eq!(
        ids.len(),
        2,
        "submit.sh prints the array's and the merge's job ids: {stdout}"
    );
    wait_for_jobs(&ids, c);
    eprintln!(
        "{SHARDS} shards and the merge ran in {:.1} s",
        t0.elapsed().as_secs_f64()
    );

    // The merged table is the local one: same header, same rows point by point (a dropped or
    // duplicated row, or a shard computing something else, shows here).
    let merged = c.join("results.csv");
    assert!(
        merged.is_file(),
        "no merged results.csv\n{}",
        slurm_report(&ids, c)
    );
    let (merged_header, merged_rows) = table(&merged);
    assert_eq!(merged_header, header);
    assert_eq!(merged_rows, rows, "merged (left) vs local (right)");

    // Each shard ran its own part: the shard folders partition the points, and each shard's rows
    // are the local rows of its points.
    let mut seen: BTreeMap<u64, usize> = BTreeMap::new();
    for shard in 0..SHARDS {
        let csv = c.join("shards").join(shard.to_string()).join("results.csv");
        assert!(csv.is_file(), "shard {shard} wrote no results.csv");
        let (h, part) = table(&csv);
        assert_eq!(h, header, "shard {shard}'s header");
        assert!(!part.is_empty(), "shard {shard} ran no points");
        for (point, row) in part {
            assert_eq!(Some(&row), rows.get(&point), "shard {shard}, point {point}");
            if let Some(other) = seen.insert(point, shard) {
                panic!("point {point} is in shards {other} and {shard}");
            }
        }
    }
    assert!(
        seen.keys().copied().eq(0..n),
        "the shards together ran {:?}, not 0..{n}",
        seen.keys().collect::<Vec<_>>()
    );
}

#[test]
fn job_ids_are_read_from_sbatch_and_from_submit_sh() {
    assert_eq!(job_ids("12\n"), [12]);
    assert_eq!(job_ids("12;udc\n"), [12]);
    assert_eq!(
        job_ids(
            "array job 12 (3 tasks), merge job 13\n\
             results: /tmp/x9/results.csv once job 13 finishes (squeue -j 12,13)\n"
        ),
        [12, 13]
    );
}
