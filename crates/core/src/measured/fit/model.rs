//! The fit's forward model: the design's PSF at a pitch and edge bias, turned, blurred by
//! defocus and moved, on the measurement's pixels.
//!
//! The pitch and the bias change the display, so they need new Fraunhofer intensities (the
//! full fine grid of each wavelength). The rest acts on those intensities:
//! - a turn of the display about the optical axis turns its PSF by the same angle (the circular
//!   pupil does not turn), so the fine grid is resampled on turned coordinates;
//! - defocus spreads every direction of light into the pupil's geometric blur circle of diameter
//!   `Δz / F#` at the sensor. The orders' mutual interference inside the circles has the period
//!   `T Δz / f` (under a micron for millimetre pitches), which the pixels average away, so the
//!   blur is a convolution of the intensity with a uniform disc;
//! - the pixels then integrate the fine samples, and a sub-pixel move (a Fourier phase ramp)
//!   registers the model on the measurement.

use ndarray::Array2;
use rustfft::num_complex::Complex64;

use super::edge::EdgeField;
use crate::SimError;
use crate::design::{Channel, Design};
use crate::display::aperture::{Display, Extent, rasterise};
use crate::measured::shift::{shifted, transform};
use crate::measured::{PsfSet, design_on_grid};
use crate::progress::Progress;
use crate::psf::route::Fraunhofer;
use crate::psf::sampling::{WavelengthSampling, next_fast_size, plan};

/// The fine intensities of one display: per channel, per wavelength, each summing to 1.
pub(super) type Fine = Vec<Vec<Array2<f64>>>;

/// How the fine intensities are laid on the pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Pose {
    /// Turn of the display, degrees counter-clockwise as seen on screen.
    pub rotation_deg: f64,
    /// Diameter of the defocus blur circle at the sensor, µm.
    pub blur_um: f64,
    /// The fine grid's coordinates are read at this multiple (a larger pitch draws the PSF
    /// smaller: the coarse pitch search reads one display's PSF at other pitches this way).
    pub scale: f64,
}

/// The model of one measurement.
pub(super) struct Model<'a> {
    /// The design on the measurement's grid, its channels the measured ones.
    design: Design,
    /// The opening whose edges the bias moves.
    pub edge: EdgeField,
    /// Per channel, per wavelength.
    samplings: Vec<Vec<WavelengthSampling>>,
    /// The measured PSFs on the fit's window, each summing to 1.
    pub measured: Vec<Array2<f64>>,
    /// Each sample's weight in the least squares: one over its noise, as photon noise with a
    /// floor gives it (`1 / √(m + floor)`, the floor a thousandth of the peak): the bright
    /// orders, whose noise is largest, do not drown the halo.
    pub weights: Vec<Array2<f64>>,
    /// Side of the fit's window, pixels.
    pub window_px: usize,
    /// Where the fine intensities are transformed.
    route: &'a dyn Fraunhofer,
    pub progress: &'a Progress,
}

impl<'a> Model<'a> {
    /// The model of `set` from `design`, fitted over the central `window_px` pixels, its fine
    /// intensities transformed on `route`.
    ///
    /// # Errors
    /// A design whose sampling fails on the measurement's grid.
    pub fn new(
        design: &Design,
        set: &PsfSet,
        window_px: usize,
        route: &'a dyn Fraunhofer,
        progress: &'a Progress,
    ) -> Result<Self, SimError> {
        let mut design = design_on_grid(design, set);
        design.channels = set
            .channels
            .iter()
            .enumerate()
            .map(|(i, c)| match c.wavelength_nm {
                Some(w) => Channel::peak(&c.name, w),
                None => matching(&design.channels, &c.name, i),
            })
            .collect();
        let mut warnings = Vec::new();
        let fine_um = design.optics.fine_sample_um;
        let samplings = plan(&design, fine_um, &mut warnings)?;
        let window_px = window_px.min(set.side_px()).max(8);
        let measured: Vec<Array2<f64>> = set
            .channels
            .iter()
            .map(|c| {
                let m = crate::measured::compare::centred_to(&c.psf, window_px);
                let sum = m.sum();
                without_nyquist(&(m / sum))
            })
            .collect();
        let weights = measured
            .iter()
            .map(|m: &Array2<f64>| {
                let floor = 1e-3 * m.iter().copied().fold(0.0, f64::max);
                m.mapv(|v| 1.0 / (v.abs() + floor).sqrt())
            })
            .collect();
        let edge = EdgeField::new(&crate::display::aperture::effective_cells(&design.opening));
        Ok(Model {
            design,
            edge,
            samplings,
            measured,
            weights,
            window_px,
            route,
            progress,
        })
    }

    /// The design as drawn.
    pub fn design(&self) -> &Design {
        &self.design
    }

    /// The refined cell's side at `pitch_um`, µm.
    pub fn cell_um(&self, pitch_um: f64) -> f64 {
        pitch_um / self.edge.n() as f64
    }

    /// The design at `pitch_um` with its edges moved out by `bias_um`.
    pub fn design_at(&self, pitch_um: f64, bias_um: f64) -> Design {
        let mut d = self.design.clone();
        let refine = self.edge.refine() as f64;
        d.opening.cells = self.edge.cells(bias_um / self.cell_um(pitch_um));
        d.opening.polygons.clear();
        // The emitters were placed on the drawn cells, which the refined grid no longer is.
        d.subpixels = None;
        d.opening.pitch_um = pitch_um;
        // The axis stays on the middle of the drawn cell it was on.
        d.tiling.origin_offset_cells = d
            .tiling
            .origin_offset_cells
            .map(|o| (o + 0.5) * refine - 0.5);
        d
    }

    /// The fine intensities of the display at `pitch_um` with its edges moved by `bias_um`.
    ///
    /// # Errors
    /// A display larger than a grid, no light through it, or a cancel.
    pub fn fine(&self, pitch_um: f64, bias_um: f64) -> Result<Fine, SimError> {
        self.progress.check()?;
        let d = self.design_at(pitch_um, bias_um);
        let cells = d.opening.cells.clone();
        let display = Display::from_design(&d, &cells);
        let op = &d.optics;
        let field = rasterise(
            &display,
            Extent::Pupil {
                diameter_um: op.pupil_diameter_um(),
            },
            op.pupil_sample_um,
        );
        self.samplings
            .iter()
            .map(|per| {
                per.iter()
                    .map(|ws| {
                        let i = self.route.full(&field, ws.fft_size, self.progress)?;
                        let total = i.sum();
                        if !(total > 0.0) {
                            return Err(SimError::Sampling("no light passes the display".into()));
                        }
                        Ok(i / total)
                    })
                    .collect()
            })
            .collect()
    }

    /// The model's PSF of each channel on the fit's window, its light's axis `axes_px[c]` from
    /// the window's middle pixel's centre (a move of the light before the pixels integrate it),
    /// then its samples moved by `shifts_px[c]` (as the import's centring moves them),
    /// (`[rows, cols]`), each summing to 1.
    pub fn render(
        &self,
        fine: &Fine,
        pose: Pose,
        axes_px: &[[f64; 2]],
        shifts_px: &[[f64; 2]],
    ) -> Vec<Array2<f64>> {
        fine.iter()
            .zip(&self.samplings)
            .enumerate()
            .map(|(c, (grids, per))| {
                let mut acc = Array2::<f64>::zeros((self.window_px, self.window_px));
                for (grid, ws) in grids.iter().zip(per) {
                    let axis = axes_px.get(c).copied().unwrap_or([0.0, 0.0]);
                    acc.scaled_add(ws.weight, &self.pixels(grid, ws, pose, axis));
                }
                let sum = acc.sum();
                let acc = if sum > 0.0 { acc / sum } else { acc };
                let [dy, dx] = shifts_px.get(c).copied().unwrap_or([0.0, 0.0]);
                let moved = without_nyquist(&shifted(&acc, dy, dx));
                let sum = moved.sum();
                if sum > 0.0 { moved / sum } else { moved }
            })
            .collect()
    }

    /// One wavelength's fine grid turned, blurred and integrated over the window's pixels.
    fn pixels(
        &self,
        grid: &Array2<f64>,
        ws: &WavelengthSampling,
        pose: Pose,
        axis_px: [f64; 2],
    ) -> Array2<f64> {
        let w = self.window_px;
        let spp = ws.binning.samples_per_px;
        let span = w * spp;
        let radius = 0.5 * pose.blur_um.abs() / ws.fine_um;
        // Room for the disc and its transfer function's ringing.
        let pad = if radius > 0.0 {
            (1.5 * radius).ceil() as usize + 2
        } else {
            0
        };
        let side = if pad > 0 {
            next_fast_size(span + 2 * pad)
        } else {
            span
        };
        // Region sample `i` lies `first[axis] + i` fine samples from the axis.
        let first = [0, 1].map(|a| -((w / 2 * spp + ws.binning.phase[a] + pad) as f64));
        let (sin, cos) = pose.rotation_deg.to_radians().sin_cos();
        let h = (grid.nrows() / 2) as f64;
        let mut region = Array2::<f64>::zeros((side, side));
        for ((y, x), v) in region.indexed_iter_mut() {
            let sx = first[0] + x as f64 - axis_px[1] * spp as f64;
            let sy = first[1] + y as f64 - axis_px[0] * spp as f64;
            let u = (cos * sx - sin * sy) * pose.scale + h;
            let t = (sin * sx + cos * sy) * pose.scale + h;
            *v = bilinear(grid, t, u);
        }
        if pad > 0 {
            region = blurred(&region, radius);
        }
        let mut out = Array2::<f64>::zeros((w, w));
        for ((py, px), v) in out.indexed_iter_mut() {
            let (y0, x0) = (pad + py * spp, pad + px * spp);
            *v = (y0..y0 + spp)
                .flat_map(|y| (x0..x0 + spp).map(move |x| (y, x)))
                .map(|at| region[at])
                .sum();
        }
        out
    }
}

/// The design channel a measured channel without a wavelength stands for: the one of its name,
/// else the one at its index (the last one past the end).
fn matching(channels: &[Channel], name: &str, index: usize) -> Channel {
    channels
        .iter()
        .find(|c| c.name.eq_ignore_ascii_case(name))
        .or_else(|| channels.get(index.min(channels.len().saturating_sub(1))))
        .cloned()
        .unwrap_or_else(|| Channel::peak(name, 550.0))
}

/// `a` (square) without its Nyquist row and column of frequencies. A sub-pixel move of real
/// samples (the import's centring, the fit's registration) scales that row and column by
/// `cos(π s)` and leaves every other frequency as a pure phase; an undersampled PSF holds much
/// of its light there, so the fit compares everything but them, where a move cannot be told
/// from a change of the display.
pub(super) fn without_nyquist(a: &Array2<f64>) -> Array2<f64> {
    let n = a.nrows();
    if n % 2 == 1 {
        return a.clone();
    }
    let mut data: Vec<Complex64> = a.iter().map(|v| Complex64::new(*v, 0.0)).collect();
    transform(&mut data, n, false);
    let half = n / 2;
    for k in 0..n {
        data[half * n + k] = Complex64::new(0.0, 0.0);
        data[k * n + half] = Complex64::new(0.0, 0.0);
    }
    transform(&mut data, n, true);
    let scale = 1.0 / (n * n) as f64;
    Array2::from_shape_vec((n, n), data.iter().map(|c| c.re * scale).collect())
        .unwrap_or_else(|_| a.clone())
}

/// `a` (square) with only its frequencies below half the Nyquist frequency.
pub(super) fn low_passed(a: &Array2<f64>) -> Array2<f64> {
    let n = a.nrows();
    let mut data: Vec<Complex64> = a.iter().map(|v| Complex64::new(*v, 0.0)).collect();
    transform(&mut data, n, false);
    let freq = |k: usize| crate::psf::fft::signed(k, n) as f64 / n as f64;
    for (k, d) in data.iter_mut().enumerate() {
        if freq(k / n).hypot(freq(k % n)) > 0.25 {
            *d = Complex64::new(0.0, 0.0);
        }
    }
    transform(&mut data, n, true);
    let scale = 1.0 / (n * n) as f64;
    Array2::from_shape_vec((n, n), data.iter().map(|c| c.re * scale).collect())
        .unwrap_or_else(|_| a.clone())
}

/// `a` at the fractional `[row, col]`, linearly interpolated; 0 outside.
fn bilinear(a: &Array2<f64>, row: f64, col: f64) -> f64 {
    let (r0, c0) = (row.floor(), col.floor());
    let (fr, fc) = (row - r0, col - c0);
    let at = |r: f64, c: f64| {
        if r < 0.0 || c < 0.0 {
            return 0.0;
        }
        a.get((r as usize, c as usize)).copied().unwrap_or(0.0)
    };
    (1.0 - fr) * ((1.0 - fc) * at(r0, c0) + fc * at(r0, c0 + 1.0))
        + fr * ((1.0 - fc) * at(r0 + 1.0, c0) + fc * at(r0 + 1.0, c0 + 1.0))
}

/// `a` (square) convolved circularly with a uniform disc of `radius` samples, through the
/// disc's transfer function `2 J₁(2π r ρ) / (2π r ρ)`: exact for the sampled intensity and
/// smooth in the radius down to none, so the fit has a slope to follow from a sharp start.
fn blurred(a: &Array2<f64>, radius: f64) -> Array2<f64> {
    let n = a.nrows();
    let mut data: Vec<Complex64> = a.iter().map(|v| Complex64::new(*v, 0.0)).collect();
    transform(&mut data, n, false);
    let freq = |k: usize| crate::psf::fft::signed(k, n) as f64 / n as f64;
    for (k, d) in data.iter_mut().enumerate() {
        let rho = freq(k / n).hypot(freq(k % n));
        let z = 2.0 * std::f64::consts::PI * radius * rho;
        let otf = if z < 1e-8 { 1.0 } else { 2.0 * libm::j1(z) / z };
        *d *= otf / (n * n) as f64;
    }
    transform(&mut data, n, true);
    Array2::from_shape_vec((n, n), data.iter().map(|c| c.re).collect())
        .unwrap_or_else(|_| a.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_blur_keeps_the_light_and_adds_a_discs_second_moment() {
        // A smooth spot (σ = 1.5 samples) blurred by a disc of radius 6: the second moments
        // add, 2σ² + r²/2 about the middle.
        let n = 64;
        let a = Array2::from_shape_fn((n, n), |(y, x)| {
            let r2 = (y as f64 - 32.0).powi(2) + (x as f64 - 32.0).powi(2);
            (-r2 / (2.0 * 1.5 * 1.5)).exp()
        });
        let a = &a / a.sum();
        let moment = |b: &Array2<f64>| -> f64 {
            b.indexed_iter()
                .map(|((y, x), v)| v * ((y as f64 - 32.0).powi(2) + (x as f64 - 32.0).powi(2)))
                .sum()
        };
        let b = blurred(&a, 6.0);
        assert!((b.sum() - 1.0).abs() < 1e-9);
        let want = 2.0 * 1.5 * 1.5 + 36.0 / 2.0;
        assert!((moment(&b) / want - 1.0).abs() < 0.03, "{}", moment(&b));
        // Spread: the middle falls to about the spot's share of a disc of radius 6.
        assert!(b[[32, 32]] < 0.2 * a[[32, 32]]);
        // No radius, no blur.
        assert!((&blurred(&a, 0.0) - &a).iter().all(|v| v.abs() < 1e-12));
    }

    #[test]
    fn a_move_and_its_return_keep_everything_but_the_nyquist_frequencies() {
        let a = Array2::from_shape_fn((16, 16), |(y, x)| {
            let (dy, dx) = (y as f64 - 8.0, x as f64 - 8.0);
            (-(dy * dy + dx * dx) / 0.8).exp() + 0.1 * f64::from(u8::from((y + x) % 2 == 0))
        });
        let there_and_back = shifted(&shifted(&a, 0.4, -0.3), -0.4, 0.3);
        let (p, q) = (without_nyquist(&a), without_nyquist(&there_and_back));
        assert!((&p - &q).iter().all(|v| v.abs() < 1e-12));
        // The checkerboard is all Nyquist: the move and return lost part of it.
        assert!((&a - &there_and_back).iter().any(|v| v.abs() > 1e-3));
    }

    #[test]
    fn bilinear_reads_samples_and_midpoints() {
        let a = Array2::from_shape_fn((3, 3), |(r, c)| (r * 3 + c) as f64);
        assert_eq!(bilinear(&a, 1.0, 2.0), 5.0);
        assert_eq!(bilinear(&a, 0.5, 0.5), 2.0);
        assert_eq!(bilinear(&a, -1.0, 0.0), 0.0);
    }
}
