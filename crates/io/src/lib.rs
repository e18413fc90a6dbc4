#![warn(missing_docs)]
//! Every file format the studio reads or writes. Core types go in, files come out; nothing here
//! simulates.

use std::path::Path;

/// The repository this crate was built from (two folders above its manifest): where the
/// presets, the test set and the reproduce specs are when the studio runs from a checkout.
#[must_use]
pub fn source_tree() -> &'static Path {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest.ancestors().nth(2).unwrap_or(manifest)
}

pub mod bin_study_csv;
pub mod design_choice;
pub mod design_file;
pub mod error;
pub mod export;
pub mod fab;
pub mod hdr;
pub mod image_planes;
pub mod mask;
pub mod numbers;
pub mod pattern;
pub mod phase_design;
pub mod phase_export;
pub mod photo;
pub mod presets;
pub mod report;
pub mod restore_report;
pub mod safe_file;
pub mod sensor_report;
pub mod spectral;
pub mod sweep;
pub mod system;
pub mod testset;

pub use error::IoError;
