//! The sensor model's files: the run's report and the bin study's table (its HDR scenes are
//! read by `photo::hdr`).

pub mod bin_study_csv;
pub mod report;
