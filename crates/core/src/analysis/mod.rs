//! The numbers of a design: [`analyze`] runs the PSF route per channel and measures it
//! ([`mtf`], [`metrics`]: MTF, AUC, light transmittance, invertibility), [`warning`] and
//! [`advice`] say when the sampling is unsafe and how to fix it, [`expected`] is the closed-form
//! PSF of a random tiling, and [`residual`] how far one PSF is from the kernel a restoration
//! assumes.

pub mod advice;
pub mod analyze;
pub mod expected;
pub mod metrics;
pub mod mtf;
pub mod residual;
pub mod warning;
