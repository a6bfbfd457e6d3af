//! Half-resolution SSS (what Unreal ships by default): the irradiance is averaged into 2×2 blocks,
//! the separable passes run on a quarter of the pixels, and the result is brought back by a
//! depth- and material-aware bilinear upsampling (half.wgsl); the final image is still composed
//! at full resolution, so albedo and specular keep their detail.

use crate::frame::context::Gpu;
use crate::frame::pool::Alloc;
use crate::frame::recording::Recording;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Uniform {
    width: u32,
    height: u32,
    half_width: u32,
    half_height: u32,
    tolerance: f32,
    _pad: [u32; 3],
}

/// The size of half.wgsl's `Params` (checked against naga's layout in a test).
pub(crate) const HALF_UNIFORM_SIZE: usize = 32;
const _: () = assert!(std::mem::size_of::<Uniform>() == HALF_UNIFORM_SIZE);

/// The compiled down- and upsampling pipelines.
pub(crate) struct HalfRes {
    down: wgpu::ComputePipeline,
    up: wgpu::ComputePipeline,
}

/// The half-resolution size of a `width`×`height` image.
pub(crate) fn half_size((w, h): (u32, u32)) -> (u32, u32) {
    (w.div_ceil(2), h.div_ceil(2))
}

impl HalfRes {
    pub(crate) fn new(gpu: &Gpu) -> HalfRes {
        let dev = &gpu.device;
        let module = dev.create_shader_module(wgpu::include_wgsl!("../shaders/half.wgsl"));
        let pipeline =
            |entry: &str| crate::frame::context::entry_pipeline(dev, &module, entry, entry);
        HalfRes {
            down: pipeline("down"),
            up: pipeline("up"),
        }
    }

    /// Records one pass of `pipeline` over `(x, y)` pixels with `buffers` at their bindings.
    fn pass(
        &self,
        rec: &mut Recording,
        pipeline: &wgpu::ComputePipeline,
        label: &str,
        (x, y): (u32, u32),
        buffers: &[(u32, &wgpu::Buffer)],
    ) {
        let (gpu, enc, timer) = (rec.gpu, &mut rec.enc, &mut rec.timer.as_mut());
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .map(|(b, buf)| wgpu::BindGroupEntry {
                binding: *b,
                resource: buf.as_entire_binding(),
            })
            .collect();
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: timer.as_mut().map(|t| t.writes(label)),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(x.div_ceil(8), y.div_ceil(8), 1);
    }

    /// Records the downsampling of `diffuse` and `geometry` (full resolution `size`) into
    /// `half_diffuse` and `half_geometry`, the blur's input at [`half_size`].
    pub(crate) fn down(
        &self,
        rec: &mut Recording,
        size: (u32, u32),
        tolerance_cm: f32,
        full: (&wgpu::Buffer, &wgpu::Buffer),
        half: (&wgpu::Buffer, &wgpu::Buffer),
    ) -> wgpu::Buffer {
        let u = Self::uniform(rec.alloc, size, tolerance_cm);
        self.pass(
            rec,
            &self.down,
            "half-res down",
            half_size(size),
            &[(0, &u), (1, full.0), (2, full.1), (3, half.0), (4, half.1)],
        );
        u
    }

    /// Records the upsampling of the blurred `half_scattered` into `scattered` (full resolution),
    /// with the uniform [`HalfRes::down`] returned.
    pub(crate) fn up(
        &self,
        rec: &mut Recording,
        size: (u32, u32),
        uniform: &wgpu::Buffer,
        full: (&wgpu::Buffer, &wgpu::Buffer),
        half: (&wgpu::Buffer, &wgpu::Buffer),
        scattered: &wgpu::Buffer,
    ) {
        self.pass(
            rec,
            &self.up,
            "half-res up",
            size,
            &[
                (0, uniform),
                (1, full.0),
                (2, full.1),
                (5, half.0),
                (6, scattered),
                (7, half.1),
            ],
        );
    }

    fn uniform(alloc: Alloc, size: (u32, u32), tolerance_cm: f32) -> wgpu::Buffer {
        let (hw, hh) = half_size(size);
        let u = Uniform {
            width: size.0,
            height: size.1,
            half_width: hw,
            half_height: hh,
            tolerance: tolerance_cm.max(1e-6),
            _pad: [0; 3],
        };
        alloc.uniform("half-res params", bytemuck::bytes_of(&u))
    }
}
