//! Recombination: the scattered diffuse light (the unscattered on pixels without SSS) × the
//! post-scatter albedo + specular, then exposure, tone curve and sRGB (combine.wgsl).

use crate::error::Result;
use crate::frame::context::{Gpu, compute_pipeline};
use crate::frame::recording::Recording;
use crate::params::RenderParams;
use crate::passes::Pass;
use crate::passes::gbuffer::GBuffer;

/// The final image: linear radiance (RGBA f32) and tone-mapped sRGB (RGBA8) per pixel.
pub(crate) struct Combined {
    pub linear: wgpu::Buffer,
    pub display: wgpu::Buffer,
}

/// The compiled recombination pipeline.
pub(crate) struct Combine {
    pipeline: wgpu::ComputePipeline,
}

impl Pass for Combine {
    /// The frame's settings, the scattered light and the G-buffer.
    type Input<'a> = (&'a RenderParams, &'a wgpu::Buffer, &'a GBuffer);
    /// The linear and the tone-mapped image.
    type Output = Combined;

    fn new(gpu: &Gpu) -> Combine {
        Combine {
            pipeline: compute_pipeline(
                &gpu.device,
                wgpu::include_wgsl!("../shaders/combine.wgsl"),
                "combine",
            ),
        }
    }

    /// Records the recombination of `scattered` with the G-buffer at the size and exposure of
    /// `params`.
    fn encode(
        &self,
        rec: &mut Recording,
        (params, scattered, g): Self::Input<'_>,
    ) -> Result<Combined> {
        let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
        let (w, h, exposure) = (params.width, params.height, params.exposure);
        let n = (w * h) as usize;
        let out = Combined {
            linear: alloc.pixels(n, "linear"),
            // RGBA8: four pixels to a 16-byte element.
            display: alloc.pixels(n.div_ceil(4), "display"),
        };
        let uniform = alloc.uniform(
            "combine params",
            bytemuck::cast_slice(&[w, h, exposure.to_bits(), 0]),
        );
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
        let bind = alloc
            .gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
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
        Ok(out)
    }
}
