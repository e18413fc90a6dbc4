//! `udc-studio sweep`: many points of one job in-process (`sweep SPEC --out DIR`), shard
//! folders merged into one (`sweep merge`), and Slurm scripts for a cluster (`sweep slurm`).

mod jobs;
mod merge;
mod run;
mod slurm;

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Subcommand};

use udc_core::sweep::Shard;

pub use jobs::{FILE_PARAMS, check_points, evaluate_point, inputs_under};
pub use run::{RunOptions, RunSummary, run_sweep};

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
                quiet: args.quiet,
                plots: !args.no_plots,
                hold_after_points: std::env::var(run::HOLD_AFTER_POINTS_ENV)
                    .ok()
                    .and_then(|v| v.parse().ok()),
            };
            run_sweep(
                &spec,
                out,
                &options,
                &udc_core::Progress::new(),
                &mut |_| {},
            )
            .map(|_| ())
        }
    }
}
