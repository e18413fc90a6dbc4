//! The optimizer's window transform on the device: `DFT_M` of a real field on a small sample box,
//! kept (complex) on the sensor window's frequency box, and its adjoint `Re(Fᴴ g)`, behind the
//! seam's [`Fraunhofer::window_spectrum`] and [`Fraunhofer::window_spectrum_adjoint`].
//!
//! Each direction is two matrix products (`window.wgsl`): along x, then along y, each against a
//! kernel `exp(∓2πi (s+k)(t+q)/M)` looked up in the roots of unity of `M`, computed in `f64` on
//! the CPU ([`crate::tables::roots`]). The CPU transforms each row with an FFT of length `M`; the
//! device does `ny·nx·nfx + nfx·ny·nfy` complex multiply-adds instead, more work but all of it in
//! tiles a GPU runs at its peak, with no `M`-long buffer per row. One upload and one read-back per
//! call.

use std::sync::Arc;

use rustfft::num_complex::Complex64;
use udc_core::SimError;
use udc_core::optimize::spectra::{Pool, Span, WindowDft};

use crate::device::{Gpu, out_of_memory, too_large};
use crate::kernels::{bind, uniform};
use crate::tables::{C32, roots};

/// Workgroup tile side (the shader's `@workgroup_size(16, 16)`).
const TILE: usize = 16;

/// Bytes per complex `f32` sample.
const COMPLEX: u64 = 8;

/// The largest `M` whose kernel index `u·v` (`u, v < M`) stays below `2³²`.
const MAX_M: usize = 65_535;

/// One stage: `out[p][q] = Σ_k in[p][k] · w((s_k + k)(s_q + q))`.
struct Stage {
    rows: usize,
    summed: Span,
    outputs: Span,
    conjugate: bool,
    transpose: bool,
}

impl Stage {
    fn words(&self, m: usize) -> [u32; 8] {
        let reduce = |s: i64| s.rem_euclid(m as i64) as u32;
        [
            m as u32,
            self.rows as u32,
            self.summed.len as u32,
            self.outputs.len as u32,
            reduce(self.summed.start),
            reduce(self.outputs.start),
            u32::from(self.conjugate),
            u32::from(self.transpose),
        ]
    }
}

impl Gpu {
    fn roots_table(&self, m: usize) -> Arc<wgpu::Buffer> {
        let mut t = self.tables.lock().unwrap_or_else(|e| e.into_inner());
        t.trim();
        t.roots
            .entry(m)
            .or_insert_with(|| Arc::new(self.upload("roots", &roots(m))))
            .clone()
    }

    /// Runs `stages` one after the other on `input` (complex, the first stage's `rows × summed`),
    /// reading back the last stage's output.
    fn window_stages(
        &self,
        m: usize,
        input: &[C32],
        stages: [Stage; 2],
    ) -> Result<Vec<C32>, SimError> {
        use wgpu::util::DeviceExt;
        if m > MAX_M {
            return Err(SimError::TooLarge(format!(
                "the device's window transform takes DFT lengths up to {MAX_M}; this one is {m} \
                 (use the CPU backend)"
            )));
        }
        let limit = self.max_binding_bytes();
        let sizes = stages
            .each_ref()
            .map(|s| (s.rows * s.outputs.len) as u64 * COMPLEX);
        for bytes in [input.len() as u64 * COMPLEX, sizes[0], sizes[1]] {
            if bytes > limit {
                return Err(too_large("the optimizer's window transform", bytes, limit));
            }
        }
        let device = &self.device;
        let kernel = &self.kernels.window_stage;
        let table = self.roots_table(m);
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let first = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("window input"),
            contents: bytemuck::cast_slice(input),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let storage = |label, bytes: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(16),
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let middle = storage("window middle", sizes[0], wgpu::BufferUsages::empty());
        let last = storage("window output", sizes[1], wgpu::BufferUsages::COPY_SRC);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("window readback"),
            size: sizes[1].max(16),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(kernel);
            for (stage, (src, dst)) in stages.iter().zip([(&first, &middle), (&middle, &last)]) {
                let params = uniform(device, &stage.words(m));
                let bufs = [(0, &params), (1, &*table), (2, src), (3, dst)];
                pass.set_bind_group(0, &bind(device, kernel, &bufs), &[]);
                let tiles = |n: usize| u32::try_from(n.div_ceil(TILE)).unwrap_or(u32::MAX);
                pass.dispatch_workgroups(tiles(stage.outputs.len), tiles(stage.rows), 1);
            }
        }
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
