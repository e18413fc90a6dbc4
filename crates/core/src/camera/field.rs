//! Field dependence of the display blur (thesis §3.7, Fig. 3.29).
//!
//! The display sits `z` in front of the lens pupil. A plane wave from field angle
//! `θ = (θx, θy)` crosses the display on its way to the pupil, so the part of the display the
//! pupil sees is shifted by `z·tan θ`: the aperture at field θ is `p(x) · o(x + z·tan θ)`, the
//! display pattern moved by `−z·tan θ` under a fixed pupil. For a periodic tiling that is only a
//! phase of every diffraction order (the PSF changes only through the tiles cut by the pupil's
//! rim); for a random tiling the pupil sees another realisation of the tile orientations and the
//! PSF changes. The lens maps θ to the image height `f·tan θ`; the PSFs here are computed about
//! that chief ray (re-centred), so the residual measures the change of shape only. Relative
//! illumination follows the `cos⁴ θ` law (reported, not applied: each PSF is normalised).
//!
//! The shift is rounded to whole pupil samples δ1: the display is only resolved at δ1, and a
//! sub-sample shift would grey its cell edges through the box filter (a change of sampling, not
//! of physics). It goes through the tiling's registration (`origin_offset_cells`), so every PSF
//! comes from the one analysis entry point.

use crate::Setting;
use ndarray::Array2;

use crate::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use crate::analysis::residual::{Deblur, channel_residuals, mean};
use crate::design::Design;
use crate::psf::route::Fraunhofer;
use crate::{Progress, SimError};

/// Largest display-to-pupil distance accepted, mm.
pub const MAX_DISPLAY_DISTANCE_MM: f64 = 100.0;
/// Largest field angle accepted, degrees.
pub const MAX_FIELD_DEG: f64 = 80.0;
/// Largest field grid per side.
pub const MAX_GRID: usize = 9;

/// What [`field_psfs`] computes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldSettings {
    /// Distance from the display to the lens pupil, mm.
    pub display_distance_mm: f64,
    /// Field angle of the grid's outer points along x and y (the corners sit at this angle on
    /// both axes), degrees.
    pub max_field_deg: f64,
    /// Points per side of the field grid (corners, edges and centre for 3).
    pub grid: usize,
    /// Noise-to-signal ratio of the Wiener filter behind `residual_rel`.
    pub nsr: f64,
    /// Sampling quality of every PSF.
    pub quality: Quality,
}

impl Default for FieldSettings {
    fn default() -> Self {
        FieldSettings {
            display_distance_mm: 1.0,
            max_field_deg: 30.0,
            grid: 3,
            nsr: crate::restore::THESIS_NSR,
            quality: Quality::Preview,
        }
    }
}

impl FieldSettings {
    /// Checks every setting.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] naming the setting.
    pub fn validate(&self) -> Result<(), SimError> {
        let z = self.display_distance_mm;
        if !(z.is_finite() && (0.0..=MAX_DISPLAY_DISTANCE_MM).contains(&z)) {
            return Err(SimError::invalid(
                Setting::DisplayDistanceMm,
                format!("must be between 0 and {MAX_DISPLAY_DISTANCE_MM} mm (got {z:?})"),
            ));
        }
        let t = self.max_field_deg;
        if !(t.is_finite() && t > 0.0 && t <= MAX_FIELD_DEG) {
            return Err(SimError::invalid(
                Setting::MaxFieldDeg,
                format!("must be above 0 and at most {MAX_FIELD_DEG}° (got {t:?})"),
            ));
        }
        if !(2..=MAX_GRID).contains(&self.grid) {
            return Err(SimError::invalid(
                Setting::Grid,
                format!(
                    "must be 2 to {MAX_GRID} points per side (got {})",
                    self.grid
                ),
            ));
        }
        if !(self.nsr.is_finite() && self.nsr >= 0.0) {
            return Err(SimError::invalid(
                Setting::Nsr,
                format!("must be a finite number ≥ 0 (got {:?})", self.nsr),
            ));
        }
        Ok(())
    }
}

/// One point of the field grid.
#[derive(Debug, Clone)]
pub struct FieldPoint {
    /// Field angle `[θx, θy]`, degrees.
    pub field_deg: [f64; 2],
    /// Shift of the display under the pupil, `z·tan θ` rounded to δ1, `[x, y]` in µm.
    pub shift_um: [f64; 2],
    /// Where the chief ray lands on the sensor, `f·tan θ`, `[x, y]` in mm.
    pub image_height_mm: [f64; 2],
    /// `cos⁴ θ` of the angle off the axis (reported, not applied).
    pub relative_illumination: f64,
    /// Sensor PSF per channel, about the chief ray, each summing to 1.
    pub psfs: Vec<Array2<f64>>,
    /// Each channel's PSF deblurred with the centre PSF's Wiener filter.
    pub deblurred: Vec<Array2<f64>>,
    /// `residual_rel` per channel (see the residual module).
    pub residual_rel_per_channel: Vec<f64>,
    /// Mean of `residual_rel_per_channel`.
    pub residual_rel: f64,
}

/// The PSFs over the field.
#[derive(Debug, Clone)]
pub struct FieldResult {
    /// Channel names, in the design's order.
    pub channels: Vec<String>,
    /// The on-axis PSF per channel: the restoration's kernel.
    pub centre: Vec<Array2<f64>>,
    /// The grid, row by row from `θy = −max` to `+max`, each row from `θx = −max` to `+max`.
    pub points: Vec<FieldPoint>,
    /// Largest `residual_rel` of the grid.
    pub max_residual_rel: f64,
    /// Sensor pixel pitch, µm.
    pub sensor_pixel_um: f64,
}

/// The angles of a grid of `n` points per side, degrees.
pub fn grid_angles_deg(max_deg: f64, n: usize) -> Vec<f64> {
    let d = (n.max(2) - 1) as f64;
    (0..n)
        .map(|i| max_deg * (-1.0 + 2.0 * i as f64 / d))
        .collect()
}

/// The design seen from field angle `field_deg` through a display `z_mm` in front of the pupil,
/// and the shift applied (µm, `[x, y]`).
pub fn design_at_field(design: &Design, z_mm: f64, field_deg: [f64; 2]) -> (Design, [f64; 2]) {
    let delta = design.optics.pupil_sample_um;
    let cell = design.opening.cell_um();
    let shift =
        field_deg.map(|deg| (z_mm * 1000.0 * deg.to_radians().tan() / delta).round() * delta);
    let mut d = design.clone();
    for (o, s) in d.tiling.origin_offset_cells.iter_mut().zip(shift) {
        *o += s / cell;
    }
    (d, shift)
}

/// PSFs on a field grid and their residual after deblurring with the centre PSF, each
/// analysis's Fraunhofer step computed by `route` (`&PsfRoute::Auto`: the CPU's choice).
///
/// # Errors
/// Bad settings or design ([`SimError::InvalidSetting`]), sampling errors of the analysis,
/// [`SimError::Cancelled`].
pub fn field_psfs(
    design: &Design,
    settings: &FieldSettings,
    route: &dyn Fraunhofer,
    progress: &Progress,
) -> Result<FieldResult, SimError> {
    settings.validate()?;
    design.validate()?;
    let options = AnalyzeOptions {
        quality: settings.quality,
        expected_psf: false,
    };
    let angles = grid_angles_deg(settings.max_field_deg, settings.grid);
    let total = (angles.len() * angles.len() + 1) as f32;
    progress.set(0.0);
    let psfs_of = |d: &Design| -> Result<Vec<Array2<f64>>, SimError> {
        progress.check()?;
        let a = analyze_with_route(d, &options, route, &Progress::new())?;
        Ok(a.channels.into_iter().map(|c| c.psf).collect())
    };
    let centre_analysis = analyze_with_route(design, &options, route, &Progress::new())?;
    let channels: Vec<String> = centre_analysis
        .channels
        .iter()
        .map(|c| c.name.clone())
        .collect();
    let centre: Vec<Array2<f64>> = centre_analysis
        .channels
        .into_iter()
        .map(|c| c.psf)
        .collect();
    let filters = centre
        .iter()
        .map(|k| Deblur::new(k, settings.nsr))
        .collect::<Result<Vec<_>, _>>()?;
    progress.set(1.0 / total);
    let f_mm = design.optics.focal_length_mm;
    let mut points = Vec::with_capacity(angles.len() * angles.len());
    for &ty in &angles {
        for &tx in &angles {
            let field_deg = [tx, ty];
            let (d, shift_um) = design_at_field(design, settings.display_distance_mm, field_deg);
            let psfs = psfs_of(&d)?;
            let (per, deblurred) = channel_residuals(&filters, &psfs)?;
            let (tanx, tany) = (tx.to_radians().tan(), ty.to_radians().tan());
            let cos_off_axis = 1.0 / (1.0 + tanx * tanx + tany * tany).sqrt();
            points.push(FieldPoint {
                field_deg,
                shift_um,
                image_height_mm: [f_mm * tanx, f_mm * tany],
                relative_illumination: cos_off_axis.powi(4),
                residual_rel: mean(&per),
                residual_rel_per_channel: per,
                psfs,
                deblurred,
            });
            progress.set((points.len() + 1) as f32 / total);
        }
    }
    let max_residual_rel = points.iter().map(|p| p.residual_rel).fold(0.0, f64::max);
    Ok(FieldResult {
        channels,
        centre,
        points,
        max_residual_rel,
        sensor_pixel_um: design.optics.sensor_pixel_um,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_holds_corners_edges_and_centre() {
        assert_eq!(grid_angles_deg(30.0, 3), vec![-30.0, 0.0, 30.0]);
        assert_eq!(grid_angles_deg(10.0, 2), vec![-10.0, 10.0]);
    }

    #[test]
    fn the_shift_is_z_tan_theta_in_whole_samples() {
        let design = Design::default_toled();
        let (d, shift) = design_at_field(&design, 1.0, [45.0, 0.0]);
        assert_eq!(shift, [1000.0, 0.0]);
        let cell = design.opening.cell_um();
        let moved = d.tiling.origin_offset_cells[0] - design.tiling.origin_offset_cells[0];
        assert!((moved - 1000.0 / cell).abs() < 1e-9);
        assert_eq!(
            d.tiling.origin_offset_cells[1],
            design.tiling.origin_offset_cells[1]
        );
    }

    #[test]
    fn bad_settings_are_named() {
        for (s, name) in [
            (
                FieldSettings {
                    display_distance_mm: f64::NAN,
                    ..FieldSettings::default()
                },
                "display_distance_mm",
            ),
            (
                FieldSettings {
                    display_distance_mm: -1.0,
                    ..FieldSettings::default()
                },
                "display_distance_mm",
            ),
            (
                FieldSettings {
                    grid: 100,
                    ..FieldSettings::default()
                },
                "grid",
            ),
            (
                FieldSettings {
                    max_field_deg: 90.0,
                    ..FieldSettings::default()
                },
                "max_field_deg",
            ),
        ] {
            let msg = s
                .validate()
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default();
            assert!(msg.contains(name), "{msg}");
        }
    }
}
