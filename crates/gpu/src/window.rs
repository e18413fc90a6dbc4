//! The optimizer's window transform on the device: `DFT_M` of a real field on a small sample box,
//! kept (complex) on the sensor window's frequency box, and its adjoint `Re(Fᴴ g)`, behind the
//! seam's [`Fraunhofer::window_spectrum`] and [`Fraunhofer::window_spectrum_adjoint`].
//!
//! Each direction is two stages (along x, then along y), each a batch of chirp-z "zooms"
//! (`window.wgsl`): a box of `K` samples at offset `s` to `Q` frequencies at offset `t`, with a
//! convolution of length `N ≥ K + Q − 1` on the power-of-two FFT the Fraunhofer step uses,
//! instead of the CPU's FFT of length `M` per row. The chirps and the kernel's spectrum are
//! computed in `f64` on the CPU ([`crate::tables::zoom`]), the adjoint's with the conjugate
//! kernel. One upload and one read-back per call.
//!
//! [`Fraunhofer::window_spectrum`]: udc_core::psf::route::Fraunhofer::window_spectrum
//! [`Fraunhofer::window_spectrum_adjoint`]: udc_core::psf::route::Fraunhofer::window_spectrum_adjoint

use std::sync::Arc;

use rustfft::num_complex::Complex64;
use udc_core::SimError;
use udc_core::psf::spectra::{Pool, Span, WindowDft};

use crate::device::{Gpu, ZoomKey, ZoomTables, out_of_memory, too_large};
use crate::kernels::{bind, groups, uniform};
use crate::tables::{C32, conv_len, zoom};
use wgpu::BufferUsages as U;

/// Bytes one chunk's work buffer may take (two are held), as the Fraunhofer step's.
const WORK_BYTES: u64 = 128 << 20;

/// Bytes per complex `f32` sample.
const COMPLEX: u64 = 8;

/// One stage: for each of `rows` vectors, `out[q] = Σ_k in[k] · ω^{(s_k + k)(s_q + q)}`.
struct Stage {
    rows: usize,
    summed: Span,
    outputs: Span,
    conjugate: bool,
    transpose: bool,
}

impl Gpu {
    /// A stage's tables, formed and uploaded once per geometry: an optimizer's every epoch
    /// uses the same few.
    fn zoom_tables(&self, m: usize, stage: &Stage) -> Arc<ZoomTables> {
        let key: ZoomKey = (
            m,
            (stage.summed.start, stage.summed.len),
            (stage.outputs.start, stage.outputs.len),
            stage.conjugate,
        );
        let mut t = self.tables.lock().unwrap_or_else(|e| e.into_inner());
        t.trim();
        t.zooms
            .entry(key)
            .or_insert_with(|| {
                let z = zoom(key.0, key.1, key.2, key.3);
                Arc::new(ZoomTables {
                    pre: self.pod("zoom pre-chirp", &z.pre),
                    post: self.pod("zoom post-chirp", &z.post),
                    kernel: self.pod("zoom kernel", &z.kernel),
                })
            })
            .clone()
    }

    /// Runs `stages` one after the other on `input` (complex, the first stage's
    /// `rows × summed`), reading back the last stage's output.
    fn window_stages(
        &self,
        m: usize,
        input: &[C32],
        stages: [Stage; 2],
    ) -> Result<Vec<C32>, SimError> {
        let sizes = stages
            .each_ref()
            .map(|s| (s.rows * s.outputs.len) as u64 * COMPLEX);
        if stages
            .iter()
            .any(|s| s.rows == 0 || s.summed.len == 0 || s.outputs.len == 0)
        {
            // An empty box or window: every output is an empty sum.
            return Ok(vec![[0.0; 2]; (sizes[1] / COMPLEX) as usize]);
        }
        let limit = self.max_binding_bytes();
        let cap = limit.min(WORK_BYTES);
        let convs = stages
            .each_ref()
            .map(|s| conv_len(s.outputs.len.max(1), s.summed.len));
        for (what, bytes) in [
            ("the optimizer's window input", input.len() as u64 * COMPLEX),
            ("the optimizer's window stage", sizes[0]),
            ("the optimizer's window spectrum", sizes[1]),
            ("one zoom", convs[0].max(convs[1]) as u64 * COMPLEX),
        ] {
            if bytes > limit {
                return Err(too_large(what, bytes, limit));
            }
        }
        let batches = [0, 1].map(|i| {
            ((cap / (convs[i] as u64 * COMPLEX)) as usize).clamp(1, stages[i].rows.min(65_535))
        });
        let work_bytes = (0..2)
            .map(|i| (batches[i] * convs[i]) as u64 * COMPLEX)
            .max()
            .unwrap_or(0);

        let device = &self.device;
        let k = &self.kernels;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let first = self.pod("window input", input);
        let middle = self.buffer("window stage", sizes[0], U::STORAGE);
        let last = self.buffer("window spectrum", sizes[1], U::STORAGE | U::COPY_SRC);
        let work = [
            self.buffer("window work a", work_bytes, U::STORAGE),
            self.buffer("window work b", work_bytes, U::STORAGE),
        ];
        for ((stage, (src, dst)), (n, batch_max)) in stages
            .iter()
            .zip([(&first, &middle), (&middle, &last)])
            .zip(convs.into_iter().zip(batches))
        {
            let tables = self.zoom_tables(m, stage);
            let (pre, post, spectrum) = (&tables.pre, &tables.post, &tables.kernel);
            let plan = self.fft_plan(n);
            for first_row in (0..stage.rows).step_by(batch_max) {
                let batch = batch_max.min(stage.rows - first_row);
                let params = uniform(
                    device,
                    &[
                        m as u32,
                        n as u32,
                        batch as u32,
                        first_row as u32,
                        stage.summed.len as u32,
                        stage.outputs.len as u32,
                        stage.rows as u32,
                        u32::from(stage.transpose),
                    ],
                );
                let mut encoder = device.create_command_encoder(&Default::default());
                {
                    let mut pass = encoder.begin_compute_pass(&Default::default());
                    let (mut cur, mut other) = (&work[0], &work[1]);
                    let bufs = [(0, &params), (1, pre), (2, src), (5, cur)];
                    pass.set_pipeline(&k.zoom_pre);
                    pass.set_bind_group(0, &bind(device, &k.zoom_pre, &bufs), &[]);
                    pass.dispatch_workgroups(groups(n), batch as u32, 1);
                    if !plan.record(device, k, &mut pass, cur, other, batch as u32) {
                        std::mem::swap(&mut cur, &mut other);
                    }
                    let bufs = [(0, &params), (4, spectrum), (5, cur)];
                    pass.set_pipeline(&k.convolve);
                    pass.set_bind_group(0, &bind(device, &k.convolve, &bufs), &[]);
                    pass.dispatch_workgroups(groups(n), batch as u32, 1);
                    if !plan.record(device, k, &mut pass, cur, other, batch as u32) {
                        std::mem::swap(&mut cur, &mut other);
                    }
                    let bufs = [(0, &params), (1, post), (3, dst), (5, cur)];
                    pass.set_pipeline(&k.zoom_post);
                    pass.set_bind_group(0, &bind(device, &k.zoom_post, &bufs), &[]);
                    pass.dispatch_workgroups(groups(stage.outputs.len), batch as u32, 1);
                }
                self.queue.submit([encoder.finish()]);
            }
        }
        let readback = self.buffer("window readback", sizes[1], U::MAP_READ | U::COPY_DST);
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&last, 0, &readback, 0, sizes[1]);
        self.queue.submit([encoder.finish()]);
        if let Some(e) = pollster::block_on(oom.pop()) {
            return Err(out_of_memory(&e));
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(SimError::Device(e.to_string()));
        }
        let data = self.read_back(&readback, sizes[1])?;
        Ok(bytemuck::cast_slice::<f32, C32>(&data).to_vec())
    }

    /// [`WindowDft::forward`] on the device, the result in a buffer from `pool`.
    pub(crate) fn window_forward(
        &self,
        dft: &WindowDft,
        field: &[f64],
        pool: &Pool,
    ) -> Result<Vec<Complex64>, SimError> {
        let (ny, nx) = (dft.rows.len, dft.cols.len);
        let input: Vec<C32> = field.iter().map(|&v| [v as f32, 0.0]).collect();
        if input.len() != ny * nx {
            return Err(SimError::Sampling(format!(
                "the field has {} samples, not the box's {ny}×{nx}",
                input.len()
            )));
        }
        // x: [row][col] → [kx][row]; y: [kx][row] → [kx][ky], the CPU's column-major layout.
        let out = self.window_stages(
            dft.m,
            &input,
            [
                Stage {
                    rows: ny,
                    summed: dft.cols,
                    outputs: dft.freq_cols,
                    conjugate: false,
                    transpose: true,
                },
                Stage {
                    rows: dft.freq_cols.len,
                    summed: dft.rows,
                    outputs: dft.freq_rows,
                    conjugate: false,
                    transpose: false,
                },
            ],
        )?;
        let mut spectrum = pool.take(out.len());
        for (z, v) in spectrum.iter_mut().zip(&out) {
            *z = Complex64::new(f64::from(v[0]), f64::from(v[1]));
        }
        Ok(spectrum)
    }

    /// [`WindowDft::adjoint`] on the device.
    pub(crate) fn window_adjoint(
        &self,
        dft: &WindowDft,
        g: &[Complex64],
    ) -> Result<Vec<f64>, SimError> {
        let (nfy, nfx) = (dft.freq_rows.len, dft.freq_cols.len);
        if g.len() != nfy * nfx {
            return Err(SimError::Sampling(format!(
                "the gradient has {} frequencies, not the window's {nfy}×{nfx}",
                g.len()
            )));
        }
        let input: Vec<C32> = g.iter().map(|z| [z.re as f32, z.im as f32]).collect();
        // y: [kx][ky] → [row][kx]; x: [row][kx] → [row][col].
        let out = self.window_stages(
            dft.m,
            &input,
            [
                Stage {
                    rows: nfx,
                    summed: dft.freq_rows,
                    outputs: dft.rows,
                    conjugate: true,
                    transpose: true,
                },
                Stage {
                    rows: dft.rows.len,
                    summed: dft.freq_cols,
                    outputs: dft.cols,
                    conjugate: true,
                    transpose: false,
                },
            ],
        )?;
        Ok(out.iter().map(|v| f64::from(v[0])).collect())
    }
}
