//! The chain's optics at one wavelength: Fresnel transfer functions, the relay through the two
//! lenslet arrays and the display, the plate's transmission, tilts and the chirp-z window
//! (cached per wavelength).

use super::*;

use rustfft::Fft;

/// Samples of a single-precision phase ramp per exactly computed anchor: its table of steps
/// ([`ramp_steps`]) keeps the rounding at a few 1e-7 and each sample one product.
const RAMP_BLOCK: usize = 256;

/// `exp(i·phase)` in single precision, the phase reduced mod 2π in double first.
fn cis32(phase: f64) -> Complex32 {
    let v = Complex64::from_polar(1.0, phase.rem_euclid(2.0 * PI));
    Complex32::new(v.re as f32, v.im as f32)
}

/// `exp(i·k·phase_per_sample)` for `k < RAMP_BLOCK`: a ramp's steps from its block's anchor.
fn ramp_steps(phase_per_sample: f64) -> Vec<Complex32> {
    (0..RAMP_BLOCK)
        .map(|k| cis32(phase_per_sample * k as f64))
        .collect()
}

/// Forward and inverse single-precision plans of `len` points, with `scratch` grown for both.
fn plans_f32(len: usize, scratch: &mut Vec<Complex32>) -> (Arc<dyn Fft<f32>>, Arc<dyn Fft<f32>>) {
    let forward = complex_plan_f32(len, false);
    let inverse = complex_plan_f32(len, true);
    let scratch_len = forward
        .get_inplace_scratch_len()
        .max(inverse.get_inplace_scratch_len());
    scratch.resize(scratch_len, Complex32::new(0.0, 0.0));
    (forward, inverse)
}

impl Chain {
    /// Samples of the Fresnel grid at this wavelength. The thesis convention pads the chain by
    /// the paraxial kernel's full reach `λz/δ` (its largest lateral shift `λ z f_max` on both
    /// sides, f_max = 1/(2δ)), so the periodic transform is a linear convolution where it
    /// matters; [`Relay::WrappedDisplay`] (and a λ0 plan under [`Relay::LensletPeriod`]) drops
    /// that padding and lets the chain's samples wrap; the centred convention keeps its
    /// two-pitch margins.
    pub(super) fn fresnel_len(&self, wavelength_um: f64) -> usize {
        match self.design.sampling {
            SamplingConvention::Centred => self.n,
            SamplingConvention::Thesis if self.wraps() => next_fast_size_235(self.n),
            SamplingConvention::Thesis => {
                let reach = wavelength_um * self.design.f_mla_um / (self.dx_um * self.dx_um);
                let raw = (self.n as f64 + reach).ceil().min(MAX_GRID_SAMPLES as f64);
                next_fast_size_235(raw as usize)
            }
        }
    }

    /// Whether the double MLA's relay runs on the wrapped grid ([`Relay::WrappedDisplay`], and
    /// a λ0 plan under [`Relay::LensletPeriod`]): the thesis convention only.
    pub(super) fn wraps(&self) -> bool {
        self.design.sampling == SamplingConvention::Thesis
            && matches!(
                self.sampling.relay,
                Relay::WrappedDisplay | Relay::LensletPeriod
            )
    }

    /// The FFT of `plate · display_rect` on the wrapped grid at this wavelength (zeros beyond
    /// the chain's samples), in `out`: the input spectrum of every direction's Bloch relay.
    pub(super) fn plate_spectrum(
        &self,
        plate: &[Complex64],
        wavelength_um: f64,
        out: &mut Vec<Complex32>,
    ) {
        let len = self.fresnel_len(wavelength_um);
        let forward = complex_plan_f32(len, false);
        out.clear();
        out.extend(
            plate
                .iter()
                .zip(&self.display_rect)
                .map(|(p, r)| Complex32::new((p.re * r) as f32, (p.im * r) as f32)),
        );
        out.resize(len, Complex32::new(0.0, 0.0));
        forward.process(out);
    }

    pub(super) fn transfer(&self, wavelength_um: f64) -> Arc<Vec<Complex32>> {
        let key = wavelength_um.to_bits();
        let mut cache = self.transfer.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(h) = cache.get(&key) {
            return h.clone();
        }
        let len = self.fresnel_len(wavelength_um);
        let z = self.design.f_mla_um;
        let span = len as f64 * self.dx_um;
        // H(fx) = exp(−iπ λ z fx²): the paraxial transfer function (the constant exp(ikz) drops),
        // fx = k/span for k < len/2 and (k − len)/span above. The FFT's 1/len is folded in.
        let a2 = -PI * wavelength_um * z / (span * span);
        let norm = 1.0 / len as f64;
        let half = len / 2;
        let to32 = |v: Complex64| Complex32::new(v.re as f32, v.im as f32);
        let h: Vec<Complex32> = quadratic_phase(a2, 0.0, 0, norm)
            .take(half)
            .chain(quadratic_phase(a2, 0.0, -(half as i64), norm).take(len - half))
            .map(to32)
            .collect();
        let h = Arc::new(h);
        if cache.len() > 64 {
            cache.clear();
        }
        cache.insert(key, h.clone());
        h
    }

    /// The transform onto the sensor pixels `pixels` for one wavelength, cached: every direction
    /// and every λ0 at that wavelength shares it. `n_in` is the number of input samples from the
    /// opening's first: all of them, or one lenslet period.
    pub(super) fn czt_for(
        &self,
        wavelength_um: f64,
        n_in: usize,
        pixels: Range<usize>,
    ) -> Arc<Czt> {
        let key = (wavelength_um.to_bits(), n_in, pixels.start, pixels.end);
        if let Some(c) = self.czt.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
            return c.clone();
        }
        let cam = &self.design.camera;
        let fine = self.sampling.fine_per_pixel;
        let (u0, du) = self.sensor_samples(wavelength_um);
        let czt = Arc::new(Czt::new(
            n_in,
            pixels.len() * fine,
            self.dx_um,
            u0 + (pixels.start * fine) as f64 * du,
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

    /// The Fraunhofer transform of the whole opening onto the whole sensor at this wavelength.
    pub(super) fn whole_sensor_czt(&self, wavelength_um: f64) -> Arc<Czt> {
        let (start, end) = self.lens_range;
        self.czt_for(wavelength_um, end - start, 0..self.design.camera.pixels)
    }

    /// The double MLA's opening factors that every direction shares: MLA 2's transmission
    /// `plate`, the main lens's opening and `czt`'s input chirp, on the opening's samples, in
    /// `out` (single precision, as the transform takes them).
    pub(super) fn opening(&self, plate: &[Complex64], czt: &Czt, out: &mut Vec<Complex32>) {
        let (start, end) = self.lens_range;
        out.clear();
        out.extend(
            plate[start..end]
                .iter()
                .zip(&self.lens_rect[start..end])
                .zip(czt.input_chirp())
                .map(|((p, r), c)| {
                    let v = p * *r * c;
                    Complex32::new(v.re as f32, v.im as f32)
                }),
        );
    }

    /// `out[n] = field[n] · opening[n] · exp(i k sinθ x)` at samples `from + n`: the tilt from
    /// one exact exponential per block of 256 times a table of the block's steps, so each
    /// sample costs two single-precision products that the compiler can vectorise.
    pub(super) fn tilted_product(
        &self,
        out: &mut [Complex32],
        field: &[Complex32],
        opening: &[Complex32],
        from: usize,
        k_sin: f64,
    ) {
        let steps = ramp_steps(k_sin * self.dx_um);
        for (b, ((out, field), opening)) in out
            .chunks_mut(RAMP_BLOCK)
            .zip(field.chunks(RAMP_BLOCK))
            .zip(opening.chunks(RAMP_BLOCK))
            .enumerate()
        {
            let anchor = cis32(k_sin * self.x_um(from + b * RAMP_BLOCK));
            for (((v, f), g), s) in out.iter_mut().zip(field).zip(opening).zip(&steps) {
                *v = f * g * (anchor * s);
            }
        }
    }

    /// The first fine sensor sample and the spacing, in µm from the axis, at this wavelength.
    ///
    /// Thesis: the `M`-point FFT's own bins, `u = k·λf/(Mδ)` with `M = 2⌊λf/(2δ δ3)⌋`, indices
    /// `k ∈ [−P·fine/2, P·fine/2)`: pixel `P/2` starts on the axis. Centred: midpoints of
    /// `fine` equal parts of each `pixel_um` pixel, the axis at the centre of pixel `P/2`.
    pub(super) fn sensor_samples(&self, wavelength_um: f64) -> (f64, f64) {
        let cam = &self.design.camera;
        let fine = self.sampling.fine_per_pixel;
        let half = (cam.pixels / 2 * fine) as f64;
        match self.design.sampling {
            SamplingConvention::Thesis => {
                let target = effective_pixel_um(&self.design) / fine as f64;
                let lambda_f = wavelength_um * cam.focal_length_um();
                let m = 2.0 * (lambda_f / (2.0 * self.dx_um * target)).floor();
                let du = lambda_f / (m * self.dx_um);
                (-half * du, du)
            }
            SamplingConvention::Centred => {
                let du = cam.pixel_um / fine as f64;
                (
                    (-((cam.pixels / 2) as f64) - 0.5) * cam.pixel_um + 0.5 * du,
                    du,
                )
            }
        }
    }

    /// The plate's transmission `exp(−i k (n−1) h)` on the chain's samples. Under the thesis
    /// convention lenslets are whole runs of samples, and a lenslet whose heights equal its left
    /// neighbour's (every lenslet of a fixed-λ0 plate; runs of equal λ0 in ascending plans)
    /// reuses its transmission: the exponentials cost as much as the FFTs otherwise.
    pub(super) fn transmission(&self, heights_um: &[f64], k_n1: f64, out: &mut Vec<Complex64>) {
        let one = Complex64::new(1.0, 0.0);
        let cis = |h: f64| {
            if h == 0.0 {
                one
            } else {
                Complex64::from_polar(1.0, -k_n1 * h)
            }
        };
        out.clear();
        let h = |i: usize| heights_um.get(i).copied().unwrap_or(0.0);
        match self.cells {
            Some((first, pattern, count)) if heights_um.len() == self.n => {
                out.extend((0..first).map(|i| cis(h(i))));
                for l in 0..count {
                    let a = first + l * pattern;
                    if l > 0 && heights_um[a..a + pattern] == heights_um[a - pattern..a] {
                        out.extend_from_within(a - pattern..a);
                    } else {
                        out.extend(heights_um[a..a + pattern].iter().map(|&v| cis(v)));
                    }
                }
                let done = out.len();
                out.extend((done..self.n).map(|i| cis(h(i))));
            }
            _ => out.extend((0..self.n).map(|i| cis(h(i)))),
        }
    }

    /// The tilt `exp(i k sinθ x)` at samples `from, from + 1, …`. The phase advances by a
    /// constant per sample, so one exact exponential per block of 256 anchors a running product
    /// (its rounding stays ~1e-14) instead of an exponential per sample.
    pub(super) fn tilt(&self, from: usize, k_sin: f64) -> impl Iterator<Item = Complex64> + '_ {
        const BLOCK: usize = 256;
        let step = Complex64::from_polar(1.0, (k_sin * self.dx_um).rem_euclid(2.0 * PI));
        let mut t = Complex64::new(0.0, 0.0);
        (from..).map(move |i| {
            if (i - from).is_multiple_of(BLOCK) {
                t = Complex64::from_polar(1.0, (k_sin * self.x_um(i)).rem_euclid(2.0 * PI));
            } else {
                t *= step;
            }
            t
        })
    }

    /// [`Chain::relay`] on the wrapped grid as a Bloch problem: the field is `exp(i k sinθ x)`
    /// times a function with the grid's period, whose Fresnel steps multiply its spectrum by
    /// the transfer function at `ν + sinθ/λ` (wrapped into the band, as
    /// [`Chain::relay_period`] does for one lenslet). `spectrum` is the plate's
    /// ([`Chain::plate_spectrum`]); the result in `field` lacks the tilt.
    pub(super) fn relay_bloch(
        &self,
        spectrum: &[Complex32],
        transfer: &mut Vec<Complex32>,
        field: &mut Vec<Complex32>,
        scratch: &mut Vec<Complex32>,
        wavelength_um: f64,
        k_sin: f64,
    ) {
        let len = spectrum.len();
        let (forward, inverse) = plans_f32(len, scratch);
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
        let untilted = self.transfer(wavelength_um);
        let cis = |phase: f64| Complex64::from_polar(1.0, phase.rem_euclid(2.0 * PI));
        let to32 = |v: Complex64| Complex32::new(v.re as f32, v.im as f32);
        let steps = ramp_steps(a1);
        // exp(i a1 (n − len)) = exp(i a1 n)·exp(−i a1 len) above len/2.
        let above = cis(-a1 * lf);
        let zero = Complex32::new(0.0, 0.0);
        transfer.resize(len, zero);
        field.resize(len, zero);
        for (b, ((out, f), (h, p))) in transfer
            .chunks_mut(RAMP_BLOCK)
            .zip(field.chunks_mut(RAMP_BLOCK))
            .zip(untilted.chunks(RAMP_BLOCK).zip(spectrum.chunks(RAMP_BLOCK)))
            .enumerate()
        {
            let n0 = b * RAMP_BLOCK;
            let anchor = cis(a1 * n0 as f64);
            let anchor = to32(if n0 >= half { anchor * above } else { anchor });
            for (((t, f), h), (p, step)) in out.iter_mut().zip(f).zip(h).zip(p.iter().zip(&steps)) {
                *t = h * (anchor * step);
                *f = p * *t;
            }
        }
        // A block that straddles len/2 took the lower ramp throughout: its upper part, and the
        // bins the tilt moves across the wrap, are formed exactly.
        let from = (half / RAMP_BLOCK * RAMP_BLOCK).min(split);
        let to = (half + RAMP_BLOCK).max(split).min(len);
        for (n, t) in transfer.iter_mut().enumerate().take(to).skip(from) {
            let m = if n < split { n as f64 } else { n as f64 - lf };
            *t = to32(cis(a2 * m * m + a1 * m) / lf);
            field[n] = spectrum[n] * *t;
        }
        inverse.process_with_scratch(field, scratch);
        self.slits_then_fresnel(field, transfer, (&forward, &inverse), scratch);
    }

    /// The display's slits on the field at the display, then the Fresnel step to MLA 2 with
    /// `transfer`: how both relays end.
    fn slits_then_fresnel(
        &self,
        field: &mut [Complex32],
        transfer: &[Complex32],
        (forward, inverse): (&Arc<dyn Fft<f32>>, &Arc<dyn Fft<f32>>),
        scratch: &mut [Complex32],
    ) {
        // Beyond the chain's samples the display is open (ones), so only these change.
        for (f, s) in field.iter_mut().zip(&self.slits) {
            *f *= *s as f32;
        }
        forward.process_with_scratch(field, scratch);
        for (f, t) in field.iter_mut().zip(transfer) {
            *f *= t;
        }
        inverse.process_with_scratch(field, scratch);
    }

    /// MLA 1 → Fresnel → display → Fresnel: the double MLA's field just before MLA 2, in
    /// `field` (samples `0..n` are the chain's), for the plate's transmission `plate`.
    pub(super) fn relay(
        &self,
        plate: &[Complex64],
        field: &mut Vec<Complex32>,
        scratch: &mut Vec<Complex32>,
        wavelength_um: f64,
        k_sin: f64,
    ) {
        let h = self.transfer(wavelength_um);
        let len = h.len();
        let (forward, inverse) = plans_f32(len, scratch);
        field.resize(len, Complex32::new(0.0, 0.0));
        let to32 = |v: Complex64| Complex32::new(v.re as f32, v.im as f32);
        let lit = field.iter_mut().zip(plate.iter().zip(&self.display_rect));
        if k_sin == 0.0 {
            for (f, (p, r)) in lit {
                *f = to32(p * *r);
            }
        } else {
            for ((f, (p, r)), t) in lit.zip(self.tilt(0, k_sin)) {
                *f = to32(p * *r * t);
            }
        }
        field[self.n..].fill(Complex32::new(0.0, 0.0));
        forward.process_with_scratch(field, scratch);
        for (f, t) in field.iter_mut().zip(h.iter()) {
            *f *= t;
        }
        inverse.process_with_scratch(field, scratch);
        self.slits_then_fresnel(field, &h, (&forward, &inverse), scratch);
    }
}
