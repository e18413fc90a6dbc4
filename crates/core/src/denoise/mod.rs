//! Denoising before deblurring (thesis §3.5 and §4.5, conventions.md §5): BM3D for grey images and
//! CBM3D for colour (Dabov, Foi, Katkovnik and Egiazarian, "Image denoising by sparse 3-D
//! transform-domain collaborative filtering", IEEE TIP 2007, and "Color image denoising via
//! sparse 3D collaborative filtering with grouping constraint in luminance-chrominance space",
//! ICIP 2007). One entry point, [`bm3d`], serves the restore pipelines, the `denoise` command, the
//! studio, the tests and the benches ([`bm3d_owned`] is the same for planes the caller gives
//! up, so a camera-size image is not held twice).
//!
//! **Scale.** Images are planes `[row, col]` of any finite values; `sigma2` is the variance of
//! additive white Gaussian noise on that same scale (for a capture normalised to [0, 1], the
//! thesis's σ² table applies directly).

mod bm3d;
mod colour;
mod transforms;

pub use bm3d::{Bm3dProfile, MAX_SIGMA2, MIN_SIGMA2, bm3d, bm3d_owned, bm3d_with, sigma2_in_range};
pub use transforms::BlockTransform;
