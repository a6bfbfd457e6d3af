//! The shadow pass: one depth map per light that casts shadows, drawn from the light (an
//! orthographic view over the SSS objects for directional lights, a perspective one for point
//! lights; [`crate::Scene`]'s `light_view_proj`). The scene pass reads them for shadows and for
//! the thickness light crosses in thin parts.

use wgpu::util::DeviceExt;

use crate::context::{Gpu, cleared_depth, mesh_pipeline, texture};
use crate::mesh::MeshBuffers;
use crate::scene::{Light, Scene};
use crate::timing::Timer;

/// Side of each shadow map [texels].
pub(crate) const SHADOW_SIZE: u32 = 2048;

/// The compiled shadow pipeline.
pub(crate) struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
}

impl ShadowPass {
    pub(crate) fn new(gpu: &Gpu) -> ShadowPass {
        let dev = &gpu.device;
        let module = dev.create_shader_module(wgpu::include_wgsl!("shaders/shadow.wgsl"));
        ShadowPass {
            pipeline: mesh_pipeline(dev, &module, "shadow", &[]),
        }
    }

    /// Records the shadow maps of `scene`'s lights: a depth array with one layer per light (at
    /// least one, so the scene pass's binding exists); layers of lights without shadows stay
    /// cleared.
    pub(crate) fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        scene: &Scene,
        mesh: &MeshBuffers,
        timer: &mut Option<&mut Timer>,
    ) -> wgpu::Texture {
        let dev = &gpu.device;
        let layers = scene.lights.len().max(1) as u32;
        let maps = texture(
            dev,
            "shadow maps",
            (SHADOW_SIZE, SHADOW_SIZE, layers),
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        for (i, light) in scene.lights.iter().enumerate() {
            let shadow = match *light {
                Light::Directional { shadow, .. } | Light::Point { shadow, .. } => shadow,
            };
            let vp = scene.light_view_proj(light);
            let ubuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("light"),
                contents: bytemuck::bytes_of(&vp.to_cols_array_2d()),
                usage: wgpu::BufferUsages::UNIFORM,
            });
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
            if shadow {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &bind, &[]);
                mesh.draw(&mut pass);
            }
        }
        maps
    }
}
