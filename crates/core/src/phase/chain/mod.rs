//! The 1-D propagation chain of conventions.md §7 for one wavelength and one incidence direction.
//!
//! Samples sit on the lattice `x = m·δ` (m an integer, δ the display sample); sample `i` of the
//! chain's arrays is lattice point `m_first + i`. Under [`SamplingConvention::Thesis`] the
//! geometry is placed on that lattice exactly as the thesis code places it, and each Fresnel step
//! runs on a grid wide enough that its periodic wrap-around never reaches the lit region: the
//! thesis pads the display to `M = 2⌊λf/(2δ δ3)⌋` ≈ 10⁶ samples, which is wrap-free too, so both
//! give the same fields (to ~1e-6 of the peak; the tails of the band-limited kernel are all that
//! differ) at a quarter of the cost. A sampling with [`Relay::LensletPeriod`] sends a plate
//! whose lenslets are all alike through one lenslet instead (the `periodic` module): the same
//! fields but for the light the array's ends diffract, many times faster. Any other plate, and
//! every plate under [`Relay::WrappedDisplay`], goes through the whole display on a grid of
//! its own width with the direction's Bloch phase (`Chain::relay_bloch`): the same
//! approximation, the display repeated instead of one lenslet.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use rayon::prelude::*;

use rustfft::num_complex::{Complex32, Complex64};

use super::czt::{Czt, CztWork};
use super::geometry::{Lenslets, display_aperture_um, height_um};
use super::{PhaseDesign, PhaseSampling, Relay, SamplingConvention, SimError};
use crate::Progress;
use crate::psf::fft::quadratic_phase;
use crate::psf::sampling::{next_fast_size, next_fast_size_235};
use udc_fft::complex_plan_f32;

mod bloch;
mod periodic;
mod propagate;

pub use bloch::{
    BlochDirection, BlochIntensity, BlochRelay, BlochWavelength, CpuBloch, RAMP_BLOCK, Ramp,
};

/// Largest display-plane grid the chain accepts (2²⁴ samples ≈ 270 MB per complex field).
pub const MAX_GRID_SAMPLES: usize = 1 << 24;

/// The thesis's Fraunhofer output spacing δ3 at 14 samples per pixel, in µm (conventions.md §7).
pub const THESIS_OUTPUT_SAMPLE_UM: f64 = 0.145;
/// Fine sensor samples per pixel that [`THESIS_OUTPUT_SAMPLE_UM`] belongs to.
pub const THESIS_FINE_PER_PIXEL: usize = 14;

/// Which optics sit at the display.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseOptics {
    /// MLA 1, display, MLA 2, each a focal length apart: the thesis's design.
    DoubleMla,
    /// The bare T-OLED against the main lens: the reference.
    Toled,
    /// MLA 1's plate pressed against the display, no MLA 2 (Lemma 1's single mask).
    SingleMask,
}

/// The direction of the incoming plane wave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Incidence {
    /// The direction imaged on sensor pixel `j` (relative to the axis pixel): sinθ = j·pixel/f
    /// with the nominal pixel pitch (2 µm in the thesis, under either convention).
    Pixel(i64),
    /// An angle in degrees from the axis.
    AngleDeg(f64),
}

impl Incidence {
    /// sinθ of this direction for `d`'s camera.
    pub fn sin_theta(self, d: &PhaseDesign) -> f64 {
        match self {
            Incidence::Pixel(j) => d.camera.sin_theta_of_pixel(j as f64),
            Incidence::AngleDeg(a) => a.to_radians().sin(),
        }
    }

    /// The sensor pixel (relative to the axis pixel) that contains `f·sinθ`, where a plain lens
    /// (and the bare T-OLED) images this direction. The double MLA sends it near the opposite
    /// pixel: each lenslet pair is a 1:1 Keplerian telescope, which inverts the beam's angle.
    /// Under the thesis convention pixels are [`effective_pixel_um`] wide and the axis is the
    /// left edge of the axis pixel, so direction `Pixel(100)` lands on pixel +98.
    pub fn image_pixel(self, d: &PhaseDesign) -> i64 {
        let u = self.sin_theta(d) * d.camera.focal_length_um();
        match d.sampling {
            SamplingConvention::Thesis => (u / effective_pixel_um(d)).floor() as i64,
            SamplingConvention::Centred => match self {
                Incidence::Pixel(j) => j,
                Incidence::AngleDeg(_) => (u / d.camera.pixel_um).round() as i64,
            },
        }
    }
}

/// The sensor pixel pitch the chain bins to: the camera's under [`SamplingConvention::Centred`];
/// under the thesis convention 14 Fraunhofer samples of 0.145 µm (2.03 µm for 2 µm pixels).
pub fn effective_pixel_um(d: &PhaseDesign) -> f64 {
    match d.sampling {
        SamplingConvention::Thesis => {
            THESIS_OUTPUT_SAMPLE_UM * THESIS_FINE_PER_PIXEL as f64 * d.camera.pixel_um / 2.0
        }
        SamplingConvention::Centred => d.camera.pixel_um,
    }
}

/// One wavelength's sensor PSF.
#[derive(Debug, Clone, PartialEq)]
pub struct MonoPsf {
    /// Energy per sensor pixel (fractions of the light on the main-lens opening). The window is
    /// the whole sensor: entry `k` is sensor pixel `k`, the axis pixel at `pixels/2`, for every
    /// direction.
    pub sensor: Vec<f64>,
    /// Σ `sensor`.
    pub window_energy: f64,
    /// All the light that leaves the main-lens opening (Parseval), inside the window or not.
    pub total_energy: f64,
    /// Where a plain lens would image the direction ([`Incidence::image_pixel`]).
    pub image_pixel: i64,
}

impl MonoPsf {
    /// Zeroes the sensor outside `pixels` and sums the window again.
    fn keep(&mut self, pixels: Range<usize>) {
        for (k, s) in self.sensor.iter_mut().enumerate() {
            if !pixels.contains(&k) {
                *s = 0.0;
            }
        }
        self.window_energy = self.sensor.iter().sum();
    }
}

/// The double MLA's plate at one wavelength, formed once for many directions.
struct Formed {
    /// Its transmission on the chain's samples.
    plate: Vec<Complex64>,
    /// Its spectrum on the wrapped grid ([`Chain::plate_spectrum`]) where the relay wraps.
    spectrum: Option<Vec<Complex32>>,
    /// The opening's factors that do not depend on the direction ([`Chain::opening`]), where
    /// the relay is not the lenslet period's.
    opening: Option<Vec<Complex32>>,
}

/// A cached chirp-z transform's key: wavelength bits, input samples, first and end sensor pixel.
type CztKey = (u64, usize, usize, usize);

/// The sampled geometry of one design, shared by every wavelength and direction.
pub struct Chain {
    design: PhaseDesign,
    sampling: PhaseSampling,
    lenslets: Lenslets,
    /// Lattice index of sample 0.
    m_first: i64,
    n: usize,
    dx_um: f64,
    display_rect: Vec<f64>,
    /// The display's transmission; ones where the thesis pads the grating beyond the display.
    slits: Vec<f64>,
    lens_rect: Vec<f64>,
    /// Samples `[start, end)` inside the main-lens opening: the Fraunhofer transform's input.
    lens_range: (usize, usize),
    heights_um: Vec<f64>,
    /// Thesis convention: (first sample, samples per lenslet, lenslets) of the lenslet cells.
    cells: Option<(usize, usize, usize)>,
    transfer: Mutex<HashMap<u64, Arc<Vec<Complex32>>>>,
    czt: Mutex<HashMap<CztKey, Arc<Czt>>>,
    /// Where the Bloch relay's batches of directions run ([`Chain::with_relay`]); the CPU when
    /// `None`.
    relay: Option<Arc<dyn BlochRelay>>,
}

thread_local! {
    /// The buffers of one propagation, per worker thread.
    static WORK: std::cell::RefCell<Work> = const { std::cell::RefCell::new(Work::new()) };
}

/// The buffers of one propagation, kept per worker thread: fresh multi-megabyte vectors per
/// call cost more in page faults than the arithmetic on them.
struct Work {
    /// The plate's transmission on the chain's samples.
    plate: Vec<Complex64>,
    /// The opening's direction-free factors ([`Chain::opening`]).
    opening: Vec<Complex32>,
    /// Its spectrum on the wrapped grid, and the direction's Bloch-shifted transfer function.
    spectrum: Vec<Complex32>,
    transfer: Vec<Complex32>,
    /// The padded Fresnel field (single precision: the relay keeps ~1e-8 relative accuracy in
    /// V and doubles the FFTs' throughput) and its FFT scratch.
    field: Vec<Complex32>,
    scratch: Vec<Complex32>,
    /// The chirp-z transform's working arrays.
    czt: CztWork,
}

impl Work {
    const fn new() -> Self {
        Work {
            plate: Vec::new(),
            opening: Vec::new(),
            spectrum: Vec::new(),
            transfer: Vec::new(),
            field: Vec::new(),
            scratch: Vec::new(),
            czt: CztWork::new(),
        }
    }
}

/// Fraction of the sample `[x − dx/2, x + dx/2]` inside `[lo, hi]` (anti-aliased edges).
fn coverage(x: f64, dx: f64, lo: f64, hi: f64) -> f64 {
    ((x + dx / 2.0).min(hi) - (x - dx / 2.0).max(lo)).clamp(0.0, dx) / dx
}

/// Rounds half to even, as the thesis code's `round` of `(patternN − slitN)/2` does.
fn round_half_even(v: f64) -> f64 {
    let r = v.round();
    if (v - v.trunc()).abs() == 0.5 && r % 2.0 != 0.0 {
        r - v.signum()
    } else {
        r
    }
}

/// The geometry arrays of one convention.
struct Layout {
    m_first: i64,
    display_rect: Vec<f64>,
    slits: Vec<f64>,
    lens_rect: Vec<f64>,
}

/// Per-lenslet sample counts of the thesis convention.
struct ThesisCells {
    /// Lattice index of the first display sample inside the display aperture: lenslet 0 starts there.
    m0: i64,
    /// Samples per lenslet, `round(pitch/δ)`.
    pattern: usize,
    /// The slit's first open sample in its cell and its width, in samples.
    slit_start: usize,
    slit_len: usize,
}

impl ThesisCells {
    fn new(d: &PhaseDesign, dx: f64) -> Self {
        let half = display_aperture_um(d) / 2.0;
        // The first lattice point with m·δ ≥ −W/2 (the comparison as the thesis code makes it).
        let mut m0 = (-half / dx).ceil() as i64;
        while (m0 as f64 - 1.0) * dx >= -half {
            m0 -= 1;
        }
        while (m0 as f64) * dx < -half {
            m0 += 1;
        }
        let pattern = (d.pitch_um / dx).round().max(1.0) as usize;
        let slit_len = ((d.open_ratio * d.pitch_um / dx).round() as usize).clamp(1, pattern);
        let slit_start = round_half_even((pattern - slit_len) as f64 / 2.0) as usize;
        ThesisCells {
            m0,
            pattern,
            slit_start,
            slit_len,
        }
    }

    /// The lenslet under lattice point `m` and the sample's index `q` in its cell, or `None`
    /// outside the array.
    fn locate(&self, m: i64, count: usize) -> Option<(usize, usize)> {
        let rel = m - self.m0;
        if rel < 0 {
            return None;
        }
        let l = rel as usize / self.pattern;
        (l < count).then_some((l, rel as usize % self.pattern))
    }

    /// Sample `q`'s distance from its lenslet's centre: the thesis's per-lenslet coordinate
    /// `(q − patternN/2)·δ` (half-integer offsets when patternN is odd).
    fn local_um(&self, q: usize, dx: f64) -> f64 {
        (q as f64 - self.pattern as f64 / 2.0) * dx
    }
}

impl Chain {
    /// Samples a design's geometry.
    ///
    /// # Errors
    /// An invalid design or sampling, or a grid beyond [`MAX_GRID_SAMPLES`].
    pub fn new(design: &PhaseDesign, sampling: &PhaseSampling) -> Result<Self, SimError> {
        design.validate()?;
        sampling.validate()?;
        let lenslets = Lenslets::new(design)?;
        let dx = sampling.display_sample_um;
        let aperture = display_aperture_um(design);
        let half_display = aperture / 2.0;
        let half_lens = design.camera.aperture_um() / 2.0;
        let too_large = |raw: f64| {
            SimError::TooLarge(format!(
                "the display plane needs {raw:.0} samples of {dx} µm; the limit is \
                 {MAX_GRID_SAMPLES} (use a coarser display sample or a smaller camera)"
            ))
        };
        let layout = match design.sampling {
            SamplingConvention::Centred => {
                // A margin of two pitches keeps the periodic FFT's wrap-around off the lit region.
                let span = lenslets.span_um().max(aperture) + 4.0 * design.pitch_um.max(25.0);
                let raw = (span / dx).ceil();
                if !(raw < MAX_GRID_SAMPLES as f64) {
                    return Err(too_large(raw));
                }
                let n = next_fast_size(raw as usize);
                let m_first = -((n / 2) as i64);
                let x = |i: usize| (m_first + i as i64) as f64 * dx;
                let slit = design.open_ratio * design.pitch_um;
                let c0 = lenslets.centre_um(0);
                Layout {
                    m_first,
                    display_rect: (0..n)
                        .map(|i| coverage(x(i), dx, -half_display, half_display))
                        .collect(),
                    lens_rect: (0..n)
                        .map(|i| coverage(x(i), dx, -half_lens, half_lens))
                        .collect(),
                    slits: (0..n)
                        .map(|i| {
                            let local = (x(i) - c0 + design.pitch_um / 2.0)
                                .rem_euclid(design.pitch_um)
                                - design.pitch_um / 2.0;
                            coverage(local, dx, -slit / 2.0, slit / 2.0)
                        })
                        .collect(),
                }
            }
            SamplingConvention::Thesis => {
                // The widest Fresnel grid this design can need: the chain plus the paraxial
                // kernel's reach at the longest wavelength accepted (1100 nm).
                let reach = 1.1 * design.f_mla_um / (dx * dx);
                let raw = (lenslets.span_um().max(aperture) + 2.0 * half_lens) / dx + reach;
                if !(raw < MAX_GRID_SAMPLES as f64) {
                    return Err(too_large(raw));
                }
                let cells = ThesisCells::new(design, dx);
                let count = lenslets.count();
                let m_lens = (half_lens / dx).ceil() as i64 + 1;
                let m_display = (half_display / dx).ceil() as i64 + 1;
                let m_first = (-m_lens).min(-m_display).min(cells.m0) - 1;
                let m_last = m_lens
                    .max(m_display)
                    .max(cells.m0 + (count * cells.pattern) as i64)
                    + 1;
                let n = (m_last - m_first) as usize;
                let x = |i: usize| (m_first + i as i64) as f64 * dx;
                let inside = |v: f64, half: f64| if v.abs() <= half { 1.0 } else { 0.0 };
                Layout {
                    m_first,
                    display_rect: (0..n).map(|i| inside(x(i), half_display)).collect(),
                    lens_rect: (0..n).map(|i| inside(x(i), half_lens)).collect(),
                    slits: (0..n)
                        .map(|i| match cells.locate(m_first + i as i64, count) {
                            Some((_, q)) => {
                                let open =
                                    q >= cells.slit_start && q < cells.slit_start + cells.slit_len;
                                if open { 1.0 } else { 0.0 }
                            }
                            None => 1.0,
                        })
                        .collect(),
                }
            }
        };
        let Layout {
            m_first,
            display_rect,
            slits,
            lens_rect,
        } = layout;
        let cells = match design.sampling {
            SamplingConvention::Thesis => {
                let c = ThesisCells::new(design, dx);
                Some(((c.m0 - m_first) as usize, c.pattern, lenslets.count()))
            }
            SamplingConvention::Centred => None,
        };
        let n = slits.len();
        let start = lens_rect.iter().position(|&v| v > 0.0).unwrap_or(0);
        let end = lens_rect
            .iter()
            .rposition(|&v| v > 0.0)
            .map_or(start, |e| e + 1);
        let mut chain = Chain {
            design: design.clone(),
            sampling: sampling.clone(),
            lenslets,
            m_first,
            n,
            dx_um: dx,
            display_rect,
            slits,
            lens_rect,
            lens_range: (start, end),
            heights_um: Vec::new(),
            cells,
            transfer: Mutex::new(HashMap::new()),
            czt: Mutex::new(HashMap::new()),
            relay: None,
        };
        chain.heights_um = chain.plate(design, &chain.lenslets);
        Ok(chain)
    }

    /// The plate's heights on this chain's samples for `d`'s lenslets.
    fn plate(&self, d: &PhaseDesign, lenslets: &Lenslets) -> Vec<f64> {
        match d.sampling {
            SamplingConvention::Centred => (0..self.n)
                .map(|i| lenslets.height_at(d, self.x_um(i)))
                .collect(),
            SamplingConvention::Thesis => {
                let cells = ThesisCells::new(d, self.dx_um);
                let first = (cells.m0 - self.m_first) as usize;
                let mut out = vec![0.0; self.n];
                let folds = &lenslets.fold_height_um;
                for (l, fold) in folds.iter().enumerate() {
                    let a = first + l * cells.pattern;
                    if l > 0 && folds[l - 1] == *fold {
                        // Equal fold heights give equal cells: copy the left neighbour's.
                        out.copy_within(a - cells.pattern..a, a);
                    } else {
                        for (q, h) in out[a..a + cells.pattern].iter_mut().enumerate() {
                            *h = height_um(d, cells.local_um(q, self.dx_um), *fold);
                        }
                    }
                }
                out
            }
        }
    }

    /// The chain with its Bloch relay's batches of directions ([`Chain::mono_directions_on`]
    /// through the double MLA on the wrapped grid, the phase model's slowest step) on `relay`:
    /// a device, or [`CpuBloch`]. The single-direction [`Chain::mono`] stays on the CPU.
    #[must_use]
    pub fn with_relay(self, relay: Arc<dyn BlochRelay>) -> Chain {
        Chain {
            relay: Some(relay),
            ..self
        }
    }

    /// [`Chain::with_relay`] where a relay is given; the CPU's own relay otherwise.
    #[must_use]
    pub fn with_relay_if(self, relay: Option<&Arc<dyn BlochRelay>>) -> Chain {
        match relay {
            Some(r) => self.with_relay(Arc::clone(r)),
            None => self,
        }
    }

    /// The design the chain was sampled for.
    pub fn design(&self) -> &PhaseDesign {
        &self.design
    }

    /// The design's lenslets (λ0 and fold heights).
    pub fn lenslets(&self) -> &Lenslets {
        &self.lenslets
    }

    /// Display-plane samples.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether the chain has no display-plane samples.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Position of display-plane sample `i` from the optical axis, in µm.
    pub fn x_um(&self, i: usize) -> f64 {
        (self.m_first + i as i64) as f64 * self.dx_um
    }

    /// The plate's height on the grid for this design.
    pub fn heights_um(&self) -> &[f64] {
        &self.heights_um
    }

    /// Heights on this grid for a design that differs only in λ0, surface or step.
    ///
    /// # Errors
    /// When the other design's lenslet plan does not fit, or its geometry differs.
    pub fn heights_for(&self, other: &PhaseDesign) -> Result<Vec<f64>, SimError> {
        let same_geometry = other.pitch_um == self.design.pitch_um
            && other.f_mla_um == self.design.f_mla_um
            && other.open_ratio == self.design.open_ratio
            && other.sampling == self.design.sampling
            && other.camera == self.design.camera;
        if !same_geometry {
            return Err(SimError::Sampling(
                "heights_for needs the same pitch, focal length, opening, convention and camera"
                    .into(),
            ));
        }
        let lenslets = Lenslets::new(other)?;
        Ok(self.plate(other, &lenslets))
    }

    /// The complex aperture on the main-lens opening at normal incidence for the bare T-OLED or
    /// Lemma 1's single mask (`heights_um` ignored for the T-OLED): the field whose
    /// autocorrelation is the continuous, unbinned OTF that Lemma 1 speaks about.
    ///
    /// # Errors
    /// [`SimError::Sampling`] for the double MLA, whose lens-plane field is not a mask.
    pub fn aperture(
        &self,
        optics: PhaseOptics,
        heights_um: &[f64],
        wavelength_nm: f64,
    ) -> Result<Vec<Complex64>, SimError> {
        let k_n1 = self.k_n1(wavelength_nm);
        let (start, end) = self.lens_range;
        let amplitude = |i: usize| self.slits[i] * self.lens_rect[i];
        match optics {
            PhaseOptics::Toled => Ok((start..end)
                .map(|i| Complex64::new(amplitude(i), 0.0))
                .collect()),
            PhaseOptics::SingleMask => Ok((start..end)
                .map(|i| {
                    let h = heights_um.get(i).copied().unwrap_or(0.0);
                    Complex64::from_polar(amplitude(i), -k_n1 * h)
                })
                .collect()),
            PhaseOptics::DoubleMla => Err(SimError::Sampling(
                "the double MLA is not a single mask at the display".into(),
            )),
        }
    }

    /// The sensor PSF of one wavelength and direction through `optics`, with the plate `heights_um`
    /// (from [`Chain::heights_um`] or [`Chain::heights_for`]; ignored for the bare T-OLED).
    pub fn mono(
        &self,
        optics: PhaseOptics,
        heights_um: &[f64],
        wavelength_nm: f64,
        incidence: Incidence,
    ) -> MonoPsf {
        match self.period(optics, heights_um) {
            Some(period) => self.mono_periodic(
                period,
                optics,
                heights_um,
                None,
                wavelength_nm,
                incidence,
                0..self.design.camera.pixels,
            ),
            None => self.mono_with(optics, heights_um, None, wavelength_nm, incidence),
        }
    }

    /// [`Chain::mono`], through the chain's Bloch relay ([`Chain::with_relay`]) where one is
    /// attached and the plate takes it (a device's errors are the caller's); otherwise `mono`
    /// itself.
    ///
    /// # Errors
    /// The relay's refusals (memory, a lost device).
    pub fn mono_relayed(
        &self,
        optics: PhaseOptics,
        heights_um: &[f64],
        wavelength_nm: f64,
        incidence: Incidence,
    ) -> Result<MonoPsf, SimError> {
        if self.relay.is_none() || !self.bloch(optics, heights_um) {
            return Ok(self.mono(optics, heights_um, wavelength_nm, incidence));
        }
        let all = 0..self.design.camera.pixels;
        // A progress of its own: one direction's, inside a caller's parallel loop.
        let psfs = self.mono_directions_on(
            optics,
            heights_um,
            wavelength_nm,
            &[incidence],
            all,
            &Progress::new(),
        )?;
        psfs.into_iter()
            .next()
            .ok_or_else(|| SimError::Sampling("the relay returned no PSF".into()))
    }

    /// [`Chain::mono`] for many directions at one wavelength, in parallel, in the order of
    /// `incidences`. Through the double MLA the plate's transmission (an exponential per
    /// sample, as costly as an FFT) is formed once for them all; each PSF equals `mono`'s to the
    /// bit. `progress` moves as the directions finish.
    ///
    /// # Errors
    /// [`SimError::Cancelled`] when `progress` is cancelled.
    pub fn mono_directions(
        &self,
        optics: PhaseOptics,
        heights_um: &[f64],
        wavelength_nm: f64,
        incidences: &[Incidence],
        progress: &Progress,
    ) -> Result<Vec<MonoPsf>, SimError> {
        let all = 0..self.design.camera.pixels;
        self.mono_directions_on(optics, heights_um, wavelength_nm, incidences, all, progress)
    }

    /// [`Chain::mono_directions`] over the sensor pixels `pixels` alone (an imaging operator's
    /// scene columns): the other pixels read zero and `window_energy` sums these. The lenslet
    /// period's transform then evaluates only these pixels' samples; the whole display's
    /// computes all of them either way.
    ///
    /// # Errors
    /// [`SimError::Cancelled`] when `progress` is cancelled; [`SimError::Sampling`] for pixels
    /// beyond the sensor.
    pub fn mono_directions_on(
        &self,
        optics: PhaseOptics,
        heights_um: &[f64],
        wavelength_nm: f64,
        incidences: &[Incidence],
        pixels: Range<usize>,
        progress: &Progress,
    ) -> Result<Vec<MonoPsf>, SimError> {
        let sensor = self.design.camera.pixels;
        if pixels.start >= pixels.end || pixels.end > sensor {
            return Err(SimError::Sampling(format!(
                "pixels {}..{} are not a window of the {sensor}-pixel sensor",
                pixels.start, pixels.end
            )));
        }
        let period = self.period(optics, heights_um);
        let formed = match optics {
            PhaseOptics::DoubleMla => {
                let mut plate = Vec::new();
                self.transmission(heights_um, self.k_n1(wavelength_nm), &mut plate);
                let lambda = wavelength_nm * 1e-3;
                let spectrum = (period.is_none() && self.wraps()).then(|| {
                    let mut spectrum = Vec::new();
                    self.plate_spectrum(&plate, lambda, &mut spectrum);
                    spectrum
                });
                let opening = period.is_none().then(|| {
                    let mut opening = Vec::new();
                    self.opening(&plate, &self.whole_sensor_czt(lambda), &mut opening);
                    opening
                });
                Some(Formed {
                    plate,
                    spectrum,
                    opening,
                })
            }
            PhaseOptics::Toled | PhaseOptics::SingleMask => None,
        };
        if let Some(formed) = formed.as_ref().filter(|_| self.bloch(optics, heights_um)) {
            let relay: &dyn BlochRelay = self.relay.as_deref().unwrap_or(&CpuBloch);
            return self.bloch_directions(
                relay,
                formed,
                wavelength_nm,
                incidences,
                pixels,
                progress,
            );
        }
        let finished = AtomicUsize::new(0);
        incidences
            .par_iter()
            .map(|&incidence| {
                progress.check()?;
                let psf = match period {
                    Some(period) => self.mono_periodic(
                        period,
                        optics,
                        heights_um,
                        formed.as_ref().map(|f| f.plate.as_slice()),
                        wavelength_nm,
                        incidence,
                        pixels.clone(),
                    ),
                    None => {
                        let mut psf = self.mono_with(
                            optics,
                            heights_um,
                            formed.as_ref(),
                            wavelength_nm,
                            incidence,
                        );
                        psf.keep(pixels.clone());
                        psf
                    }
                };
                let n = finished.fetch_add(1, Ordering::Relaxed) + 1;
                progress.set(n as f32 / incidences.len() as f32);
                Ok(psf)
            })
            .collect()
    }

    /// `k (n − 1)` at this wavelength: the plate's phase per µm of height.
    fn k_n1(&self, wavelength_nm: f64) -> f64 {
        2.0 * PI / (wavelength_nm * 1e-3) * (self.design.refractive_index - 1.0)
    }

    /// [`Chain::mono_directions_on`] through the Bloch relay: `relay` runs the directions from
    /// the wavelength's tables, formed here from `formed` (the plate's spectrum and opening).
    fn bloch_directions(
        &self,
        relay: &dyn BlochRelay,
        formed: &Formed,
        wavelength_nm: f64,
        incidences: &[Incidence],
        pixels: Range<usize>,
        progress: &Progress,
    ) -> Result<Vec<MonoPsf>, SimError> {
        let lambda = wavelength_nm * 1e-3;
        let czt = self.whole_sensor_czt(lambda);
        let untilted = self.transfer(lambda);
        let (spectrum, opening) = match (&formed.spectrum, &formed.opening) {
            (Some(s), Some(o)) => (s, o),
            _ => {
                return Err(SimError::Sampling(
                    "the Bloch relay needs the plate's spectrum and opening".into(),
                ));
            }
        };
        let wavelength = BlochWavelength {
            spectrum,
            untilted: &untilted,
            slits: &self.slits,
            opening,
            start: self.lens_range.0,
            czt: czt.convolution(),
        };
        let k = 2.0 * PI / lambda;
        let k_sins: Vec<f64> = incidences
            .iter()
            .map(|i| k * i.sin_theta(&self.design))
            .collect();
        let len = spectrum.len();
        let direction = |i: usize| self.bloch_direction(len, lambda, k_sins[i]);
        let out = relay.directions(&wavelength, incidences.len(), &direction, progress)?;
        Ok(out
            .iter()
            .zip(incidences)
            .map(|(o, &incidence)| {
                let mut psf = self.finish(&o.fine, 0, o.total, lambda, incidence);
                psf.keep(pixels.clone());
                psf
            })
            .collect())
    }

    /// [`Chain::mono`] through the Bloch relay on the CPU, with the plate given (`formed`) or
    /// formed here in the thread's buffers.
    fn mono_bloch(
        &self,
        heights_um: &[f64],
        formed: Option<&Formed>,
        wavelength_nm: f64,
        incidence: Incidence,
    ) -> MonoPsf {
        let lambda = wavelength_nm * 1e-3;
        let k_sin = 2.0 * PI / lambda * incidence.sin_theta(&self.design);
        let czt = self.whole_sensor_czt(lambda);
        let untilted = self.transfer(lambda);
        let mut fine = vec![0.0; czt.convolution().n_out()];
        let total = WORK.with(|cell| {
            let work = &mut *cell.borrow_mut();
            // The plate's buffers leave the thread's work while the relay borrows the rest.
            let mut plate = std::mem::take(&mut work.plate);
            let mut spectrum = std::mem::take(&mut work.spectrum);
            let mut opening = std::mem::take(&mut work.opening);
            let given_plate = formed.map(|f| f.plate.as_slice());
            if given_plate.is_none() {
                self.transmission(heights_um, self.k_n1(wavelength_nm), &mut plate);
            }
            let plate_ref = given_plate.unwrap_or(&plate);
            let spectrum_ref: &[Complex32] = match formed.and_then(|f| f.spectrum.as_deref()) {
                Some(given) => given,
                None => {
                    self.plate_spectrum(plate_ref, lambda, &mut spectrum);
                    &spectrum
                }
            };
            let opening_ref: &[Complex32] = match formed.and_then(|f| f.opening.as_deref()) {
                Some(given) => given,
                None => {
                    self.opening(plate_ref, &czt, &mut opening);
                    &opening
                }
            };
            let wavelength = BlochWavelength {
                spectrum: spectrum_ref,
                untilted: &untilted,
                slits: &self.slits,
                opening: opening_ref,
                start: self.lens_range.0,
                czt: czt.convolution(),
            };
            let direction = self.bloch_direction(spectrum_ref.len(), lambda, k_sin);
            let total = CpuBloch::one(&wavelength, &direction, work, &mut fine);
            work.plate = plate;
            work.spectrum = spectrum;
            work.opening = opening;
            total
        });
        self.finish(&fine, 0, total, lambda, incidence)
    }

    /// [`Chain::mono`], with the double MLA's plate given (`formed`, at this wavelength) or
    /// formed here (`None`).
    fn mono_with(
        &self,
        optics: PhaseOptics,
        heights_um: &[f64],
        formed: Option<&Formed>,
        wavelength_nm: f64,
        incidence: Incidence,
    ) -> MonoPsf {
        // The wrapped grid carries the tilt as a Bloch shift of the transfer function, so the
        // plate's spectrum serves every direction and the tilt is applied at the end.
        if optics == PhaseOptics::DoubleMla && self.wraps() {
            return self.mono_bloch(heights_um, formed, wavelength_nm, incidence);
        }
        let lambda = wavelength_nm * 1e-3;
        let k = 2.0 * PI / lambda;
        let k_sin = k * incidence.sin_theta(&self.design);
        let k_n1 = self.k_n1(wavelength_nm);
        let (start, end) = self.lens_range;
        let cam = &self.design.camera;
        let fine = self.sampling.fine_per_pixel;
        let mut intensity = vec![0.0; cam.pixels * fine];
        // The window is the sensor, not the image point: the double MLA moves light to the
        // opposite side of the axis, which a window that followed f·sinθ would cut off.
        let czt = self.whole_sensor_czt(lambda);
        let mut total = 0.0;
        WORK.with(|cell| {
            let work = &mut *cell.borrow_mut();
            let Work {
                plate: own_plate,
                opening: own_opening,
                field,
                scratch,
                czt: czt_work,
                ..
            } = work;
            let plate: &[Complex64] = match (optics, formed) {
                (PhaseOptics::DoubleMla, Some(given)) => &given.plate,
                (PhaseOptics::DoubleMla, None) => {
                    self.transmission(heights_um, k_n1, own_plate);
                    own_plate
                }
                (PhaseOptics::Toled | PhaseOptics::SingleMask, _) => &[],
            };
            if optics == PhaseOptics::DoubleMla {
                self.relay(plate, field, scratch, lambda, k_sin);
            }
            // The field on the main-lens opening, fed to the Fraunhofer transform as it is
            // formed; one closure per optics keeps the loop free of branches.
            let one = Complex64::new(1.0, 0.0);
            let mut tilt = self.tilt(start, k_sin);
            let mut tilted = |v: Complex64| {
                if k_sin == 0.0 {
                    v
                } else {
                    v * tilt.next().unwrap_or(one)
                }
            };
            let total = &mut total;
            match optics {
                PhaseOptics::DoubleMla => {
                    let opening: &[Complex32] = match formed.and_then(|f| f.opening.as_deref()) {
                        Some(given) => given,
                        None => {
                            self.opening(plate, &czt, own_opening);
                            own_opening
                        }
                    };
                    let field = &field[start..end];
                    czt.intensity_filled(
                        czt_work,
                        |input| {
                            for ((v, f), g) in input.iter_mut().zip(field).zip(opening) {
                                *v = f * g;
                            }
                            // The tilt and the chirp have modulus 1.
                            *total = input.iter().map(|v| f64::from(v.norm_sqr())).sum();
                        },
                        &mut intensity,
                    );
                }
                PhaseOptics::Toled => czt.intensity_with(
                    czt_work,
                    |j| {
                        let i = start + j;
                        let v = tilted(Complex64::new(self.slits[i] * self.lens_rect[i], 0.0));
                        *total += v.norm_sqr();
                        v
                    },
                    &mut intensity,
                ),
                PhaseOptics::SingleMask => czt.intensity_with(
                    czt_work,
                    |j| {
                        let i = start + j;
                        let h = heights_um.get(i).copied().unwrap_or(0.0);
                        let v = tilted(Complex64::from_polar(
                            self.slits[i] * self.lens_rect[i],
                            -k_n1 * h,
                        ));
                        *total += v.norm_sqr();
                        v
                    },
                    &mut intensity,
                ),
            }
        });
        self.finish(&intensity, 0, total, lambda, incidence)
    }

    /// The sensor PSF from the fine intensities of the chirp-z transform, which start at sensor
    /// pixel `first_pixel` (the pixels outside read zero), and the energy on the main-lens
    /// opening `Σ|U|²` (in samples).
    fn finish(
        &self,
        intensity: &[f64],
        first_pixel: usize,
        total: f64,
        lambda: f64,
        incidence: Incidence,
    ) -> MonoPsf {
        let cam = &self.design.camera;
        let fine = self.sampling.fine_per_pixel;
        let dx = self.dx_um;
        let aperture = cam.aperture_um();
        let total_energy = total * dx / aperture;
        let image_pixel = incidence.image_pixel(&self.design);
        // |E(u)|² = |Σ U dx e^{…}|² / (λf); energy per fine sample multiplies by du.
        let (_, du) = self.sensor_samples(lambda);
        let scale = dx * dx / (lambda * cam.focal_length_um()) * du / aperture;
        let mut sensor = vec![0.0; cam.pixels];
        for (s, c) in sensor[first_pixel..]
            .iter_mut()
            .zip(intensity.chunks_exact(fine))
        {
            *s = c.iter().sum::<f64>() * scale;
        }
        MonoPsf {
            window_energy: sensor.iter().sum(),
            sensor,
            total_energy,
            image_pixel,
        }
    }
}
