//! The shadow pass: one depth map per emitter that casts shadows, drawn from it (an
//! orthographic view over the SSS objects for directional lights, a perspective one for point
//! lights and the cells of area lights; [`crate::Scene`]'s `light_view_proj`). The scene pass reads them for shadows and for
//! the thickness light crosses in thin parts. Where a material has a shape table
//! ([`shading::Shading::shape`]), each emitter also gets a back map (the layers after the shadow
//! maps, [`back_layers`]): the nearest surface behind its first one (depth peeling), where the
//! light ray leaves the body it entered, so that the scene pass knows the body's chord along it.

use crate::error::Result;
use crate::frame::context::{Gpu, bind, bind_view, cleared_depth};
use crate::frame::recording::Recording;
use crate::frame::timing::Timer;
use crate::mesh::MeshBuffers;
use crate::params::RenderParams;
use crate::passes::Pass;
use crate::scene::Scene;

/// Side of each shadow map [texels]: 2048, or 1024 beyond 16 emitters (an area light's cells),
/// which keeps the maps within 256 MB.
pub(crate) fn shadow_size(layers: u32) -> u32 {
    if layers > 16 { 1024 } else { 2048 }
}

/// Where the back maps start in the shadow maps' array: after one layer per emitter where some
/// material of `params` has a shape table, 0 (none) otherwise.
pub(crate) fn back_layers(scene: &Scene, params: &RenderParams) -> u32 {
    if params.shading.iter().any(|s| s.shape.is_some()) {
        scene.emitters().len().max(1) as u32
    } else {
        0
    }
}

/// The compiled shadow pipelines: the first surfaces, and the next ones behind them.
pub(crate) struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
    peel: wgpu::RenderPipeline,
}

impl Pass for ShadowPass {
    /// The scene, its mesh as uploaded, and where the back maps start (0: none, [`back_layers`]).
    type Input<'a> = (&'a Scene, &'a MeshBuffers, u32);
    /// The shadow maps (then the back maps).
    type Output = wgpu::Texture;

    fn new(gpu: &Gpu) -> ShadowPass {
        let dev = &gpu.device;
        let module = dev.create_shader_module(wgpu::include_wgsl!("../shaders/shadow.wgsl"));
        ShadowPass {
            pipeline: crate::mesh::pipeline(dev, &module, "shadow", &[]),
            peel: crate::mesh::pipeline_with(dev, &module, "shadow peel", &[], Some("fs_peel")),
        }
    }

    /// Records the shadow maps of `scene`'s emitters: a depth array with one layer per emitter
    /// (at least one, so the scene pass's binding exists); layers of emitters without shadows
    /// stay cleared. With `back` > 0 (= the layers), emitter i's back map follows in layer
    /// back + i: its shadow map drawn again keeping only what lies behind the first surface,
    /// into a scratch depth target copied there.
    fn encode(
        &self,
        rec: &mut Recording,
        (scene, mesh, back): Self::Input<'_>,
    ) -> Result<wgpu::Texture> {
        let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
        let dev = &alloc.gpu.device;
        let emitters = scene.emitters();
        let layers = emitters.len().max(1) as u32 + back;
        let size = shadow_size(layers);
        // Each light's layer is cleared by its pass; without lights nothing reads the map.
        let maps = alloc.texture(
            "shadow maps",
            (size, size, layers),
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_DST,
        );
        let peeled = (back > 0).then(|| {
            alloc.texture(
                "shadow peel",
                (size, size, 1),
                wgpu::TextureFormat::Depth32Float,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            )
        });
        for (i, light) in emitters.iter().enumerate() {
            let vp = scene.light_view_proj(light);
            let ubuf = alloc.uniform("light", bytemuck::bytes_of(&vp.to_cols_array_2d()));
            let group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &self.pipeline.get_bind_group_layout(0),
                entries: &[bind(0, &ubuf)],
            });
            let view = maps.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: i as u32,
                array_layer_count: Some(1),
                ..Default::default()
            });
            let draw = |pipeline, group| light.shadow.then_some((pipeline, group, mesh));
            let label = format!("shadow map {}", i + 1);
            depth_pass(enc, timer, &label, &view, draw(&self.pipeline, &group));
            let Some(peeled) = &peeled else { continue };
            // The back map: cleared (depth 1, "none") for an emitter without shadows.
            let first = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &self.peel.get_bind_group_layout(0),
                entries: &[bind(0, &ubuf), bind_view(1, &view)],
            });
            let target = peeled.create_view(&Default::default());
            let label = format!("back map {}", i + 1);
            depth_pass(enc, timer, &label, &target, draw(&self.peel, &first));
            enc.copy_texture_to_texture(
                peeled.as_image_copy(),
                wgpu::TexelCopyTextureInfo {
                    texture: &maps,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: back + i as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::Extent3d {
                    width: size,
                    height: size,
                    depth_or_array_layers: 1,
                },
            );
        }
        Ok(maps)
    }
}

/// One depth pass into `target`, cleared to 1 (nothing), timed as `label`; with `draw`, the mesh
/// drawn by its pipeline and bind group.
fn depth_pass(
    enc: &mut wgpu::CommandEncoder,
    timer: &mut Option<&mut Timer>,
    label: &str,
    target: &wgpu::TextureView,
    draw: Option<(&wgpu::RenderPipeline, &wgpu::BindGroup, &MeshBuffers)>,
) {
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(cleared_depth(target)),
        timestamp_writes: timer.as_mut().map(|t| t.render_writes(label)),
        ..Default::default()
    });
    if let Some((pipeline, group, mesh)) = draw {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        mesh.draw(&mut pass);
    }
}
