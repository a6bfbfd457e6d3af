//! The disc gather: the per-pixel integral of a BSSRDF over the lit surface that the
//! directional dipole ([`crate::dipole`]) and the Monte Carlo BSSRDF ([`crate::surface_gather`])
//! share (`shaders/disc_gather.wgsl`, with the model's functions prepended).
//!
//! For each SSS pixel x_o and each light, points p are drawn on a disc of radius r* around x_o
//! in the plane perpendicular to the light ray; the light's position/normal map (a light-space
//! G-buffer, the translucent-shadow-map idea the directional-dipole draft implies: Dachsbacher &
//! Stamminger 2003) carries p along the light ray onto the first surface the light reaches, the
//! entry point x_i. We chose the light-perpendicular disc because the flux it intercepts is
//! exact whatever the orientation of the surface at x_i: E⊥·dA⊥ for a directional light,
//! I·cos α·dA⊥/|p − x_light|² for a point light. Points the map marks as non-SSS (an occluder, the
//! floor) are in shadow and contribute nothing, and points on the far side of a thin part reach
//! x_o through the model's response to them (translucency). Each sample is divided by the model's
//! density per unit disc area.
//!
//! Output: π·L_o per pixel (the exitance convention of the separable pipeline, whose images are
//! irradiance × albedo), without the post-scatter albedo: the colour comes from the model.
//! Ambient light is not scattered. Every frame adds 1/frames of its estimate, so after `frames`
//! frames the image is their mean; frames differ only in their random numbers, which depend on
//! the pixel, the frame and the seed alone.

use std::sync::{Mutex, OnceLock};

use glam::Mat4;

use crate::context::{cleared_depth, compute_pipeline};
use crate::error::{GpuError, Result};
use crate::mesh::MeshBuffers;
use crate::pool::Alloc;
use crate::recording::Recording;
use crate::target::Target;

/// The lights the disc gather holds: directional and point lights only (an area light's cells
/// would need their own emission lobe and many more light maps).
pub const DISC_LIGHTS: usize = 4;

/// How the disc gather samples: the same settings for every model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// Samples per pixel, light and frame.
    pub samples: u32,
    /// Frames accumulated.
    pub frames: u32,
    /// Disc radius r* [cm].
    pub radius_cm: f32,
    /// Side of each light's position/normal map [texels].
    pub map_size: u32,
    /// Seed of the per-pixel random numbers.
    pub seed: u32,
}

impl Sampling {
    /// Checks the settings; the error names the field.
    pub fn validate(&self) -> Result<()> {
        if !(1..=4096).contains(&self.samples) {
            return Err(GpuError::invalid(
                "samples",
                self.samples,
                "must lie in 1..=4096",
            ));
        }
        if !(1..=65536).contains(&self.frames) {
            return Err(GpuError::invalid(
                "frames",
                self.frames,
                "must lie in 1..=65536",
            ));
        }
        if !(self.radius_cm.is_finite() && self.radius_cm > 0.0) {
            return Err(GpuError::invalid(
                "disc radius",
                self.radius_cm,
                "must be positive and finite [cm]",
            ));
        }
        if !(64..=8192).contains(&self.map_size) {
            return Err(GpuError::invalid(
                "light map size",
                self.map_size,
                "must lie in 64..=8192 texels",
            ));
        }
        Ok(())
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GatherLight {
    view_proj: [[f32; 4]; 4],
    pos_or_dir: [f32; 4],
    color: [f32; 4],
}

/// The shader's `Gather` uniform (shaders/disc_gather.wgsl), field for field.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GatherUniform {
    lights: [GatherLight; DISC_LIGHTS],
    camera_pos: [f32; 4],
    disc: [f32; 4],
    size: [u32; 4],
    frame: [u32; 4],
}

/// WGSL's size of `Gather`: 4 lights × 96 + 4 vec4 × 16 bytes (checked against naga's layout in
/// a test).
pub(crate) const GATHER_UNIFORM_SIZE: usize = DISC_LIGHTS * 96 + 4 * 16;
const _: () = assert!(std::mem::size_of::<GatherUniform>() == GATHER_UNIFORM_SIZE);

/// The gather's WGSL after a model's (`fresnel.wgsl` first, which both models use).
macro_rules! gather_wgsl {
    ($model:literal) => {
        concat!(
            include_str!("shaders/fresnel.wgsl"),
            include_str!($model),
            include_str!("shaders/disc_gather.wgsl")
        )
    };
}
pub(crate) use gather_wgsl;

/// A model of the gather: its shader (from [`gather_wgsl`]) and its resources, bound from
/// binding 6 on in order.
pub(crate) struct Model<'a> {
    /// Label of the pipeline and of the timed span.
    pub label: &'a str,
    /// The whole WGSL source.
    pub wgsl: &'static str,
    /// Buffers bound at 6, 7, ….
    pub buffers: Vec<&'a wgpu::Buffer>,
}

const MAP_FORMATS: [wgpu::TextureFormat; 2] = [
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba32Float,
];

/// The disc gathers' pipelines, compiled on first use and kept for every later frame of the
/// [`crate::Renderer`] that holds them: the position/normal map pipeline and one accumulation
/// pipeline per model's WGSL (the directional dipole's, the Monte Carlo BSSRDF's).
#[derive(Default)]
pub(crate) struct DiscPipelines {
    maps: OnceLock<wgpu::RenderPipeline>,
    models: Mutex<Vec<(&'static str, wgpu::ComputePipeline)>>,
}

impl DiscPipelines {
    fn maps(&self, dev: &wgpu::Device) -> &wgpu::RenderPipeline {
        self.maps.get_or_init(|| {
            let module = dev.create_shader_module(wgpu::include_wgsl!("shaders/dipole_maps.wgsl"));
            crate::mesh::pipeline(dev, &module, "gather maps", &MAP_FORMATS)
        })
    }

    fn model(&self, dev: &wgpu::Device, model: &Model) -> wgpu::ComputePipeline {
        let mut models = self.models.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, p)) = models
            .iter()
            .find(|(wgsl, _)| std::ptr::eq(*wgsl, model.wgsl))
        {
            return p.clone();
        }
        let p = compute_pipeline(
            dev,
            wgpu::ShaderModuleDescriptor {
                label: Some(model.label),
                source: wgpu::ShaderSource::Wgsl(model.wgsl.into()),
            },
            model.label,
        );
        models.push((model.wgsl, p.clone()));
        p
    }
}

/// Position and normal maps, one array layer per view.
struct Maps {
    position: wgpu::Texture,
    normal: wgpu::Texture,
}

fn draw_maps(
    alloc: Alloc,
    pipeline: &wgpu::RenderPipeline,
    enc: &mut wgpu::CommandEncoder,
    mesh: &MeshBuffers,
    views: &[Mat4],
    (w, h): (u32, u32),
) -> Maps {
    let dev = &alloc.gpu.device;
    let layers = views.len().max(1) as u32;
    // Each layer is cleared by its pass; without views nothing reads the maps.
    let texture = |label: &'static str, format| {
        alloc.texture(
            label,
            (w, h, layers),
            format,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        )
    };
    let maps = Maps {
        position: texture("gather positions", MAP_FORMATS[0]),
        normal: texture("gather normals", MAP_FORMATS[1]),
    };
    let depth = texture("gather depth", wgpu::TextureFormat::Depth32Float);
    for (layer, vp) in views.iter().enumerate() {
        let ubuf = alloc.uniform(
            "gather map view",
            bytemuck::bytes_of(&vp.to_cols_array_2d()),
        );
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: ubuf.as_entire_binding(),
            }],
        });
        let layer_view = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer as u32,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        let (pv, nv, dv) = (
            layer_view(&maps.position),
            layer_view(&maps.normal),
            layer_view(&depth),
        );
        let clear = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gather maps"),
            color_attachments: &[clear(&pv), clear(&nv)],
            depth_stencil_attachment: Some(cleared_depth(&dv)),
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        mesh.draw(&mut pass);
    }
    maps
}

/// Encodes the gather's passes: the camera's and each light's position/normal maps, then
/// `sampling.frames` accumulation passes of `model` adding π·L_o/frames into the target's
/// scattered light (which is cleared first).
pub(crate) fn encode(
    rec: &mut Recording,
    target: &Target,
    sampling: &Sampling,
    model: &Model,
    pipelines: &DiscPipelines,
) -> Result<()> {
    let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
    let out = target.scattered;
    sampling.validate()?;
    let dev = &alloc.gpu.device;
    let (w, h) = target.size;
    let scene = target.scene;
    let maps = pipelines.maps(dev);
    let cam = draw_maps(
        alloc,
        maps,
        enc,
        target.mesh,
        &[target.camera_view_proj],
        (w, h),
    );
    // At most DISC_LIGHTS point or directional emitters: `Renderer::record` checked them.
    let emitters = scene.emitters();
    let light_vps: Vec<Mat4> = emitters.iter().map(|l| scene.light_view_proj(l)).collect();
    let size = sampling.map_size;
    let lights = draw_maps(alloc, maps, enc, target.mesh, &light_vps, (size, size));
    let mut u_lights = [GatherLight {
        view_proj: Mat4::IDENTITY.to_cols_array_2d(),
        pos_or_dir: [0.0; 4],
        color: [0.0; 4],
    }; DISC_LIGHTS];
    for (i, (light, vp)) in emitters.iter().zip(&light_vps).enumerate() {
        u_lights[i] = GatherLight {
            view_proj: vp.to_cols_array_2d(),
            pos_or_dir: light.pos_or_dir.into(),
            color: light.power.extend(i as f32).into(),
        };
    }
    let base = GatherUniform {
        lights: u_lights,
        camera_pos: scene.camera.position.extend(1.0).into(),
        disc: [
            sampling.radius_cm,
            1.0 / (sampling.samples as f32 * sampling.frames as f32),
            0.0,
            0.0,
        ],
        size: [w, h, emitters.len() as u32, sampling.samples],
        frame: [0, sampling.seed, size, 0],
    };
    let pipeline = pipelines.model(dev, model);
    let array = |t: &wgpu::Texture, dim| {
        t.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(dim),
            ..Default::default()
        })
    };
    let views = [
        array(&cam.position, wgpu::TextureViewDimension::D2),
        array(&cam.normal, wgpu::TextureViewDimension::D2),
        array(&lights.position, wgpu::TextureViewDimension::D2Array),
        array(&lights.normal, wgpu::TextureViewDimension::D2Array),
    ];
    enc.clear_buffer(out, 0, None);
    let span = timer
        .as_mut()
        .map(|t| t.span(&format!("{} ({} frames)", model.label, sampling.frames)));
    for frame in 0..sampling.frames {
        let uniform = GatherUniform {
            frame: [frame, sampling.seed, size, 0],
            ..base
        };
        let ubuf = alloc.uniform("gather frame", bytemuck::bytes_of(&uniform));
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: ubuf.as_entire_binding(),
        }];
        entries.extend(views.iter().enumerate().map(|(i, v)| wgpu::BindGroupEntry {
            binding: 1 + i as u32,
            resource: wgpu::BindingResource::TextureView(v),
        }));
        entries.push(wgpu::BindGroupEntry {
            binding: 5,
            resource: out.as_entire_binding(),
        });
        entries.extend(
            model
                .buffers
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry {
                    binding: 6 + i as u32,
                    resource: b.as_entire_binding(),
                }),
        );
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let writes = match (timer.as_ref(), span) {
            (Some(t), Some(k)) => t.span_writes(k, frame == 0, frame + 1 == sampling.frames),
            _ => None,
        };
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(model.label),
            timestamp_writes: writes,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    Ok(())
}
