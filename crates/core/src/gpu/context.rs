//! The device and queue every GPU computation runs on.

use super::GpuError;

/// A wgpu device and queue with a description of the adapter behind them.
///
/// `wgpu::Device` and `wgpu::Queue` are reference-counted handles, so a context is cheap to
/// clone, and the egui app can wrap eframe's own device with [`GpuContext::from_device`].
#[derive(Clone, Debug)]
pub struct GpuContext {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    /// A lower binding limit than the device's, for tests of split arrays.
    binding_limit: Option<u64>,
}

impl GpuContext {
    /// The optional features lightpick asks of a device when the adapter has them:
    /// `TIMESTAMP_QUERY`, so that pass times come from the GPU's own clock
    /// ([`super::PassTimer`]).
    pub const TIMING_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY;

    /// Creates a device on the best adapter available.
    ///
    /// The primary backends (Vulkan, Metal, DX12) are tried first and every backend (GL too)
    /// only if they find no adapter; wgpu's environment overrides are honoured:
    /// `WGPU_BACKEND` (e.g. `vulkan`, `gl`) restricts the backends, `WGPU_POWER_PREF`
    /// (`low`, `high`, `none`) replaces the default high-performance preference, and
    /// `WGPU_ADAPTER_NAME` picks the first adapter whose name contains it. The device gets
    /// the adapter's own limits (`required_limits = adapter.limits()`), so compute works on
    /// GL adapters too and large light tables may use all the memory the adapter offers.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        // The primary backends first; GL (an EGL probe, slow, and a second adapter of the
        // same device) only when none of them has an adapter, or when WGPU_BACKEND asks.
        let mut adapter = Err(GpuError::NoAdapter {
            reason: "no backend tried".to_owned(),
        });
        for backends in [wgpu::Backends::PRIMARY, wgpu::Backends::all()] {
            let descriptor = wgpu::InstanceDescriptor {
                backends,
                ..wgpu::InstanceDescriptor::new_without_display_handle()
            }
            .with_env();
            let instance = wgpu::Instance::new(descriptor);
            adapter = Self::pick_adapter(&instance).await;
            if adapter.is_ok() {
                break;
            }
        }
        let adapter = adapter?;
        let info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("lightpick"),
                required_features: adapter.features() & Self::TIMING_FEATURES,
                required_limits: adapter.limits(),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|e| GpuError::RequestDevice {
                adapter: info.name.clone(),
                reason: e.to_string(),
            })?;
        Ok(Self {
            device,
            queue,
            info,
            binding_limit: None,
        })
    }

    async fn pick_adapter(instance: &wgpu::Instance) -> Result<wgpu::Adapter, GpuError> {
        if let Ok(name) = std::env::var("WGPU_ADAPTER_NAME") {
            let name = name.to_lowercase();
            let adapters = instance.enumerate_adapters(wgpu::Backends::all()).await;
            let found: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
            return adapters
                .into_iter()
                .find(|a| a.get_info().name.to_lowercase().contains(&name))
                .ok_or_else(|| GpuError::AdapterNameNotFound {
                    name,
                    found: if found.is_empty() {
                        "none".to_owned()
                    } else {
                        found.join(", ")
                    },
                });
        }
        let power_preference =
            wgpu::PowerPreference::from_env().unwrap_or(wgpu::PowerPreference::HighPerformance);
        instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            })
            .await
            .map_err(|e| GpuError::NoAdapter {
                reason: e.to_string(),
            })
    }

    /// Wraps an existing device and queue (for example eframe's `RenderState`), described by
    /// `info` (from `adapter.get_info()`).
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue, info: wgpu::AdapterInfo) -> Self {
        Self {
            device,
            queue,
            info,
            binding_limit: None,
        }
    }

    /// The most bytes one storage binding may hold here: the device's
    /// `max_storage_buffer_binding_size` (and `max_buffer_size`, if lower). Arrays beyond it
    /// are split over several bindings ([`crate::gpu`] § Limits).
    pub fn storage_binding_limit(&self) -> u64 {
        let limits = self.device.limits();
        let device = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        self.binding_limit.map_or(device, |l| l.min(device))
    }

    /// The same device with a smaller binding limit (at least 16 bytes), so that tests can
    /// split arrays over several bindings without allocating hundreds of megabytes.
    #[doc(hidden)]
    #[must_use]
    pub fn with_storage_binding_limit(mut self, bytes: u64) -> Self {
        self.binding_limit = Some(bytes.max(16));
        self
    }

    /// The logical device.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue work is submitted to.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// The adapter's description as wgpu reports it.
    pub fn info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    /// The adapter's name, e.g. `llvmpipe (LLVM 19.1.7, 256 bits)`.
    pub fn adapter_name(&self) -> &str {
        &self.info.name
    }

    /// The backend the device runs on.
    pub fn backend(&self) -> wgpu::Backend {
        self.info.backend
    }

    /// A one-line description for notices: `name (backend)`.
    pub fn description(&self) -> String {
        format!("{} ({})", self.info.name, self.info.backend)
    }

    /// Whether the adapter is a software rasterizer on the CPU (lavapipe, llvmpipe, WARP).
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }
}
