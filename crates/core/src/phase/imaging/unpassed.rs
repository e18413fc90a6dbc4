//! How much of a photo sits where a setup passes (almost) no light: the horizontal frequencies
//! at which the setup's MTF is below 1 % of its zero-frequency value, and the PSNR of the photo
//! with exactly its content there removed (conventions.md §7, "unpassed contrast").
//!
//! A T-OLED's slits pass no light at a band of horizontal frequencies: its OTF is the
//! autocorrelation of the slit grating, zero wherever the shift `λ f ν` falls between one
//! slit's width and the next slit (`a·p < λ f ν < (1 − a)·p`, `a` the open ratio, `p` the
//! pitch). Over a channel's wavelengths the bands overlap in about 45 … 110 sensor pixels per
//! cycle at 600 DPI. The capture carries next to nothing of the photo there, and the restorations
//! recover little of it, so the T-OLED's PSNR follows how much of a photo's contrast lies at
//! those scales more than it follows the light level. It is a measure, not a bound: at high light
//! the denoiser and the prior win back part of it (the T-OLED restores the astronaut at 256² to
//! 18.6 dB at 10 000 photons, against 16.8 dB here).

use ndarray::Array2;

use super::PhaseBlur;
use crate::SimError;

/// A frequency counts as not passed where the channel's MTF at the axis is below this
/// fraction of its value at zero frequency.
pub const UNPASSED_MTF: f64 = 0.01;

/// Per channel, which of the `width / 2 + 1` horizontal frequencies of a `width`-pixel row
/// (`k` cycles per row, `k = 0 … width/2`) the setup passes less than [`UNPASSED_MTF`] of: the
/// MTF of the axis direction's PSF over the whole sensor ([`PhaseBlur::axis_psf`]), evaluated
/// at `k / width` cycles per pixel. The whole PSF, not the scene's window of it: a narrow
/// window cuts the T-OLED's diffraction orders and would hide the zeros they make.
pub fn unpassed_frequencies(blur: &PhaseBlur) -> Vec<Vec<bool>> {
    let width = blur.width();
    blur.axis_psf
        .iter()
        .map(|psf| {
            let mtf: Vec<f64> = (0..=width / 2)
                .map(|k| dtft_magnitude(psf, k as f64 / width as f64))
                .collect();
            let dc = mtf.first().copied().unwrap_or(0.0);
            mtf.iter().map(|&m| !(m >= UNPASSED_MTF * dc)).collect()
        })
        .collect()
}

/// `|Σ_i psf[i] e^{−2πi ν i}|` at `nu` cycles per sample.
fn dtft_magnitude(psf: &[f64], nu: f64) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for (i, &p) in psf.iter().enumerate() {
        let phase = -2.0 * std::f64::consts::PI * nu * i as f64;
        re += p * phase.cos();
        im += p * phase.sin();
    }
    re.hypot(im)
}

/// The mean square per pixel of `scene`'s content at the unpassed frequencies of
/// [`unpassed_frequencies`] (each channel its own; the rows' circular spectrum over the whole
/// width): the MSE of the photo with exactly that content removed, `10 log10(1/MSE)` its PSNR
/// (peak 1). Zero when the setup passes every frequency.
///
/// # Errors
/// A scene whose planes do not match the operator's channels or width.
pub fn unpassed_mse(blur: &PhaseBlur, scene: &[Array2<f64>]) -> Result<f64, SimError> {
    super::check_scene(blur, scene)?;
    let unpassed = unpassed_frequencies(blur);
    let mut lost = 0.0;
    let mut pixels = 0usize;
    for (plane, skip) in scene.iter().zip(&unpassed) {
        let width = plane.ncols();
        let spectrum = RowSpectrum::new(width);
        for row in plane.rows() {
            let power = spectrum.power(&row.to_vec());
            // Parseval for a real row: the bins other than 0 and width/2 stand for two.
            lost += power
                .iter()
                .zip(skip)
                .enumerate()
                .filter(|(_, (_, s))| **s)
                .map(|(f, (p, _))| {
                    let twice = f != 0 && !(width % 2 == 0 && f == width / 2);
                    if twice { 2.0 * p } else { *p }
                })
                .sum::<f64>()
                / width as f64;
        }
        pixels += plane.len();
    }
    Ok(lost / pixels.max(1) as f64)
}

/// `|FFT(row)|²` for the frequencies `0 … len/2`, one plan for every row of a length.
struct RowSpectrum(std::sync::Arc<dyn udc_fft::RealToComplex<f64>>);

impl RowSpectrum {
    fn new(len: usize) -> Self {
        RowSpectrum(udc_fft::real_plan(len))
    }

    fn power(&self, row: &[f64]) -> Vec<f64> {
        let mut input = row.to_vec();
        let mut out = self.0.make_output_vec();
        // Rows of the plan's own length: the transform cannot refuse them.
        if self.0.process(&mut input, &mut out).is_err() {
            return vec![0.0; out.len()];
        }
        out.iter().map(|c| c.norm_sqr()).collect()
    }
}
