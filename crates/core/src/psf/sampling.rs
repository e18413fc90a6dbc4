//! The sampling plan: FFT size per wavelength, fine spacing, sensor binning and the warnings
//! conventions.md §2 asks for when the sampling is unsafe.

use crate::SimError;
use crate::design::{Design, MAX_FFT_SIZE};
use crate::psf::warning::{SamplingWarning, WarningKind};

/// How fine samples are integrated into sensor pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Binning {
    /// Side of the square sensor window, in pixels; the axis pixel is `window_px / 2`.
    pub window_px: usize,
    /// Fine samples per sensor pixel along each axis.
    pub samples_per_px: usize,
    /// Index (`0..samples_per_px`) of the on-axis fine sample inside its pixel, `[x, y]`.
    pub phase: [usize; 2],
}

impl Binning {
    /// Sensor pixel index holding fine sample at signed offset `s` from the axis along one
    /// axis, or `None` outside the window.
    #[inline]
    pub fn pixel_of(&self, s: i64, axis: usize) -> Option<usize> {
        let sp = self.samples_per_px as i64;
        let j = (self.window_px / 2) as i64 + (s + self.phase[axis] as i64).div_euclid(sp);
        (0..self.window_px as i64)
            .contains(&j)
            .then_some(j as usize)
    }
}

/// Sampling of one wavelength.
#[derive(Debug, Clone, PartialEq)]
pub struct WavelengthSampling {
    /// The wavelength, nm.
    pub wavelength_nm: f64,
    /// Its share of the channel's spectral weight (the channel's weights sum to 1).
    pub weight: f64,
    /// FFT size `M` (even).
    pub fft_size: usize,
    /// The real fine spacing `λ f / (M δ1)` in µm.
    pub fine_um: f64,
    /// How this wavelength's fine samples are integrated into sensor pixels.
    pub binning: Binning,
}

/// `M = 2·floor(λ f / (2 δ1 δ2))`, conventions.md §4.
pub fn fft_size(
    wavelength_nm: f64,
    focal_length_mm: f64,
    pupil_sample_um: f64,
    fine_sample_um: f64,
) -> usize {
    // λ[µm]·f[µm] = λ[nm]·f[mm]
    let lf_um2 = wavelength_nm * focal_length_mm;
    let half = lf_um2 / (2.0 * pupil_sample_um * fine_sample_um);
    // The tiny epsilon keeps exact integers (e.g. 762.0) from flooring to 761 through rounding.
    // Absurd inputs (1e308 mm, 1e-300 µm, NaN) saturate instead of wrapping: the caller
    // refuses anything above its limit.
    let half = (half + 1e-9).floor();
    if half.is_nan() || half <= 0.0 {
        0
    } else if half >= (usize::MAX / 4) as f64 {
        usize::MAX / 2
    } else {
        2 * half as usize
    }
}

/// The smallest even size `≥ m` whose prime factors are all ≤ 7 (fast for the FFT).
pub fn next_fast_size(m: usize) -> usize {
    next_smooth_size(m, &[2, 3, 5, 7])
}

/// The smallest even size `≥ m` whose prime factors are 2, 3 and 5 only: rustfft's fastest
/// radices (a 2⁵·5²·7³ transform of 274 400 points takes ~10 % longer than 276 480 = 2¹¹·3³·5).
pub fn next_fast_size_235(m: usize) -> usize {
    next_smooth_size(m, &[2, 3, 5])
}

/// Sizes above this are returned as they are (no FFT is that large; the caller refuses them).
const SMOOTH_SEARCH_LIMIT: usize = 1 << 40;

fn next_smooth_size(m: usize, primes: &[usize]) -> usize {
    if m > SMOOTH_SEARCH_LIMIT {
        return m;
    }
    let smooth = |mut v: usize| {
        for &p in primes {
            while v.is_multiple_of(p) {
                v /= p;
            }
        }
        v == 1
    };
    (m.max(2)..)
        .step_by(1)
        .find(|v| v.is_multiple_of(2) && smooth(*v))
        .unwrap_or(m)
}

/// The per-channel, per-wavelength sampling of a design at the given target fine spacing.
/// Each FFT size is the one conventions.md §4 gives, never rounded to a faster size (§2): a
/// periodic layout's diffraction orders fall `M δ1 / pitch` fine samples apart, and moving
/// them by the 0.3–1 % such a rounding costs moved a 600-DPI T-OLED's AUC by up to 56 %.
///
/// # Errors
/// [`SimError::Sampling`] when the grid cannot hold the pupil or the window, and
/// [`SimError::TooLarge`] when an FFT would exceed [`MAX_FFT_SIZE`].
pub fn plan(
    design: &Design,
    fine_sample_um: f64,
    warnings: &mut Vec<SamplingWarning>,
) -> Result<Vec<Vec<WavelengthSampling>>, SimError> {
    let op = &design.optics;
    let d_um = op.pupil_diameter_um();
    let pupil_samples = d_um / op.pupil_sample_um;
    let mut out = Vec::with_capacity(design.channels.len());
    let mut warned_padding = false;
    let mut warned_pixel = false;
    // The wavelength whose grid the window overshoots most: (excess, λ, M, samples per pixel).
    let mut beyond: Option<(usize, f64, usize, usize)> = None;
    for ch in &design.channels {
        let mut per = Vec::with_capacity(ch.wavelengths_nm.len());
        let wsum: f64 = ch.weights.iter().sum();
        for (&l, &w) in ch.wavelengths_nm.iter().zip(&ch.weights) {
            let m = fft_size(l, op.focal_length_mm, op.pupil_sample_um, fine_sample_um);
            if m > MAX_FFT_SIZE {
                return Err(SimError::TooLarge(format!(
                    "channel {} at {l} nm needs an FFT of {m}² samples (limit {MAX_FFT_SIZE}²); \
                     increase optics.pupil_sample_um or optics.fine_sample_um",
                    ch.name
                )));
            }
            if (m as f64) < pupil_samples + 2.0 {
                return Err(SimError::Sampling(format!(
                    "channel {} at {l} nm: the FFT grid ({m} samples of {} µm) is smaller than the \
                     pupil ({pupil_samples:.0} samples); decrease optics.fine_sample_um",
                    ch.name, op.pupil_sample_um
                )));
            }
            // Padding and pixel integration are judged at the design's own δ2, which full
            // quality uses: a preview's doubled spacing pads less where that is harmless (its
            // rule is in `Quality::doubles_spacing`), and advice must not chase that.
            let lf_um2 = l * op.focal_length_mm;
            let m_design = fft_size(l, op.focal_length_mm, op.pupil_sample_um, op.fine_sample_um);
            if !warned_padding && (m_design as f64) < 2.0 * pupil_samples {
                warned_padding = true;
                warnings.push(SamplingWarning::warning(
                    WarningKind::UnderPadded,
                    format!(
                        "pupil zero-padding is only {:.2}× (< 2×) at {l} nm: the PSF is \
                         under-sampled; decrease optics.fine_sample_um",
                        m_design as f64 / pupil_samples
                    ),
                ));
            }
            let fine_design_um = lf_um2 / (m_design.max(1) as f64 * op.pupil_sample_um);
            let spp_design = (op.sensor_pixel_um / fine_design_um).round().max(1.0);
            if !warned_pixel
                && ((spp_design * fine_design_um - op.sensor_pixel_um).abs()
                    > 0.02 * op.sensor_pixel_um)
            {
                warned_pixel = true;
                warnings.push(SamplingWarning::warning(
                    WarningKind::PixelNotWhole,
                    format!(
                        "the sensor pixel ({} µm) is not a whole number of fine samples \
                         ({fine_design_um:.4} µm): pixels are integrated over {spp_design} \
                         samples = {:.3} µm; set optics.fine_sample_um to the pixel divided by a \
                         whole number",
                        op.sensor_pixel_um,
                        spp_design * fine_design_um
                    ),
                ));
            }
            let fine_um = lf_um2 / (m as f64 * op.pupil_sample_um);
            let spp = (op.sensor_pixel_um / fine_um).round().max(1.0) as usize;
            let phase = [
                ((op.axis_in_pixel_um[0] / fine_um).floor().max(0.0) as usize).min(spp - 1),
                ((op.axis_in_pixel_um[1] / fine_um).floor().max(0.0) as usize).min(spp - 1),
            ];
            let window_fine = op.window_px * spp;
            // A couple of missing fine samples at the rim (the thesis recipe's blue channel) are noise.
            if window_fine > m + 2 * spp && beyond.is_none_or(|(e, ..)| window_fine - m > e) {
                beyond = Some((window_fine - m, l, m, spp));
            }
            per.push(WavelengthSampling {
                wavelength_nm: l,
                weight: w / wsum,
                fft_size: m,
                fine_um,
                binning: Binning {
                    window_px: op.window_px,
                    samples_per_px: spp,
                    phase,
                },
            });
        }
        out.push(per);
    }
    if let Some((_, l, m, spp)) = beyond {
        warnings.push(SamplingWarning::about_the_crop(
            WarningKind::WindowBeyondGrid,
            op,
            &format!(
                "the sensor window ({} px = {} fine samples) is larger than the FFT grid at {l} nm \
                 ({m} samples)",
                op.window_px,
                op.window_px * spp
            ),
            &format!(
                "its edges are empty; shrink optics.window_px to {:.0} or decrease \
                 optics.pupil_sample_um",
                (m as f64 / spp as f64).round()
            ),
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iccp21_fft_sizes_match_physics_md() {
        assert_eq!(fft_size(610.0, 10.0, 8.0, 0.5), 1524);
        assert_eq!(fft_size(530.0, 10.0, 8.0, 0.5), 1324);
        assert_eq!(fft_size(470.0, 10.0, 8.0, 0.5), 1174);
    }

    #[test]
    fn absurd_inputs_saturate_and_the_smooth_search_ends() {
        // 1e308 mm or 1e-300 µm used to overflow the size and loop forever.
        for (f_mm, fine_um) in [(1e308, 1.0), (50.0, 1e-300), (f64::INFINITY, 1.0)] {
            let m = fft_size(550.0, f_mm, 1.0, fine_um);
            assert!(m > MAX_FFT_SIZE, "{m}");
            assert_eq!(next_fast_size(m), m);
            assert_eq!(next_fast_size_235(m), m);
        }
        assert_eq!(fft_size(f64::NAN, 50.0, 1.0, 1.0), 0);
        assert_eq!(fft_size(550.0, -1.0, 1.0, 1.0), 0);
    }

    #[test]
    fn fast_sizes_are_even_7_smooth_and_not_smaller() {
        assert_eq!(next_fast_size(762), 768);
        assert_eq!(next_fast_size(586), 588);
        assert_eq!(next_fast_size(662), 672);
        assert_eq!(next_fast_size(1024), 1024);
        for m in (2..3000).step_by(2) {
            let f = next_fast_size(m);
            assert!(f >= m && f.is_multiple_of(2) && f - m < m / 10 + 8);
        }
    }

    #[test]
    fn binning_puts_the_axis_on_the_first_sample_of_the_centre_pixel() {
        let b = Binning {
            window_px: 294,
            samples_per_px: 4,
            phase: [0, 0],
        };
        assert_eq!(b.pixel_of(0, 0), Some(147));
        assert_eq!(b.pixel_of(3, 0), Some(147));
        assert_eq!(b.pixel_of(4, 0), Some(148));
        assert_eq!(b.pixel_of(-1, 0), Some(146));
        assert_eq!(b.pixel_of(-588, 0), Some(0));
        assert_eq!(b.pixel_of(-589, 0), None);
        assert_eq!(b.pixel_of(587, 0), Some(293));
        assert_eq!(b.pixel_of(588, 0), None);
    }
}
