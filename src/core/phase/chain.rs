//! The 1-D propagation chain of PHYSICS.md §7 for one wavelength and one incidence direction.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::{Arc, Mutex};

use rustfft::num_complex::Complex64;

use super::czt::Czt;
use super::geometry::{Lenslets, display_aperture_um};
use super::{PhaseDesign, PhaseSampling, SimError};
use crate::core::fft::{complex_inverse_plan, complex_plan, signed};
use crate::core::sampling::next_fast_size;

/// Largest display-plane grid the chain accepts (2²⁴ samples ≈ 270 MB per complex field).
pub const MAX_GRID_SAMPLES: usize = 1 << 24;

/// Which optics sit at the display.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Optics {
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
    /// The direction imaged on sensor pixel `j` (relative to the axis pixel): sinθ = j·pixel/f.
    Pixel(i64),
    /// An angle in degrees from the axis.
    AngleDeg(f64),
}

impl Incidence {
    pub fn sin_theta(self, d: &PhaseDesign) -> f64 {
        match self {
            Incidence::Pixel(j) => d.camera.sin_theta_of_pixel(j as f64),
            Incidence::AngleDeg(a) => a.to_radians().sin(),
        }
    }

    /// The sensor pixel (relative to the axis pixel) nearest `f·sinθ`, where a plain lens (and the
    /// bare T-OLED) images this direction. The double MLA sends it near the opposite pixel: each
    /// lenslet pair is a 1:1 Keplerian telescope, which inverts the beam's angle.
    pub fn image_pixel(self, d: &PhaseDesign) -> i64 {
        match self {
            Incidence::Pixel(j) => j,
            Incidence::AngleDeg(_) => {
                (self.sin_theta(d) * d.camera.focal_length_um() / d.camera.pixel_um).round() as i64
            }
        }
    }
}

/// One wavelength's sensor PSF.
#[derive(Debug, Clone, PartialEq)]
pub struct MonoPsf {
    /// Energy per sensor pixel (fractions of the light on the main-lens opening). The window is
    /// the whole sensor: entry `k` is sensor pixel `k`, the axis at `pixels/2`, for every direction.
    pub sensor: Vec<f64>,
    /// Σ `sensor`.
    pub window_energy: f64,
    /// All the light that leaves the main-lens opening (Parseval), inside the window or not.
    pub total_energy: f64,
    /// Where a plain lens would image the direction ([`Incidence::image_pixel`]).
    pub image_pixel: i64,
}

/// The sampled geometry of one design, shared by every wavelength and direction.
pub struct Chain {
    design: PhaseDesign,
    sampling: PhaseSampling,
    lenslets: Lenslets,
    n: usize,
    dx_um: f64,
    display_rect: Vec<f64>,
    slits: Vec<f64>,
    lens_rect: Vec<f64>,
    /// Samples `[start, end)` inside the main-lens opening: the Fraunhofer transform's input.
    lens_range: (usize, usize),
    heights_um: Vec<f64>,
    transfer: Mutex<HashMap<u64, Arc<Vec<Complex64>>>>,
    czt: Mutex<HashMap<u64, Arc<Czt>>>,
}

thread_local! {
    /// FFT scratch per worker thread: a fresh multi-megabyte buffer per call costs page faults.
    static SCRATCH: std::cell::RefCell<Vec<Complex64>> = const { std::cell::RefCell::new(Vec::new()) };
    /// The chirp-z transform's padded working array, per worker thread.
    static CZT_WORK: std::cell::RefCell<Vec<Complex64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Runs `f` with this thread's scratch buffer of at least `len` elements.
pub(crate) fn with_scratch<T>(len: usize, f: impl FnOnce(&mut [Complex64]) -> T) -> T {
    SCRATCH.with(|cell| {
        let mut buf = cell.borrow_mut();
        if buf.len() < len {
            buf.resize(len, Complex64::new(0.0, 0.0));
        }
        f(&mut buf[..len])
    })
}

/// Fraction of the sample `[x − dx/2, x + dx/2]` inside `[lo, hi]` (anti-aliased edges).
fn coverage(x: f64, dx: f64, lo: f64, hi: f64) -> f64 {
    ((x + dx / 2.0).min(hi) - (x - dx / 2.0).max(lo)).clamp(0.0, dx) / dx
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
        // A margin of two pitches keeps the periodic FFT's wrap-around off the lit region.
        let span = lenslets.span_um().max(aperture) + 4.0 * design.pitch_um.max(25.0);
        let raw = (span / dx).ceil();
        if !(raw < MAX_GRID_SAMPLES as f64) {
            return Err(SimError::TooLarge(format!(
                "the display plane needs {raw:.0} samples of {dx} µm; the limit is {MAX_GRID_SAMPLES} \
                 (use a coarser display sample or a smaller camera)"
            )));
        }
        let n = next_fast_size(raw as usize);
        let x = |i: usize| (i as f64 - (n / 2) as f64) * dx;
        let half_display = aperture / 2.0;
        let half_lens = design.camera.aperture_um() / 2.0;
        let slit = design.open_ratio * design.pitch_um;
        let c0 = lenslets.centre_um(0);
        let display_rect = (0..n)
            .map(|i| coverage(x(i), dx, -half_display, half_display))
            .collect();
        let lens_rect: Vec<f64> = (0..n)
            .map(|i| coverage(x(i), dx, -half_lens, half_lens))
            .collect();
        let slits = (0..n)
            .map(|i| {
                let local = (x(i) - c0 + design.pitch_um / 2.0).rem_euclid(design.pitch_um)
                    - design.pitch_um / 2.0;
                coverage(local, dx, -slit / 2.0, slit / 2.0)
            })
            .collect();
        let start = lens_rect.iter().position(|&v| v > 0.0).unwrap_or(0);
        let end = lens_rect
            .iter()
            .rposition(|&v| v > 0.0)
            .map_or(start, |e| e + 1);
        let heights_um = (0..n).map(|i| lenslets.height_at(design, x(i))).collect();
        Ok(Chain {
            design: design.clone(),
            sampling: sampling.clone(),
            lenslets,
            n,
            dx_um: dx,
            display_rect,
            slits,
            lens_rect,
            lens_range: (start, end),
            heights_um,
            transfer: Mutex::new(HashMap::new()),
            czt: Mutex::new(HashMap::new()),
        })
    }

    pub fn design(&self) -> &PhaseDesign {
        &self.design
    }

    pub fn lenslets(&self) -> &Lenslets {
        &self.lenslets
    }

    /// Display-plane samples.
    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Position of display-plane sample `i`, in µm.
    pub fn x_um(&self, i: usize) -> f64 {
        (i as f64 - (self.n / 2) as f64) * self.dx_um
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
            && other.camera == self.design.camera;
        if !same_geometry {
            return Err(SimError::Sampling(
                "heights_for needs the same pitch, focal length and camera".into(),
            ));
        }
        let lenslets = Lenslets::new(other)?;
        Ok((0..self.n)
            .map(|i| lenslets.height_at(other, self.x_um(i)))
            .collect())
    }

    fn transfer(&self, wavelength_um: f64) -> Arc<Vec<Complex64>> {
        let key = wavelength_um.to_bits();
        let mut cache = self.transfer.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(h) = cache.get(&key) {
            return h.clone();
        }
        let z = self.design.f_mla_um;
        let span = self.n as f64 * self.dx_um;
        // H(fx) = exp(−iπ λ z fx²): the paraxial transfer function (the constant exp(ikz) drops).
        let h: Vec<Complex64> = (0..self.n)
            .map(|k| {
                let fx = signed(k, self.n) as f64 / span;
                Complex64::from_polar(
                    1.0,
                    (-PI * wavelength_um * z * fx * fx).rem_euclid(2.0 * PI),
                )
            })
            .collect();
        let h = Arc::new(h);
        if cache.len() > 64 {
            cache.clear();
        }
        cache.insert(key, h.clone());
        h
    }

    /// The transform onto the sensor window (the whole sensor) for one wavelength, cached: every
    /// direction and every λ0 at that wavelength shares it.
    fn czt_for(&self, wavelength_um: f64) -> Arc<Czt> {
        let key = wavelength_um.to_bits();
        if let Some(c) = self.czt.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
            return c.clone();
        }
        let cam = &self.design.camera;
        let fine = self.sampling.fine_per_pixel;
        let du = cam.pixel_um / fine as f64;
        let u0 = (-((cam.pixels / 2) as f64) - 0.5) * cam.pixel_um + 0.5 * du;
        let (start, end) = self.lens_range;
        let czt = Arc::new(Czt::new(
            end - start,
            cam.pixels * fine,
            self.dx_um,
            u0,
            du,
            wavelength_um * cam.focal_length_um(),
        ));
        let mut cache = self.czt.lock().unwrap_or_else(|e| e.into_inner());
        if cache.len() > 64 {
            cache.clear();
        }
        cache.insert(key, czt.clone());
        czt
    }

    fn propagate(&self, field: &mut [Complex64], wavelength_um: f64) {
        let h = self.transfer(wavelength_um);
        let forward = complex_plan(self.n);
        let inverse = complex_inverse_plan(self.n);
        with_scratch(
            forward
                .get_inplace_scratch_len()
                .max(inverse.get_inplace_scratch_len()),
            |scratch| {
                forward.process_with_scratch(field, scratch);
                let norm = 1.0 / self.n as f64;
                for (f, t) in field.iter_mut().zip(h.iter()) {
                    *f *= t * norm;
                }
                inverse.process_with_scratch(field, scratch);
            },
        );
    }

    /// The sensor PSF of one wavelength and direction through `optics`, with the plate `heights_um`
    /// (from [`Chain::heights_um`] or [`Chain::heights_for`]; ignored for the bare T-OLED).
    pub fn mono(
        &self,
        optics: Optics,
        heights_um: &[f64],
        wavelength_nm: f64,
        incidence: Incidence,
    ) -> MonoPsf {
        let lambda = wavelength_nm * 1e-3;
        let k = 2.0 * PI / lambda;
        let sin_t = incidence.sin_theta(&self.design);
        let n_minus_1 = self.design.refractive_index - 1.0;
        // One cis per sample and mask: the plate's transmission is shared by MLA 1 and MLA 2, and
        // the tilt is skipped on axis (these exponentials cost as much as the FFTs).
        let plate = |range: std::ops::Range<usize>| -> Vec<Complex64> {
            range
                .map(|i| {
                    let h = heights_um.get(i).copied().unwrap_or(0.0);
                    Complex64::from_polar(1.0, -k * n_minus_1 * h)
                })
                .collect()
        };
        let tilt = |i: usize| Complex64::from_polar(1.0, k * sin_t * self.x_um(i));
        let tilted = sin_t != 0.0;
        let (start, end) = self.lens_range;
        let mut lens_field: Vec<Complex64> = match optics {
            Optics::Toled => (start..end)
                .map(|i| Complex64::new(self.slits[i] * self.lens_rect[i], 0.0))
                .collect(),
            Optics::SingleMask => plate(start..end)
                .into_iter()
                .zip(start..end)
                .map(|(p, i)| p * (self.slits[i] * self.lens_rect[i]))
                .collect(),
            Optics::DoubleMla => {
                let plate = plate(0..self.n);
                let mut field: Vec<Complex64> = plate
                    .iter()
                    .zip(&self.display_rect)
                    .map(|(p, r)| p * *r)
                    .collect();
                if tilted {
                    for (i, f) in field.iter_mut().enumerate() {
                        if self.display_rect[i] != 0.0 {
                            *f *= tilt(i);
                        }
                    }
                }
                self.propagate(&mut field, lambda);
                for (f, s) in field.iter_mut().zip(&self.slits) {
                    *f *= *s;
                }
                self.propagate(&mut field, lambda);
                (start..end)
                    .map(|i| field[i] * plate[i] * self.lens_rect[i])
                    .collect()
            }
        };
        if tilted && optics != Optics::DoubleMla {
            for (f, i) in lens_field.iter_mut().zip(start..end) {
                *f *= tilt(i);
            }
        }
        let dx = self.dx_um;
        let aperture = self.design.camera.aperture_um();
        let total_energy = lens_field.iter().map(|v| v.norm_sqr()).sum::<f64>() * dx / aperture;

        let image_pixel = incidence.image_pixel(&self.design);
        // The window is the sensor, not the image point: the double MLA moves light to the
        // opposite side of the axis, which a window that followed f·sinθ would cut off.
        let czt = self.czt_for(lambda);
        let cam = &self.design.camera;
        let fine = self.sampling.fine_per_pixel;
        let mut intensity = vec![0.0; cam.pixels * fine];
        CZT_WORK.with(|w| czt.intensity(&lens_field, &mut w.borrow_mut(), &mut intensity));
        // |E(u)|² = |Σ U dx e^{…}|² / (λf); energy per fine sample multiplies by du.
        let du = cam.pixel_um / fine as f64;
        let scale = dx * dx / (lambda * cam.focal_length_um()) * du / aperture;
        let sensor: Vec<f64> = intensity
            .chunks_exact(fine)
            .map(|c| c.iter().sum::<f64>() * scale)
            .collect();
        MonoPsf {
            window_energy: sensor.iter().sum(),
            sensor,
            total_energy,
            image_pixel,
        }
    }
}
