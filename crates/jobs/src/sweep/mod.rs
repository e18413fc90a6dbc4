//! The one sweep runner: many points of one job, each a [`crate::JobSpec`] built from the
//! spec's parameters, in parallel, resumable by each point's hash. The command line, the Python
//! package, `reproduce` and the studio drive it with a [`udc_core::Progress`] and a per-row
//! callback.

mod points;
mod run;
mod slurm;

pub use points::{
    FILE_PARAMS, FileDigests, PointOutput, check_points, evaluate_point, hash_of, inputs_under,
    job_of, point_params,
};
pub use run::{HOLD_AFTER_POINTS_ENV, RunOptions, RunSummary, run_sweep};
pub use slurm::{SlurmJob, SlurmWritten, write_slurm};
