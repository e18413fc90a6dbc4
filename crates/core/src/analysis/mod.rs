//! The numbers of a design: [`analyze`] runs the PSF route per channel and measures it
//! ([`mtf`], [`metrics`]: MTF, AUC, light transmittance, invertibility), [`advice`] finds the
//! least costly fix for each sampling warning (`psf::warning`), [`expected`] is the closed-form
//! PSF of a random tiling, [`residual`] how far one PSF is from the kernel a restoration
//! assumes, and [`light`] whether a capture through the design keeps its light.

pub mod advice;
pub mod analyze;
pub mod expected;
pub mod light;
pub mod metrics;
pub mod mtf;
pub mod residual;
