//! Fraunhofer intensities `|DFT(a)|²` of real fields, computed the cheap way:
//! real-input FFTs over the field's nonzero rows only, then complex FFTs over the `M/2 + 1`
//! non-redundant columns, mirroring the rest through `|A(−u)| = |A(u)|`. Columns are streamed
//! into the consumer (binning or a dense array), so a large grid never sits in memory twice.
//! Plans come from `udc-fft`'s process-wide cache; rows and columns run in parallel on rayon's
//! pool.

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use udc_fft::{complex_plan, real_plan};

use crate::SimError;
use crate::display::aperture::Field;
use crate::display::tiling::D4;
use crate::progress::Progress;
use crate::psf::sampling::Binning;

/// Checks that `m` is an even grid size of at least 2 and that `field` fits the `m×m` grid
/// centred on the axis (every route, the CPU's and a device's, refuses with the same words).
pub fn check_grid<T>(field: &Field<T>, m: usize) -> Result<(), SimError> {
    if m < 2 || !m.is_multiple_of(2) {
        return Err(SimError::Sampling(format!(
            "FFT size {m} must be even and at least 2"
        )));
    }
    let (lo, hi) = field.extent();
    let h = (m / 2) as i64;
    if lo < -h || hi >= h {
        return Err(SimError::Sampling(format!(
            "the aperture spans samples {lo}..={hi} but the FFT grid holds only {}..={}",
            -h,
            h - 1
        )));
    }
    Ok(())
}

/// Row spectra of the field's rows (`M/2 + 1` bins each), transposed to column-major
/// (`[kx][row]`) so the column pass reads contiguous memory, and the grid row of each row.
fn column_spectra(field: &Field, m: usize) -> (Vec<usize>, Vec<Complex64>) {
    let plan = real_plan(m);
    let h = (m / 2) as i64;
    let bins = m / 2 + 1;
    let n_rows = field.rows.len();
    let mut row_major = vec![Complex64::new(0.0, 0.0); n_rows * bins];
    row_major
        .par_chunks_mut(bins)
        .zip(field.rows.par_iter())
        .for_each_init(
            || (plan.make_input_vec(), plan.make_scratch_vec()),
            |(input, scratch), (out, row)| {
                input.iter_mut().for_each(|v| *v = 0.0);
                let start = (row.ix0 + h) as usize;
                input[start..start + row.values.len()].copy_from_slice(&row.values);
                // Lengths come from the plan itself, so this cannot fail.
                let _ = plan.process_with_scratch(input, out, scratch);
            },
        );
    let mut col_major = vec![Complex64::new(0.0, 0.0); n_rows * bins];
    const BLOCK: usize = 32;
    col_major
        .par_chunks_mut(n_rows * BLOCK)
        .enumerate()
        .for_each(|(b, chunk)| {
            let kx0 = b * BLOCK;
            for (r, row) in row_major.chunks(bins).enumerate() {
                for (dk, v) in row[kx0..(kx0 + BLOCK).min(bins)].iter().enumerate() {
                    chunk[dk * n_rows + r] = *v;
                }
            }
        });
    let rows = field.rows.iter().map(|r| (r.iy + h) as usize).collect();
    (rows, col_major)
}

/// Streams `|A|²` column by column: `visit(acc, s_x, column)` receives the signed column offset
/// `s_x ∈ [−M/2, M/2)` and the intensities of that column indexed by DFT row index `k_y`
/// (signed offset `k_y` if `k_y < M/2`, else `k_y − M`). Every one of the `M` columns is visited
/// exactly once. Per-thread accumulators are merged with `merge`.
fn fold_columns<A, I, V, R>(
    field: &Field,
    m: usize,
    progress: &Progress,
    init: I,
    visit: V,
    merge: R,
) -> Result<A, SimError>
where
    A: Send,
    I: Fn() -> A + Sync + Send,
    V: Fn(&mut A, i64, &[f64]) + Sync + Send,
    R: Fn(A, A) -> A + Sync + Send,
{
    check_grid(field, m)?;
    // A display that lets no light through (an opening closed by an edit or a fit's step)
    // has no rows to transform.
    if field.rows.is_empty() {
        return Err(SimError::Sampling("no light passes the aperture".into()));
    }
    progress.check()?;
    let (grid_rows, spectra) = column_spectra(field, m);
    let n_rows = grid_rows.len();
    progress.check()?;
    let plan = complex_plan(m);
    let half = m / 2;
    // Fixed chunks merged in index order: the floating-point sums come out the same bit for bit
    // whatever the thread scheduling (rayon's fold/reduce would merge in a racy order).
    let n_cols = half + 1;
    // Eight chunks keep both cores busy while holding only eight window-sized accumulators.
    let chunk = n_cols.div_ceil(8).max(8);
    let starts: Vec<usize> = (0..n_cols).step_by(chunk).collect();
    let partials: Vec<A> = starts
        .par_iter()
        .map(|&first| {
            let mut acc = init();
            let mut col = vec![Complex64::new(0.0, 0.0); m];
            let mut scratch = vec![Complex64::new(0.0, 0.0); plan.get_inplace_scratch_len()];
            let mut inten = vec![0.0f64; m];
            let mut mirrored = vec![0.0f64; m];
            for kx in first..(first + chunk).min(n_cols) {
                if progress.is_cancelled() {
                    break;
                }
                col.iter_mut().for_each(|c| *c = Complex64::new(0.0, 0.0));
                let src = &spectra[kx * n_rows..(kx + 1) * n_rows];
                for (r, v) in grid_rows.iter().zip(src) {
                    col[*r] = *v;
                }
                plan.process_with_scratch(&mut col, &mut scratch);
                for (i, c) in col.iter().enumerate() {
                    inten[i] = c.norm_sqr();
                }
                let s = if kx == half {
                    -(half as i64)
                } else {
                    kx as i64
                };
                visit(&mut acc, s, &inten);
                if kx != 0 && kx != half {
                    // Column −kx of a real field: A(−ky, −kx) = conj A(ky, kx).
                    mirrored[0] = inten[0];
                    for ky in 1..m {
                        mirrored[ky] = inten[m - ky];
                    }
                    visit(&mut acc, -(kx as i64), &mirrored);
                }
            }
            acc
        })
        .collect();
    let result = partials.into_iter().reduce(&merge);
    progress.check()?;
    result.ok_or_else(|| SimError::Sampling("empty FFT".into()))
}

/// `r·exp(i(a2 k² + a1 k))` for `k = from, from + 1, …`: chirps and ramps without an
/// exponential per sample. Every 64th value is exact (its phase reduced mod 2π in double
/// precision first); in between a second-order recurrence multiplies the last value by a
/// step that itself advances by `exp(2i a2)`, so the rounding stays ~1e-14.
pub fn quadratic_phase(a2: f64, a1: f64, from: i64, r: f64) -> impl Iterator<Item = Complex64> {
    const BLOCK: i64 = 64;
    let exact = move |k: f64, c2: f64, c1: f64| {
        Complex64::from_polar(
            1.0,
            (c2 * k * k + c1 * k).rem_euclid(2.0 * std::f64::consts::PI),
        )
    };
    let turn = exact(1.0, 2.0 * a2, 0.0);
    let mut value = Complex64::new(0.0, 0.0);
    let mut step = Complex64::new(0.0, 0.0);
    (from..).map(move |k| {
        if (k - from) % BLOCK == 0 {
            value = exact(k as f64, a2, a1);
            // exp(i(a2(2k+1) + a1)): the ratio of the next value to this one.
            step = Complex64::from_polar(
                1.0,
                (a2 * (2.0 * k as f64 + 1.0) + a1).rem_euclid(2.0 * std::f64::consts::PI),
            );
        } else {
            value *= step;
            step *= turn;
        }
        value * r
    })
}

/// Signed offset of DFT index `k` on an `m` grid.
#[inline]
pub fn signed(k: usize, m: usize) -> i64 {
    if k < m / 2 {
        k as i64
    } else {
        k as i64 - m as i64
    }
}

/// Sensor-binned intensity of one field.
#[derive(Debug, Clone)]
pub struct Binned {
    /// `[row, col]` sums of `|A|²` over each sensor pixel of the window (axis pixel at `W/2`).
    pub sensor: Array2<f64>,
    /// `Σ |A|²` over the whole `M×M` grid.
    pub total: f64,
    /// `Σ |A|²` over the outer band of the grid (`|offset| ≥ 0.45 M` on either axis), where the
    /// periodic DFT wraps light around: a measure of aliasing.
    pub edge: f64,
}

/// `|DFT_M(a)|²` integrated over the sensor pixels of `binning`'s window by the full route:
/// every column FFT, every sample binned (the reference; the route module picks the pruned route
/// when it is cheaper).
///
/// # Errors
/// [`SimError::Sampling`] if the field does not fit the grid; [`SimError::Cancelled`].
pub fn binned_intensity(
    field: &Field,
    m: usize,
    binning: &Binning,
    progress: &Progress,
) -> Result<Binned, SimError> {
    let w = binning.window_px;
    let row_pixel: Vec<Option<usize>> = (0..m)
        .map(|ky| binning.pixel_of(signed(ky, m), 1))
        .collect();
    let edge_from = (0.45 * m as f64).ceil() as i64;
    let edge_rows: Vec<usize> = (0..m)
        .filter(|&ky| signed(ky, m).abs() >= edge_from)
        .collect();
    // Accumulated column-major (`[jx][jy]`) so each fine column adds into contiguous memory.
    let (sensor_t, total, edge) = fold_columns(
        field,
        m,
        progress,
        || (vec![0.0f64; w * w], 0.0f64, 0.0f64),
        |(acc, total, edge), s, inten| {
            let col_sum = inten.iter().sum::<f64>();
            *total += col_sum;
            *edge += if s.abs() >= edge_from {
                col_sum
            } else {
                edge_rows.iter().map(|&ky| inten[ky]).sum::<f64>()
            };
            if let Some(jx) = binning.pixel_of(s, 0) {
                let out = &mut acc[jx * w..(jx + 1) * w];
                for (v, p) in inten.iter().zip(&row_pixel) {
                    if let Some(jy) = p {
                        out[*jy] += v;
                    }
                }
            }
        },
        |(mut a, ta, ea), (b, tb, eb)| {
            a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
            (a, ta + tb, ea + eb)
        },
    )?;
    let sensor = Array2::from_shape_fn((w, w), |(jy, jx)| sensor_t[jx * w + jy]);
    Ok(Binned {
        sensor,
        total,
        edge,
    })
}

/// `Σ_g bin(|FT(g·a)|²) / |G|` for an orbit of D4 elements, where `|FT(g·a)|²` is `|FT(a)|²`
/// with its frequency axes flipped/swapped ([`D4::source_frequency`]). One transform serves the
/// whole orbit; each element only changes which sensor pixel a fine sample lands in. Returns the
/// binned mean and the mean total (`= total`, flips preserve energy).
///
/// # Errors
/// As [`binned_intensity`].
pub fn binned_orbit_intensity(
    field: &Field,
    m: usize,
    binning: &Binning,
    group: &[D4],
    progress: &Progress,
) -> Result<Binned, SimError> {
    let w = binning.window_px;
    let mi = m as i64;
    let wrap = |v: i64| -> i64 { (v + mi / 2).rem_euclid(mi) - mi / 2 };
    let tab = |axis: usize, negate: bool| -> Vec<Option<usize>> {
        (0..m)
            .map(|k| {
                let t = signed(k, m);
                binning.pixel_of(wrap(if negate { -t } else { t }), axis)
            })
            .collect()
    };
    // Tables indexed by DFT row index ky: pixel along y or x of ±t.
    let ty = [tab(1, false), tab(1, true)];
    let tx = [tab(0, false), tab(0, true)];
    let weight = 1.0 / group.len().max(1) as f64;
    let (sensor, total) = fold_columns(
        field,
        m,
        progress,
        || (Array2::<f64>::zeros((w, w)), 0.0f64),
        |(acc, total), s, inten| {
            *total += inten.iter().sum::<f64>();
            for g in group {
                let (ny, nx) = (usize::from(g.flip_ud), usize::from(g.flip_lr));
                if g.transpose {
                    // jy from the column offset, jx from the row offset.
                    let Some(jy) = binning.pixel_of(wrap(if g.flip_ud { -s } else { s }), 1) else {
                        continue;
                    };
                    let mut row = acc.row_mut(jy);
                    for (v, p) in inten.iter().zip(&tx[nx]) {
                        if let Some(jx) = p {
                            row[*jx] += weight * v;
                        }
                    }
                } else {
                    let Some(jx) = binning.pixel_of(wrap(if g.flip_lr { -s } else { s }), 0) else {
                        continue;
                    };
                    let mut col = acc.column_mut(jx);
                    for (v, p) in inten.iter().zip(&ty[ny]) {
                        if let Some(jy) = p {
                            col[*jy] += weight * v;
                        }
                    }
                }
            }
        },
        |(a, ta), (b, tb)| (a + b, ta + tb),
    )?;
    let edge = 0.0;
    Ok(Binned {
        sensor,
        total,
        edge,
    })
}

/// The full centred `M×M` intensity `|DFT_M(a)|²` (axis at `[M/2, M/2]`).
///
/// # Errors
/// As [`binned_intensity`].
pub fn full_intensity(
    field: &Field,
    m: usize,
    progress: &Progress,
) -> Result<Array2<f64>, SimError> {
    let cols = fold_columns(
        field,
        m,
        progress,
        Vec::new,
        |acc: &mut Vec<(i64, Vec<f64>)>, s, inten| acc.push((s, inten.to_vec())),
        |mut a, mut b| {
            a.append(&mut b);
            a
        },
    )?;
    let h = (m / 2) as i64;
    let mut out = Array2::<f64>::zeros((m, m));
    for (s, col) in cols {
        let x = (s + h) as usize;
        for (ky, v) in col.iter().enumerate() {
            let y = (signed(ky, m) + h) as usize;
            out[[y, x]] = *v;
        }
    }
    Ok(out)
}

/// `|DFT_M(a)|²` of a complex field (a pupil with a phase) binned to `binning`'s window, with
/// the grid's total and its outer band as [`Binned`] has them: the dense `M×M` transform (the
/// field has no mirror symmetry to halve it by), rows then columns, in parallel. The CPU's
/// route for the Fraunhofer seam's `binned_complex`.
///
/// # Errors
/// [`SimError::Sampling`] if the field does not fit the grid or passes no light;
/// [`SimError::Cancelled`].
pub fn binned_intensity_complex(
    field: &Field<Complex64>,
    m: usize,
    binning: &Binning,
    progress: &Progress,
) -> Result<Binned, SimError> {
    check_grid(field, m)?;
    let mut data = vec![Complex64::new(0.0, 0.0); m * m];
    for r in &field.rows {
        let y = r.iy.rem_euclid(m as i64) as usize;
        for (j, v) in r.values.iter().enumerate() {
            let x = (r.ix0 + j as i64).rem_euclid(m as i64) as usize;
            data[y * m + x] = *v;
        }
    }
    let plan = complex_plan(m);
    data.par_chunks_mut(m).for_each(|row| plan.process(row));
    progress.check()?;
    let mut t = vec![Complex64::new(0.0, 0.0); m * m];
    t.par_chunks_mut(m).enumerate().for_each(|(x, col)| {
        for (y, c) in col.iter_mut().enumerate() {
            *c = data[y * m + x];
        }
    });
    t.par_chunks_mut(m).for_each(|col| plan.process(col));
    progress.check()?;
    // t[kx·m + ky] now holds the transform at (ky, kx); centre it (axis at m/2).
    let h = (m / 2) as i64;
    let edge_from = (0.45 * m as f64).ceil() as i64;
    let mut fine = Array2::<f64>::zeros((m, m));
    let (mut total, mut edge) = (0.0, 0.0);
    for (kx, col) in t.chunks(m).enumerate() {
        let s = signed(kx, m);
        let cx = (s + h) as usize;
        for (ky, v) in col.iter().enumerate() {
            let p = v.norm_sqr();
            let t = signed(ky, m);
            total += p;
            if s.abs() >= edge_from || t.abs() >= edge_from {
                edge += p;
            }
            fine[[(t + h) as usize, cx]] = p;
        }
    }
    if !(total > 0.0) {
        return Err(SimError::Sampling("no light passes the aperture".into()));
    }
    Ok(Binned {
        sensor: bin_dense(&fine, binning),
        total,
        edge,
    })
}

/// Integrates a centred fine `M×M` array over the sensor pixels of `binning`.
pub fn bin_dense(fine: &Array2<f64>, binning: &Binning) -> Array2<f64> {
    let m = fine.nrows();
    let h = (m / 2) as i64;
    let w = binning.window_px;
    let mut out = Array2::<f64>::zeros((w, w));
    let col_pixel: Vec<Option<usize>> = (0..m).map(|x| binning.pixel_of(x as i64 - h, 0)).collect();
    for (y, row) in fine.outer_iter().enumerate() {
        let Some(jy) = binning.pixel_of(y as i64 - h, 1) else {
            continue;
        };
        for (x, v) in row.iter().enumerate() {
            if let Some(jx) = col_pixel[x] {
                out[[jy, jx]] += v;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::display::aperture::SparseRow;

    /// A real field taken as a complex one with no phase: the dense whole-grid transform gives
    /// the full route's window, total and band.
    #[test]
    fn a_complex_field_without_a_phase_bins_as_the_real_one() {
        let field = Field {
            rows: (-6i64..7)
                .map(|iy| SparseRow {
                    iy,
                    ix0: -5 + iy.rem_euclid(3),
                    values: (0..9)
                        .map(|i| 0.1 + ((i + iy) as f64).sin().abs())
                        .collect(),
                })
                .collect(),
        };
        let binning = Binning {
            window_px: 12,
            samples_per_px: 3,
            phase: [1, 2],
        };
        let p = Progress::new();
        let real = binned_intensity(&field, 48, &binning, &p).unwrap();
        let complex =
            binned_intensity_complex(&field.with_phase(|_, _| 0.0), 48, &binning, &p).unwrap();
        let peak = real.sensor.iter().copied().fold(0.0, f64::max);
        for (a, b) in real.sensor.iter().zip(complex.sensor.iter()) {
            assert!((a - b).abs() <= 1e-12 * peak, "{a} vs {b}");
        }
        assert!((real.total - complex.total).abs() <= 1e-12 * real.total);
        assert!((real.edge - complex.edge).abs() <= 1e-12 * real.total);
    }

    fn brute_dft_intensity(dense: &[Vec<f64>], ky: usize, kx: usize) -> f64 {
        let m = dense.len();
        let mut acc = Complex64::new(0.0, 0.0);
        for (y, row) in dense.iter().enumerate() {
            for (x, v) in row.iter().enumerate() {
                let ph = -2.0 * std::f64::consts::PI * ((ky * y + kx * x) % m) as f64 / m as f64;
                acc += Complex64::from_polar(*v, ph);
            }
        }
        acc.norm_sqr()
    }

    #[test]
    fn pruned_transform_matches_brute_force_dft() {
        let field = Field {
            rows: vec![
                SparseRow {
                    iy: -3,
                    ix0: -2,
                    values: vec![0.5, 1.0, 0.0, 0.25],
                },
                SparseRow {
                    iy: 0,
                    ix0: 1,
                    values: vec![1.0, 0.7],
                },
                SparseRow {
                    iy: 2,
                    ix0: -4,
                    values: vec![0.3],
                },
            ],
        };
        let m = 10;
        let full = full_intensity(&field, m, &Progress::new()).expect("fits");
        // The brute force works on the uncentred grid (axis at index 0 after the shift
        // contributes only a phase); its DFT index k maps to centred index signed(k) + m/2.
        let dense = field.to_dense(m);
        for ky in 0..m {
            for kx in 0..m {
                let want = brute_dft_intensity(&dense, ky, kx);
                let got = full[[(signed(ky, m) + 5) as usize, (signed(kx, m) + 5) as usize]];
                assert!(
                    (want - got).abs() < 1e-9 * (1.0 + want),
                    "({ky},{kx}) {want} vs {got}"
                );
            }
        }
        // Parseval: Σ|A|² = M² Σ|a|²
        let total: f64 = full.sum();
        assert!((total - (m * m) as f64 * field.energy()).abs() < 1e-9 * total);
        // Binning sums the same energy when the window covers the grid: pixels 0…4 hold fine
        // offsets −5…4 when the axis is the second sample of its pixel.
        let b = Binning {
            window_px: 5,
            samples_per_px: 2,
            phase: [1, 1],
        };
        let binned = binned_intensity(&field, m, &b, &Progress::new()).expect("fits");
        assert!((binned.sensor.sum() - total).abs() < 1e-9 * total);
        assert!((binned.total - total).abs() < 1e-9 * total);
        let dense_binned = bin_dense(&full, &b);
        for (a, b) in dense_binned.iter().zip(binned.sensor.iter()) {
            assert!((a - b).abs() < 1e-9 * (1.0 + a.abs()));
        }
    }

    #[test]
    fn a_field_without_light_is_an_error_not_a_panic() {
        let empty = Field { rows: Vec::new() };
        let got = full_intensity(&empty, 16, &Progress::new());
        assert!(matches!(got, Err(SimError::Sampling(m)) if m.contains("no light")));
    }

    #[test]
    fn a_field_larger_than_the_grid_is_an_error() {
        let field = Field {
            rows: vec![SparseRow {
                iy: 0,
                ix0: -6,
                values: vec![1.0; 3],
            }],
        };
        assert!(matches!(
            full_intensity(&field, 10, &Progress::new()),
            Err(SimError::Sampling(_))
        ));
    }

    #[test]
    fn cancellation_stops_the_job() {
        let field = Field {
            rows: vec![SparseRow {
                iy: 0,
                ix0: 0,
                values: vec![1.0; 3],
            }],
        };
        let p = Progress::new();
        p.cancel();
        assert_eq!(
            full_intensity(&field, 10, &p).err(),
            Some(SimError::Cancelled)
        );
    }
}
