//! The shadow pass: one depth map per emitter that casts shadows, drawn from it (an
//! orthographic view over the SSS objects for directional lights, a perspective one for point
//! lights and the cells of area lights; [`crate::Scene`]'s `light_view_proj`). The scene pass reads them for shadows and for
//! the thickness light crosses in thin parts.

use crate::error::Result;
use crate::frame::context::{Gpu, cleared_depth};
use crate::frame::recording::Recording;
use crate::mesh::MeshBuffers;
use crate::passes::Pass;
use crate::scene::Scene;

/// Side of each shadow map [texels]: 2048, or 1024 beyond 16 emitters (an area light's cells),
/// which keeps the maps within 256 MB.
pub(crate) fn shadow_size(layers: u32) -> u32 {
    if layers > 16 { 1024 } else { 2048 }
}

/// The compiled shadow pipeline.
pub(crate) struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
}

impl Pass for ShadowPass {
    /// The scene and its mesh as uploaded.
    type Input<'a> = (&'a Scene, &'a MeshBuffers);
    /// The shadow maps.
    type Output = wgpu::Texture;

    fn new(gpu: &Gpu) -> ShadowPass {
        let dev = &gpu.device;
        let module = dev.create_shader_module(wgpu::include_wgsl!("../shaders/shadow.wgsl"));
        ShadowPass {
            pipeline: crate::mesh::pipeline(dev, &module, "shadow", &[]),
        }
    }

    /// Records the shadow maps of `scene`'s emitters: a depth array with one layer per emitter
    /// (at least one, so the scene pass's binding exists); layers of emitters without shadows
    /// stay cleared.
    fn encode(&self, rec: &mut Recording, (scene, mesh): Self::Input<'_>) -> Result<wgpu::Texture> {
        let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
        let dev = &alloc.gpu.device;
        let emitters = scene.emitters();
        let layers = emitters.len().max(1) as u32;
        // Each light's layer is cleared by its pass; without lights nothing reads the map.
        let maps = alloc.texture(
            "shadow maps",
            (shadow_size(layers), shadow_size(layers), layers),
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        for (i, light) in emitters.iter().enumerate() {
            let vp = scene.light_view_proj(light);
            let ubuf = alloc.uniform("light", bytemuck::bytes_of(&vp.to_cols_array_2d()));
            let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &self.pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: ubuf.as_entire_binding(),
                }],
            });
            let view = maps.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: i as u32,
                array_layer_count: Some(1),
                ..Default::default()
            });
            let label = format!("shadow map {}", i + 1);
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&label),
                color_attachments: &[],
                depth_stencil_attachment: Some(cleared_depth(&view)),
                timestamp_writes: timer.as_mut().map(|t| t.render_writes(&label)),
                ..Default::default()
            });
            if light.shadow {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &bind, &[]);
                mesh.draw(&mut pass);
            }
        }
        Ok(maps)
    }
}
