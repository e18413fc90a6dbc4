//! The phase model's slowest step on the device: the double MLA's Bloch relay and its chirp-z
//! transform for a batch of directions at one wavelength, behind the core's seam
//! ([`BlochRelay`]).
//!
//! The wavelength's tables (the plate's spectrum, the untilted transfer function, the slits,
//! the opening's factors, the chirp-z kernel's spectrum) go up once per call; each chunk of
//! directions sends its ramps (formed on the CPU in `f64`, in parallel), and per direction the
//! device forms the shifted transfer function, runs three FFTs of the wrapped grid's length
//! (mixed radix 2·3·4·5: the grid's length is its wrap-around period, so it is not rounded to a
//! power of two), the opening's product, the chirp-z convolution's two FFTs and the fine
//! intensities. Only the fine intensities and 256 partial sums of the light per direction come
//! back.

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::num_complex::Complex32;
use udc_core::SimError;
use udc_core::phase::chain::{
    BlochDirection, BlochIntensity, BlochRelay, BlochWavelength, RAMP_BLOCK, Ramp,
};
use udc_core::progress::Progress;

use crate::device::{Gpu, out_of_memory, too_large};
use crate::kernels::{MixedPlan, bind, groups, uniform};

/// Bytes one chunk's largest buffer may take (five of that size are held).
const WORK_BYTES: u64 = 64 << 20;

/// Bytes per complex `f32` sample.
const COMPLEX: u64 = 8;

/// Directions per chunk at most: a chunk is one submission, between which progress moves and a
/// cancel is seen (a wavelength of a 1 024-column operator is then 32 steps).
const MAX_DIRECTIONS: usize = 32;

/// Partial sums of the light per direction (one per thread of the `energy` kernel).
const PARTIALS: usize = 256;

fn pairs(v: &[Complex32]) -> Vec<[f32; 2]> {
    v.iter().map(|c| [c.re, c.im]).collect()
}

/// One chunk's ramps, packed as the kernels read them.
struct Ramps {
    shift_anchors: Vec<[f32; 2]>,
    shift_steps: Vec<[f32; 2]>,
    exact_at: Vec<[u32; 4]>,
    exact: Vec<[f32; 2]>,
    tilt_anchors: Vec<[f32; 2]>,
    tilt_steps: Vec<[f32; 2]>,
}

impl Ramps {
    fn pack(
        dirs: &[BlochDirection],
        shift_anchors: usize,
        tilt_anchors: usize,
    ) -> Result<Ramps, SimError> {
        let fits =
            |r: &Ramp, anchors: usize| r.anchors.len() == anchors && r.steps.len() == RAMP_BLOCK;
        if dirs
            .iter()
            .any(|d| !fits(&d.shift, shift_anchors) || !fits(&d.tilt, tilt_anchors))
        {
            return Err(SimError::Sampling(
                "a direction's ramps do not match the wavelength's grid".into(),
            ));
        }
        let mut out = Ramps {
            shift_anchors: Vec::with_capacity(dirs.len() * shift_anchors),
            shift_steps: Vec::with_capacity(dirs.len() * RAMP_BLOCK),
            exact_at: Vec::with_capacity(dirs.len()),
            exact: Vec::new(),
            tilt_anchors: Vec::with_capacity(dirs.len() * tilt_anchors),
            tilt_steps: Vec::with_capacity(dirs.len() * RAMP_BLOCK),
        };
        for d in dirs {
            out.shift_anchors.extend(pairs(&d.shift.anchors));
            out.shift_steps.extend(pairs(&d.shift.steps));
            out.exact_at.push([
                d.shift.exact_from as u32,
                d.shift.exact.len() as u32,
                out.exact.len() as u32,
                0,
            ]);
            out.exact.extend(pairs(&d.shift.exact));
            out.tilt_anchors.extend(pairs(&d.tilt.anchors));
            out.tilt_steps.extend(pairs(&d.tilt.steps));
        }
        // A binding may not be empty.
        if out.exact.is_empty() {
            out.exact.push([0.0, 0.0]);
        }
        Ok(out)
    }
}

impl Gpu {
    fn mixed_plan(&self, n: usize) -> Result<Arc<MixedPlan>, SimError> {
        let mut t = self.tables.lock().unwrap_or_else(|e| e.into_inner());
        t.trim();
        if let Some(plan) = t.mixed.get(&n) {
            return Ok(plan.clone());
        }
        let plan = MixedPlan::new(&self.device, n).map(Arc::new).ok_or_else(|| {
            SimError::Sampling(format!(
                "the device's FFT takes lengths whose prime factors are 2, 3 and 5; {n} is not one"
            ))
        })?;
        t.mixed.insert(n, plan.clone());
        Ok(plan)
    }

    fn relay(
        &self,
        w: &BlochWavelength<'_>,
        count: usize,
        direction: &(dyn Fn(usize) -> BlochDirection + Sync),
        progress: &Progress,
    ) -> Result<Vec<BlochIntensity>, SimError> {
        let len = w.spectrum.len();
        let n_in = w.opening.len();
        let conv = w.czt.fft_len();
        let n_out = w.czt.n_out();
        let n_slits = w.slits.len().min(len);
        if w.untilted.len() != len
            || w.start + n_in > len
            || n_in > conv
            || n_out > conv
            || w.czt.kernel_hat().len() != conv
        {
            return Err(SimError::Sampling(
                "the Bloch relay's tables do not fit one grid".into(),
            ));
        }
        let limit = self.max_binding_bytes();
        let widest = len.max(conv) as u64 * COMPLEX;
        if widest > limit {
            return Err(too_large("one direction's field", widest, limit));
        }
        let max_groups = self.device.limits().max_compute_workgroups_per_dimension;
        if groups(len.max(conv)) > max_groups {
            return Err(SimError::TooLarge(format!(
                "a grid of {} samples is more than one dispatch covers on this device \
                 (use the CPU backend)",
                len.max(conv)
            )));
        }
        let batch_max =
            ((limit.min(WORK_BYTES) / widest) as usize).clamp(1, count.clamp(1, MAX_DIRECTIONS));
        let (fft_len, fft_conv) = (self.mixed_plan(len)?, self.mixed_plan(conv)?);
        let device = &self.device;
        let k = &self.kernels;

        let spectrum = self.pod("spectrum", &pairs(w.spectrum));
        let untilted = self.pod("untilted", &pairs(w.untilted));
        let slits: Vec<f32> = w.slits[..n_slits].iter().map(|&s| s as f32).collect();
        let slits = self.pod("slits", &slits);
        let opening = self.pod("opening", &pairs(w.opening));
        let kernel = self.pod("kernel", &pairs(w.czt.kernel_hat()));
        let rw = wgpu::BufferUsages::STORAGE;
        let out = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let grid_bytes = (batch_max * len) as u64 * COMPLEX;
        let conv_bytes = (batch_max * conv) as u64 * COMPLEX;
        let transfer = self.buffer("transfer", grid_bytes, rw);
        let field = [
            self.buffer("field a", grid_bytes, rw),
            self.buffer("field b", grid_bytes, rw),
        ];
        let convs = [
            self.buffer("conv a", conv_bytes, rw),
            self.buffer("conv b", conv_bytes, rw),
        ];
        let fine_bytes = (batch_max * n_out) as u64 * 4;
        let partial_bytes = (batch_max * PARTIALS) as u64 * 4;
        let fine = self.buffer("fine", fine_bytes, out);
        let partials = self.buffer("partials", partial_bytes, out);
        let readback = self.buffer(
            "readback",
            fine_bytes + partial_bytes,
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        let shift_anchors = len.div_ceil(RAMP_BLOCK);
        let tilt_anchors = n_in.div_ceil(RAMP_BLOCK);
        let failed = |e: &dyn std::fmt::Display| SimError::Device(e.to_string());

        let mut results = Vec::with_capacity(count);
        for first in (0..count).step_by(batch_max) {
            progress.check()?;
            let batch = batch_max.min(count - first);
            let dirs: Vec<BlochDirection> = (first..first + batch)
                .into_par_iter()
                .map(direction)
                .collect();
            let ramps = Ramps::pack(&dirs, shift_anchors, tilt_anchors)?;
            drop(dirs);
            let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
            let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
            let params = uniform(
                device,
                &[
                    len as u32,
                    batch as u32,
                    n_slits as u32,
                    w.start as u32,
                    n_in as u32,
                    conv as u32,
                    n_out as u32,
                    shift_anchors as u32,
                    tilt_anchors as u32,
                    0,
                    0,
                    0,
                ],
            );
            let s_anchors = self.pod("shift anchors", &ramps.shift_anchors);
            let s_steps = self.pod("shift steps", &ramps.shift_steps);
            let exact_at = self.pod("exact at", &ramps.exact_at);
            let exact = self.pod("exact", &ramps.exact);
            let t_anchors = self.pod("tilt anchors", &ramps.tilt_anchors);
            let t_steps = self.pod("tilt steps", &ramps.tilt_steps);
            let b = batch as u32;
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                let fft = |pass: &mut wgpu::ComputePass<'_>, plan: &MixedPlan, pair, inverse| {
                    plan.record(device, k, pass, pair, b, inverse)
                };
                let step = |pass: &mut wgpu::ComputePass<'_>,
                            pipeline: &wgpu::ComputePipeline,
                            buffers: &[(u32, &wgpu::Buffer)],
                            threads: usize,
                            rows: u32| {
                    let mut all = vec![(0, &params)];
                    all.extend_from_slice(buffers);
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, &bind(device, pipeline, &all), &[]);
                    pass.dispatch_workgroups(groups(threads), rows, 1);
                };
                step(
                    &mut pass,
                    &k.form_transfer,
                    &[
                        (1, &spectrum),
                        (2, &untilted),
                        (3, &s_anchors),
                        (4, &s_steps),
                        (5, &exact_at),
                        (6, &exact),
                        (7, &transfer),
                        (8, &field[0]),
                    ],
                    len,
                    b,
                );
                // MLA 1's plate to the display: the shifted spectrum back to space.
                let cur = fft(&mut pass, &fft_len, (&field[0], &field[1]), true);
                step(
                    &mut pass,
                    &k.apply_slits,
                    &[(8, cur.0), (9, &slits)],
                    n_slits,
                    b,
                );
                let cur = fft(&mut pass, &fft_len, cur, false);
                step(
                    &mut pass,
                    &k.apply_transfer,
                    &[(7, &transfer), (8, cur.0)],
                    len,
                    b,
                );
                let cur = fft(&mut pass, &fft_len, cur, true);
                step(
                    &mut pass,
                    &k.opening_input,
                    &[
                        (3, &t_anchors),
                        (4, &t_steps),
                        (8, cur.0),
                        (10, &opening),
                        (11, &convs[0]),
                    ],
                    conv,
                    b,
                );
                // One workgroup per direction.
                pass.set_pipeline(&k.energy);
                let energy = bind(
                    device,
                    &k.energy,
                    &[(0, &params), (11, &convs[0]), (14, &partials)],
                );
                pass.set_bind_group(0, &energy, &[]);
                pass.dispatch_workgroups(1, b, 1);
                let c = fft(&mut pass, &fft_conv, (&convs[0], &convs[1]), false);
                step(
                    &mut pass,
                    &k.apply_kernel,
                    &[(11, c.0), (12, &kernel)],
                    conv,
                    b,
                );
                let c = fft(&mut pass, &fft_conv, c, true);
                step(
                    &mut pass,
                    &k.fine_intensity,
                    &[(11, c.0), (13, &fine)],
                    n_out,
                    b,
                );
            }
            let (fine_used, partial_used) =
                ((batch * n_out) as u64 * 4, (batch * PARTIALS) as u64 * 4);
            encoder.copy_buffer_to_buffer(&fine, 0, &readback, 0, fine_used);
            encoder.copy_buffer_to_buffer(&partials, 0, &readback, fine_used, partial_used);
            self.queue.submit([encoder.finish()]);
            if let Some(e) = pollster::block_on(oom.pop()) {
                return Err(out_of_memory(&e));
            }
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(failed(&e));
            }
            let data = self.read_back(&readback, fine_used + partial_used)?;
            let (fines, sums) = data.split_at(batch * n_out);
            for (f, s) in fines.chunks_exact(n_out).zip(sums.chunks_exact(PARTIALS)) {
                results.push(BlochIntensity {
                    fine: f.iter().map(|&v| f64::from(v)).collect(),
                    total: s.iter().map(|&v| f64::from(v)).sum(),
                });
            }
            progress.set((first + batch) as f32 / count as f32);
        }
        Ok(results)
    }
}

impl BlochRelay for Gpu {
    fn directions(
        &self,
        wavelength: &BlochWavelength<'_>,
        count: usize,
        direction: &(dyn Fn(usize) -> BlochDirection + Sync),
        progress: &Progress,
    ) -> Result<Vec<BlochIntensity>, SimError> {
        progress.check()?;
        if count == 0 {
            return Ok(Vec::new());
        }
        self.relay(wavelength, count, direction, progress)
    }
}
