#![warn(missing_docs)]
//! # udc-core: the simulation core of UDC Studio
//!
//! The pure simulation: display apertures and tilings, the PSF route, MTF and the numbers the
//! studio shows, capture, denoising and restoration, phase masks, the sensor model, the opening
//! optimizer and the sweep engine. Nothing here knows about the GUI or files, and it starts no
//! threads of its own (rayon's pool is used for data parallelism inside a call). One entry point
//! per job, e.g. [`analyze()`], shared by the studio, the CLI, the tests and the benches.
//!
//! ## Conventions (written down once, here)
//!
//! **Units.** Lengths in micrometres (`_um`), wavelengths in nanometres (`_nm`), focal lengths in
//! millimetres (`_mm`), spatial frequency in cycles per sensor pixel (`_cyc_per_px`). Every public
//! field and argument carries its unit in its name.
//!
//! **Axis order.** 2-D arrays are `[row, col]` = `[y, x]`; row 0 is the top row of an image.
//! Opening patterns are stored row by row in the same order.
//!
//! **Centring.** For an array of even length `N` the optical axis (in space) or DC (in frequency)
//! sits at index `N / 2` (the `fftshift` convention); for odd `N` at `(N - 1) / 2`.
//! On the pupil grid of size `M` and spacing `δ1`, sample `i` sits at `x = (i − M/2)·δ1`.
//!
//! **Fourier transforms.** Forward DFTs are unnormalised, `X[k] = Σ x[n] e^{−2πi kn/N}`. The
//! fine PSF of one wavelength is `|DFT(a)|²` on an `M×M` grid of spacing `λf/(M δ1)` (conventions.md §2);
//! its absolute scale is irrelevant because every PSF is normalised before it is used.
//!
//! **PSF normalisation.** Each wavelength's fine PSF is divided by its total energy over the whole
//! fine grid, so that wavelengths weigh by their spectral weight only. A channel's sensor PSF is
//! then normalised to sum 1 over its window; the energy that fell outside the window is reported.
//!
//! **MTF.** OTF = 2-D DFT of the normalised sensor PSF, MTF = |OTF| with MTF(0) = 1. Ring `d` of the
//! DC-centred `N×N` MTF holds the samples with `round(hypot(Δrow, Δcol)) = d` at frequency `d/N`
//! cycles/pixel; AUC is the trapezoidal area under the radial minimum for `d = 0 … N/2 − 1`.
//!
//! **Phase sign.** Only intensities of real apertures are computed in chapter 3, so the sign of the
//! Fourier kernel never shows: `|A(−u)| = |A(u)|`.
//!
//! **Randomness.** Every random choice takes an explicit `u64` seed and uses ChaCha8 streams keyed
//! by the tile index, so a design reproduces bit-for-bit on every machine, whatever the FFT size.
//! Sensor noise ([`restore`]) likewise uses one stream per channel and image row, so a
//! capture does not depend on the number of threads.

/// The physics and numeric conventions, stated once (`docs/src/conventions.md`).
#[doc = include_str!("../../../docs/src/conventions.md")]
pub mod conventions {}

pub mod analysis;
pub mod budget;
pub mod camera;
pub mod denoise;
pub mod design;
pub mod display;
pub mod error;
pub mod figure;
pub mod lesson;
pub mod mask;
pub mod measured;
pub mod optimize;
pub mod phase;
pub mod progress;
pub mod psf;
pub mod reproduce;
pub mod restore;
pub mod sample;
pub mod sensor;
pub mod setting;
pub mod sweep;
pub mod theory;
pub mod views;

pub use analysis::analyze::{Analysis, ChannelAnalysis, Quality, analyze, analyze_with};
pub use design::Design;
pub use error::{SimError, ValueError};
pub use progress::Progress;
pub use sample::Sample;
pub use setting::{Setting, SettingPath};
