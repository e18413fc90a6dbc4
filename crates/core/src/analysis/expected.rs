//! The closed-form expected PSF of a random tiling (thesis §3.4.1, its 2-D form with b1…b4).
//!
//! With tiles drawn independently and uniformly from an orbit `{g·P}`, the expected intensity is
//! `E|A|² = |FT(p · tiled m̄)|² + R · (mean_g |M_g|² − |M̄|²)`, where `m̄` is the orbit's mean
//! pattern, `M_g` the transform of one tile in orientation `g`, and `R` the number of tiles in
//! the pupil. For the random-4 set this is exactly the thesis's
//! `R²(|B1|² + |B2|² + |B3|²) + |B4 Δ|²` (`R²` there counts tiles as we do with `R`), since
//! `B4 = M̄` and, by Parseval over the Hadamard basis, `Σ_{i≤3} |B_i|² = mean_g |M_g|² − |M̄|²`.
//! Tiles cut by the pupil edge are counted by their area: that is the approximation.
//! Because `|FT(g·P)|²` is `|FT(P)|²` with its frequency axes flipped or swapped, one tile
//! transform serves the whole orbit.

use ndarray::Array2;

use crate::SimError;
use crate::display::aperture::{Display, Extent, pupil_sample_count, rasterise};
use crate::display::tiling::orbit;
use crate::progress::Progress;
use crate::psf::fft::binned_orbit_intensity;
use crate::psf::route::Fraunhofer;
use crate::psf::sampling::WavelengthSampling;

/// The orbit's mean pattern `m̄`.
pub fn mean_pattern(display: &Display) -> Vec<Vec<f64>> {
    let group = orbit(display.mode);
    let n = display.cells.len();
    let mut mean = vec![vec![0.0; n]; n];
    for g in &group {
        for (r, row) in g.apply(display.cells).iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                mean[r][c] += v / group.len() as f64;
            }
        }
    }
    mean
}

/// Expected sensor PSF of one channel (sums to 1), for the random tiling of `display`. The
/// pupil-sized transform of the mean pattern and the mean tile's go through `route` (the
/// analysis's Fraunhofer step, a device's included); the orbit's, whose eight orientations bin
/// one transform differently, through the CPU's full route.
///
/// # Errors
/// As [`crate::psf::fft::binned_intensity`], and `route`'s own.
pub fn expected_channel_psf(
    display: &Display,
    (pupil_diameter_um, pupil_sample_um): (f64, f64),
    samplings: &[WavelengthSampling],
    route: &dyn Fraunhofer,
    progress: &Progress,
) -> Result<Array2<f64>, SimError> {
    let group = orbit(display.mode);
    let mean = mean_pattern(display);
    let periodic_display = Display {
        cells: &mean,
        mode: crate::design::TilingMode::Repeat,
        ..display.clone()
    };
    let tile_display = Display {
        mode: crate::design::TilingMode::Repeat,
        ..display.clone()
    };
    let periodic = rasterise(
        &periodic_display,
        Extent::Pupil {
            diameter_um: pupil_diameter_um,
        },
        pupil_sample_um,
    );
    let tile = rasterise(&tile_display, Extent::SingleTile, pupil_sample_um);
    let tile_mean = rasterise(&periodic_display, Extent::SingleTile, pupil_sample_um);
    let period = display.pitch_um + display.gap_um;
    let tiles_in_pupil = pupil_sample_count(pupil_diameter_um, pupil_sample_um)
        * pupil_sample_um.powi(2)
        / (period * period);

    let w = samplings.first().map_or(0, |s| s.binning.window_px);
    let mut acc = Array2::<f64>::zeros((w, w));
    for ws in samplings {
        let m = ws.fft_size;
        let p = route.binned(&periodic, m, &ws.binning, progress)?;
        let f1 = binned_orbit_intensity(&tile, m, &ws.binning, &group, progress)?;
        let fbar = route.binned(&tile_mean, m, &ws.binning, progress)?;
        // mean_g |M_g|² − |M̄|² ≥ 0 pointwise (Jensen); binned sums keep the sign up to rounding.
        let variance = (&f1.sensor - &fbar.sensor).mapv(|v| v.max(0.0));
        let total = p.total + tiles_in_pupil * (f1.total - fbar.total).max(0.0);
        if !(total > 0.0) {
            return Err(SimError::Sampling("no light passes the aperture".into()));
        }
        acc.scaled_add(ws.weight / total, &p.sensor);
        acc.scaled_add(ws.weight * tiles_in_pupil / total, &variance);
    }
    let s = acc.sum();
    if s > 0.0 {
        acc /= s;
    }
    Ok(acc)
}
