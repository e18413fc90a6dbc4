//! What the display-layout analysis writes: PSF images and MTF tables, the analysis JSON, and the restoration's report and images.

pub mod export;
pub mod report;
pub mod restore_report;
