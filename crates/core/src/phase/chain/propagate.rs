//! The chain's optics at one wavelength: Fresnel transfer functions, the relay through the two
//! lenslet arrays and the display, the plate's transmission, tilts and the chirp-z window
//! (cached per wavelength).

use super::*;

use super::bloch::{plans_f32, slits_then_fresnel};

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
        slits_then_fresnel(field, &self.slits, &h, (&forward, &inverse), scratch);
    }
}
