//! A design shown at another display density: the pixel pitch set from the DPI, and the pupil
//! sampling δ1 made an odd fraction of the cell, `δ1 = cell / k` with `k` the smallest odd
//! whole number at least `cell / δ1`, as the thesis's T-OLED presets are sampled (cells of 8, 4
//! and 2 µm at δ1 = 8, 4 and 2 µm, the 294-pixel window kept).
//!
//! Why: a pupil sample is the area-weighted mean of the cells it covers, and the LTR sums its
//! square, so a sample that straddles a cell edge loses light. Samples lie on the axis
//! (`i·δ1`, edges at `(i ± ½)·δ1`) and the cells' edges at half-cells from it; with `k` odd they
//! coincide. Cells finer than δ1 are averaged away (at 600 DPI the 150-DPI recipe's 8 µm reads
//! the slit's LTR of 0.238 as 0.175); cells of 8.06 µm (150 DPI) on 8 µm samples, or 12.1 µm
//! cells on two samples each (100 DPI), read 0.222 and 0.226. A cell within 1e-4 of a whole
//! odd number of samples keeps the design's δ1: the edge moves by a few hundredths of a sample
//! across the pupil (151.19 DPI for the 168 µm T-OLED).

use super::{Design, OpticsRecipe};
use crate::SimError;

/// Micrometres in an inch: a display of `d` DPI has a pitch of `25 400 / d` µm.
pub const UM_PER_INCH: f64 = 25_400.0;

impl Design {
    /// This design at `dpi` dots per inch (see the module's documentation).
    ///
    /// # Errors
    /// A DPI that is not a positive finite number.
    pub fn at_dpi(&self, dpi: f64) -> Result<Design, SimError> {
        if !(dpi.is_finite() && dpi > 0.0) {
            return Err(SimError::invalid(
                "dpi",
                format!("{dpi} is not a positive number of dots per inch"),
            ));
        }
        let mut d = self.clone();
        d.opening.pitch_um = UM_PER_INCH / dpi;
        let cell = d.opening.cell_um();
        let delta1 = d.optics.pupil_sample_um;
        let mut samples = (cell / delta1 - 1e-4).ceil().max(1.0);
        if samples % 2.0 == 0.0 {
            samples += 1.0;
        }
        let whole = cell / samples;
        if (whole - delta1).abs() > 1e-4 * delta1 {
            d.optics.pupil_sample_um = whole;
            d.optics.recipe = OpticsRecipe::Custom;
        }
        Ok(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_finer_display_refines_the_sampling_to_its_cells_and_a_coarser_keeps_it() {
        let coarse = Design::default_toled();
        let fine = coarse.at_dpi(UM_PER_INCH / 42.0).expect("a valid DPI");
        assert!((fine.opening.pitch_um - 42.0).abs() < 1e-9);
        assert!((fine.optics.pupil_sample_um - 2.0).abs() < 1e-9);
        assert_eq!(fine.optics.recipe, OpticsRecipe::Custom);
        // 150 DPI's own 168 µm pitch (also as 151.19 DPI) keeps the design's 8 µm; 100 DPI's
        // 12.1 µm cells take three samples, an odd number.
        for dpi in [UM_PER_INCH / 168.0, 151.19] {
            let same = coarse.at_dpi(dpi).expect("a valid DPI");
            assert_eq!(same.optics, coarse.optics);
        }
        let wide = coarse.at_dpi(100.0).expect("a valid DPI");
        assert!((3.0 * wide.optics.pupil_sample_um - wide.opening.cell_um()).abs() < 1e-9);
        for bad in [0.0, -3.0, f64::NAN, f64::INFINITY] {
            assert!(coarse.at_dpi(bad).is_err(), "{bad}");
        }
    }
}
