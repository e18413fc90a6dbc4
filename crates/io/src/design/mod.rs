//! The design's files: design files and their choice by preset or file with overrides, the built-in presets, pattern PNGs and spectral responses.

pub mod choice;
pub mod file;
pub mod pattern;
pub mod presets;
pub mod spectral;
