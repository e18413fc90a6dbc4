//! The seam of the phase model's slowest step: the double MLA's relay on the wrapped grid (a
//! λ0 plan, or any plate under [`Relay::WrappedDisplay`]) and its Fraunhofer transform, for a
//! batch of directions at one wavelength. Per direction it is two Fresnel steps on the wrapped
//! grid (three FFTs of the grid's length) and a chirp-z transform onto the fine sensor samples.
//!
//! The chain forms everything a direction needs on the CPU in `f64` and rounds it once: the
//! wavelength's tables ([`BlochWavelength`]) and each direction's two ramps ([`BlochDirection`]:
//! the Bloch shift of the transfer function and the tilt). An implementation of
//! [`BlochRelay`] runs the FFTs and products: [`CpuBloch`] here (the reference, `f32` FFTs as
//! before the seam), a device outside the core. Nothing above the chain knows which ran.

use super::*;

use rustfft::Fft;

use crate::psf::chirp_z::ChirpZ;

/// Samples of a single-precision ramp per exactly computed anchor: its table of steps keeps
/// the rounding at a few 1e-7 and each sample one product.
pub const RAMP_BLOCK: usize = 256;

/// `exp(i·phase)` in single precision, the phase reduced mod 2π in double first.
pub(super) fn cis32(phase: f64) -> Complex32 {
    let v = Complex64::from_polar(1.0, phase.rem_euclid(2.0 * PI));
    Complex32::new(v.re as f32, v.im as f32)
}

/// `exp(i·k·phase_per_sample)` for `k < RAMP_BLOCK`: a ramp's steps from its block's anchor.
pub(super) fn ramp_steps(phase_per_sample: f64) -> Vec<Complex32> {
    (0..RAMP_BLOCK)
        .map(|k| cis32(phase_per_sample * k as f64))
        .collect()
}

/// A phase ramp in single precision: sample `n` is `anchors[n / RAMP_BLOCK] ·
/// steps[n % RAMP_BLOCK]`, each anchor computed exactly in `f64`, except samples `exact_from ..
/// exact_from + exact.len()`, which are given whole (see [`BlochDirection::shift`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Ramp {
    /// One per block of [`RAMP_BLOCK`] samples.
    pub anchors: Vec<Complex32>,
    /// [`RAMP_BLOCK`] steps from a block's anchor.
    pub steps: Vec<Complex32>,
    /// The first sample given exactly.
    pub exact_from: usize,
    /// The samples given exactly.
    pub exact: Vec<Complex32>,
}

/// One direction of a wavelength's batch.
#[derive(Debug, Clone, PartialEq)]
pub struct BlochDirection {
    /// The transfer function shifted by the tilt, on the grid's `len` bins: bin `n` is
    /// `untilted[n] · shift(n)`, but for the bins in `shift.exact`, which are the whole shifted
    /// transfer function (the bins the tilt moves across the wrap).
    pub shift: Ramp,
    /// The tilt `exp(i k sinθ x)` on the opening's samples.
    pub tilt: Ramp,
}

/// One wavelength's tables, shared by its directions (all `f32`, rounded once from `f64`).
pub struct BlochWavelength<'a> {
    /// The plate's spectrum on the wrapped grid (`len` bins).
    pub spectrum: &'a [Complex32],
    /// The untilted transfer function over `len` (the inverse FFT's `1/len` folded in).
    pub untilted: &'a [Complex32],
    /// The display's slits on the grid's first samples; the grid is open beyond them.
    pub slits: &'a [f64],
    /// MLA 2, the main lens's opening and the chirp-z input chirp, on the opening's samples.
    pub opening: &'a [Complex32],
    /// The grid sample of the opening's first.
    pub start: usize,
    /// The chirp-z convolution onto the fine sensor samples.
    pub czt: &'a ChirpZ<f32>,
}

/// One direction's result.
#[derive(Debug, Clone, PartialEq)]
pub struct BlochIntensity {
    /// `|·|²` of the chirp-z transform on every fine sensor sample.
    pub fine: Vec<f64>,
    /// `Σ|U|²` over the opening's samples (the light leaving the main-lens opening, in samples).
    pub total: f64,
}

/// The Bloch relay and Fraunhofer transform of a batch of directions at one wavelength. An
/// implementation must give [`CpuBloch`]'s numbers to its own precision and check `progress`
/// for cancellation.
pub trait BlochRelay: Send + Sync {
    /// The `count` directions `direction(0) … direction(count − 1)` through `wavelength`'s
    /// tables, in that order. `direction` forms one on the CPU; call it for a few at a time
    /// (each holds a few grid-lengths of ramps).
    ///
    /// # Errors
    /// [`SimError::Cancelled`]; an implementation's own refusals (memory, a lost device).
    fn directions(
        &self,
        wavelength: &BlochWavelength<'_>,
        count: usize,
        direction: &(dyn Fn(usize) -> BlochDirection + Sync),
        progress: &Progress,
    ) -> Result<Vec<BlochIntensity>, SimError>;
}

/// The CPU's Bloch relay: `f32` FFTs by rustfft, directions in parallel.
#[derive(Debug, Clone, Copy, Default)]
pub struct CpuBloch;

impl BlochRelay for CpuBloch {
    fn directions(
        &self,
        wavelength: &BlochWavelength<'_>,
        count: usize,
        direction: &(dyn Fn(usize) -> BlochDirection + Sync),
        progress: &Progress,
    ) -> Result<Vec<BlochIntensity>, SimError> {
        let finished = AtomicUsize::new(0);
        (0..count)
            .into_par_iter()
            .map(|i| {
                progress.check()?;
                let d = direction(i);
                let mut fine = vec![0.0; wavelength.czt.n_out()];
                let total = WORK
                    .with(|cell| CpuBloch::one(wavelength, &d, &mut cell.borrow_mut(), &mut fine));
                let n = finished.fetch_add(1, Ordering::Relaxed) + 1;
                progress.set(n as f32 / count as f32);
                Ok(BlochIntensity { fine, total })
            })
            .collect()
    }
}

impl CpuBloch {
    /// One direction in the thread's buffers: the fine intensities in `fine`, `Σ|U|²` returned.
    pub(super) fn one(
        w: &BlochWavelength<'_>,
        d: &BlochDirection,
        work: &mut Work,
        fine: &mut [f64],
    ) -> f64 {
        let Work {
            transfer,
            field,
            scratch,
            czt,
            ..
        } = work;
        let len = w.spectrum.len();
        let (forward, inverse) = plans_f32(len, scratch);
        let zero = Complex32::new(0.0, 0.0);
        transfer.resize(len, zero);
        field.resize(len, zero);
        for (b, ((out, f), (h, p))) in transfer
            .chunks_mut(RAMP_BLOCK)
            .zip(field.chunks_mut(RAMP_BLOCK))
            .zip(
                w.untilted
                    .chunks(RAMP_BLOCK)
                    .zip(w.spectrum.chunks(RAMP_BLOCK)),
            )
            .enumerate()
        {
            let anchor = d.shift.anchors[b];
            for (((t, f), h), (p, step)) in out
                .iter_mut()
                .zip(f)
                .zip(h)
                .zip(p.iter().zip(&d.shift.steps))
            {
                *t = h * (anchor * step);
                *f = p * *t;
            }
        }
        for (i, v) in d.shift.exact.iter().enumerate() {
            let n = d.shift.exact_from + i;
            transfer[n] = *v;
            field[n] = w.spectrum[n] * *v;
        }
        inverse.process_with_scratch(field, scratch);
        slits_then_fresnel(field, w.slits, transfer, (&forward, &inverse), scratch);
        let field = &field[w.start..w.start + w.opening.len()];
        let mut total = 0.0;
        for (o, s) in fine.iter_mut().zip(w.czt.convolve_filled(
            w.opening.len(),
            |input| {
                tilted_product(input, field, w.opening, &d.tilt);
                // The tilt and the chirp have modulus 1.
                total = input.iter().map(|v| f64::from(v.norm_sqr())).sum();
            },
            czt,
        )) {
            *o = f64::from(s.norm_sqr());
        }
        total
    }
}

/// `out[n] = field[n] · opening[n] · tilt(n)`: two single-precision products a sample, which
/// the compiler can vectorise.
fn tilted_product(out: &mut [Complex32], field: &[Complex32], opening: &[Complex32], tilt: &Ramp) {
    for (b, ((out, field), opening)) in out
        .chunks_mut(RAMP_BLOCK)
        .zip(field.chunks(RAMP_BLOCK))
        .zip(opening.chunks(RAMP_BLOCK))
        .enumerate()
    {
        let anchor = tilt.anchors[b];
        for (((v, f), g), s) in out.iter_mut().zip(field).zip(opening).zip(&tilt.steps) {
            *v = f * g * (anchor * s);
        }
    }
}

/// The display's slits on the field at the display, then the Fresnel step to MLA 2 with
/// `transfer`: how both relays end.
pub(super) fn slits_then_fresnel(
    field: &mut [Complex32],
    slits: &[f64],
    transfer: &[Complex32],
    (forward, inverse): (&Arc<dyn Fft<f32>>, &Arc<dyn Fft<f32>>),
    scratch: &mut [Complex32],
) {
    // Beyond the chain's samples the display is open (ones), so only these change.
    for (f, s) in field.iter_mut().zip(slits) {
        *f *= *s as f32;
    }
    forward.process_with_scratch(field, scratch);
    for (f, t) in field.iter_mut().zip(transfer) {
        *f *= t;
    }
    inverse.process_with_scratch(field, scratch);
}

/// Forward and inverse single-precision plans of `len` points, with `scratch` grown for both.
pub(super) fn plans_f32(
    len: usize,
    scratch: &mut Vec<Complex32>,
) -> (Arc<dyn Fft<f32>>, Arc<dyn Fft<f32>>) {
    let forward = complex_plan_f32(len, false);
    let inverse = complex_plan_f32(len, true);
    let scratch_len = forward
        .get_inplace_scratch_len()
        .max(inverse.get_inplace_scratch_len());
    scratch.resize(scratch_len, Complex32::new(0.0, 0.0));
    (forward, inverse)
}

impl Chain {
    /// Whether the double MLA goes through the Bloch relay for this plate: the wrapped grid,
    /// and no lenslet period to take instead.
    pub(super) fn bloch(&self, optics: PhaseOptics, heights_um: &[f64]) -> bool {
        optics == PhaseOptics::DoubleMla
            && self.wraps()
            && self.period(optics, heights_um).is_none()
    }

    /// The direction `k_sin` (`k sinθ`, per µm) of the relay on the `len`-bin wrapped grid:
    /// the transfer function's Bloch shift and the tilt on the opening.
    pub(super) fn bloch_direction(
        &self,
        len: usize,
        wavelength_um: f64,
        k_sin: f64,
    ) -> BlochDirection {
        // Bin n holds ν δ = n/len + s (s = ν0 δ), taken in [−1/2, 1/2): the phase
        // −πλz ν² = a2 (m + s·len)² with m = n below the wrap and n − len above it; its
        // constant part a2 (s·len)² is common to every sample and drops out. The rest is the
        // untilted transfer function (cached, wrapped at len/2) times the ramp exp(i a1 m),
        // but for the bins between len/2 and the tilted wrap, which are taken exactly.
        let dx = self.dx_um;
        let s = k_sin * dx / (2.0 * PI);
        let lf = len as f64;
        let a2 = -PI * wavelength_um * self.design.f_mla_um / (dx * dx * lf * lf);
        let a1 = 2.0 * a2 * s * lf;
        let half = len / 2;
        let split = (((0.5 - s) * lf).ceil().max(0.0) as usize).min(len);
        let cis = |phase: f64| Complex64::from_polar(1.0, phase.rem_euclid(2.0 * PI));
        let to32 = |v: Complex64| Complex32::new(v.re as f32, v.im as f32);
        // exp(i a1 (n − len)) = exp(i a1 n)·exp(−i a1 len) above len/2.
        let above = cis(-a1 * lf);
        let anchors = (0..len.div_ceil(RAMP_BLOCK))
            .map(|b| {
                let n0 = b * RAMP_BLOCK;
                let anchor = cis(a1 * n0 as f64);
                to32(if n0 >= half { anchor * above } else { anchor })
            })
            .collect();
        // A block that straddles len/2 took the lower ramp throughout: its upper part, and the
        // bins the tilt moves across the wrap, are formed exactly.
        let from = (half / RAMP_BLOCK * RAMP_BLOCK).min(split);
        let to = (half + RAMP_BLOCK).max(split).min(len);
        let exact = (from..to)
            .map(|n| {
                let m = if n < split { n as f64 } else { n as f64 - lf };
                to32(cis(a2 * m * m + a1 * m) / lf)
            })
            .collect();
        let (start, end) = self.lens_range;
        BlochDirection {
            shift: Ramp {
                anchors,
                steps: ramp_steps(a1),
                exact_from: from,
                exact,
            },
            tilt: Ramp {
                anchors: (0..(end - start).div_ceil(RAMP_BLOCK))
                    .map(|b| cis32(k_sin * self.x_um(start + b * RAMP_BLOCK)))
                    .collect(),
                steps: ramp_steps(k_sin * dx),
                exact_from: 0,
                exact: Vec::new(),
            },
        }
    }
}
