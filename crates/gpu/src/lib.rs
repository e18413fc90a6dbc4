//! UDC Studio's compute backend on wgpu, the GPU API the studio's window already draws with:
//! the display-layout PSF's Fraunhofer step (conventions.md §2, "PSF route") as WGSL kernels
//! behind the core's seam, [`udc_core::psf::route::Fraunhofer`], so nothing above the core knows
//! how a transform ran.
//!
//! - [`Gpu`]: a device with the kernels compiled on it, opened headless ([`Gpu::headless`],
//!   [`Gpu::shared`]), on a given adapter ([`Gpu::on_adapter`]: the studio's, the adapter its
//!   window draws with), or on a device someone else opened ([`Gpu::from_device`]);
//! - [`Route`]: the user's [`udc_core::psf::route::Backend`] resolved (`cpu`, `gpu`, or
//!   `auto`, which falls back to the CPU with one line saying why);
//! - the transform ([`fraunhofer`]): `f32` on the device, with every twiddle and chirp computed
//!   in `f64` on the CPU ([`tables`]); arbitrary DFT lengths by the chirp-z (Bluestein) step on
//!   power-of-two Stockham FFTs ([`kernels`]);
//! - the phase model's Bloch relay ([`relay`]), behind the core's
//!   [`udc_core::phase::chain::BlochRelay`]: a λ0 plan's propagations through the double MLA on
//!   the wrapped grid, many directions at once, on mixed-radix (2·3·4·5) Stockham FFTs;
//! - the optimizer's window transform and its adjoint ([`window`]), as batches of chirp-z zooms
//!   on the same power-of-two FFTs.
//!
//! The crate opens no window and links no window crate; the studio hands it the adapter eframe
//! draws with.

pub mod backend;
pub mod device;
pub mod fraunhofer;
pub mod kernels;
pub mod relay;
pub mod tables;
pub mod window;

pub use backend::Route;
pub use device::{AdapterKind, AdapterSummary, Gpu, GpuError};
