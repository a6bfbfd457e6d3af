//! The disc gather: the per-pixel integral of a BSSRDF over the lit surface that the
//! directional dipole ([`crate::gathers::dipole`]) and the Monte Carlo BSSRDF ([`crate::gathers::surface_gather`])
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

use crate::error::{GpuError, Result};
use crate::frame::context::{bind, bind_view, cleared_depth, compute_pipeline};
use crate::frame::pool::Alloc;
use crate::frame::recording::Recording;
use crate::frame::target::Target;
use crate::light::{Emitter, Light};
use crate::mesh::MeshBuffers;
use crate::passes::Pass;
use crate::passes::denoise::{Denoise, DenoiseInput};

/// The emitters the disc gather holds per frame: directional and point lights count one each,
/// and the slots left are shared by the area lights, each drawn as that many points per frame
/// ([`frame_emitters`]).
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
    /// Whether the frames' mean goes through the edge-aware denoiser
    /// ([`crate::passes::denoise`]) at the model's widths.
    pub denoise: bool,
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
    lobe: [f32; 4],
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

/// WGSL's size of `Gather`: 4 lights × 112 + 4 vec4 × 16 bytes (checked against naga's layout
/// in a test).
pub(crate) const GATHER_UNIFORM_SIZE: usize = DISC_LIGHTS * 112 + 4 * 16;
const _: () = assert!(std::mem::size_of::<GatherUniform>() == GATHER_UNIFORM_SIZE);

/// The gather's WGSL after a model's parts (`fresnel.wgsl` and `angles.wgsl` first, which the
/// models use).
macro_rules! gather_wgsl {
    ($($part:expr),+) => {
        const_format::concatcp!(
            shading::FRESNEL_WGSL,
            shading::ANGLES_WGSL,
            $($part,)+
            include_str!("../shaders/disc_gather.wgsl")
        )
    };
}
pub(crate) use gather_wgsl;

/// A model of the gather: its shader (from [`gather_wgsl`]) and its resources, bound from
/// binding 7 on in order.
pub(crate) struct Model<'a> {
    /// Label of the pipeline and of the timed span.
    pub label: &'a str,
    /// The whole WGSL source.
    pub wgsl: &'static str,
    /// Buffers bound at 6, 7, ….
    pub buffers: Vec<&'a wgpu::Buffer>,
    /// Whether the light maps carry the body's chord along the light (the normal map's w, from
    /// `dipole_maps.wgsl`'s `fs_chord`; else 0).
    pub chords: bool,
    /// The denoiser's width σ per channel [cm] ([`crate::passes::denoise`]); None where the
    /// model has none.
    pub denoise_cm: Option<[f32; 3]>,
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
    maps: OnceLock<[wgpu::RenderPipeline; 2]>,
    models: Mutex<Vec<(&'static str, wgpu::ComputePipeline)>>,
    denoise: OnceLock<Denoise>,
}

impl DiscPipelines {
    /// The position/normal maps' pipeline and the chords' (which writes the normal map's w).
    fn maps(&self, dev: &wgpu::Device) -> &[wgpu::RenderPipeline; 2] {
        self.maps.get_or_init(|| {
            let module =
                dev.create_shader_module(wgpu::include_wgsl!("../shaders/dipole_maps.wgsl"));
            let w = Some(wgpu::ColorTargetState {
                format: MAP_FORMATS[1],
                blend: None,
                write_mask: wgpu::ColorWrites::ALPHA,
            });
            [
                crate::mesh::pipeline(dev, &module, "gather maps", &MAP_FORMATS),
                crate::mesh::pipeline_with(dev, &module, "gather chords", &[w], Some("fs_chord")),
            ]
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

/// Position and normal maps (and the depth they are drawn with), one array layer per view.
struct Maps {
    position: wgpu::Texture,
    normal: wgpu::Texture,
    depth: wgpu::Texture,
}

impl Maps {
    fn new(alloc: Alloc, layers: usize, (w, h): (u32, u32)) -> Maps {
        // Each layer is cleared by its pass; without views nothing reads the maps.
        let texture = |label: &'static str, format| {
            alloc.texture(
                label,
                (w, h, layers.max(1) as u32),
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
        };
        Maps {
            position: texture("gather positions", MAP_FORMATS[0]),
            normal: texture("gather normals", MAP_FORMATS[1]),
            depth: texture("gather depth", wgpu::TextureFormat::Depth32Float),
        }
    }

    /// Records drawing `mesh` into layer k of the maps from `views[k]`; with `chords` (the
    /// chords' pipeline), then the body's chord along the view behind each texel's first surface
    /// into the normal map's w.
    fn draw(
        &self,
        alloc: Alloc,
        pipeline: &wgpu::RenderPipeline,
        chords: Option<&wgpu::RenderPipeline>,
        enc: &mut wgpu::CommandEncoder,
        mesh: &MeshBuffers,
        views: &[Mat4],
    ) {
        let dev = &alloc.gpu.device;
        for (layer, vp) in views.iter().enumerate() {
            let ubuf = alloc.uniform(
                "gather map view",
                bytemuck::bytes_of(&vp.to_cols_array_2d()),
            );
            let group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
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
                layer_view(&self.position),
                layer_view(&self.normal),
                layer_view(&self.depth),
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
            pass.set_bind_group(0, &group, &[]);
            mesh.draw(&mut pass);
            drop(pass);
            let Some(chords) = chords else { continue };
            let (w, h, _) = self.size();
            let peeled = alloc
                .texture(
                    "gather chord depth",
                    (w, h, 1),
                    wgpu::TextureFormat::Depth32Float,
                    wgpu::TextureUsages::RENDER_ATTACHMENT,
                )
                .create_view(&Default::default());
            let first = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &chords.get_bind_group_layout(0),
                entries: &[bind(0, &ubuf), bind_view(1, &dv), bind_view(2, &pv)],
            });
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gather chords"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &nv,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(cleared_depth(&peeled)),
                ..Default::default()
            });
            pass.set_pipeline(chords);
            pass.set_bind_group(0, &first, &[]);
            mesh.draw(&mut pass);
        }
    }

    /// The maps' width, height and layers [texels].
    fn size(&self) -> (u32, u32, u32) {
        let s = self.position.size();
        (s.width, s.height, s.depth_or_array_layers)
    }
}

/// How many points per frame each area light of `lights` is drawn as: the [`DISC_LIGHTS`]
/// slots the directional and point lights leave, shared evenly (0 without area lights;
/// `check_lights` refuses scenes where that leaves an area light none).
pub(crate) fn area_slots(lights: &[Light]) -> usize {
    let areas = lights
        .iter()
        .filter(|l| matches!(l, Light::Area { .. }))
        .count();
    if areas == 0 {
        return 0;
    }
    DISC_LIGHTS.saturating_sub(lights.len() - areas) / areas
}

/// The PCG hash (Jarzynski & Olano 2020), the shader's `pcg`.
fn pcg(v: u32) -> u32 {
    let s = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let w = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
    (w >> 22) ^ w
}

/// The emitters the disc gather draws in frame `frame` with seed `seed`: each directional or
/// point light as itself, and each area light as [`area_slots`] points on it
/// ([`Light::point_on`]), each with 1/slots of its power. The points are numbers
/// frame·slots + j of the R2 sequence (Roberts 2018: k·(1/g, 1/g²) mod 1, g the plastic number)
/// shifted by a hash of the seed (a Cranley–Patterson rotation): each frame draws new points,
/// those of the frames so far are evenly spread over the light whatever their number, and
/// their mean irradiance is an unbiased estimate of the area light's.
pub(crate) fn frame_emitters(lights: &[Light], frame: u32, seed: u32) -> Vec<Emitter> {
    const G: f64 = 1.324_717_957_244_746;
    let slots = area_slots(lights);
    let shift = |v: u32| pcg(v) as f64 / 4_294_967_296.0;
    let (s0, t0) = (shift(seed), shift(seed ^ 0x9e37_79b9));
    lights
        .iter()
        .flat_map(|light| match light {
            Light::Area { .. } => (0..slots)
                .map(|j| {
                    let k = (frame as usize * slots + j) as f64;
                    let st = (
                        (s0 + k / G).fract() as f32,
                        (t0 + k / (G * G)).fract() as f32,
                    );
                    let mut e = light.point_on(st).expect("an area light");
                    e.power /= slots as f32;
                    e
                })
                .collect(),
            _ => light.emitters(),
        })
        .collect()
}

/// The denoiser's widths [cm] where `sampling` asks for it: the model's, or an error naming
/// `denoise` where the model has none.
fn denoise_widths(sampling: &Sampling, model: &Model) -> Result<Option<[f32; 3]>> {
    match (sampling.denoise, model.denoise_cm) {
        (false, _) => Ok(None),
        (true, Some(widths)) => Ok(Some(widths)),
        (true, None) => Err(GpuError::invalid(
            "denoise",
            "on",
            format!("the {} has no denoiser widths", model.label),
        )),
    }
}

/// Encodes the gather's passes: the camera's and each light's position/normal maps, then
/// `sampling.frames` accumulation passes of `model` adding π·L_o/frames into the target's
/// scattered light (which is cleared first; the samples' part) and a base (the control
/// variate's part, kept apart only with `sampling.denoise`), then the denoiser's levels over the
/// samples' part at the model's widths, ending in their sum.
pub(crate) fn encode(
    rec: &mut Recording,
    target: &Target,
    sampling: &Sampling,
    model: &Model,
    pipelines: &DiscPipelines,
) -> Result<()> {
    sampling.validate()?;
    let denoise_cm = denoise_widths(sampling, model)?;
    let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
    let out = target.scattered;
    let dev = &alloc.gpu.device;
    let (w, h) = target.size;
    let scene = target.scene;
    let maps = pipelines.maps(dev);
    let cam = Maps::new(alloc, 1, (w, h));
    cam.draw(
        alloc,
        &maps[0],
        None,
        enc,
        target.mesh,
        &[target.camera_view_proj],
    );
    // At most DISC_LIGHTS emitters per frame: `Renderer::record` checked the lights. Area
    // lights are new points every frame, and their maps are drawn anew.
    let moving = area_slots(&scene.lights) > 0;
    let size = sampling.map_size;
    let mut emitters = frame_emitters(&scene.lights, 0, sampling.seed);
    let lights = Maps::new(alloc, emitters.len(), (size, size));
    let mut vps = Vec::new();
    let uniform = |frame: u32, emitters: &[Emitter], vps: &[Mat4]| {
        let mut u_lights = [GatherLight {
            view_proj: Mat4::IDENTITY.to_cols_array_2d(),
            pos_or_dir: [0.0; 4],
            color: [0.0; 4],
            lobe: [0.0; 4],
        }; DISC_LIGHTS];
        for (i, (light, vp)) in emitters.iter().zip(vps).enumerate() {
            let lobe = light
                .emitting_normal()
                .map_or(glam::Vec4::ZERO, |n| n.extend(1.0));
            u_lights[i] = GatherLight {
                view_proj: vp.to_cols_array_2d(),
                pos_or_dir: light.pos_or_dir.into(),
                color: light.power.extend(i as f32).into(),
                lobe: lobe.into(),
            };
        }
        GatherUniform {
            lights: u_lights,
            camera_pos: scene.camera.position.extend(1.0).into(),
            disc: [
                sampling.radius_cm,
                1.0 / (sampling.samples as f32 * sampling.frames as f32),
                f32::from(u8::from(denoise_cm.is_some())),
                0.0,
            ],
            size: [w, h, emitters.len() as u32, sampling.samples],
            frame: [frame, sampling.seed, size, sampling.frames],
        }
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
    // The control's deterministic part, kept apart from the samples' part in `out` until the
    // denoiser (or the plain sum without it) joins them.
    let base = alloc.pixels((w * h) as usize, "gather base");
    enc.clear_buffer(out, 0, None);
    enc.clear_buffer(&base, 0, None);
    let span = timer
        .as_mut()
        .map(|t| t.span(&format!("{} ({} frames)", model.label, sampling.frames)));
    for frame in 0..sampling.frames {
        if frame > 0 && moving {
            emitters = frame_emitters(&scene.lights, frame, sampling.seed);
        }
        if frame == 0 || moving {
            vps = emitters.iter().map(|l| scene.light_view_proj(l)).collect();
            let chords = model.chords.then_some(&maps[1]);
            lights.draw(alloc, &maps[0], chords, enc, target.mesh, &vps);
        }
        let uniform = uniform(frame, &emitters, &vps);
        let ubuf = alloc.uniform("gather frame", bytemuck::bytes_of(&uniform));
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: ubuf.as_entire_binding(),
        }];
        entries.extend(views.iter().enumerate().map(|(i, v)| wgpu::BindGroupEntry {
            binding: 1 + i as u32,
            resource: wgpu::BindingResource::TextureView(v),
        }));
        entries.push(bind(5, out));
        entries.push(bind(6, &base));
        entries.extend(
            model
                .buffers
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry {
                    binding: 7 + i as u32,
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
    if let Some(widths_cm) = denoise_cm {
        let denoise = pipelines.denoise.get_or_init(|| Denoise::new(alloc.gpu));
        let input = DenoiseInput {
            size: (w, h),
            camera: &scene.camera,
            position: &views[0],
            normal: &views[1],
            widths_cm,
            image: out,
            base: &base,
        };
        denoise.encode(rec, input)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// An area light beside a point light takes the three slots left, each point with a third
    /// of its power; every frame draws new points on it, the same for the same seed; over 64
    /// frames the points fill the square evenly (every cell of an 8×8 grid holds 3 ± 2 of the
    /// 192), where independent uniform points would leave some cell empty or crowded.
    #[test]
    fn an_area_light_is_new_evenly_spread_points_every_frame() {
        let square =
            Light::square(Vec3::new(0.0, 10.0, 0.0), Vec3::ZERO, 2.0, Vec3::ONE, true).unwrap();
        let point = Light::Point {
            position: Vec3::new(5.0, 5.0, 0.0),
            intensity: Vec3::ONE,
            shadow: true,
        };
        let lights = [square, point];
        assert_eq!(area_slots(&lights), 3);
        let a = frame_emitters(&lights, 0, 1);
        assert_eq!(a.len(), 4);
        assert!(a[..3].iter().all(|e| (e.power.x - 4.0 / 3.0).abs() < 1e-6));
        assert_eq!(a[3], point.emitters()[0]);
        assert_eq!(a, frame_emitters(&lights, 0, 1));
        assert_ne!(a[0], frame_emitters(&lights, 1, 1)[0]);
        assert_ne!(a[0], frame_emitters(&lights, 0, 2)[0]);
        let mut cells = [0u32; 64];
        for frame in 0..64 {
            for e in &frame_emitters(&lights, frame, 7)[..3] {
                // The square spans x and z in [−1, 1] (it faces down).
                let p = e.pos_or_dir;
                let (i, j) = (((p.x + 1.0) * 4.0) as usize, ((p.z + 1.0) * 4.0) as usize);
                cells[i.min(7) * 8 + j.min(7)] += 1;
            }
        }
        assert!(cells.iter().all(|&c| (1..=5).contains(&c)), "{cells:?}");
        // No slot left for an area light beside four point lights.
        assert_eq!(area_slots(&[square, point, point, point, point]), 0);
    }
}
