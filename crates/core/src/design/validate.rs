//! Every design value checked against its documented range (the Limits table of docs/src/command-line.md), the
//! error naming the field by its path in the design file.

use super::*;
use crate::{Setting, SettingPath};

fn finite_positive(field: impl Into<SettingPath>, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SimError::invalid(
            field,
            format!("must be a positive finite number (got {v:?})"),
        ))
    }
}

fn finite(field: impl Into<SettingPath>, v: f64) -> Result<(), SimError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(SimError::invalid(
            field,
            format!("must be a finite number (got {v:?})"),
        ))
    }
}

/// `v` in `[lo, hi]` (both positive): the documented range of a length or ratio, so that no
/// overflow or degenerate sampling reaches the simulation.
fn within(
    field: impl Into<SettingPath>,
    v: f64,
    lo: f64,
    hi: f64,
    unit: &str,
) -> Result<(), SimError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(SimError::invalid(
            field,
            format!("must be between {lo} and {hi}{unit} (got {v:?})"),
        ))
    }
}

impl Design {
    /// Checks every value; the error names the first bad field by its path in the design file.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for the first value out of range.
    pub fn validate(&self) -> Result<(), SimError> {
        let o = &self.opening;
        finite_positive(Setting::OpeningPitchUm, o.pitch_um)?;
        within(Setting::OpeningPitchUm, o.pitch_um, 0.0, 20_000.0, " µm")?;
        let n = o.cells.len();
        if n == 0 {
            return Err(SimError::invalid(
                Setting::OpeningCells,
                "must have at least one row",
            ));
        }
        if n > MAX_CELLS {
            return Err(SimError::invalid(
                Setting::OpeningCells,
                format!("{n} rows is more than the {MAX_CELLS} the studio supports"),
            ));
        }
        for (r, row) in o.cells.iter().enumerate() {
            if row.len() != n {
                return Err(SimError::invalid(
                    format!("opening.cells[{r}]"),
                    format!(
                        "has {} entries; the grid must be square ({n}×{n})",
                        row.len()
                    ),
                ));
            }
            for (c, &v) in row.iter().enumerate() {
                if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                    return Err(SimError::invalid(
                        format!("opening.cells[{r}][{c}]"),
                        format!("transmittance must be in [0, 1] (got {v:?})"),
                    ));
                }
            }
        }
        for (i, p) in o.polygons.iter().enumerate() {
            if p.vertices_um.len() < 3 {
                return Err(SimError::invalid(
                    format!("opening.polygons[{i}].vertices_um"),
                    "a polygon needs at least 3 vertices",
                ));
            }
            for (j, v) in p.vertices_um.iter().enumerate() {
                if !(v[0].is_finite() && v[1].is_finite()) {
                    return Err(SimError::invalid(
                        format!("opening.polygons[{i}].vertices_um[{j}]"),
                        "coordinates must be finite",
                    ));
                }
            }
        }
        if let Some(sp) = &self.subpixels {
            validate_subpixels(sp, &o.cells)?;
        }
        let t = &self.tiling;
        finite("tiling.origin_offset_cells[0]", t.origin_offset_cells[0])?;
        finite("tiling.origin_offset_cells[1]", t.origin_offset_cells[1])?;
        within(
            Setting::TilingWiringGapUm,
            t.wiring_gap_um,
            0.0,
            20_000.0,
            " µm",
        )?;
        if !(t.wiring_gap_um.is_finite() && t.wiring_gap_um >= 0.0) {
            return Err(SimError::invalid(
                Setting::TilingWiringGapUm,
                format!(
                    "must be zero or a positive finite number of µm (got {:?})",
                    t.wiring_gap_um
                ),
            ));
        }
        let op = &self.optics;
        finite_positive(Setting::OpticsFocalLengthMm, op.focal_length_mm)?;
        finite_positive(Setting::OpticsFNumber, op.f_number)?;
        finite_positive(Setting::OpticsPupilSampleUm, op.pupil_sample_um)?;
        finite_positive(Setting::OpticsFineSampleUm, op.fine_sample_um)?;
        finite_positive(Setting::OpticsSensorPixelUm, op.sensor_pixel_um)?;
        within(
            Setting::OpticsFocalLengthMm,
            op.focal_length_mm,
            0.1,
            1000.0,
            " mm",
        )?;
        within(Setting::OpticsFNumber, op.f_number, 0.5, 64.0, "")?;
        within(
            Setting::OpticsPupilSampleUm,
            op.pupil_sample_um,
            0.05,
            1000.0,
            " µm",
        )?;
        within(
            Setting::OpticsFineSampleUm,
            op.fine_sample_um,
            0.01,
            100.0,
            " µm",
        )?;
        within(
            Setting::OpticsSensorPixelUm,
            op.sensor_pixel_um,
            0.1,
            100.0,
            " µm",
        )?;
        if op.window_px < 2 || op.window_px > MAX_WINDOW_PX {
            return Err(SimError::invalid(
                Setting::OpticsWindowPx,
                format!(
                    "must be between 2 and {MAX_WINDOW_PX} sensor pixels (got {:?})",
                    op.window_px
                ),
            ));
        }
        for (k, v) in op.axis_in_pixel_um.iter().enumerate() {
            if !(v.is_finite() && *v >= 0.0 && *v < op.sensor_pixel_um) {
                return Err(SimError::invalid(
                    format!("optics.axis_in_pixel_um[{k}]"),
                    format!(
                        "must lie inside the pixel, in [0, {}) µm (got {v:?})",
                        op.sensor_pixel_um
                    ),
                ));
            }
        }
        let across = op.pupil_diameter_um() / o.pitch_um;
        let pixels = std::f64::consts::FRAC_PI_4 * across * across;
        if pixels > MAX_PUPIL_PIXELS {
            let min_pitch =
                op.pupil_diameter_um() * (std::f64::consts::FRAC_PI_4 / MAX_PUPIL_PIXELS).sqrt();
            return Err(SimError::invalid(
                Setting::OpeningPitchUm,
                format!(
                    "at {:?} µm the lens pupil ({:.2} mm) spans {:.2e} display pixels; at most \
                     {MAX_PUPIL_PIXELS:.0} are simulated: use a pitch of at least {:.1} µm",
                    o.pitch_um,
                    op.pupil_diameter_um() / 1000.0,
                    pixels,
                    (min_pitch * 10.0).ceil() / 10.0
                ),
            ));
        }
        if self.channels.is_empty() {
            return Err(SimError::invalid(
                "channels",
                "at least one colour channel is needed",
            ));
        }
        for (i, ch) in self.channels.iter().enumerate() {
            if ch.wavelengths_nm.is_empty() {
                return Err(SimError::invalid(
                    format!("channels[{i}].wavelengths_nm"),
                    "needs at least one wavelength",
                ));
            }
            if ch.wavelengths_nm.len() > MAX_WAVELENGTHS {
                return Err(SimError::invalid(
                    format!("channels[{i}].wavelengths_nm"),
                    format!(
                        "has {} wavelengths; at most {MAX_WAVELENGTHS} per channel are simulated",
                        ch.wavelengths_nm.len()
                    ),
                ));
            }
            if ch.wavelengths_nm.len() != ch.weights.len() {
                return Err(SimError::invalid(
                    format!("channels[{i}].weights"),
                    format!(
                        "has {} entries but wavelengths_nm has {}",
                        ch.weights.len(),
                        ch.wavelengths_nm.len()
                    ),
                ));
            }
            for (j, &l) in ch.wavelengths_nm.iter().enumerate() {
                if !(l.is_finite() && (100.0..=20_000.0).contains(&l)) {
                    return Err(SimError::invalid(
                        format!("channels[{i}].wavelengths_nm[{j}]"),
                        format!("must be a wavelength between 100 and 20000 nm (got {l:?})"),
                    ));
                }
            }
            for (j, &w) in ch.weights.iter().enumerate() {
                if !(w.is_finite() && w >= 0.0) {
                    return Err(SimError::invalid(
                        format!("channels[{i}].weights[{j}]"),
                        format!("must be zero or positive (got {w:?})"),
                    ));
                }
            }
            if ch.weights.iter().sum::<f64>() <= 0.0 {
                return Err(SimError::invalid(
                    format!("channels[{i}].weights"),
                    "at least one weight must be positive",
                ));
            }
        }
        Ok(())
    }
}

/// The emitter grid matches the opening and every emitter sits on a closed cell.
fn validate_subpixels(sp: &Subpixels, cells: &[Vec<f64>]) -> Result<(), SimError> {
    let n = cells.len();
    if sp.cells.len() != n {
        return Err(SimError::invalid(
            "subpixels.cells",
            format!(
                "has {} rows; it must match the opening's {n}×{n} cells",
                sp.cells.len()
            ),
        ));
    }
    for (r, row) in sp.cells.iter().enumerate() {
        if row.len() != n {
            return Err(SimError::invalid(
                format!("subpixels.cells[{r}]"),
                format!(
                    "has {} entries; it must match the opening's {n}×{n} cells",
                    row.len()
                ),
            ));
        }
        for (c, s) in row.iter().enumerate() {
            if let Some(s) = s
                && cells[r][c] > 0.0
            {
                return Err(SimError::invalid(
                    format!("subpixels.cells[{r}][{c}]"),
                    format!(
                        "the {} emitter at row {r}, column {c} sits on an open cell; emitters \
                         are opaque and must lie in the closed area",
                        s.name()
                    ),
                ));
            }
        }
    }
    Ok(())
}
