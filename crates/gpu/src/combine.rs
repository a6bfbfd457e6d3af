//! Recombination: the scattered diffuse light (the unscattered on pixels without SSS) × the
//! post-scatter albedo + specular, then exposure, tone curve and sRGB (combine.wgsl).

use wgpu::util::DeviceExt;

use crate::context::{Gpu, compute_pipeline, pixels};
use crate::gbuffer::GBuffer;
use crate::params::RenderParams;
use crate::recording::Recording;

/// The final image: linear radiance (RGBA f32) and tone-mapped sRGB (RGBA8) per pixel.
pub(crate) struct Combined {
    pub linear: wgpu::Buffer,
    pub display: wgpu::Buffer,
}

/// The compiled recombination pipeline.
pub(crate) struct Combine {
    pipeline: wgpu::ComputePipeline,
}

impl Combine {
    pub(crate) fn new(gpu: &Gpu) -> Combine {
        Combine {
            pipeline: compute_pipeline(
                &gpu.device,
                wgpu::include_wgsl!("shaders/combine.wgsl"),
                "combine",
            ),
        }
    }

    /// Records the recombination of `scattered` with the G-buffer at the size and exposure of
    /// `params`.
    pub(crate) fn encode(
        &self,
        rec: &mut Recording,
        params: &RenderParams,
        scattered: &wgpu::Buffer,
        g: &GBuffer,
    ) -> Combined {
        let (gpu, enc, timer) = (rec.gpu, &mut rec.enc, &mut rec.timer.as_mut());
        let dev = &gpu.device;
        let (w, h, exposure) = (params.width, params.height, params.exposure);
        let n = (w * h) as usize;
        let out = Combined {
            linear: pixels(gpu, n, "linear"),
            display: dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("display"),
                size: (n * 4).max(4) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
        };
        let uniform = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("combine params"),
            contents: bytemuck::cast_slice(&[w, h, exposure.to_bits(), 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let resources = [
            &uniform,
            scattered,
            &g.specular,
            &g.albedo,
            &out.linear,
            &out.display,
            &g.diffuse,
            &g.geometry,
        ];
        let entries: Vec<wgpu::BindGroupEntry> = resources
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("combine"),
            timestamp_writes: timer.as_mut().map(|t| t.writes("combine")),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        drop(pass);
        out
    }
}
