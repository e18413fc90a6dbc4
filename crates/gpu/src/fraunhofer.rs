//! The display-layout Fraunhofer step on the device: a sparse field's `|DFT_M|²` by the
//! chirp-z transform on power-of-two FFTs, binned into the sensor window, read back once. A
//! complex field (a defocused pupil) keeps every column; a real one half of them.
//!
//! Per call: the field's nonzero rows go up as `f32` (with their positions); each row's DFT along
//! x fills one column per kept frequency `kx ≤ M/2`; each column's DFT along y gives the
//! intensity of half the grid (the other half is its mirror image, the field being real); the
//! window's pixels gather their fine samples from it, and each column sums its share of the
//! aliasing band. Only the window (`W²` values) and the band's column sums come back. The grid's
//! total is `M² Σ a²` (Parseval), computed on the CPU in `f64`.

use std::sync::Arc;

use ndarray::Array2;
use rustfft::num_complex::Complex64;
use udc_core::SimError;
use udc_core::display::aperture::Field;
use udc_core::progress::Progress;
use udc_core::psf::fft::{Binned, check_grid};
use udc_core::psf::route::Fraunhofer;
use udc_core::psf::sampling::Binning;
use udc_core::psf::spectra::{Pool, WindowDft};

use crate::device::{Gpu, out_of_memory, too_large};
use crate::kernels::{FftPlan, bind, groups, uniform};
use crate::tables::{chirp, conv_len, kernel_spectrum};
use wgpu::BufferUsages as U;

/// Bytes one chunk's work buffer may take (two are held): large enough to keep a GPU busy,
/// small enough that a laptop's shared memory is not exhausted.
const WORK_BYTES: u64 = 128 << 20;

/// Bytes per complex `f32` sample.
const COMPLEX: u64 = 8;

/// A field's samples as the kernels read them: `f32`, a complex one as `(re, im)` pairs.
trait Sample: Copy {
    /// `f32`s per sample.
    const FLOATS: usize;
    fn push(self, out: &mut Vec<f32>);
}

impl Sample for f64 {
    const FLOATS: usize = 1;
    fn push(self, out: &mut Vec<f32>) {
        out.push(self as f32);
    }
}

impl Sample for Complex64 {
    const FLOATS: usize = 2;
    fn push(self, out: &mut Vec<f32>) {
        out.extend([self.re as f32, self.im as f32]);
    }
}

/// The field's nonzero rows, from its corner: `(y, x0, samples, offset)` and the samples.
struct Packed {
    headers: Vec<[u32; 4]>,
    values: Vec<f32>,
    /// Columns and rows the field spans.
    lx: usize,
    ly: usize,
    /// The samples are complex: the whole grid is kept (no mirror symmetry).
    complex: bool,
}

fn pack<T: Sample>(field: &Field<T>) -> Packed {
    let rows: Vec<_> = field.rows.iter().filter(|r| !r.values.is_empty()).collect();
    let x_lo = rows.iter().map(|r| r.ix0).min().unwrap_or(0);
    let x_hi = rows
        .iter()
        .map(|r| r.ix0 + r.values.len() as i64)
        .max()
        .unwrap_or(0);
    let y_lo = rows.iter().map(|r| r.iy).min().unwrap_or(0);
    let y_hi = rows.iter().map(|r| r.iy + 1).max().unwrap_or(0);
    let mut values = Vec::new();
    let headers = rows
        .iter()
        .map(|r| {
            let h = [
                (r.iy - y_lo) as u32,
                (r.ix0 - x_lo) as u32,
                r.values.len() as u32,
                (values.len() / T::FLOATS) as u32,
            ];
            for v in &r.values {
                v.push(&mut values);
            }
            h
        })
        .collect();
    Packed {
        headers,
        values,
        lx: (x_hi - x_lo) as usize,
        ly: (y_hi - y_lo) as usize,
        complex: T::FLOATS == 2,
    }
}

/// A Bluestein kernel's bindings: the parameters at 0, `extra`, and the work buffer at 5.
fn with<'a>(
    params: &'a wgpu::Buffer,
    extra: &[(u32, &'a wgpu::Buffer)],
    work: &'a wgpu::Buffer,
) -> Vec<(u32, &'a wgpu::Buffer)> {
    let mut v = vec![(0, params)];
    v.extend_from_slice(extra);
    v.push((5, work));
    v
}

impl Gpu {
    pub(crate) fn fft_plan(&self, n: usize) -> Arc<FftPlan> {
        let mut t = self.tables.lock().unwrap_or_else(|e| e.into_inner());
        t.trim();
        t.ffts
            .entry(n)
            .or_insert_with(|| Arc::new(FftPlan::new(&self.device, n)))
            .clone()
    }

    fn chirp(&self, m: usize) -> Arc<wgpu::Buffer> {
        let mut t = self.tables.lock().unwrap_or_else(|e| e.into_inner());
        t.chirps
            .entry(m)
            .or_insert_with(|| Arc::new(self.pod("chirp", &chirp(m))))
            .clone()
    }

    fn spectrum(&self, m: usize, l: usize) -> Arc<wgpu::Buffer> {
        let mut t = self.tables.lock().unwrap_or_else(|e| e.into_inner());
        t.spectra
            .entry((m, l))
            .or_insert_with(|| Arc::new(self.pod("kernel", &kernel_spectrum(m, l, conv_len(m, l)))))
            .clone()
    }

    /// The binned intensity of `packed`, whose `Σ|a|²` is `energy`.
    fn run(
        &self,
        packed: &Packed,
        energy: f64,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        let limit = self.max_binding_bytes();
        let cols = if packed.complex { m } else { m / 2 + 1 };
        let (nx, ny) = (conv_len(m, packed.lx), conv_len(m, packed.ly));
        let columns_bytes = (cols * packed.ly) as u64 * COMPLEX;
        let intensity_bytes = (cols * m) as u64 * 4;
        let vector_bytes = nx.max(ny) as u64 * COMPLEX;
        let w = binning.window_px;
        let sensor_bytes = (w * w) as u64 * 4;
        for (what, bytes) in [
            ("the row spectra", columns_bytes),
            ("the intensity", intensity_bytes),
            ("one transform", vector_bytes),
            ("the window", sensor_bytes),
        ] {
            if bytes > limit {
                return Err(too_large(what, bytes, limit));
            }
        }
        let cap = limit.min(WORK_BYTES);
        let batch_of = |n: usize, count: usize| {
            ((cap / (n as u64 * COMPLEX)) as usize).clamp(1, count.min(65_535))
        };
        let (row_batch, col_batch) = (batch_of(nx, packed.headers.len()), batch_of(ny, cols));
        let work_bytes = ((row_batch * nx).max(col_batch * ny)) as u64 * COMPLEX;

        let device = &self.device;
        let k = &self.kernels;
        let (fft_x, fft_y) = (self.fft_plan(nx), self.fft_plan(ny));
        let chirp = self.chirp(m);
        let (spec_x, spec_y) = (self.spectrum(m, packed.lx), self.spectrum(m, packed.ly));
        let rows = self.pod("rows", &packed.headers);
        let values = self.pod("values", &packed.values);
        let work = [
            self.buffer("work a", work_bytes, U::STORAGE),
            self.buffer("work b", work_bytes, U::STORAGE),
        ];
        let columns = self.buffer("columns", columns_bytes, U::STORAGE);
        let intensity = self.buffer("intensity", intensity_bytes, U::STORAGE);

        let params = |n: usize, batch: usize, first: usize| {
            uniform(
                device,
                &[
                    m as u32,
                    n as u32,
                    batch as u32,
                    first as u32,
                    packed.ly as u32,
                    cols as u32,
                    (1.0 / n as f32).to_bits(),
                    u32::from(packed.complex),
                ],
            )
        };
        // One chunk of vectors: pre-chirp into a work buffer, FFT, product with the kernel's
        // spectrum, FFT again; `post` reads the buffer the result ended in.
        let chunk = |pre: &wgpu::ComputePipeline,
                     pre_bufs: &[(u32, &wgpu::Buffer)],
                     plan: &FftPlan,
                     spectrum: &wgpu::Buffer,
                     post: &wgpu::ComputePipeline,
                     post_bufs: &[(u32, &wgpu::Buffer)],
                     post_threads: usize,
                     p: &wgpu::Buffer,
                     batch: usize| {
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                let (mut cur, mut other) = (&work[0], &work[1]);
                pass.set_pipeline(pre);
                pass.set_bind_group(0, &bind(device, pre, &with(p, pre_bufs, cur)), &[]);
                pass.dispatch_workgroups(groups(plan.n), batch as u32, 1);
                if !plan.record(device, k, &mut pass, cur, other, batch as u32) {
                    std::mem::swap(&mut cur, &mut other);
                }
                pass.set_pipeline(&k.convolve);
                let conv = bind(device, &k.convolve, &with(p, &[(4, spectrum)], cur));
                pass.set_bind_group(0, &conv, &[]);
                pass.dispatch_workgroups(groups(plan.n), batch as u32, 1);
                if !plan.record(device, k, &mut pass, cur, other, batch as u32) {
                    std::mem::swap(&mut cur, &mut other);
                }
                pass.set_pipeline(post);
                pass.set_bind_group(0, &bind(device, post, &with(p, post_bufs, cur)), &[]);
                pass.dispatch_workgroups(groups(post_threads), batch as u32, 1);
            }
            self.queue.submit([encoder.finish()]);
        };

        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let n_rows = packed.headers.len();
        for first in (0..n_rows).step_by(row_batch) {
            progress.check()?;
            let batch = row_batch.min(n_rows - first);
            let p = params(nx, batch, first);
            chunk(
                &k.prechirp_rows,
                &[(1, &chirp), (2, &rows), (3, &values)],
                &fft_x,
                &spec_x,
                &k.postchirp_rows,
                &[(1, &chirp), (2, &rows), (6, &columns)],
                cols,
                &p,
                batch,
            );
        }
        for first in (0..cols).step_by(col_batch) {
            progress.check()?;
            let batch = col_batch.min(cols - first);
            let p = params(ny, batch, first);
            chunk(
                &k.prechirp_columns,
                &[(1, &chirp), (6, &columns)],
                &fft_y,
                &spec_y,
                &k.intensity_columns,
                &[(7, &intensity)],
                m,
                &p,
                batch,
            );
        }
        progress.check()?;

        let band_bytes = cols as u64 * 4;
        let sensor = self.buffer("sensor", sensor_bytes, U::STORAGE | U::COPY_SRC);
        let band = self.buffer("band", band_bytes, U::STORAGE | U::COPY_SRC);
        let readback = self.buffer(
            "readback",
            sensor_bytes + band_bytes,
            U::MAP_READ | U::COPY_DST,
        );
        let edge_from = (0.45 * m as f64).ceil() as u32;
        let bin_params = uniform(
            device,
            &[
                m as u32,
                w as u32,
                binning.samples_per_px as u32,
                edge_from,
                binning.phase[0] as u32,
                binning.phase[1] as u32,
                u32::from(packed.complex),
                0,
            ],
        );
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            let bufs = [(0, &bin_params), (1, &intensity), (2, &sensor)];
            pass.set_pipeline(&k.bin_window);
            pass.set_bind_group(0, &bind(device, &k.bin_window, &bufs), &[]);
            let tiles = u32::try_from(w.div_ceil(8)).unwrap_or(u32::MAX);
            pass.dispatch_workgroups(tiles, tiles, 1);
            let bufs = [(0, &bin_params), (1, &intensity), (3, &band)];
            pass.set_pipeline(&k.band_columns);
            pass.set_bind_group(0, &bind(device, &k.band_columns, &bufs), &[]);
            pass.dispatch_workgroups(u32::try_from(cols.div_ceil(64)).unwrap_or(u32::MAX), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&sensor, 0, &readback, 0, sensor_bytes);
        encoder.copy_buffer_to_buffer(&band, 0, &readback, sensor_bytes, band_bytes);
        self.queue.submit([encoder.finish()]);

        let failed = |e: wgpu::Error| SimError::Device(e.to_string());
        if let Some(e) = pollster::block_on(oom.pop()) {
            return Err(out_of_memory(&e));
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(failed(e));
        }
        let data = self.read_back(&readback, sensor_bytes + band_bytes)?;

        let (win, bands) = data.split_at(w * w);
        let sensor = Array2::from_shape_fn((w, w), |(jy, jx)| f64::from(win[jy * w + jx]));
        let edge = bands
            .iter()
            .enumerate()
            .map(|(kx, &v)| {
                // A real field's kept column stands for its mirror image too.
                let twice = !packed.complex && kx != 0 && kx != m / 2;
                f64::from(v) * if twice { 2.0 } else { 1.0 }
            })
            .sum();
        let mf = m as f64;
        Ok(Binned {
            sensor,
            total: mf * mf * energy,
            edge,
        })
    }
}

impl Fraunhofer for Gpu {
    fn binned(
        &self,
        field: &Field,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        check_grid(field, m)?;
        if field.rows.iter().all(|r| r.values.is_empty()) {
            return Err(SimError::Sampling("no light passes the aperture".into()));
        }
        progress.check()?;
        self.run(&pack(field), field.energy(), m, binning, progress)
    }

    fn binned_complex(
        &self,
        field: &Field<Complex64>,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        check_grid(field, m)?;
        let energy = field.energy();
        if !(energy > 0.0) {
            return Err(SimError::Sampling("no light passes the aperture".into()));
        }
        progress.check()?;
        self.run(&pack(field), energy, m, binning, progress)
    }

    /// The whole grid as a window of `M` pixels of one sample each: the same kernels, the
    /// `M²` intensity read back.
    fn full(&self, field: &Field, m: usize, progress: &Progress) -> Result<Array2<f64>, SimError> {
        let whole = Binning {
            window_px: m,
            samples_per_px: 1,
            phase: [0, 0],
        };
        Ok(self.binned(field, m, &whole, progress)?.sensor)
    }

    fn window_spectrum(
        &self,
        dft: &WindowDft,
        field: &[f64],
        pool: &Pool,
    ) -> Result<Vec<Complex64>, SimError> {
        self.window_forward(dft, field, pool)
    }

    fn window_spectrum_adjoint(
        &self,
        dft: &WindowDft,
        g: &[Complex64],
        _pool: &Pool,
    ) -> Result<Vec<f64>, SimError> {
        self.window_adjoint(dft, g)
    }
}
