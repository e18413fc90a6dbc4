//! The differentiable image-formation model of the optimizer: cell transmittances → pupil field
//! → per-wavelength Fraunhofer intensity in the sensor window → binned, normalised channel PSF →
//! OTF → `L_inv` (conventions.md §2–3, §6). Every step is the same arithmetic as
//! [`crate::analyze()`] (so `L_inv` here equals the analysis's for the same cells), written
//! out with its adjoint so gradients reach the cells exactly. The window transform and its
//! adjoint go through the Fraunhofer seam ([`Fraunhofer::window_spectrum`]), so a device can
//! run them; the rest (binning, the OTF, the selection of the lowest `H`) stays here.

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::SimError;
use crate::analysis::metrics::{INVERTIBILITY_EPSILON, INVERTIBILITY_FRACTION};
use crate::design::Design;
use crate::display::aperture::{CellMap, Display, Extent};
use crate::psf::route::Fraunhofer;
use crate::psf::sampling::{Binning, WavelengthSampling};
use crate::psf::spectra::{Pool, Span, WindowDft, dft2_complex};

/// One sampled wavelength of one channel.
#[derive(Debug, Clone)]
struct Wave {
    weight: f64,
    m: usize,
    dft: WindowDft,
    /// Sensor pixel of each kept frequency row / column.
    row_px: Vec<usize>,
    col_px: Vec<usize>,
}

/// Where a model's window transforms run: a route through the seam.
#[derive(Clone, Copy)]
struct On<'r>(&'r dyn Fraunhofer);

impl std::fmt::Debug for On<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("dyn Fraunhofer")
    }
}

/// The model of one design geometry (pitch, tiling, optics); the cells are the variables.
#[derive(Debug, Clone)]
pub struct Model<'r> {
    map: CellMap,
    rows: Span,
    cols: Span,
    /// Index of each map sample in the dense `rows × cols` box.
    dense_index: Vec<usize>,
    channels: Vec<Vec<Wave>>,
    /// Side of the square sensor window, in sensor pixels.
    pub window_px: usize,
    /// Cells per side `N` of the opening.
    pub n: usize,
    pool: Pool,
    route: On<'r>,
}

/// The forward pass of one evaluation, kept for [`Model::backward`].
#[derive(Debug, Clone)]
pub struct Forward {
    /// `L_inv` (negative; more negative is better).
    pub loss_inv: f64,
    field: Vec<f64>,
    channels: Vec<ChannelForward>,
    /// The pooled lowest-30 % `H` values as `(H, channel · W² + frequency)`.
    lowest: Vec<(f64, usize)>,
}

#[derive(Debug, Clone)]
struct ChannelForward {
    spectra: Vec<Vec<Complex64>>,
    binned: Vec<Array2<f64>>,
    totals: Vec<f64>,
    sum: f64,
    psf: Array2<f64>,
    otf: Array2<Complex64>,
}

impl Forward {
    /// Per channel sensor PSF (sums to 1, axis at `[W/2, W/2]`).
    pub fn psfs(&self) -> Vec<Array2<f64>> {
        self.channels.iter().map(|c| c.psf.clone()).collect()
    }
}

fn window_span(binning: &Binning, m: usize, axis: usize) -> (Span, Vec<usize>) {
    let h = (m / 2) as i64;
    let kept: Vec<(i64, usize)> = (-h..h)
        .filter_map(|s| binning.pixel_of(s, axis).map(|p| (s, p)))
        .collect();
    let start = kept.first().map_or(0, |k| k.0);
    (
        Span {
            start,
            len: kept.len(),
        },
        kept.into_iter().map(|k| k.1).collect(),
    )
}

impl<'r> Model<'r> {
    /// Builds the model for `design`'s geometry with the given per-channel sampling, its
    /// transforms on `route`.
    ///
    /// # Errors
    /// [`SimError::Sampling`] if the pupil does not fit a grid.
    pub fn new(
        design: &Design,
        samplings: &[Vec<WavelengthSampling>],
        route: &'r dyn Fraunhofer,
    ) -> Result<Self, SimError> {
        let n = design.opening.n();
        let geometry = vec![vec![0.0; n]; n];
        let display = Display::from_design(design, &geometry);
        let op = &design.optics;
        let map = CellMap::new(
            &display,
            Extent::Pupil {
                diameter_um: op.pupil_diameter_um(),
            },
            op.pupil_sample_um,
        );
        let (Some(y0), Some(y1)) = (map.iy.iter().min(), map.iy.iter().max()) else {
            return Err(SimError::Sampling("the pupil holds no sample".into()));
        };
        let (Some(x0), Some(x1)) = (map.ix.iter().min(), map.ix.iter().max()) else {
            return Err(SimError::Sampling("the pupil holds no sample".into()));
        };
        let rows = Span {
            start: *y0,
            len: (y1 - y0 + 1) as usize,
        };
        let cols = Span {
            start: *x0,
            len: (x1 - x0 + 1) as usize,
        };
        let dense_index = map
            .iy
            .iter()
            .zip(&map.ix)
            .map(|(y, x)| (y - y0) as usize * cols.len + (x - x0) as usize)
            .collect();
        let mut channels = Vec::with_capacity(samplings.len());
        for samp in samplings {
            let mut waves = Vec::with_capacity(samp.len());
            for ws in samp {
                let m = ws.fft_size;
                let h = (m / 2) as i64;
                if *y0 < -h || *y1 >= h || *x0 < -h || *x1 >= h {
                    return Err(SimError::Sampling(format!(
                        "the pupil does not fit the {m}-sample FFT grid at {} nm",
                        ws.wavelength_nm
                    )));
                }
                let (freq_rows, row_px) = window_span(&ws.binning, m, 1);
                let (freq_cols, col_px) = window_span(&ws.binning, m, 0);
                waves.push(Wave {
                    weight: ws.weight,
                    m,
                    dft: WindowDft {
                        m,
                        rows,
                        cols,
                        freq_rows,
                        freq_cols,
                    },
                    row_px,
                    col_px,
                });
            }
            channels.push(waves);
        }
        let window_px = samplings
            .first()
            .and_then(|s| s.first())
            .map_or(0, |w| w.binning.window_px);
        Ok(Model {
            map,
            rows,
            cols,
            dense_index,
            channels,
            window_px,
            n,
            pool: Pool::default(),
            route: On(route),
        })
    }

    /// The pupil field of the cells, densely on the model's box.
    fn field(&self, cells: &[f64]) -> Vec<f64> {
        let mut dense = vec![0.0; self.rows.len * self.cols.len];
        for (k, v) in self.map.apply(cells).into_iter().enumerate() {
            dense[self.dense_index[k]] = v;
        }
        dense
    }

    /// The forward pass for `cells` (flattened `N×N`, amplitude in `[0, 1]`).
    ///
    /// # Errors
    /// [`SimError::Sampling`] when no light passes; the route's refusals.
    pub fn forward(&self, cells: &[f64]) -> Result<Forward, SimError> {
        let field = self.field(cells);
        let field_energy: f64 = field.iter().map(|v| v * v).sum();
        if !(field_energy > 0.0) {
            return Err(SimError::Sampling("no light passes the aperture".into()));
        }
        let w = self.window_px;
        let channels: Vec<ChannelForward> = self
            .channels
            .par_iter()
            .map(|waves| -> Result<ChannelForward, SimError> {
                let mut acc = Array2::<f64>::zeros((w, w));
                let mut spectra = Vec::with_capacity(waves.len());
                let mut binned = Vec::with_capacity(waves.len());
                let mut totals = Vec::with_capacity(waves.len());
                for wave in waves {
                    let a = self
                        .route
                        .0
                        .window_spectrum(&wave.dft, &field, &self.pool)?;
                    let nfy = wave.dft.freq_rows.len;
                    let mut b = Array2::<f64>::zeros((w, w));
                    for (j, col) in a.chunks(nfy).enumerate() {
                        let jx = wave.col_px[j];
                        for (i, z) in col.iter().enumerate() {
                            b[[wave.row_px[i], jx]] += z.norm_sqr();
                        }
                    }
                    // Parseval: Σ over the whole M×M grid of |A|² = M² Σ a².
                    let total = (wave.m * wave.m) as f64 * field_energy;
                    acc.scaled_add(wave.weight / total, &b);
                    spectra.push(a);
                    binned.push(b);
                    totals.push(total);
                }
                let sum = acc.sum();
                let psf = acc / sum;
                let otf = dft2_complex(&psf.mapv(|v| Complex64::new(v, 0.0)), false);
                Ok(ChannelForward {
                    spectra,
                    binned,
                    totals,
                    sum,
                    psf,
                    otf,
                })
            })
            .collect::<Result<_, _>>()?;
        if channels.iter().any(|f| !(f.sum > 0.0)) {
            return Err(SimError::Sampling(
                "no light reaches the sensor window".into(),
            ));
        }
        // L_inv: the lowest 30 % of H pooled over the channels (same count as metrics.rs).
        let per = w * w;
        let mut h: Vec<(f64, usize)> = channels
            .iter()
            .enumerate()
            .flat_map(|(c, f)| {
                f.otf.iter().enumerate().map(move |(k, z)| {
                    let p = z.norm_sqr();
                    (p / (p + INVERTIBILITY_EPSILON), c * per + k)
                })
            })
            .collect();
        let count = ((INVERTIBILITY_FRACTION * h.len() as f64).floor() as usize).max(1);
        h.select_nth_unstable_by(count - 1, |a, b| a.0.total_cmp(&b.0));
        h.truncate(count);
        let loss_inv = -h.iter().map(|v| v.0).sum::<f64>() / count as f64;
        Ok(Forward {
            loss_inv,
            field,
            channels,
            lowest: h,
        })
    }

    /// Hands a finished forward pass's buffers back for the next one.
    pub fn recycle(&self, fwd: Forward) {
        for c in fwd.channels {
            for s in c.spectra {
                self.pool.give(s);
            }
        }
    }

    /// The gradient with respect to the cells of `inv_weight · L_inv + Σ_c ⟨extra_c, psf_c⟩`
    /// (`extra` is another loss's `∂/∂psf`, e.g. the data loss's).
    ///
    /// # Errors
    /// The route's refusals (memory, a lost device).
    pub fn backward(
        &self,
        fwd: &Forward,
        inv_weight: f64,
        extra: Option<&[Array2<f64>]>,
    ) -> Result<Vec<f64>, SimError> {
        let w = self.window_px;
        let per = w * w;
        let count = fwd.lowest.len().max(1) as f64;
        // ∂L/∂P at the selected frequencies, P = |K|²; H = P/(P+ε).
        let mut g_power = vec![Array2::<f64>::zeros((w, w)); fwd.channels.len()];
        for &(_, idx) in &fwd.lowest {
            let (c, k) = (idx / per, idx % per);
            let p = fwd.channels[c]
                .otf
                .as_slice()
                .map_or(0.0, |s| s[k].norm_sqr());
            let d = p + INVERTIBILITY_EPSILON;
            if let Some(s) = g_power[c].as_slice_mut() {
                s[k] = -inv_weight * INVERTIBILITY_EPSILON / (d * d) / count;
            }
        }
        let field = &fwd.field;
        let g_field_parts: Vec<Vec<f64>> = fwd
            .channels
            .par_iter()
            .zip(&self.channels)
            .zip(g_power.par_iter())
            .enumerate()
            .map(|(c, ((f, waves), gp))| -> Result<Vec<f64>, SimError> {
                // K = DFT(psf): ∂L/∂psf = Re(DFTᴴ(2 ∂L/∂P · K)).
                let g_otf = ndarray::Zip::from(gp)
                    .and(&f.otf)
                    .map_collect(|g, k| 2.0 * g * k);
                let mut g_psf = dft2_complex(&g_otf, true).mapv(|z| z.re);
                if let Some(e) = extra.and_then(|e| e.get(c)) {
                    g_psf += e;
                }
                // psf = acc / Σacc.
                let dot = (&g_psf * &f.psf).sum();
                let g_acc = (g_psf - dot) / f.sum;
                let mut g_field = vec![0.0; field.len()];
                for (k, wave) in waves.iter().enumerate() {
                    let (b, t) = (&f.binned[k], f.totals[k]);
                    let g_total = -wave.weight / (t * t) * (&g_acc * b).sum();
                    let scale = wave.weight / t;
                    let nfy = wave.dft.freq_rows.len;
                    let mut g_spec = self.pool.take(f.spectra[k].len());
                    for (j, (gcol, col)) in g_spec
                        .chunks_mut(nfy)
                        .zip(f.spectra[k].chunks(nfy))
                        .enumerate()
                    {
                        let jx = wave.col_px[j];
                        for (i, (g, z)) in gcol.iter_mut().zip(col).enumerate() {
                            *g = 2.0 * scale * g_acc[[wave.row_px[i], jx]] * z;
                        }
                    }
                    let back = self
                        .route
                        .0
                        .window_spectrum_adjoint(&wave.dft, &g_spec, &self.pool);
                    self.pool.give(g_spec);
                    let back = back?;
                    // T = M² Σ a²: ∂T/∂a = 2 M² a.
                    let parseval = 2.0 * g_total * (wave.m * wave.m) as f64;
                    for ((g, b), a) in g_field.iter_mut().zip(&back).zip(field) {
                        *g += b + parseval * a;
                    }
                }
                Ok(g_field)
            })
            .collect::<Result<_, _>>()?;
        let mut g_field = vec![0.0; field.len()];
        for part in &g_field_parts {
            for (g, p) in g_field.iter_mut().zip(part) {
                *g += p;
            }
        }
        let g_samples: Vec<f64> = self.dense_index.iter().map(|&i| g_field[i]).collect();
        Ok(self.map.adjoint(&g_samples))
    }
}
