//! The headless device: any adapter wgpu finds (a discrete GPU first, else a software one such as
//! Mesa's lavapipe), with timestamp queries where the adapter has them.

use crate::error::{GpuError, Result};

/// A device and its queue.
pub struct Gpu {
    /// The device every buffer, texture and pipeline is created on.
    pub device: wgpu::Device,
    /// Its queue: every frame's commands are submitted here.
    pub queue: wgpu::Queue,
    /// Adapter name and backend, for reports.
    pub adapter_name: String,
    /// Whether per-pass GPU timestamps are available.
    pub timestamps: bool,
    /// Whether rgba32float render targets can blend (additive splats accumulate in f32; else in
    /// f16, whose 11-bit mantissa drops contributions below 2⁻¹² of the running sum).
    pub float32_blend: bool,
}

/// Keeps Mesa's device-select Vulkan layer quiet on a headless machine: where
/// `XDG_RUNTIME_DIR` is unset it looks for a Wayland display anyway and prints "error:
/// XDG_RUNTIME_DIR is invalid or not set in the environment." twice, though nothing failed.
/// There, unless the user has set it, this sets `NODEVICE_SELECT=1`, which skips the layer: it
/// only orders the adapters, and [`Gpu::new`] picks one by power preference itself. A desktop
/// session (which sets `XDG_RUNTIME_DIR`) is left as it is.
///
/// # Safety
/// It changes the process's environment: call it before any other thread starts (first thing in
/// a binary's `main`).
pub unsafe fn quiet_headless_vulkan() {
    let unset = |k| std::env::var_os(k).is_none();
    if unset("XDG_RUNTIME_DIR") && unset("NODEVICE_SELECT") {
        // SAFETY: the caller guarantees that no other thread reads the environment meanwhile.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

impl Gpu {
    /// Opens the best adapter of Vulkan, Metal or DX12 (a GL backend only adds noise headless).
    pub fn new() -> Result<Gpu> {
        Gpu::with_backends(wgpu::Backends::PRIMARY)
    }

    /// Opens the best adapter of the given backends.
    pub fn with_backends(backends: wgpu::Backends) -> Result<Gpu> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let float32_blend = adapter
            .features()
            .contains(wgpu::Features::FLOAT32_BLENDABLE);
        let mut limits = wgpu::Limits::default().using_resolution(adapter.limits());
        limits.max_storage_buffer_binding_size = adapter.limits().max_storage_buffer_binding_size;
        limits.max_buffer_size = adapter.limits().max_buffer_size;
        limits.max_storage_buffers_per_shader_stage = 8;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sss"),
            required_features: adapter.features()
                & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::FLOAT32_BLENDABLE),
            required_limits: limits,
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Gpu {
            device,
            queue,
            adapter_name: format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type),
            timestamps,
            float32_blend,
        })
    }

    /// Copies `size` bytes of `buffer` (which must have COPY_SRC usage) to the CPU.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([enc.finish()]);
        let slice = staging.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let bytes = slice
            .get_mapped_range()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .to_vec();
        staging.unmap();
        Ok(bytes)
    }
}

/// A compute pipeline from a WGSL module's `main`, its layout derived from the shader.
pub(crate) fn compute_pipeline(
    dev: &wgpu::Device,
    module: wgpu::ShaderModuleDescriptor,
    label: &str,
) -> wgpu::ComputePipeline {
    let module = dev.create_shader_module(module);
    entry_pipeline(dev, &module, "main", label)
}

/// A compute pipeline from entry point `entry` of a compiled module, its layout derived from the
/// shader.
pub(crate) fn entry_pipeline(
    dev: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry: &str,
    label: &str,
) -> wgpu::ComputePipeline {
    dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// A whole buffer at `binding` of a bind group.
pub(crate) fn bind(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// A texture view at `binding` of a bind group.
pub(crate) fn bind_view(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}

/// A depth attachment cleared to the far plane (1) and kept.
pub(crate) fn cleared_depth(
    view: &wgpu::TextureView,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// Storage buffer for `n` RGBA f32 pixels.
pub(crate) fn pixels(gpu: &Gpu, n: usize, label: &str) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: (n * 16).max(16) as u64,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A 2D texture (array of `layers`) of one mip level.
pub(crate) fn texture(
    dev: &wgpu::Device,
    label: &str,
    (width, height, layers): (u32, u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    dev.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}
