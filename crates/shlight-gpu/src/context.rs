//! Opening a GPU device: headless (no window) or for a window's surface.

use crate::GpuError;

/// An open adapter, device and queue.
#[derive(Debug)]
pub struct GpuContext {
    /// The wgpu instance (the viewer creates its surface from it).
    pub instance: wgpu::Instance,
    /// The adapter chosen.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl GpuContext {
    /// Opens the preferred adapter without a window (a GPU when there is
    /// one, else a software rasteriser such as Mesa's lavapipe).
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] when no Vulkan adapter exists (with what to
    /// install), [`GpuError::Device`] when the adapter refuses a device.
    pub fn headless() -> Result<Self, GpuError> {
        let instance = new_instance(None);
        Self::with_instance(instance, None)
    }

    /// Opens an adapter on `instance` able to present to `surface` (when
    /// given), with the adapter's limits and, when it has it,
    /// `FLOAT32_FILTERABLE` (the volume pass's filtered interpolation).
    ///
    /// # Errors
    /// As [`GpuContext::headless`].
    pub fn with_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        // Linear filtering of Rgba32Float textures, where the adapter has
        // it: on a CPU adapter the volume pass then interpolates its probes
        // with the sampler (VolumeFetch::best).
        let features = adapter.features() & wgpu::Features::FLOAT32_FILTERABLE;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("shlight"),
            required_features: features,
            // The adapter's own limits: large storage buffers for projection.
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device {
            adapter: describe(&adapter),
            reason: e.to_string(),
        })?;
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// The adapter's name, device type and backend, e.g.
    /// `llvmpipe (LLVM 15.0.6, 256 bits) (Cpu, Vulkan)`.
    #[must_use]
    pub fn adapter_name(&self) -> String {
        describe(&self.adapter)
    }

    /// Waits until the queue is idle; a lost device becomes an error.
    pub(crate) fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Runtime(e.to_string()))
    }

    /// Runs `f` inside an error scope and returns the first validation or
    /// out-of-memory error it raised.
    pub(crate) fn checked<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let out = f();
        let oom = pollster::block_on(memory.pop());
        let invalid = pollster::block_on(validation.pop());
        match invalid.or(oom) {
            Some(e) => Err(GpuError::Runtime(e.to_string())),
            None => Ok(out),
        }
    }
}

/// An instance with the Vulkan backend (the one shlight is built with),
/// taking `WGPU_*` environment overrides into account.
#[must_use]
pub fn new_instance(display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>) -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::VULKAN;
    desc.display = display;
    wgpu::Instance::new(desc.with_env())
}

fn describe(adapter: &wgpu::Adapter) -> String {
    let info = adapter.get_info();
    format!("{} ({:?}, {:?})", info.name, info.device_type, info.backend)
}

/// A sampler that filters bilinearly between texel centres (and linearly
/// between a 3D texture's slices), clamped at the edges, with no mip
/// blending: what the volume's probes and a lightmap's pages are read
/// with.
pub(crate) fn linear_clamp_sampler(device: &wgpu::Device, label: &str) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(label),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        ..Default::default()
    })
}
