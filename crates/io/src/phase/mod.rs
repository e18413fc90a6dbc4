//! The phase-mask design file and the plate's fabrication files.

pub mod design;
pub mod export;
