//! The scene pass (G-buffer): every surface lit by the scene's lights with shadows, the SSS
//! materials' incidence, exit and thin-part tables ([`shading::Shading`]) applied, into three render
//! targets (32 bytes per pixel, WebGPU's portable limit), then unpacked into the storage buffers
//! the blur and the recombination read: diffuse light (irradiance × pre-scatter albedo), specular,
//! geometry (x: view depth [cm], y: SSS strength, z: material index) and the post-scatter albedo
//! (× exit factor).

use glam::Mat4;

use crate::error::Result;
use crate::frame::context::{Gpu, cleared_depth, compute_pipeline};
use crate::frame::recording::Recording;
use crate::light::MAX_EMITTERS;
use crate::mesh::MeshBuffers;
use crate::params::{MAX_MATERIALS, RenderParams};
use crate::passes::Pass;
use crate::scene::{AlbedoMode, Scene};
use shading::{LOOKUPS_WGSL, PACKED_SHADING_SIZE, PackedShading, Shading};

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct LightU {
    view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    pos_or_dir: [f32; 4],
    color: [f32; 4],
    /// A cell of an area light: xyz its half edges [cm], w 1 (0: not a cell).
    cell_u: [f32; 4],
    cell_v: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    view: [[f32; 4]; 4],
    camera_pos: [f32; 4],
    params: [f32; 4],
    ambient: [f32; 4],
    lights: [LightU; MAX_EMITTERS],
    /// Per SSS material.
    materials: [PackedShading; MAX_MATERIALS],
}

/// The scene shader with the shading model's lookups and the lighting functions prepended.
pub(crate) const SCENE_WGSL: &str = const_format::concatcp!(
    LOOKUPS_WGSL,
    include_str!("../shaders/lighting.wgsl"),
    include_str!("../shaders/scene.wgsl")
);

/// The size of scene.wgsl's `Globals`: 2 mat4 + 3 vec4 + 64 emitters × 192 + per material its
/// packed tables (checked against naga's layout in a test).
pub(crate) const GLOBALS_SIZE: usize =
    2 * 64 + 3 * 16 + MAX_EMITTERS * 192 + MAX_MATERIALS * PACKED_SHADING_SIZE;
const _: () = assert!(std::mem::size_of::<Globals>() == GLOBALS_SIZE);

/// Scene targets: diffuse; specular + strength; view depth + packed post-scatter albedo.
const FORMATS: [wgpu::TextureFormat; 3] = [
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rg32Float,
];
/// Near and far planes of the camera [cm]; the background's depth is FAR.
pub(crate) const NEAR: f32 = 1.0;
pub(crate) const FAR: f32 = 5000.0;

/// The camera's view-projection for a `width`×`height` image.
pub(crate) fn camera_view_proj(scene: &Scene, (w, h): (u32, u32)) -> Mat4 {
    scene.camera.projection(w as f32 / h as f32, NEAR, FAR) * scene.camera.view()
}

/// The scene pass's output, one RGBA f32 per pixel each.
pub(crate) struct GBuffer {
    /// Irradiance × pre-scatter albedo: the blur's input.
    pub diffuse: wgpu::Buffer,
    /// Specular light.
    pub specular: wgpu::Buffer,
    /// x: view depth [cm] (background: FAR), y: SSS strength, z: material index.
    pub geometry: wgpu::Buffer,
    /// Post-scatter albedo × exit factor.
    pub albedo: wgpu::Buffer,
    /// scene.wgsl's `Globals` (lights, materials' tables, albedo mode), for the splats' lighting.
    pub globals: wgpu::Buffer,
    /// The shadow maps as lighting.wgsl reads them.
    pub shadow_view: wgpu::TextureView,
}

/// lighting.wgsl's bindings 0–2: the globals, the shadow maps and their comparison sampler.
fn lighting_entries<'a>(
    globals: &'a wgpu::Buffer,
    shadow_view: &'a wgpu::TextureView,
    sampler: &'a wgpu::Sampler,
) -> [wgpu::BindGroupEntry<'a>; 3] {
    [
        wgpu::BindGroupEntry {
            binding: 0,
            resource: globals.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 1,
            resource: wgpu::BindingResource::TextureView(shadow_view),
        },
        wgpu::BindGroupEntry {
            binding: 2,
            resource: wgpu::BindingResource::Sampler(sampler),
        },
    ]
}

/// The scene pass's uniform block for `scene` at `params`' size: the camera, the lights with
/// their shadow maps' projections, the albedo mode and each material's packed tables (`plain`:
/// no albedo split and all tables off but η).
pub(crate) fn globals_bytes(scene: &Scene, params: &RenderParams, plain: bool) -> Vec<u8> {
    bytemuck::bytes_of(&globals(scene, params, plain)).to_vec()
}

/// The scene pass's uniform block (see [`globals_bytes`]).
fn globals(scene: &Scene, params: &RenderParams, plain: bool) -> Globals {
    let (w, h) = (params.width, params.height);
    let cam = &scene.camera;
    let emitters = scene.emitters();
    let mut lights = [LightU {
        view_proj: Mat4::IDENTITY.to_cols_array_2d(),
        inv_view_proj: Mat4::IDENTITY.to_cols_array_2d(),
        pos_or_dir: [0.0; 4],
        color: [0.0; 4],
        cell_u: [0.0; 4],
        cell_v: [0.0; 4],
    }; MAX_EMITTERS];
    for (i, light) in emitters.iter().enumerate() {
        let vp = scene.light_view_proj(light);
        let [u, v] = light.cell.unwrap_or([glam::Vec3::ZERO; 2]);
        lights[i] = LightU {
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            pos_or_dir: light.pos_or_dir.into(),
            color: light
                .power
                .extend(if light.shadow { i as f32 } else { -1.0 })
                .into(),
            cell_u: u
                .extend(if light.cell.is_some() { 1.0 } else { 0.0 })
                .into(),
            cell_v: v.extend(0.0).into(),
        };
    }
    Globals {
        view_proj: camera_view_proj(scene, (w, h)).to_cols_array_2d(),
        view: cam.view().to_cols_array_2d(),
        camera_pos: cam.position.extend(1.0).into(),
        params: [
            emitters.len() as f32,
            match params.albedo {
                _ if plain => 0.0,
                AlbedoMode::Pre => 0.0,
                AlbedoMode::Post => 1.0,
                AlbedoMode::PrePost => 2.0,
            },
            scene.specular,
            scene.shininess,
        ],
        // w: where the back maps start in the shadow maps (0: none; shadow::back_layers).
        ambient: scene
            .ambient
            .extend(if plain {
                0.0
            } else {
                crate::passes::shadow::back_layers(scene, params) as f32
            })
            .into(),
        lights,
        // `plain`: all off but η (the disc gathers bring their own physics).
        materials: params.shading.map(|s| {
            PackedShading::new(&if plain {
                Shading {
                    eta: s.eta,
                    ..Shading::default()
                }
            } else {
                s
            })
        }),
    }
}

/// The compiled scene and unpack pipelines and the shadow-map sampler.
pub(crate) struct GBufferPass {
    scene: wgpu::RenderPipeline,
    unpack: wgpu::ComputePipeline,
    sampler: wgpu::Sampler,
}

impl Pass for GBufferPass {
    /// The scene, its mesh as uploaded, the shadow maps, the frame's settings and `plain`: no
    /// albedo split and no SSS shading tables (the disc gathers, [`crate::gathers::disc_gather`],
    /// bring their own colour and angular dependence).
    type Input<'a> = (
        &'a Scene,
        &'a MeshBuffers,
        &'a wgpu::Texture,
        &'a RenderParams,
        bool,
    );
    /// The G-buffer.
    type Output = GBuffer;

    fn new(gpu: &Gpu) -> GBufferPass {
        let dev = &gpu.device;
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene"),
            source: wgpu::ShaderSource::Wgsl(SCENE_WGSL.into()),
        });
        GBufferPass {
            scene: crate::mesh::pipeline(dev, &module, "scene", &FORMATS),
            unpack: compute_pipeline(dev, wgpu::include_wgsl!("../shaders/unpack.wgsl"), "unpack"),
            sampler: dev.create_sampler(&wgpu::SamplerDescriptor {
                compare: Some(wgpu::CompareFunction::LessEqual),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
        }
    }

    /// Records the scene pass and the unpacking.
    fn encode(
        &self,
        rec: &mut Recording,
        (scene, mesh, shadow_maps, params, plain): Self::Input<'_>,
    ) -> Result<GBuffer> {
        let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
        let dev = &alloc.gpu.device;
        let (w, h) = (params.width, params.height);
        let globals = globals(scene, params, plain);
        let gbuf = alloc.uniform("globals", bytemuck::bytes_of(&globals));
        let shadow_view = shadow_maps.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.scene.get_bind_group_layout(0),
            entries: &lighting_entries(&gbuf, &shadow_view, &self.sampler),
        });
        let target = |label: &'static str, format| {
            alloc.texture(
                label,
                (w, h, 1),
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
        };
        let views: Vec<wgpu::TextureView> = ["diffuse", "specular", "geometry"]
            .iter()
            .zip(FORMATS)
            .map(|(l, f)| target(l, f).create_view(&Default::default()))
            .collect();
        let depth = target("depth", wgpu::TextureFormat::Depth32Float);
        let depth_view = depth.create_view(&Default::default());
        {
            // Background: no light, no strength, far depth, material 0; its albedo bits are 0
            // (black), and it has no diffuse light to scale anyway.
            let clears = [[0.0; 4], [0.0; 4], [FAR as f64, 0.0, 0.0, 0.0]];
            let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = views
                .iter()
                .zip(clears)
                .map(|(v, c)| {
                    Some(wgpu::RenderPassColorAttachment {
                        view: v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color {
                                r: c[0],
                                g: c[1],
                                b: c[2],
                                a: c[3],
                            }),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                })
                .collect();
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(cleared_depth(&depth_view)),
                timestamp_writes: timer.as_mut().map(|t| t.render_writes("scene")),
                ..Default::default()
            });
            pass.set_pipeline(&self.scene);
            pass.set_bind_group(0, &bind, &[]);
            mesh.draw(&mut pass);
        }
        let n = (w * h) as usize;
        let out = GBuffer {
            diffuse: alloc.pixels(n, "diffuse"),
            specular: alloc.pixels(n, "specular"),
            geometry: alloc.pixels(n, "geometry"),
            albedo: alloc.pixels(n, "albedo"),
            globals: gbuf,
            shadow_view,
        };
        let mut entries: Vec<wgpu::BindGroupEntry> = views
            .iter()
            .enumerate()
            .map(|(i, v)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: wgpu::BindingResource::TextureView(v),
            })
            .collect();
        for (i, b) in [&out.diffuse, &out.specular, &out.geometry, &out.albedo]
            .into_iter()
            .enumerate()
        {
            entries.push(wgpu::BindGroupEntry {
                binding: 3 + i as u32,
                resource: b.as_entire_binding(),
            });
        }
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.unpack.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("unpack"),
            timestamp_writes: timer.as_mut().map(|t| t.writes("unpack")),
        });
        pass.set_pipeline(&self.unpack);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        drop(pass);
        Ok(out)
    }
}

impl GBufferPass {
    /// The lighting bindings of `g`'s frame, for other passes that light surfaces as the scene
    /// pass does (the splats).
    pub(crate) fn lighting<'a>(&'a self, g: &'a GBuffer) -> [wgpu::BindGroupEntry<'a>; 3] {
        lighting_entries(&g.globals, &g.shadow_view, &self.sampler)
    }
}
