//! `udc-studio sensor`: the sensor jobs of thesis chapter 5 on the command line.

use clap::{Args, Subcommand};

use anyhow::Result;

use crate::{JobArgs, run_job};
use udc_core::Progress;
use udc_jobs::JobSpec;
use udc_jobs::sensor::{FlatPatchJob, SensorJob};

/// Arguments of `udc-studio sensor`: a run on a scene, or a check (`sensor flat-patch`).
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SensorArgs {
    /// A check of the noise model instead of a run on a scene.
    #[command(subcommand)]
    pub check: Option<SensorCheck>,
    /// The run on a scene.
    #[command(flatten)]
    pub run: JobArgs<SensorJob>,
}

/// A check of the sensor model, `udc-studio sensor <CHECK>`.
#[derive(Debug, Subcommand)]
pub enum SensorCheck {
    /// Expose a flat patch at light E, read it at the gain of eq. 5.3 for E with η, and compare
    /// the saturated fraction with the model's prediction (η = 2: ≈ 2.2 % per pixel).
    FlatPatch(JobArgs<FlatPatchJob>),
}

/// Runs `udc-studio sensor` (or its check).
///
/// # Errors
/// The job's own error.
pub fn sensor_cmd(args: SensorArgs, progress: &Progress) -> Result<()> {
    match args.check {
        Some(SensorCheck::FlatPatch(c)) => {
            run_job(JobSpec::SensorFlatPatch(c.job), c.json, progress)
        }
        None => run_job(JobSpec::Sensor(args.run.job), args.run.json, progress),
    }
}
