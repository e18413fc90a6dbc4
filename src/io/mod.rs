//! Every file format the studio reads or writes. Core types go in, files come out; nothing here
//! simulates.

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
