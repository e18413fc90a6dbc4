//! Which route computes a sensor-binned `|DFT_M(a)|²` (conventions.md §2, "PSF route"): the full
//! FFT of every column, or the pruned route that computes only what the window and the aliasing
//! measure read ([`crate::psf::pruned`]). Both give the same numbers to rounding; the cheaper one by
//! an operation count runs.
//!
//! Cost model (complex multiply-adds; `fft(n) = n log2 n`, ×4 for sizes with a prime factor
//! above 7, see [`crate::psf::zoom`]), with `R` nonzero rows, `C` field columns, `kw` the window's
//! largest column, `B` band columns or rows (`|k| ≥ ⌈0.45 M⌉`):
//! - full: `R·fft(M)/2 + (M/2 + 1)·(fft(M) + 3M) + 8M²` (row FFTs, every column FFT, then
//!   every sample's intensity, sums, mirror and two table look-ups to bin it);
//! - pruned: `R·fft(M)/2 + (kw + 1)·zoom(window rows) + (B/2 + C/2)·zoom(band rows) + 2·R·kept
//!   + 2·window samples`, each `zoom` the cheapest of slice / chirp-z / matrix DFT.
//!
//! **The seam.** Every PSF the analysis computes goes through one [`Fraunhofer`]: the CPU
//! routes ([`PsfRoute`]) implement it here, and a transform that runs elsewhere (another
//! device) implements it outside the core and is handed to the analysis
//! (`analyze_with_route`, which sits above this module). What the analysis does with the binned
//! intensity (spectral weighting, normalising, the window's energy, the MTF) stays in the core,
//! so nothing above the core knows how a transform ran.

use rustfft::num_complex::Complex64;

use crate::SimError;
use crate::display::aperture::Field;
use crate::progress::Progress;
use crate::psf::fft::{Binned, binned_intensity, binned_intensity_complex, full_intensity};
use crate::psf::pruned::{binned_pruned, pruned_ops};
use crate::psf::sampling::Binning;
use crate::psf::spectra::{Pool, WindowDft};
use crate::psf::zoom::fft_ops;

/// Where the Fraunhofer steps of a job run: the user's switch (`--backend`, Python's
/// `backend=`, the studio's setting). The device route lives outside the core (the `udc-gpu`
/// crate); the core only names the choice.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Backend {
    /// The CPU routes, in f64 (the reference).
    #[default]
    Cpu,
    /// A GPU through wgpu (Vulkan, Metal, DX12), in f32; a software driver counts, and a machine
    /// without one is an error.
    Gpu,
    /// A hardware GPU when there is one, else the CPU, with one line saying why.
    Auto,
}

/// How the Fraunhofer intensity is computed and binned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PsfRoute {
    /// The cheaper of the two by the operation count.
    #[default]
    Auto,
    /// Every column FFT, every sample binned (the reference).
    Full,
    /// Only the window's and the aliasing band's samples.
    Pruned,
}

/// The Fraunhofer step of a PSF: a field's `|DFT_M(a)|²` on an `m × m` grid, integrated over
/// the sensor pixels of `binning`'s window, with the grid's total and its outer band
/// ([`Binned`]). An implementation must give the numbers of [`PsfRoute::Full`] to its own
/// precision, and check `progress` for cancellation.
pub trait Fraunhofer: Sync {
    /// The binned intensity of `field` (see the trait's docs).
    ///
    /// # Errors
    /// [`SimError::Cancelled`] when `progress` is cancelled; [`SimError::Sampling`] when the
    /// field does not fit the grid; an implementation's own refusals (memory, a lost device).
    fn binned(
        &self,
        field: &Field,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError>;

    /// [`Fraunhofer::binned`] of a complex field (the aperture with a phase across it, as a
    /// defocused pupil): the transform has no mirror symmetry, so the whole grid is computed.
    /// The CPU's dense transform ([`binned_intensity_complex`]) unless an implementation has
    /// its own.
    ///
    /// # Errors
    /// As [`Fraunhofer::binned`].
    fn binned_complex(
        &self,
        field: &Field<Complex64>,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        binned_intensity_complex(field, m, binning, progress)
    }

    /// The whole centred `M×M` intensity `|DFT_M(a)|²`, unbinned (the measured-PSF fit resamples
    /// it on turned and scaled coordinates). The CPU's [`full_intensity`] unless an
    /// implementation has its own.
    ///
    /// # Errors
    /// As [`Fraunhofer::binned`].
    fn full(
        &self,
        field: &Field,
        m: usize,
        progress: &Progress,
    ) -> Result<ndarray::Array2<f64>, SimError> {
        full_intensity(field, m, progress)
    }

    /// The optimizer's step: `DFT_M` of a real field on `dft`'s sample box, kept (complex, not
    /// its intensity) on `dft`'s frequency box and laid out as [`WindowDft::forward`]'s. The
    /// CPU's pruned FFTs unless an implementation has its own; temporaries and the result come
    /// from `pool`.
    ///
    /// # Errors
    /// An implementation's refusals (memory, a lost device).
    fn window_spectrum(
        &self,
        dft: &WindowDft,
        field: &[f64],
        pool: &Pool,
    ) -> Result<Vec<Complex64>, SimError> {
        Ok(dft.forward(field, pool))
    }

    /// The adjoint of [`Fraunhofer::window_spectrum`], `Re(Fᴴ g)` on the sample box
    /// ([`WindowDft::adjoint`]): the way the optimizer's gradient goes back to the cells.
    ///
    /// # Errors
    /// As [`Fraunhofer::window_spectrum`].
    fn window_spectrum_adjoint(
        &self,
        dft: &WindowDft,
        g: &[Complex64],
        pool: &Pool,
    ) -> Result<Vec<f64>, SimError> {
        Ok(dft.adjoint(g, pool))
    }
}

impl Fraunhofer for PsfRoute {
    fn binned(
        &self,
        field: &Field,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        binned_by(*self, field, m, binning, progress)
    }
}

/// Modelled cost of the full route.
pub fn full_ops(field: &Field, m: usize) -> f64 {
    let mf = m as f64;
    field.rows.len() as f64 * 0.5 * fft_ops(m)
        + (m / 2 + 1) as f64 * (fft_ops(m) + 3.0 * mf)
        + 8.0 * mf * mf
}

/// The route [`PsfRoute::Auto`] picks for this field, grid and window: `Full` or `Pruned`.
pub fn choose(field: &Field, m: usize, binning: &Binning) -> PsfRoute {
    if pruned_ops(field, m, binning) < full_ops(field, m) {
        PsfRoute::Pruned
    } else {
        PsfRoute::Full
    }
}

/// `|DFT_M(a)|²` over `binning`'s window by `route`.
///
/// # Errors
/// As [`binned_intensity`].
pub fn binned_by(
    route: PsfRoute,
    field: &Field,
    m: usize,
    binning: &Binning,
    progress: &Progress,
) -> Result<Binned, SimError> {
    let route = match route {
        PsfRoute::Auto => choose(field, m, binning),
        r => r,
    };
    match route {
        PsfRoute::Pruned => binned_pruned(field, m, binning, progress),
        _ => binned_intensity(field, m, binning, progress),
    }
}
