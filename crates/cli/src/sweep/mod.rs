//! `udc-studio sweep`: many points of one job in-process (`sweep SPEC --out DIR`), shard
//! folders merged into one (`sweep merge`), and Slurm scripts for a cluster (`sweep slurm`).

mod merge;
mod slurm;

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Subcommand};

use udc_core::sweep::Shard;

pub use udc_jobs::sweep::{
    FILE_PARAMS, HOLD_AFTER_POINTS_ENV, RunOptions, RunSummary, check_points, inputs_under,
    run_sweep,
};

/// Arguments of `udc-studio sweep`: a run, or an action on runs.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    /// Merge shard folders, or write Slurm scripts, instead of running.
    #[command(subcommand)]
    pub action: Option<SweepAction>,
    /// The sweep spec (TOML, or JSON): job, base, axes, metrics, plots (see docs/src/formats/sweep-spec.md).
    #[arg(required = true)]
    pub spec: Option<PathBuf>,
    /// The results folder: results.csv, results.parquet, sweep.json and plots/. A folder with
    /// results of the same sweep is resumed: finished points are skipped by hash.
    #[arg(long, required_unless_present = "check")]
    pub out: Option<PathBuf>,
    /// Run only shard I of N (0-based): the points whose index is I modulo N.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
    /// Worker threads (default: every core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bar or summary (errors still go to stderr).
    #[arg(long)]
    pub quiet: bool,
    /// Do not draw the plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Check the spec and every axis value, print the number of points, run nothing.
    #[arg(long)]
    pub check: bool,
}

/// What `sweep` does instead of running a spec.
#[derive(Debug, Subcommand)]
pub enum SweepAction {
    /// Merge the results folders of a sweep's shards into one, checking that every point is
    /// there exactly once.
    Merge(merge::MergeArgs),
    /// Write a Slurm job array (one task per shard) and a dependent merge job for a spec.
    Slurm(slurm::SlurmArgs),
}

/// Runs `udc-studio sweep …`.
///
/// # Errors
/// An invalid spec, a point that cannot be set up, unwritable results, an interrupted run.
pub fn sweep_cmd(args: &SweepArgs) -> Result<()> {
    match &args.action {
        Some(SweepAction::Merge(m)) => merge::merge_cmd(m),
        Some(SweepAction::Slurm(s)) => slurm::slurm_cmd(s),
        None => {
            let Some(spec_path) = &args.spec else {
                anyhow::bail!("sweep needs a SPEC (see --help)");
            };
            let spec = udc_io::sweep::load_spec(spec_path)?;
            if args.check {
                let n = check_points(&spec)?;
                println!(
                    "{}: {n} points of `{}`, every axis value accepted",
                    spec_path.display(),
                    spec.job.as_str()
                );
                return Ok(());
            }
            let Some(out) = &args.out else {
                anyhow::bail!("sweep needs --out DIR (see --help)");
            };
            let options = RunOptions {
                shard: args.shard.unwrap_or(Shard::WHOLE),
                threads: args.threads,
                plots: !args.no_plots,
                check_values: true,
                hold_after_points: std::env::var(HOLD_AFTER_POINTS_ENV)
                    .ok()
                    .and_then(|v| v.parse().ok()),
            };
            let progress = udc_core::Progress::new();
            let summary = crate::progress_bar::with_bar(&progress, !args.quiet, "points", || {
                run_sweep(&spec, out, &options, &progress, &mut |_| {})
            })?;
            if !args.quiet {
                print_summary(&summary, out);
            }
            Ok(())
        }
    }
}

/// The line a finished (or resumed) run ends with, on stderr.
pub fn print_summary(s: &RunSummary, out: &std::path::Path) {
    eprintln!(
        "{} of {} points in {} ({} computed in {:.1} s, {:.1} points/s; {} already done; {} failed)",
        s.rows,
        s.total,
        out.display(),
        s.computed,
        s.elapsed_s,
        s.points_per_s,
        s.skipped,
        s.failed_total
    );
    for p in &s.plots {
        eprintln!("wrote {}", p.display());
    }
}
