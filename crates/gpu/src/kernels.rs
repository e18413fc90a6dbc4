//! The compute pipelines (one per WGSL entry point) and the recording of a batched
//! power-of-two FFT: Stockham passes (radix 4, and one radix 2 where `log2 N` is odd), one
//! dispatch each, ping-ponging between two buffers. (An FFT held in workgroup memory, one
//! dispatch per transform, was 1.3–1.9× slower on the software driver the tests run on, for
//! its barriers; it waits for a hardware GPU to be measured on.)

use crate::tables::twiddles;

/// The shader sources, compiled once per device.
const FFT_WGSL: &str = include_str!("shaders/fft.wgsl");
const BLUESTEIN_WGSL: &str = include_str!("shaders/bluestein.wgsl");
const BIN_WGSL: &str = include_str!("shaders/bin.wgsl");
const MIXED_WGSL: &str = include_str!("shaders/mixed.wgsl");
const RELAY_WGSL: &str = include_str!("shaders/relay.wgsl");
const WINDOW_WGSL: &str = include_str!("shaders/window.wgsl");

/// Threads per workgroup along x in the 1-D kernels (the shaders' `@workgroup_size(256)`).
pub(crate) const GROUP: u32 = 256;

/// The compiled pipelines.
pub struct Kernels {
    pub(crate) fft_pass: wgpu::ComputePipeline,
    pub(crate) fft_pass4: wgpu::ComputePipeline,
    pub(crate) prechirp_rows: wgpu::ComputePipeline,
    pub(crate) convolve: wgpu::ComputePipeline,
    pub(crate) postchirp_rows: wgpu::ComputePipeline,
    pub(crate) prechirp_columns: wgpu::ComputePipeline,
    pub(crate) intensity_columns: wgpu::ComputePipeline,
    pub(crate) bin_window: wgpu::ComputePipeline,
    pub(crate) band_columns: wgpu::ComputePipeline,
    /// The mixed-radix pass for radix 2, 3, 4 and 5 (index `radix − 2`).
    pub(crate) fft_radix: [wgpu::ComputePipeline; 4],
    pub(crate) form_transfer: wgpu::ComputePipeline,
    pub(crate) apply_slits: wgpu::ComputePipeline,
    pub(crate) apply_transfer: wgpu::ComputePipeline,
    pub(crate) opening_input: wgpu::ComputePipeline,
    pub(crate) energy: wgpu::ComputePipeline,
    pub(crate) apply_kernel: wgpu::ComputePipeline,
    pub(crate) fine_intensity: wgpu::ComputePipeline,
    pub(crate) zoom_pre: wgpu::ComputePipeline,
    pub(crate) zoom_post: wgpu::ComputePipeline,
}

impl Kernels {
    pub(crate) fn new(device: &wgpu::Device) -> Kernels {
        let module = |label: &str, source: &'static str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
        };
        let fft = module("fft.wgsl", FFT_WGSL);
        let bluestein = module("bluestein.wgsl", BLUESTEIN_WGSL);
        let bin = module("bin.wgsl", BIN_WGSL);
        let mixed = module("mixed.wgsl", MIXED_WGSL);
        let relay = module("relay.wgsl", RELAY_WGSL);
        let window = module("window.wgsl", WINDOW_WGSL);
        let pipeline = |module: &wgpu::ShaderModule, entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        Kernels {
            fft_pass: pipeline(&fft, "fft_pass"),
            fft_pass4: pipeline(&fft, "fft_pass4"),
            prechirp_rows: pipeline(&bluestein, "prechirp_rows"),
            convolve: pipeline(&bluestein, "convolve"),
            postchirp_rows: pipeline(&bluestein, "postchirp_rows"),
            prechirp_columns: pipeline(&bluestein, "prechirp_columns"),
            intensity_columns: pipeline(&bluestein, "intensity_columns"),
            bin_window: pipeline(&bin, "bin_window"),
            band_columns: pipeline(&bin, "band_columns"),
            fft_radix: [2u32, 3, 4, 5].map(|r| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some("fft_radix"),
                    layout: None,
                    module: &mixed,
                    entry_point: Some("fft_radix"),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &[("RADIX", f64::from(r))],
                        ..Default::default()
                    },
                    cache: None,
                })
            }),
            form_transfer: pipeline(&relay, "form_transfer"),
            apply_slits: pipeline(&relay, "apply_slits"),
            apply_transfer: pipeline(&relay, "apply_transfer"),
            opening_input: pipeline(&relay, "opening_input"),
            energy: pipeline(&relay, "energy"),
            apply_kernel: pipeline(&relay, "apply_kernel"),
            fine_intensity: pipeline(&relay, "fine_intensity"),
            zoom_pre: pipeline(&window, "zoom_pre"),
            zoom_post: pipeline(&window, "zoom_post"),
        }
    }
}

/// A bind group for `pipeline`'s group 0 with `buffers` at their bindings.
pub(crate) fn bind(
    device: &wgpu::Device,
    pipeline: &wgpu::ComputePipeline,
    buffers: &[(u32, &wgpu::Buffer)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .map(|&(binding, buffer)| wgpu::BindGroupEntry {
            binding,
            resource: buffer.as_entire_binding(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

/// A uniform buffer holding `words`.
pub(crate) fn uniform(device: &wgpu::Device, words: &[u32]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("params"),
        contents: bytemuck::cast_slice(words),
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

/// Workgroups covering `n` threads of `GROUP`.
pub(crate) fn groups(n: usize) -> u32 {
    u32::try_from(n.div_ceil(GROUP as usize)).unwrap_or(u32::MAX)
}

/// One FFT length's twiddles and per-pass parameters, uploaded once: radix-4 passes with
/// spans 1, 4, 16, … while they fit, then one radix-2 pass where `log2 N` is odd.
pub(crate) struct FftPlan {
    pub(crate) n: usize,
    twiddles: wgpu::Buffer,
    /// Each pass's radix (4 or 2) and its `(N, span)` parameters.
    passes: Vec<(usize, wgpu::Buffer)>,
}

impl FftPlan {
    pub(crate) fn new(device: &wgpu::Device, n: usize) -> FftPlan {
        use wgpu::util::DeviceExt;
        debug_assert!(n.is_power_of_two() && n >= 2);
        let twiddles = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("twiddles"),
            contents: bytemuck::cast_slice(&twiddles(n)),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let mut passes = Vec::new();
        let mut span = 1usize;
        while span * 4 <= n {
            passes.push((4, uniform(device, &[n as u32, span as u32, 0, 0])));
            span *= 4;
        }
        if span * 2 == n {
            passes.push((2, uniform(device, &[n as u32, span as u32, 0, 0])));
        }
        FftPlan {
            n,
            twiddles,
            passes,
        }
    }

    /// Records the forward FFT of `batch` vectors held in `a`; returns whether the result ended
    /// in `a` (an even number of passes) or in `b`.
    pub(crate) fn record(
        &self,
        device: &wgpu::Device,
        kernels: &Kernels,
        pass: &mut wgpu::ComputePass<'_>,
        a: &wgpu::Buffer,
        b: &wgpu::Buffer,
        batch: u32,
    ) -> bool {
        let mut in_a = true;
        for (radix, params) in &self.passes {
            let (src, dst) = if in_a { (a, b) } else { (b, a) };
            let kernel = if *radix == 4 {
                &kernels.fft_pass4
            } else {
                &kernels.fft_pass
            };
            let group = bind(
                device,
                kernel,
                &[(0, params), (1, &self.twiddles), (2, src), (3, dst)],
            );
            pass.set_pipeline(kernel);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(groups(self.n / radix), batch, 1);
            in_a = !in_a;
        }
        in_a
    }
}

/// The radices of a mixed-radix FFT of length `n` (fours, a two, threes, fives), or `None`
/// when `n` has a prime factor above 5.
pub(crate) fn radices(mut n: usize) -> Option<Vec<usize>> {
    let mut out = Vec::new();
    while n.is_multiple_of(4) {
        out.push(4);
        n /= 4;
    }
    for r in [2, 3, 5] {
        while n.is_multiple_of(r) {
            out.push(r);
            n /= r;
        }
    }
    (n == 1).then_some(out)
}

/// One 2·3·5-smooth FFT length's table `exp(−2πi t/N)` (t < N) and per-pass parameters, forward
/// and inverse, uploaded once.
pub(crate) struct MixedPlan {
    pub(crate) n: usize,
    table: wgpu::Buffer,
    /// Each pass's radix and its forward and inverse `(N, span, radix, inverse)` parameters.
    passes: Vec<(usize, wgpu::Buffer, wgpu::Buffer)>,
}

impl MixedPlan {
    /// `None` when `n` has a prime factor above 5.
    pub(crate) fn new(device: &wgpu::Device, n: usize) -> Option<MixedPlan> {
        use wgpu::util::DeviceExt;
        let table = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mixed twiddles"),
            contents: bytemuck::cast_slice(&crate::tables::roots(n)),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let mut span = 1usize;
        let passes = radices(n)?
            .into_iter()
            .map(|r| {
                let words = |inverse: u32| [n as u32, span as u32, r as u32, inverse];
                let pass = (r, uniform(device, &words(0)), uniform(device, &words(1)));
                span *= r;
                pass
            })
            .collect();
        Some(MixedPlan { n, table, passes })
    }

    /// Records the FFT (`inverse`: unnormalised inverse) of `batch` vectors held in `a`;
    /// returns `(the buffer the result ended in, the other)`.
    pub(crate) fn record<'b>(
        &self,
        device: &wgpu::Device,
        kernels: &Kernels,
        pass: &mut wgpu::ComputePass<'_>,
        (a, b): (&'b wgpu::Buffer, &'b wgpu::Buffer),
        batch: u32,
        inverse: bool,
    ) -> (&'b wgpu::Buffer, &'b wgpu::Buffer) {
        let mut in_a = true;
        for (radix, forward, backward) in &self.passes {
            let kernel = &kernels.fft_radix[radix - 2];
            pass.set_pipeline(kernel);
            let (src, dst) = if in_a { (a, b) } else { (b, a) };
            let params = if inverse { backward } else { forward };
            let group = bind(
                device,
                kernel,
                &[(0, params), (1, &self.table), (2, src), (3, dst)],
            );
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(groups(self.n / radix), batch, 1);
            in_a = !in_a;
        }
        if in_a { (a, b) } else { (b, a) }
    }
}
