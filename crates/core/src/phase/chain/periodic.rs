//! The lenslet-period route ([`Relay::LensletPeriod`]): when every lenslet of the plate is alike,
//! the field on the main-lens opening repeats from lenslet to lenslet up to the direction's
//! tilt, so one period carries all of it.
//!
//! - **Relay.** The input `exp(i k sinθ x)·p(x)` with `p` periodic keeps that form through the
//!   Fresnel steps (Bloch's theorem): the output is `exp(i k sinθ x)·q(x)` with `q` the
//!   periodic convolution of `p` with the kernel's transfer function shifted by the tilt,
//!   `H(ν + sinθ/λ)`, wrapped into the lattice's band as the whole-display grid wraps it. One
//!   lenslet's samples then stand for the whole array; what is lost is the light the array's
//!   two ends diffract, which the whole display keeps.
//! - **Fraunhofer.** A sum over `C` whole periods and `r` samples more is the first period's
//!   transform times the geometric series `Σ_c Z^{cL}` (`Z` the tilt's and the sensor sample's
//!   phase per sample) plus the first `r` samples' transform times `Z^{CL}`: two chirp-z
//!   transforms of one period's length instead of one of the opening's. For the bare T-OLED and
//!   the single mask the opening's field is periodic exactly, so this part changes only roundings.

use super::*;

/// Where the field on the main-lens opening repeats.
#[derive(Debug, Clone, Copy)]
pub(super) struct Period {
    /// Array index of lenslet 0's first sample.
    first: usize,
    /// Samples per lenslet.
    len: usize,
}

impl Chain {
    /// The lenslet period of the opening's field through `optics` with `heights_um`, when the
    /// sampling asks for [`Relay::LensletPeriod`] and it applies: the thesis convention (lenslets
    /// are whole runs of samples), the opening inside the array, and every lenslet's heights
    /// alike (the bare T-OLED has none).
    pub(super) fn period(&self, optics: PhaseOptics, heights_um: &[f64]) -> Option<Period> {
        if self.sampling.relay != Relay::LensletPeriod {
            return None;
        }
        let (first, len, count) = self.cells?;
        let (start, end) = self.lens_range;
        let cells_end = first + len * count;
        if count < 2 || start < first || end > cells_end || end <= start {
            return None;
        }
        let alike = match optics {
            PhaseOptics::Toled => true,
            PhaseOptics::DoubleMla | PhaseOptics::SingleMask => {
                heights_um.len() == self.n
                    && heights_um[first + len..cells_end] == heights_um[first..cells_end - len]
            }
        };
        alike.then_some(Period { first, len })
    }

    /// [`Chain::mono`] by the lenslet-period route over the sensor pixels `pixels` (the rest read
    /// zero); `plate` is the double MLA's transmission when the caller has formed it.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn mono_periodic(
        &self,
        period: Period,
        optics: PhaseOptics,
        heights_um: &[f64],
        plate: Option<&[Complex64]>,
        wavelength_nm: f64,
        incidence: Incidence,
        pixels: Range<usize>,
    ) -> MonoPsf {
        let Period { first, len } = period;
        let lambda = wavelength_nm * 1e-3;
        let k_sin = 2.0 * PI / lambda * incidence.sin_theta(&self.design);
        let k_n1 = self.k_n1(wavelength_nm);
        let cis = |h: f64| Complex64::from_polar(1.0, -k_n1 * h);
        let plate_at = |i: usize| plate.map_or_else(|| cis(heights_um[i]), |p| p[i]);
        // One period of the opening's field, sample r at array index first + r, untilted.
        let cell: Vec<Complex64> = match optics {
            PhaseOptics::DoubleMla => {
                let p: Vec<Complex64> = (first..first + len).map(plate_at).collect();
                let q = self.relay_period(&p, first, lambda, k_sin);
                q.iter().zip(&p).map(|(q, p)| q * p).collect()
            }
            PhaseOptics::Toled => (first..first + len)
                .map(|i| Complex64::new(self.slits[i], 0.0))
                .collect(),
            PhaseOptics::SingleMask => (first..first + len)
                .map(|i| self.slits[i] * cis(heights_um[i]))
                .collect(),
        };
        // The opening's field from its first sample, over one period, tilted (the tilt's constant
        // phase at the opening's start drops out of intensities).
        let (start, end) = self.lens_range;
        let offset = (start - first) % len;
        let field: Vec<Complex64> = self
            .tilt(start, k_sin)
            .zip(0..len)
            .map(|(t, i)| t * cell[(offset + i) % len])
            .collect();
        let periods = (end - start) / len;
        let rest = (end - start) % len;
        let energy = |v: &[Complex64]| v.iter().map(|a| a.norm_sqr()).sum::<f64>();
        let total = periods as f64 * energy(&field) + energy(&field[..rest]);

        let czt = self.czt_for(lambda, len, pixels.clone());
        let (u0, du) = self.sensor_samples(lambda);
        let fine = self.sampling.fine_per_pixel;
        let u0 = u0 + (pixels.start * fine) as f64 * du;
        let beta_dx = 2.0 * PI / (lambda * self.design.camera.focal_length_um()) * self.dx_um;
        let c = periods as f64;
        let mut intensity = vec![0.0; pixels.len() * fine];
        WORK.with(|work| {
            let work = &mut *work.borrow_mut();
            let whole: Vec<Complex32> = czt.partial_with(&mut work.czt, len, |t| field[t]).to_vec();
            let part = czt.partial_with(&mut work.czt, rest, |t| field[t]);
            // Z's phase over one period falls by the same step from sample to sample, so
            // exp(iφ/2) and exp(iCφ/2) advance by a rotation (re-anchored exactly every 64),
            // not an exponential each. Σ_{c<C} e^{icφ} = e^{i(C−1)φ/2}·sin(Cφ/2)/sin(φ/2) holds
            // for every φ, so φ need not be reduced.
            let phi0 = len as f64 * (k_sin * self.dx_um - beta_dx * u0);
            let dphi = len as f64 * beta_dx * du;
            let half0 = Complex64::from_polar(1.0, (0.5 * phi0).rem_euclid(2.0 * PI));
            let c_half0 = Complex64::from_polar(1.0, (0.5 * c * phi0).rem_euclid(2.0 * PI));
            let half = quadratic_phase(0.0, -0.5 * dphi, 0, 1.0).map(|v| v * half0);
            let c_half = quadratic_phase(0.0, -0.5 * c * dphi, 0, 1.0).map(|v| v * c_half0);
            for (((out, (w, r)), a), b) in intensity
                .iter_mut()
                .zip(whole.iter().zip(part))
                .zip(half)
                .zip(c_half)
            {
                // sin(Cφ/2)/sin(φ/2), or its limit ±C where sin(φ/2) vanishes.
                let dirichlet = if a.im.abs() < 1e-9 {
                    c * b.re / a.re
                } else {
                    b.im / a.im
                };
                let series = b * a.conj() * dirichlet;
                let w = Complex64::new(f64::from(w.re), f64::from(w.im));
                let r = Complex64::new(f64::from(r.re), f64::from(r.im));
                *out = (w * series + r * b * b).norm_sqr();
            }
        });
        self.finish(&intensity, pixels.start, total, lambda, incidence)
    }

    /// MLA 1 → Fresnel → display → Fresnel over one lenslet period: `p` is the plate's
    /// transmission on the period's samples (array indices `first …`), the result the field
    /// before MLA 2 on the same samples, without the tilt `exp(i k sinθ x)` that both carry.
    fn relay_period(
        &self,
        p: &[Complex64],
        first: usize,
        wavelength_um: f64,
        k_sin: f64,
    ) -> Vec<Complex64> {
        let len = p.len();
        let forward = udc_fft::complex_plan(len);
        let inverse = udc_fft::complex_inverse_plan(len);
        let z = self.design.f_mla_um;
        let dx = self.dx_um;
        // Bin n holds the frequencies n/(Lδ) + j/δ; with the tilt ν0 = sinθ/λ the light is at
        // n/(Lδ) + ν0, taken in the band [−1/(2δ), 1/(2δ)) as the whole display's grid takes it.
        let nu0_dx = k_sin * dx / (2.0 * PI);
        let norm = 1.0 / len as f64;
        let transfer: Vec<Complex64> = (0..len)
            .map(|n| {
                let x = n as f64 / len as f64 + nu0_dx;
                let x = x - (x + 0.5).floor();
                Complex64::from_polar(norm, -PI * wavelength_um * z * x * x / (dx * dx))
            })
            .collect();
        let mut q = p.to_vec();
        forward.process(&mut q);
        q.iter_mut().zip(&transfer).for_each(|(v, h)| *v *= h);
        inverse.process(&mut q);
        for (v, s) in q.iter_mut().zip(&self.slits[first..first + len]) {
            *v *= *s;
        }
        forward.process(&mut q);
        q.iter_mut().zip(&transfer).for_each(|(v, h)| *v *= h);
        inverse.process(&mut q);
        q
    }
}
