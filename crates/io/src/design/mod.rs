//! The design's files: design files and the hash a sweep row records of one, the built-in
//! presets, pattern PNGs and spectral responses.

pub mod file;
pub mod hash;
pub mod pattern;
pub mod presets;
pub mod spectral;
