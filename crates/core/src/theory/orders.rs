//! The diffraction orders of a tiled display from the tile's Fourier series, and the light the
//! simulated PSF holds around each order.

use ndarray::Array2;
use rustfft::num_complex::Complex64;

use crate::SimError;
use crate::design::Design;
use crate::display::aperture::effective_cells;
use crate::display::tiling::orbit;
use crate::psf::sampling::WavelengthSampling;

use super::sinc;

/// The orders along x (n = 0) that fit the window, theory beside simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderEnergy {
    /// Order positions `m · λf / P` at the channel's mean wavelength, µm.
    pub x_um: Vec<f64>,
    /// Fraction of all the channel's light inside each order's cell of the sensor window.
    pub simulated: Vec<f64>,
    /// `|mean c(m, 0)|² / mean |t|²`: the coherent fraction theory puts in each order.
    pub predicted: Vec<f64>,
    /// The fraction of the light all coherent orders hold together (1 for a periodic tiling).
    pub coherent_fraction: f64,
}

/// Fewest sensor pixels between orders for their light to be told apart.
const MIN_SPACING_PX: f64 = 3.0;

/// Compares the orders along the x axis of `psf` (one channel of an analysis of `design`
/// sampled as `samp`, holding `energy_in_window` of the light) with the tile's Fourier series.
///
/// # Errors
/// [`SimError::Sampling`] when neighbouring orders are under `MIN_SPACING_PX` sensor pixels
/// apart (the tile is too large for its orders to be resolved).
pub fn order_energies(
    design: &Design,
    samp: &[WavelengthSampling],
    psf: &Array2<f64>,
    energy_in_window: f64,
) -> Result<OrderEnergy, SimError> {
    let op = &design.optics;
    let period_um = design.opening.pitch_um + design.tiling.wiring_gap_um;
    let wsum: f64 = samp.iter().map(|w| w.weight).sum();
    let wavelength_nm = samp.iter().map(|w| w.weight * w.wavelength_nm).sum::<f64>() / wsum;
    let spacing_um = wavelength_nm * op.focal_length_mm / period_um;
    let pixel_um = op.sensor_pixel_um;
    if !(spacing_um >= MIN_SPACING_PX * pixel_um) {
        return Err(SimError::Sampling(format!(
            "the display's diffraction orders are {spacing_um:.2} µm apart, under \
             {MIN_SPACING_PX} sensor pixels: the tile ({period_um:.0} µm) is too large for its \
             orders to be told apart"
        )));
    }
    let (coefficients, coherent_fraction) = mean_coefficients(design, period_um);
    let w = psf.nrows();
    let centre = |j: usize, axis: usize| {
        (j as f64 - (w / 2) as f64 + 0.5) * pixel_um - op.axis_in_pixel_um[axis]
    };
    let half_window_um = (w / 2) as f64 * pixel_um - pixel_um;
    let max_m = ((half_window_um - spacing_um / 2.0) / spacing_um)
        .floor()
        .max(0.0) as i64;
    let mut out = OrderEnergy {
        x_um: Vec::new(),
        simulated: Vec::new(),
        predicted: Vec::new(),
        coherent_fraction,
    };
    let rows: Vec<usize> = (0..w)
        .filter(|&i| centre(i, 1).abs() <= spacing_um / 2.0)
        .collect();
    for m in -max_m..=max_m {
        let x_m = m as f64 * spacing_um;
        let light: f64 = (0..w)
            .filter(|&j| (centre(j, 0) - x_m).abs() <= spacing_um / 2.0)
            .map(|j| rows.iter().map(|&i| psf[[i, j]]).sum::<f64>())
            .sum();
        out.x_um.push(x_m);
        out.simulated.push(light * energy_in_window);
        out.predicted.push(coefficients(m));
    }
    Ok(out)
}

/// `m ↦ |mean c(m, 0)|² / mean |t|²` over the tiling's orientations, and the coherent fraction
/// `mean |t̄|² / mean |t|²` (t̄ the orientation-averaged tile).
fn mean_coefficients(design: &Design, period_um: f64) -> (impl Fn(i64) -> f64 + use<>, f64) {
    let cells = effective_cells(&design.opening);
    let n = cells.len().max(1);
    let cell_um = design.opening.pitch_um / n as f64;
    let orientations = orbit(design.tiling.mode);
    let k = orientations.len() as f64;
    // The orientation-averaged tile: its orders are the coherent ones.
    let mut mean = vec![vec![0.0; n]; n];
    for g in &orientations {
        for (mr, row) in mean.iter_mut().zip(g.apply(&cells)) {
            for (m, v) in mr.iter_mut().zip(row) {
                *m += v / k;
            }
        }
    }
    let fill = (cell_um / period_um).powi(2);
    let power: f64 = cells.iter().flatten().map(|t| t * t).sum::<f64>() * fill;
    let coherent: f64 = mean.iter().flatten().map(|t| t * t).sum::<f64>() * fill;
    let column_sums: Vec<f64> = (0..n)
        .map(|j| mean.iter().map(|r| r.get(j).copied().unwrap_or(0.0)).sum())
        .collect();
    let coefficient = move |m: i64| {
        if !(power > 0.0) {
            return 0.0;
        }
        // Square cells: each column is a box of width `cell_um` at x_j, whose transform is
        // the sinc factor.
        let f = m as f64 / period_um;
        let c: Complex64 = column_sums
            .iter()
            .enumerate()
            .map(|(j, s)| {
                let x = (j as f64 + 0.5) * cell_um;
                Complex64::from_polar(*s, -2.0 * std::f64::consts::PI * f * x)
            })
            .sum::<Complex64>()
            * fill
            * sinc(f * cell_um);
        c.norm_sqr() / power
    };
    let fraction = if power > 0.0 { coherent / power } else { 0.0 };
    (coefficient, fraction)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::TilingMode;

    /// A slit of duty a/P: |c(m)|² / (a/P) = (a/P)·sinc²(m a/P), zero at multiples of P/a.
    #[test]
    fn a_slit_grating_has_the_textbook_orders() {
        let mut d = Design::default_toled();
        d.opening.pitch_um = 160.0;
        d.opening.cells = (0..20)
            .map(|_| (0..20).map(|j| f64::from((8..12).contains(&j))).collect())
            .collect();
        d.tiling.wiring_gap_um = 0.0;
        let (c, coherent) = mean_coefficients(&d, 160.0);
        assert!((coherent - 1.0).abs() < 1e-12);
        let duty: f64 = 0.2;
        for m in 0..12 {
            let t = duty * m as f64;
            let expect = duty * sinc(t).powi(2);
            assert!(
                (c(m) - expect).abs() < 1e-12,
                "order {m}: {} vs {expect}",
                c(m)
            );
        }
        assert!(c(5) < 1e-20 && c(10) < 1e-20);
        // The whole series holds all the light.
        let total: f64 = (-4000..=4000).map(&c).sum();
        assert!((total - 1.0).abs() < 1e-3, "{total}");
        // A random tiling of a symmetric slit: transposes turn it into a horizontal slit, so
        // only the mean (a cross) stays coherent.
        d.tiling.mode = TilingMode::RandomD4;
        let (_, coherent) = mean_coefficients(&d, 160.0);
        assert!(coherent < 0.99 && coherent > 0.2, "{coherent}");
    }
}
