//! Sweep files: the spec (TOML or JSON), the results table (CSV and Parquet, streamed), the
//! manifest beside them, the plots, and the Slurm scripts that run shards on a cluster.

pub mod manifest;
pub mod metrics;
pub mod plots;
pub mod slurm;
pub mod spec_file;
pub mod table;
pub mod table_parquet;

pub use metrics::flatten_metrics;
pub use spec_file::{load_spec, parse_spec, save_spec_toml};
pub use table::{Row, TableSchema};

/// The example sweeps shipped in `presets/sweeps/`, built into the binary: `(file name, TOML
/// text)`. They name their designs by preset, so they run from any folder.
pub const EXAMPLES: &[(&str, &str)] = &[(
    "dpi-tiling-seed.toml",
    include_str!("../../../../presets/sweeps/dpi-tiling-seed.toml"),
)];
