//! The pure simulation core. Nothing here knows about the GUI, files or threads of its own
//! (rayon's pool is used for data parallelism inside a call).

pub mod advice;
pub mod analyze;
pub mod aperture;
pub mod appearance;
pub mod budget;
pub mod denoise;
pub mod depth;
pub mod depth_capture;
pub mod design;
pub mod emitters;
pub mod error;
pub mod expected;
pub mod fft;
pub mod field;
pub mod field_capture;
pub mod mask;
pub mod metrics;
pub mod mtf;
pub mod opening_ops;
pub mod optimize;
pub mod phase;
pub mod progress;
pub mod pruned;
mod pruned_grid;
mod pruned_rows;
pub mod psf;
pub mod reproduce;
pub mod residual;
pub mod restore;
pub mod route;
pub mod sampling;
pub mod saturation;
pub mod sensor;
pub mod sweep;
pub mod theory;
pub mod tiling;
pub mod warning;
pub mod zoom;

pub use analyze::{Analysis, ChannelAnalysis, Quality, analyze, analyze_with};
pub use design::Design;
pub use error::SimError;
pub use progress::Progress;
