//! Sweeps (issue 19): a spec names a job, base parameters and axes; its points are the axes'
//! Cartesian product, enumerated lazily and cut into shards; each point has a content hash that
//! makes a sweep resumable; and the summaries its plots draw. Running points, files and
//! clusters are the CLI's and `io`'s business.

pub mod hash;
pub mod one_axis;
pub mod points;
pub mod spec;
pub mod study;
pub mod summary;

pub use points::{Points, Shard};
pub use spec::{Axis, ParamValue, PlotKind, PlotSpec, SweepJob, SweepSpec};
