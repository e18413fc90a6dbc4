//! The device the kernels run on: a headless one opened here (the CLI, Python, tests), or the
//! studio's own, built from the device and queue its window draws with.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::kernels::Kernels;

/// Why no device could be used.
#[derive(Debug, Clone, thiserror::Error, PartialEq, Eq)]
pub enum GpuError {
    /// No adapter of the kind asked for (no Vulkan, Metal or DX12 driver, or only a software
    /// one where a GPU was asked for).
    #[error("no GPU adapter: {0}")]
    NoAdapter(String),
    /// The adapter refused a device.
    #[error("the GPU adapter `{adapter}` refused a device: {reason}")]
    NoDevice {
        /// The adapter's name.
        adapter: String,
        /// Its driver's words.
        reason: String,
    },
}

/// Which adapters a headless device may be opened on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdapterKind {
    /// A hardware GPU only (discrete, integrated or virtual): what `auto` takes, since a
    /// software rasteriser is slower than the CPU route.
    Hardware,
    /// Any adapter, a software one (lavapipe, WARP) included: `gpu` forces it, and the tests run
    /// on it.
    Any,
}

/// What the user is told about the device: the adapter's name, its driver and its API.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdapterSummary {
    /// The adapter's name ("NVIDIA H100", "llvmpipe (LLVM 15.0.6, 256 bits)").
    pub name: String,
    /// The driver and its version, as the driver reports them.
    pub driver: String,
    /// The graphics API (Vulkan, Metal, Dx12, Gl).
    pub api: String,
    /// Whether it is a software rasteriser (lavapipe, WARP).
    pub software: bool,
}

impl AdapterSummary {
    fn of(info: &wgpu::AdapterInfo) -> Self {
        AdapterSummary {
            name: info.name.clone(),
            driver: format!("{} {}", info.driver, info.driver_info)
                .trim()
                .to_string(),
            api: format!("{:?}", info.backend),
            software: info.device_type == wgpu::DeviceType::Cpu,
        }
    }
}

impl std::fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({}", self.name, self.api)?;
        if !self.driver.is_empty() {
            write!(f, ", {}", self.driver)?;
        }
        if self.software {
            f.write_str(", software")?;
        }
        f.write_str(")")
    }
}

/// The one line for a buffer larger than the device binds: a refusal by size, which `auto`
/// hands to the CPU.
pub(crate) fn too_large(what: &str, bytes: u64, limit: u64) -> udc_core::SimError {
    udc_core::SimError::TooLarge(format!(
        "{what} needs a {} MiB buffer; this device binds at most {} MiB (use the CPU backend)",
        bytes.div_ceil(1 << 20),
        limit >> 20
    ))
}

/// The one line for a transform the device had no memory for: a refusal by size, which `auto`
/// hands to the CPU.
pub(crate) fn out_of_memory(e: &wgpu::Error) -> udc_core::SimError {
    udc_core::SimError::TooLarge(format!(
        "the GPU has no memory left for this transform ({e}); use the CPU backend"
    ))
}

/// Tables uploaded once per size: the twiddles and pass parameters of one FFT length (power of
/// two, or mixed radix), the chirp of one DFT length, the kernel spectrum of one (DFT length,
/// input length), the chirps and kernel of one optimizer's zoom.
#[derive(Default)]
pub(crate) struct TableCache {
    pub(crate) ffts: HashMap<usize, Arc<crate::kernels::FftPlan>>,
    pub(crate) chirps: HashMap<usize, Arc<wgpu::Buffer>>,
    pub(crate) spectra: HashMap<(usize, usize), Arc<wgpu::Buffer>>,
    pub(crate) mixed: HashMap<usize, Arc<crate::kernels::MixedPlan>>,
    pub(crate) zooms: HashMap<ZoomKey, Arc<ZoomTables>>,
}

/// One chirp-z zoom's tables on the device (`crate::tables::zoom`): the optimizer's window
/// stages.
pub(crate) struct ZoomTables {
    pub(crate) pre: wgpu::Buffer,
    pub(crate) post: wgpu::Buffer,
    pub(crate) kernel: wgpu::Buffer,
}

/// What a zoom's tables depend on: `M`, the summed and output spans, the kernel's sign.
pub(crate) type ZoomKey = (usize, (i64, usize), (i64, usize), bool);

impl TableCache {
    /// Entries kept per table before the cache starts afresh (a sweep over many wavelengths
    /// and sizes would otherwise hold every table it met).
    const MAX_ENTRIES: usize = 48;

    pub(crate) fn trim(&mut self) {
        if self.ffts.len()
            + self.chirps.len()
            + self.spectra.len()
            + self.mixed.len()
            + self.zooms.len()
            > Self::MAX_ENTRIES
        {
            *self = TableCache::default();
        }
    }
}

/// The memory budget of the window's instance (the studio's eframe): a buffer that would take
/// the device past 90 % of the budget the driver reports is refused as out of memory, so a
/// transform too large for the free memory goes to the CPU in one line. No device-loss
/// threshold there: the window draws on the same instance, and losing its device on purpose
/// would close the window.
pub const WINDOW_MEMORY_BUDGET: wgpu::MemoryBudgetThresholds = wgpu::MemoryBudgetThresholds {
    for_resource_creation: Some(90),
    for_device_loss: None,
};

/// A compute device with the kernels compiled on it.
pub struct Gpu {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) kernels: Kernels,
    pub(crate) tables: Mutex<TableCache>,
    adapter: AdapterSummary,
}

impl std::fmt::Debug for Gpu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gpu")
            .field("adapter", &self.adapter)
            .finish_non_exhaustive()
    }
}

impl Gpu {
    /// Opens a device of its own on the first adapter of `kind` (high performance preferred),
    /// with the adapter's own limits, so the largest buffers it can hold are allowed.
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] when no adapter of `kind` exists, [`GpuError::NoDevice`] when
    /// the adapter refuses.
    pub fn headless(kind: AdapterKind) -> Result<Gpu, GpuError> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        // The job budget's view of the device's free memory: where the driver reports a memory
        // budget (Vulkan's VK_EXT_memory_budget, D3D12), a buffer that would take it past 90 %
        // is refused as out of memory ([`out_of_memory`]) instead of risking a lost device.
        descriptor.memory_budget_thresholds = wgpu::MemoryBudgetThresholds {
            for_device_loss: Some(95),
            ..WINDOW_MEMORY_BUDGET
        };
        let instance = wgpu::Instance::new(descriptor);
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::PRIMARY));
        let usable = |a: &wgpu::Adapter| {
            let info = a.get_info();
            // GL adapters have no compute shaders on many drivers; the kernels need them.
            info.backend != wgpu::Backend::Gl
                && info.backend != wgpu::Backend::Noop
                && (kind == AdapterKind::Any || info.device_type != wgpu::DeviceType::Cpu)
        };
        let rank = |a: &wgpu::Adapter| match a.get_info().device_type {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu => 2,
            wgpu::DeviceType::Other => 3,
            wgpu::DeviceType::Cpu => 4,
        };
        let seen: Vec<String> = adapters
            .iter()
            .map(|a| AdapterSummary::of(&a.get_info()).to_string())
            .collect();
        let Some(adapter) = adapters.into_iter().filter(usable).min_by_key(rank) else {
            return Err(GpuError::NoAdapter(if seen.is_empty() {
                "no Vulkan, Metal or DX12 driver found".into()
            } else {
                format!("only {} (a software renderer)", seen.join(", "))
            }));
        };
        Gpu::on_adapter(&adapter)
    }

    /// A device of its own on `adapter` (the studio's: the adapter its window draws with, but
    /// not the window's device, whose surface cannot be reconfigured, on a resize, while a long
    /// transform keeps its queue busy), with the adapter's own limits.
    ///
    /// # Errors
    /// [`GpuError::NoDevice`] when the adapter refuses.
    pub fn on_adapter(adapter: &wgpu::Adapter) -> Result<Gpu, GpuError> {
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("udc-gpu"),
            required_features: wgpu::Features::empty(),
            required_limits: adapter.limits(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| GpuError::NoDevice {
            adapter: info.name.clone(),
            reason: e.to_string(),
        })?;
        Ok(Gpu::from_device(device, queue, &info))
    }

    /// The process's shared headless device of `kind`, opened on first use (the CLI, Python and
    /// tests ask for it many times; the kernels compile once).
    ///
    /// # Errors
    /// As [`Gpu::headless`], remembered: a machine without an adapter is not asked again.
    pub fn shared(kind: AdapterKind) -> Result<Arc<Gpu>, GpuError> {
        shared_cell(kind)
            .get_or_init(|| Gpu::headless(kind).map(Arc::new))
            .clone()
    }

    /// Makes `gpu` the process's shared device (for [`AdapterKind::Any`], and for
    /// [`AdapterKind::Hardware`] unless it is a software one), where none was opened yet: the
    /// studio hands in the device on its window's adapter, so that the jobs it runs by their
    /// `backend` parameter (a study, a quick reproduction) use the GPU its menu names rather
    /// than opening another. Whether `gpu` is now the shared device of any kind.
    pub fn share(gpu: &Arc<Gpu>) -> bool {
        let any = shared_cell(AdapterKind::Any).set(Ok(gpu.clone())).is_ok();
        let hardware = !gpu.adapter().software
            && shared_cell(AdapterKind::Hardware)
                .set(Ok(gpu.clone()))
                .is_ok();
        any || hardware
    }

    /// The kernels on a device someone else opened. (Not the studio's window device: see
    /// [`Gpu::on_adapter`].)
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue, info: &wgpu::AdapterInfo) -> Gpu {
        let kernels = Kernels::new(&device);
        Gpu {
            device,
            queue,
            kernels,
            tables: Mutex::new(TableCache::default()),
            adapter: AdapterSummary::of(info),
        }
    }

    /// The adapter the kernels run on.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    /// The largest storage buffer one kernel may bind, bytes.
    pub fn max_binding_bytes(&self) -> u64 {
        let l = self.device.limits();
        l.max_buffer_size.min(l.max_storage_buffer_binding_size)
    }

    /// The first `bytes` of `readback` (a `MAP_READ` buffer whose copy has been submitted), as
    /// `f32`s, once the device has finished.
    pub(crate) fn read_back(
        &self,
        readback: &wgpu::Buffer,
        bytes: u64,
    ) -> Result<Vec<f32>, udc_core::SimError> {
        let failed = |e: &dyn std::fmt::Display| udc_core::SimError::Device(e.to_string());
        let slice = readback.slice(..bytes);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| failed(&e))?;
        rx.recv().map_err(|e| failed(&e))?.map_err(|e| failed(&e))?;
        let data: Vec<f32> = {
            let view = slice.get_mapped_range().map_err(|e| failed(&e))?;
            bytemuck::cast_slice(&view).to_vec()
        };
        readback.unmap();
        Ok(data)
    }

    /// A storage buffer holding `data`.
    pub(crate) fn pod<T: bytemuck::Pod>(&self, label: &str, data: &[T]) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(data),
                usage: wgpu::BufferUsages::STORAGE,
            })
    }

    /// A buffer of `bytes` for `usage`, at least 16 (a binding may not be empty).
    pub(crate) fn buffer(
        &self,
        label: &str,
        bytes: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.max(16),
            usage,
            mapped_at_creation: false,
        })
    }
}

/// The process's shared device of `kind`, once opened or handed in.
fn shared_cell(kind: AdapterKind) -> &'static OnceLock<Result<Arc<Gpu>, GpuError>> {
    static HARDWARE: OnceLock<Result<Arc<Gpu>, GpuError>> = OnceLock::new();
    static ANY: OnceLock<Result<Arc<Gpu>, GpuError>> = OnceLock::new();
    match kind {
        AdapterKind::Hardware => &HARDWARE,
        AdapterKind::Any => &ANY,
    }
}
