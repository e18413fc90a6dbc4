//! Display appearance (thesis §3.7, Fig. 3.27): what an image looks like on a layout whose
//! R, G, B emitters sit in the opaque area, seen by an eye at a viewing distance, and the
//! display-quality numbers that go beside the camera's AUC.
//!
//! Model (documented in docs/src/conventions.md, "Display appearance"):
//! - the layout is scaled to the chosen DPI (pixel period `25400 / dpi` µm, the opening's `N×N`
//!   cells inside it) and tiled over a square region of whole pixels, each tile in the
//!   orientation the simulation gives it (`tiling::tile_orientation`, tile 0 at the centre);
//! - each emitter cell of colour c emits the image's channel c at that display pixel, scaled by
//!   `N² / (cells of colour c)` so every layout shows a flat field at the same mean radiance;
//! - the eye is a Gaussian PSF whose FWHM subtends `acuity_arcmin` at the viewing distance
//!   (1 arcmin, the 20/20 letter-stroke resolution, by default), applied with wrap-around so the
//!   region has no border;
//! - luminance is Rec. 709: `0.2126 R + 0.7152 G + 0.0722 B`.

use crate::Setting;
use ndarray::Array2;

use crate::SimError;
use crate::design::{Design, Subpixels, TilingMode};
use crate::display::emitters::auto_place;
use crate::display::tiling::tile_orientation;
use crate::progress::Progress;

/// Rec. 709 luminance weights of R, G, B.
pub const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];
/// Largest rendered grid per side, in cells (region × DPI × cells per pixel).
pub const MAX_RENDER_CELLS: usize = 6144;

/// What the eye sees and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AppearanceSettings {
    /// Display resolution, dots per inch; the layout is scaled to this pitch.
    pub dpi: f64,
    /// Distance from the eye to the display, mm.
    pub viewing_distance_mm: f64,
    /// Side of the square display region rendered, mm (thesis Fig. 3.27: 8.4 mm).
    pub region_mm: f64,
    /// FWHM of the eye's Gaussian PSF, arcminutes (1 arcmin = 20/20 acuity).
    pub acuity_arcmin: f64,
}

impl Default for AppearanceSettings {
    fn default() -> Self {
        AppearanceSettings {
            dpi: 300.0,
            viewing_distance_mm: 300.0,
            region_mm: 8.4,
            acuity_arcmin: 1.0,
        }
    }
}

impl AppearanceSettings {
    /// Display pixel pitch at this DPI, µm.
    pub fn pitch_um(&self) -> f64 {
        25400.0 / self.dpi
    }

    /// FWHM of the eye's PSF projected on the display, µm.
    pub fn eye_fwhm_um(&self) -> f64 {
        self.viewing_distance_mm * 1000.0 * (self.acuity_arcmin / 60.0).to_radians().tan()
    }

    /// Display pixels per side of the region (at least 1).
    pub fn pixels_per_side(&self) -> usize {
        ((self.region_mm * 1000.0 / self.pitch_um()).round() as usize).max(1)
    }

    /// Checks every value; the error names the setting.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for the first value out of range.
    pub fn validate(&self, cells_per_pixel: usize) -> Result<(), SimError> {
        let check = |field: Setting, v: f64, lo: f64, hi: f64, unit: &str| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(SimError::invalid(
                    field,
                    format!("must be between {lo} and {hi}{unit} (got {v:?})"),
                ))
            }
        };
        check(Setting::Dpi, self.dpi, 10.0, 5000.0, " DPI")?;
        check(
            Setting::ViewingDistanceMm,
            self.viewing_distance_mm,
            10.0,
            10_000.0,
            " mm",
        )?;
        check(Setting::RegionMm, self.region_mm, 0.1, 100.0, " mm")?;
        check(
            Setting::AcuityArcmin,
            self.acuity_arcmin,
            0.1,
            10.0,
            " arcmin",
        )?;
        let side = self.pixels_per_side() * cells_per_pixel;
        if side > MAX_RENDER_CELLS {
            return Err(SimError::invalid(
                Setting::RegionMm,
                format!(
                    "{} mm at {} DPI with {cells_per_pixel} cells per pixel is {side} cells per \
                     side; at most {MAX_RENDER_CELLS} are rendered: use a smaller region or DPI",
                    self.region_mm, self.dpi
                ),
            ));
        }
        Ok(())
    }
}

/// The display-quality numbers of a layout (definitions in docs/src/conventions.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayQuality {
    /// Coefficient of variation of the eye-blurred luminance of a flat white field (0 = uniform).
    pub nonuniformity: f64,
    /// Energy of (layout − ideal) over the energy of the ideal's contrast, for a slanted
    /// black/white edge, both eye-blurred (0 = indistinguishable from a full-fill display).
    pub aliasing: f64,
    /// Fraction of the flat field's non-DC energy at harmonics of the pixel frequency (1 for a
    /// periodic layout; a random tiling spreads energy elsewhere).
    pub harmonic_fraction: f64,
    /// As `aliasing`, for the image shown.
    pub image_error: f64,
    /// FWHM of the eye's PSF on the display, µm.
    pub eye_fwhm_um: f64,
    /// Display pixels per side of the region.
    pub pixels_per_side: usize,
}

/// An eye-blurred rendering: R, G, B planes resampled to `sample_um`.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendering {
    /// R, G, B planes, linear radiance (1 = a flat white field's mean).
    pub planes: [Array2<f64>; 3],
    /// Sample spacing on the display, µm.
    pub sample_um: f64,
}

/// A layout scaled to the settings, ready to render images.
struct Layout {
    /// Colour index (0..3) of every cell of the region, or `None`.
    colour: Array2<Option<u8>>,
    /// Cells per display pixel side.
    n: usize,
    /// `N² / cells of colour c`: the per-colour emission gain.
    gain: [f64; 3],
    /// Cell size at this DPI, µm.
    cell_um: f64,
}

fn layout(design: &Design, sp: &Subpixels, s: &AppearanceSettings) -> Result<Layout, SimError> {
    let n = design.opening.n();
    let counts = sp.counts();
    if counts.contains(&0) {
        return Err(SimError::invalid(
            "subpixels",
            "every colour needs at least one emitter cell",
        ));
    }
    let px = s.pixels_per_side();
    let side = px * n;
    let half = (px / 2) as i64;
    let mut colour = Array2::from_elem((side, side), None);
    for ty in 0..px {
        for tx in 0..px {
            let d4 = tile_orientation(
                design.tiling.mode,
                design.tiling.seed,
                tx as i64 - half,
                ty as i64 - half,
            );
            for r in 0..n {
                for c in 0..n {
                    let (sr, sc) = d4.source(r, c, n);
                    colour[[ty * n + r, tx * n + c]] = sp.cells[sr][sc].map(|k| k.index() as u8);
                }
            }
        }
    }
    let nn = (n * n) as f64;
    Ok(Layout {
        colour,
        n,
        gain: counts.map(|c| nn / c as f64),
        cell_um: s.pitch_um() / n as f64,
    })
}

/// The design's emitter layer, or an automatic placement when it has none.
///
/// # Errors
/// [`SimError::InvalidSetting`] on `subpixels` when the opening leaves no room for three.
pub fn subpixels_of(design: &Design) -> Result<Subpixels, SimError> {
    match &design.subpixels {
        Some(sp) => Ok(sp.clone()),
        None => auto_place(&design.opening, 0.0).ok_or_else(|| {
            SimError::invalid(
                "subpixels",
                "the design has no emitter layer and its opaque area leaves no room for three \
                 equal R, G, B emitters",
            )
        }),
    }
}

/// The image's value at every display pixel: centre square crop, box-averaged to `px × px`.
fn pixel_values(image: &[Array2<f64>], px: usize) -> Vec<[f64; 3]> {
    let (h, w) = image.first().map_or((0, 0), |p| p.dim());
    let side = h.min(w);
    let mut out = vec![[0.0; 3]; px * px];
    if side == 0 {
        return out;
    }
    let (oy, ox) = ((h - side) / 2, (w - side) / 2);
    for (i, v) in out.iter_mut().enumerate() {
        let (py, pxx) = (i / px, i % px);
        let (y0, y1) = (
            py * side / px,
            ((py + 1) * side / px).max(py * side / px + 1),
        );
        let (x0, x1) = (
            pxx * side / px,
            ((pxx + 1) * side / px).max(pxx * side / px + 1),
        );
        for (k, plane) in image.iter().take(3).enumerate() {
            let mut sum = 0.0;
            for y in y0..y1.min(side) {
                for x in x0..x1.min(side) {
                    sum += plane[[oy + y, ox + x]].clamp(0.0, 1.0);
                }
            }
            v[k] = sum / ((y1.min(side) - y0) * (x1.min(side) - x0)).max(1) as f64;
        }
    }
    // A grey image drives all three channels alike.
    if image.len() == 1 {
        for v in &mut out {
            *v = [v[0]; 3];
        }
    }
    out
}

/// The emitted luminance (or one colour plane) of the layout showing `values`, binned by `bin`.
fn emitted(
    lay: &Layout,
    values: &[[f64; 3]],
    px: usize,
    weights: [f64; 3],
    bin: usize,
) -> Array2<f64> {
    let side = lay.colour.nrows();
    let out_side = side / bin;
    let mut out = Array2::zeros((out_side, out_side));
    let norm = 1.0 / (bin * bin) as f64;
    for ((r, c), k) in lay.colour.indexed_iter() {
        if let Some(k) = *k {
            let k = usize::from(k);
            let v = values[(r / lay.n).min(px - 1) * px + (c / lay.n).min(px - 1)][k];
            out[[r / bin, c / bin]] += weights[k] * v * lay.gain[k] * norm;
        }
    }
    out
}

/// The same image on an ideal full-fill display (every cell emits every channel).
fn ideal(values: &[[f64; 3]], px: usize, n: usize, weights: [f64; 3], bin: usize) -> Array2<f64> {
    let out_side = px * n / bin;
    Array2::from_shape_fn((out_side, out_side), |(r, c)| {
        let v = values[(r * bin / n) * px + (c * bin / n)];
        (0..3).map(|k| weights[k] * v[k]).sum()
    })
}

/// Gaussian blur with wrap-around, separable; `sigma` in samples.
fn blur(img: &Array2<f64>, sigma: f64) -> Array2<f64> {
    let (h, w) = img.dim();
    if sigma <= 0.0 || h == 0 {
        return img.clone();
    }
    let radius = ((4.0 * sigma).ceil() as usize).min(h.max(w));
    let mut kernel: Vec<f64> = (0..=2 * radius)
        .map(|i| {
            let x = i as f64 - radius as f64;
            (-0.5 * (x / sigma).powi(2)).exp()
        })
        .collect();
    let sum: f64 = kernel.iter().sum();
    kernel.iter_mut().for_each(|k| *k /= sum);
    // Along rows, then along columns (a transposed pass): each output sample is a dot product
    // over a contiguous, wrapped copy of its row, summed in the kernel's order.
    let rows = blur_rows(img, &kernel, radius);
    let cols = blur_rows(&rows.t().as_standard_layout().into_owned(), &kernel, radius);
    cols.t().as_standard_layout().into_owned()
}

/// Kernels longer than this are applied by the FFT ([`blur_rows_fft`]): the direct sum's cost
/// grows with the kernel, the transform's only with the row. A fine layout whose cells per pixel
/// have no divisor to bin by keeps σ at 10 … 40 samples, a kernel of 80 … 320 taps.
const DIRECT_TAPS: usize = 48;

/// Circular convolution of every row with `kernel` (length `2·radius + 1`, centred).
fn blur_rows(src: &Array2<f64>, kernel: &[f64], radius: usize) -> Array2<f64> {
    if kernel.len() > DIRECT_TAPS {
        return blur_rows_fft(src, kernel, radius);
    }
    blur_rows_direct(src, kernel, radius)
}

/// [`blur_rows`] as the direct sum over the kernel's taps.
fn blur_rows_direct(src: &Array2<f64>, kernel: &[f64], radius: usize) -> Array2<f64> {
    use ndarray::Zip;
    let w = src.ncols();
    let mut out = Array2::zeros(src.dim());
    Zip::from(out.rows_mut())
        .and(src.rows())
        .par_for_each(|mut out_row, row| {
            let wrapped: Vec<f64> = (0..w + 2 * radius)
                .map(|j| row[(j as i64 - radius as i64).rem_euclid(w as i64) as usize])
                .collect();
            for (c, o) in out_row.iter_mut().enumerate() {
                *o = wrapped[c..c + kernel.len()]
                    .iter()
                    .zip(kernel)
                    .map(|(x, k)| x * k)
                    .sum();
            }
        });
    out
}

/// [`blur_rows`] by the FFT: output sample `c` is `Σ_i row[(c + i − radius) mod w]·kernel[i]`,
/// the circular correlation of the row with the kernel folded onto its `w` samples. The folded
/// kernel is real, so two rows share one complex transform (one as the real part, the other as
/// the imaginary part) and come back apart. Equal to the direct sum to rounding (~1e-15).
fn blur_rows_fft(src: &Array2<f64>, kernel: &[f64], radius: usize) -> Array2<f64> {
    use rayon::prelude::*;
    use rustfft::num_complex::Complex64;
    let (h, w) = src.dim();
    if w == 0 {
        return src.clone();
    }
    let forward = udc_fft::complex_plan(w);
    let inverse = udc_fft::complex_inverse_plan(w);
    let mut folded = vec![Complex64::new(0.0, 0.0); w];
    for (i, k) in kernel.iter().enumerate() {
        folded[(i as i64 - radius as i64).rem_euclid(w as i64) as usize].re += k;
    }
    forward.process(&mut folded);
    // A correlation multiplies by the kernel's conjugate spectrum; the inverse's 1/w is folded in.
    let filter: Vec<Complex64> = folded.iter().map(|k| k.conj() / w as f64).collect();
    let pairs: Vec<Vec<Complex64>> = (0..h.div_ceil(2))
        .into_par_iter()
        .map(|p| {
            let (a, b) = (2 * p, 2 * p + 1);
            let mut buf: Vec<Complex64> = (0..w)
                .map(|c| Complex64::new(src[[a, c]], if b < h { src[[b, c]] } else { 0.0 }))
                .collect();
            forward.process(&mut buf);
            for (v, f) in buf.iter_mut().zip(&filter) {
                *v *= f;
            }
            inverse.process(&mut buf);
            buf
        })
        .collect();
    let mut out = Array2::zeros((h, w));
    for (p, buf) in pairs.iter().enumerate() {
        for (c, v) in buf.iter().enumerate() {
            out[[2 * p, c]] = v.re;
            if 2 * p + 1 < h {
                out[[2 * p + 1, c]] = v.im;
            }
        }
    }
    out
}

/// Samples per eye σ below which binning stops: a Gaussian of σ = 2 samples is still well
/// sampled, so the binned grid resolves the blur.
const SAMPLES_PER_SIGMA: f64 = 2.0;

/// Largest divisor of `n` that keeps at least [`SAMPLES_PER_SIGMA`] samples per σ, so a bin
/// never straddles two display pixels.
fn bin_of(n: usize, sigma_cells: f64) -> usize {
    let limit = (sigma_cells / SAMPLES_PER_SIGMA).floor().max(1.0) as usize;
    (1..=n.min(limit))
        .rev()
        .find(|b| n.is_multiple_of(*b))
        .unwrap_or(1)
}

fn cv(img: &Array2<f64>) -> f64 {
    let mean = img.mean().unwrap_or(0.0);
    if mean <= 0.0 {
        return 0.0;
    }
    let var = img.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / img.len().max(1) as f64;
    var.sqrt() / mean
}

/// `Σ(a − b)² / Σ(b − mean b)²`: the error energy relative to the ideal's contrast energy.
fn relative_error(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
    let mean = b.mean().unwrap_or(0.0);
    let contrast: f64 = b.iter().map(|v| (v - mean).powi(2)).sum();
    if contrast <= 0.0 {
        return 0.0;
    }
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / contrast
}

/// Fraction of the non-DC energy of `img` that is periodic with the pixel (`period` samples):
/// by Parseval, the energy at the pixel-frequency harmonics.
fn harmonic_fraction(img: &Array2<f64>, period: usize) -> f64 {
    let (h, w) = img.dim();
    let mean = img.mean().unwrap_or(0.0);
    let total: f64 = img.iter().map(|v| (v - mean).powi(2)).sum();
    if total <= 0.0 || period == 0 {
        return 0.0;
    }
    let mut fold = Array2::<f64>::zeros((period, period));
    for ((r, c), v) in img.indexed_iter() {
        fold[[r % period, c % period]] += v;
    }
    let copies = ((h / period) * (w / period)).max(1) as f64;
    let periodic: f64 = fold
        .iter()
        .map(|s| (s / copies - mean).powi(2))
        .sum::<f64>()
        * copies;
    (periodic / total).clamp(0.0, 1.0)
}

/// A slanted black/white edge (white on the left, slope 1 : 8) at `px × px` display pixels.
fn edge_values(px: usize) -> Vec<[f64; 3]> {
    (0..px * px)
        .map(|i| {
            let (y, x) = ((i / px) as f64, (i % px) as f64);
            let v = if x + 0.5 < px as f64 / 2.0 + (y - px as f64 / 2.0) / 8.0 {
                1.0
            } else {
                0.0
            };
            [v; 3]
        })
        .collect()
}

/// The design tiled periodically and randomly (its own random mode, else random D4), with
/// their labels: Fig. 3.27's side-by-side pair.
pub fn periodic_and_random(design: &Design) -> [(String, Design); 2] {
    let mut periodic = design.clone();
    periodic.tiling.mode = TilingMode::Repeat;
    let mut random = design.clone();
    if !random.tiling.mode.is_random() {
        random.tiling.mode = TilingMode::RandomD4;
    }
    let random_label = format!("random ({})", random.tiling.mode.as_str());
    [("periodic".into(), periodic), (random_label, random)]
}

/// Renders `image` (R, G, B or one grey plane, values in `[0, 1]`) on the design's layout and
/// measures the display quality.
///
/// # Errors
/// Bad settings, a design whose emitters do not fit, or cancellation.
pub fn appearance(
    design: &Design,
    image: &[Array2<f64>],
    settings: &AppearanceSettings,
    progress: &Progress,
) -> Result<(DisplayQuality, Rendering), SimError> {
    settings.validate(design.opening.n())?;
    let sp = subpixels_of(design)?;
    let lay = layout(design, &sp, settings)?;
    let px = settings.pixels_per_side();
    let sigma_cells = settings.eye_fwhm_um() / (8.0 * 2f64.ln()).sqrt() / lay.cell_um;
    let bin = bin_of(lay.n, sigma_cells);
    let sigma = sigma_cells / bin as f64;
    let white = vec![[1.0; 3]; px * px];
    progress.check()?;
    let flat = blur(&emitted(&lay, &white, px, LUMA, bin), sigma);
    progress.set(0.2);
    progress.check()?;
    let edge = edge_values(px);
    let edge_layout = blur(&emitted(&lay, &edge, px, LUMA, bin), sigma);
    let edge_ideal = blur(&ideal(&edge, px, lay.n, LUMA, bin), sigma);
    progress.set(0.4);
    progress.check()?;
    let values = pixel_values(image, px);
    let mut planes = Vec::with_capacity(3);
    let mut image_luma: Option<Array2<f64>> = None;
    for k in 0..3 {
        let mut w = [0.0; 3];
        w[k] = 1.0;
        let plane = blur(&emitted(&lay, &values, px, w, bin), sigma);
        image_luma = Some(match image_luma {
            None => plane.mapv(|v| v * LUMA[k]),
            Some(acc) => acc + plane.mapv(|v| v * LUMA[k]),
        });
        planes.push(plane);
        progress.set(0.4 + 0.15 * (k + 1) as f32);
        progress.check()?;
    }
    let image_ideal = blur(&ideal(&values, px, lay.n, LUMA, bin), sigma);
    let image_error = image_luma.map_or(0.0, |l| relative_error(&l, &image_ideal));
    progress.set(1.0);
    let quality = DisplayQuality {
        nonuniformity: cv(&flat),
        aliasing: relative_error(&edge_layout, &edge_ideal),
        harmonic_fraction: harmonic_fraction(&flat, lay.n / bin),
        image_error,
        eye_fwhm_um: settings.eye_fwhm_um(),
        pixels_per_side: px,
    };
    let [r, g, b]: [Array2<f64>; 3] = planes
        .try_into()
        .map_err(|_| SimError::Sampling("three colour planes expected".into()))?;
    Ok((
        quality,
        Rendering {
            planes: [r, g, b],
            sample_um: lay.cell_um * bin as f64,
        },
    ))
}

/// A preset's place on the appearance scatter.
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterPoint {
    /// Preset name.
    pub name: String,
    /// Radially-minimum AUC averaged over the channels (preview quality).
    pub camera_auc: f64,
    /// Eye-blurred flat-field nonuniformity at the view's DPI and distance.
    pub nonuniformity: f64,
}

/// The presets' camera AUC against their display nonuniformity: the trade-off a layout makes
/// between the camera behind it and the eye in front of it. One named point a preset.
pub fn scatter_panel(points: &[ScatterPoint]) -> crate::figure::Panel {
    use crate::figure::{Axis, Mark, Panel, Series, palette};
    Panel {
        title: "Presets: camera AUC against display nonuniformity".into(),
        x: Axis::new("camera AUC", None),
        y: Axis::new("display nonuniformity", None),
        series: points
            .iter()
            .enumerate()
            .map(|(i, p)| Series {
                name: p.name.clone(),
                colour: palette::series(i),
                mark: Mark::Points,
                points: vec![[p.camera_auc, p.nonuniformity]],
                band: None,
            })
            .collect(),
        ..Panel::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transform's rows equal the direct sum's, for an odd number of rows (the last one
    /// without a partner) and kernels 1.4 to 10 times the row's length (wrapping it once and
    /// several times), one of them asymmetric so a convolution would not pass for a correlation.
    #[test]
    fn the_transform_blurs_rows_as_the_direct_sum_does() {
        let img = Array2::from_shape_fn((9, 40), |(r, c)| ((r * 37 + c * 13) % 17) as f64 / 16.0);
        for (sigma, w) in [(12.5_f64, 40), (6.1, 37), (30.0, 23)] {
            let img = Array2::from_shape_fn((9, w), |(r, c)| img[[r, c % 40]]);
            let radius = (4.0 * sigma).ceil() as usize;
            let kernel: Vec<f64> = (0..=2 * radius)
                .map(|i| {
                    (-0.5 * ((i as f64 - radius as f64) / sigma).powi(2)).exp() + 0.01 * i as f64
                })
                .collect();
            assert!(kernel.len() > DIRECT_TAPS);
            let direct = blur_rows_direct(&img, &kernel, radius);
            let fft = blur_rows_fft(&img, &kernel, radius);
            for ((at, d), f) in direct.indexed_iter().zip(fft.iter()) {
                assert!(
                    (d - f).abs() < 1e-12 * (1.0 + d.abs()),
                    "σ {sigma}, w {w} at {at:?}: {d} vs {f}"
                );
            }
        }
    }

    /// The separable blur equals the direct wrapped 2-D sum it stands for, also when the kernel
    /// is wider than the image and wraps more than once.
    #[test]
    fn blur_is_the_wrapped_gaussian_sum() {
        // The last case's kernel (61 taps) takes the transform, the others the direct sum.
        for (h, w, sigma) in [(7, 5, 0.6_f64), (7, 5, 1.7), (7, 5, 3.0), (30, 26, 12.5)] {
            let img =
                Array2::from_shape_fn((h, w), |(r, c)| ((r * 31 + c * 17) % 11) as f64 / 10.0);
            let radius = ((4.0 * sigma).ceil() as usize).min(h.max(w)) as i64;
            let g = |d: i64| (-0.5 * (d as f64 / sigma).powi(2)).exp();
            let norm: f64 = (-radius..=radius).map(g).sum();
            let got = blur(&img, sigma);
            for ((r, c), v) in got.indexed_iter() {
                let mut want = 0.0;
                for dr in -radius..=radius {
                    for dc in -radius..=radius {
                        let rr = (r as i64 + dr).rem_euclid(h as i64) as usize;
                        let cc = (c as i64 + dc).rem_euclid(w as i64) as usize;
                        want += img[[rr, cc]] * g(dr) * g(dc) / (norm * norm);
                    }
                }
                assert!(
                    (v - want).abs() < 1e-12,
                    "σ {sigma} at ({r}, {c}): {v} vs {want}"
                );
            }
        }
    }
}
