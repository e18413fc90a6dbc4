//! Per-channel PSFs of a phase-mask design beside the bare T-OLED's, and the kernel matrix of all
//! sensor directions (eq. 4.12).

use std::sync::atomic::{AtomicUsize, Ordering};

use ndarray::Array2;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::chain::{Chain, Incidence, MonoPsf, PhaseOptics};
use super::invertibility::{invertibility_score, mtf_one_sided};
use super::{POLARISER_TRANSMISSION, PhaseDesign, PhaseSampling, SimError};
use crate::Progress;
use crate::design::Channel;

/// One colour channel through the design and through the bare T-OLED.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ChannelPsf {
    /// Channel name (e.g. "G").
    pub name: String,
    /// The peak wavelength, or the response-weighted mean wavelength of a spectral channel.
    pub wavelength_nm: f64,
    /// Sensor PSF normalised to sum 1 over the whole sensor (entry `k` is pixel `k`, axis at `P/2`).
    pub psf: Vec<f64>,
    /// The bare T-OLED's PSF, normalised the same way.
    pub toled_psf: Vec<f64>,
    /// Light on the sensor window, as a fraction of the light on the main-lens opening, before
    /// the polariser's ½.
    pub window_energy: f64,
    /// The bare T-OLED's `window_energy`.
    pub toled_window_energy: f64,
    /// All light leaving the main-lens opening (the display's transmission), before the ½.
    pub transmission: f64,
    /// The bare T-OLED's `transmission`.
    pub toled_transmission: f64,
    /// `window_energy / toled_window_energy` (≈ 1/0.238 for the thesis design at λ0).
    pub energy_vs_toled_before_polariser: f64,
    /// The same with the polarisation-dependent plate's ½: what the camera gains over a T-OLED.
    pub energy_vs_toled: f64,
    /// Largest value of the normalised PSF (the brightest pixel's share).
    pub peak: f64,
    /// The bare T-OLED's `peak`.
    pub toled_peak: f64,
    /// Sum of the one-sided MTF ([`invertibility_score`]).
    pub invertibility: f64,
    /// The bare T-OLED's `invertibility`.
    pub toled_invertibility: f64,
    /// One-sided MTFs, frequencies `k / P` cycles per pixel, `k = 0 … P/2 − 1`.
    pub mtf: Vec<f64>,
    /// The bare T-OLED's one-sided MTF.
    pub toled_mtf: Vec<f64>,
}

/// All channels for one direction.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PhasePsfs {
    /// One entry per colour channel.
    pub channels: Vec<ChannelPsf>,
    /// Incidence angle of the direction, degrees from the axis.
    pub angle_deg: f64,
    /// Where a plain lens images the direction, in pixels from the axis (the T-OLED's PSF sits
    /// there; the double MLA's near the opposite pixel).
    pub image_pixel: i64,
    /// Number of lenslets in the design.
    pub lenslets: usize,
    /// Light transmittance with the polariser: ½ × the mean channel transmission.
    pub ltr_with_polariser: f64,
    /// The bare T-OLED's light transmittance: the mean channel transmission (no polariser).
    pub toled_ltr: f64,
}

/// Weighted sum of monochromatic PSFs: (window energies per pixel, window energy, transmission).
fn combine(parts: &[(f64, MonoPsf)]) -> (Vec<f64>, f64, f64) {
    let len = parts.first().map_or(0, |(_, p)| p.sensor.len());
    let mut sum = vec![0.0; len];
    let mut window = 0.0;
    let mut total = 0.0;
    for (w, p) in parts {
        for (s, v) in sum.iter_mut().zip(&p.sensor) {
            *s += w * v;
        }
        window += w * p.window_energy;
        total += w * p.total_energy;
    }
    (sum, window, total)
}

fn normalised(v: &[f64]) -> Vec<f64> {
    let s: f64 = v.iter().sum();
    if s > 0.0 {
        v.iter().map(|x| x / s).collect()
    } else {
        vec![0.0; v.len()]
    }
}

fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 { a / b } else { 0.0 }
}

fn check_channels(channels: &[Channel]) -> Result<(), SimError> {
    if channels.is_empty() {
        return Err(SimError::invalid(
            "channels",
            "at least one channel is needed",
        ));
    }
    for (i, ch) in channels.iter().enumerate() {
        let ok = !ch.wavelengths_nm.is_empty()
            && ch.wavelengths_nm.len() == ch.weights.len()
            && ch
                .wavelengths_nm
                .iter()
                .all(|l| (300.0..=1100.0).contains(l))
            && ch.weights.iter().all(|w| w.is_finite() && *w >= 0.0)
            && ch.weights.iter().sum::<f64>() > 0.0;
        if !ok {
            return Err(SimError::invalid(
                format!("channels[{i}]"),
                "needs wavelengths within 300–1100 nm and non-negative weights with a positive sum",
            ));
        }
    }
    Ok(())
}

/// PSFs of every channel through `optics` (the double MLA, or Lemma 1's single mask) and through
/// the bare T-OLED, for one incidence direction. Wavelengths run in parallel.
///
/// # Errors
/// An invalid design, sampling or channel, or [`SimError::Cancelled`].
pub fn phase_psfs(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    channels: &[Channel],
    optics: PhaseOptics,
    incidence: Incidence,
    progress: &Progress,
) -> Result<PhasePsfs, SimError> {
    check_channels(channels)?;
    phase_psfs_on(
        &Chain::new(design, sampling)?,
        channels,
        optics,
        incidence,
        progress,
    )
}

/// [`phase_psfs`] on a sampled chain: one whose Bloch relay runs on a device
/// ([`Chain::with_relay`]) computes the design's PSFs through the wrapped grid there.
///
/// # Errors
/// As [`phase_psfs`].
pub fn phase_psfs_on(
    chain: &Chain,
    channels: &[Channel],
    optics: PhaseOptics,
    incidence: Incidence,
    progress: &Progress,
) -> Result<PhasePsfs, SimError> {
    check_channels(channels)?;
    let jobs: Vec<(usize, f64, f64)> = channels
        .iter()
        .enumerate()
        .flat_map(|(c, ch)| {
            let sum: f64 = ch.weights.iter().sum();
            ch.wavelengths_nm
                .iter()
                .zip(&ch.weights)
                .filter(|(_, w)| **w > 0.0)
                .map(move |(&l, &w)| (c, l, w / sum))
        })
        .collect();
    let done = AtomicUsize::new(0);
    let results: Vec<(MonoPsf, MonoPsf)> = jobs
        .par_iter()
        .map(|&(_, l, _)| {
            progress.check()?;
            let ours = chain.mono_relayed(optics, chain.heights_um(), l, incidence)?;
            let toled = chain.mono(PhaseOptics::Toled, &[], l, incidence);
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress.set(n as f32 / jobs.len() as f32);
            Ok((ours, toled))
        })
        .collect::<Result<_, SimError>>()?;
    let mut out = Vec::with_capacity(channels.len());
    for (c, ch) in channels.iter().enumerate() {
        let mine: Vec<usize> = (0..jobs.len()).filter(|&i| jobs[i].0 == c).collect();
        let ours: Vec<(f64, MonoPsf)> = mine
            .iter()
            .map(|&i| (jobs[i].2, results[i].0.clone()))
            .collect();
        let toled: Vec<(f64, MonoPsf)> = mine
            .iter()
            .map(|&i| (jobs[i].2, results[i].1.clone()))
            .collect();
        let mean_nm: f64 = mine.iter().map(|&i| jobs[i].1 * jobs[i].2).sum();
        let (sum, window, total) = combine(&ours);
        let (tsum, twindow, ttotal) = combine(&toled);
        let psf = normalised(&sum);
        let toled_psf = normalised(&tsum);
        let before = ratio(window, twindow);
        out.push(ChannelPsf {
            name: ch.name.clone(),
            wavelength_nm: mean_nm,
            peak: psf.iter().copied().fold(0.0, f64::max),
            toled_peak: toled_psf.iter().copied().fold(0.0, f64::max),
            invertibility: invertibility_score(&psf),
            toled_invertibility: invertibility_score(&toled_psf),
            mtf: mtf_one_sided(&psf),
            toled_mtf: mtf_one_sided(&toled_psf),
            psf,
            toled_psf,
            window_energy: window,
            toled_window_energy: twindow,
            transmission: total,
            toled_transmission: ttotal,
            energy_vs_toled_before_polariser: before,
            energy_vs_toled: before * POLARISER_TRANSMISSION,
        });
    }
    let n = out.len().max(1) as f64;
    let design = chain.design();
    Ok(PhasePsfs {
        ltr_with_polariser: POLARISER_TRANSMISSION
            * out.iter().map(|c| c.transmission).sum::<f64>()
            / n,
        toled_ltr: out.iter().map(|c| c.toled_transmission).sum::<f64>() / n,
        channels: out,
        angle_deg: incidence
            .sin_theta(design)
            .clamp(-1.0, 1.0)
            .asin()
            .to_degrees(),
        image_pixel: incidence.image_pixel(design),
        lenslets: chain.lenslets().count(),
    })
}

/// The blur matrix of eq. 4.12 for one channel: `K[[i, j]]` is the energy that sensor pixel `i`
/// receives from the direction imaged on pixel `j` (both absolute, the axis at `P/2`), before the
/// polariser's ½. One propagation per direction and wavelength, in parallel, with progress.
///
/// # Errors
/// An invalid design, sampling or channel, or [`SimError::Cancelled`].
pub fn kernel_matrix(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    channel: &Channel,
    optics: PhaseOptics,
    progress: &Progress,
) -> Result<Array2<f64>, SimError> {
    check_channels(std::slice::from_ref(channel))?;
    kernel_matrix_on(&Chain::new(design, sampling)?, channel, optics, progress)
}

/// [`kernel_matrix`] on a sampled chain: wavelength by wavelength, every direction at once
/// ([`Chain::mono_directions`], the plate formed once per wavelength), so one whose Bloch relay
/// runs on a device ([`Chain::with_relay`]) computes the matrix's propagations there. Each
/// column sums its wavelengths in their order, as one direction at a time would.
///
/// # Errors
/// As [`kernel_matrix`].
pub fn kernel_matrix_on(
    chain: &Chain,
    channel: &Channel,
    optics: PhaseOptics,
    progress: &Progress,
) -> Result<Array2<f64>, SimError> {
    check_channels(std::slice::from_ref(channel))?;
    let p = chain.design().camera.pixels;
    let sum: f64 = channel.weights.iter().sum();
    let incidences: Vec<Incidence> = (0..p)
        .map(|j| Incidence::Pixel(j as i64 - (p / 2) as i64))
        .collect();
    let used: Vec<(f64, f64)> = channel
        .wavelengths_nm
        .iter()
        .zip(&channel.weights)
        .filter(|(_, w)| **w > 0.0)
        .map(|(&l, &w)| (l, w))
        .collect();
    let share = |i: usize| i as f32 / used.len() as f32;
    let mut columns = vec![vec![0.0; p]; p];
    for (i, &(l, w)) in used.iter().enumerate() {
        let psfs = {
            let _span = progress.span(share(i), share(i + 1));
            chain.mono_directions(optics, chain.heights_um(), l, &incidences, progress)?
        };
        columns.par_iter_mut().zip(&psfs).for_each(|(column, psf)| {
            for (c, v) in column.iter_mut().zip(&psf.sensor) {
                *c += w / sum * v;
            }
        });
    }
    progress.set(1.0);
    Ok(Array2::from_shape_fn((p, p), |(i, j)| columns[j][i]))
}
