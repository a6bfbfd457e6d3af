//! A frame: the [`Renderer`] (every pipeline, built once) runs the shadow pass (`shadow.rs`), the
//! scene pass into the G-buffer (`gbuffer.rs`), the SSS passes (`blur.rs` or [`crate::gathers::dipole`])
//! and the recombination (`combine.rs`), and reads the images back.

use crate::error::{GpuError, Result};
use crate::frame::context::Gpu;
use crate::frame::pool::{Alloc, FramePool};
use crate::frame::recording::Recording;
use crate::frame::target::Target;
use crate::frame::timing::{PassTime, Timer};
use crate::gathers::DiscModel;
use crate::gathers::area_gather::{AreaGather, AreaGatherSetup};
use crate::gathers::dipole::DipoleSetup;
use crate::gathers::disc_gather::DiscPipelines;
use crate::gathers::surface_gather::SurfaceGatherSetup;
use crate::mesh::MeshBuffers;
use crate::params::{MAX_MATERIALS, RenderParams};
use crate::passes::Pass;
use crate::passes::combine::Combine;
use crate::passes::gbuffer::{GBufferPass, camera_view_proj};
use crate::passes::separable::Separable;
pub use crate::passes::separable::{SUBPIXEL_PX, kernel_footprint_px};
use crate::passes::shadow::ShadowPass;
use crate::passes::splat::Splats;
use crate::scene::Scene;
use shading::KernelTaps;

/// How the diffuse light of SSS surfaces is scattered.
#[derive(Clone, Copy, Debug)]
pub enum Scatter<'a> {
    /// Not at all: plain Lambertian shading.
    None,
    /// Separable screen-space kernels (thesis §4.2–4.4), one per SSS material: the i-th scatters
    /// the light of the pixels whose `material` is i. A pixel's kernel takes no light from pixels of
    /// another SSS material: their samples are rejected and the weight goes to the samples kept
    /// (per channel, as the depth test's reject mode does), so materials side by side neither
    /// bleed into each other nor lose energy at their border. Samples of surfaces without SSS
    /// (the floor) are taken as before, subject to the depth test.
    Separable(&'a [KernelTaps]),
    /// The directional dipole evaluated per pixel over lit surface points ([`crate::gathers::dipole`]);
    /// the albedo split and incidence table of [`RenderParams`] do not apply (the colour and the
    /// dependence on incidence come from the model).
    DirectionalDipole(&'a DipoleSetup),
    /// Maisch & Ropinski's gather of an area pre-integrated kernel over their layered sampling
    /// pattern ([`crate::gathers::area_gather`]), for large scattering distances; one SSS material.
    AreaGather(&'a AreaGatherSetup),
    /// The material's own Monte Carlo BSSRDF (radial or directional) integrated per pixel over
    /// lit surface points ([`crate::gathers::surface_gather`]), like the directional dipole.
    SurfaceGather(&'a SurfaceGatherSetup),
}

impl Scatter<'_> {
    /// Whether the method gathers over the lit surface through the lights' maps (the directional
    /// dipole and the surface gather, [`crate::gathers::disc_gather`]).
    fn gathers_lit_surface(&self) -> bool {
        matches!(
            self,
            Scatter::DirectionalDipole(_) | Scatter::SurfaceGather(_)
        )
    }
}

/// A rendered frame: row-major, top row first.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Image width [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// Final linear radiance (scattered diffuse × post albedo + specular).
    pub linear: Vec<[f32; 4]>,
    /// Tone-mapped sRGB, RGBA8.
    pub display: Vec<u8>,
    /// The scene pass's diffuse target (irradiance × pre-scatter albedo): the blur's input.
    pub irradiance: Vec<[f32; 4]>,
    /// The blur's output (before the post-scatter albedo); pixels without SSS strength hold 0,
    /// and the final image uses their unscattered light.
    pub scattered: Vec<[f32; 4]>,
    /// x: view depth [cm] (background: far plane), y: SSS strength.
    pub geometry: Vec<[f32; 4]>,
    /// With [`Scatter::AreaGather`]: xyz the world position [cm], w the area [cm²] of the pixel's
    /// footprint that entered the gather (0 off the material or at grazing view); else empty.
    pub surface: Vec<[f32; 4]>,
    /// Per-pass GPU times; empty where the adapter has no timestamp queries.
    pub times: Vec<PassTime>,
}

/// GPU and wall time of one frame, without reading its images back.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTime {
    /// Wall time from recording to the GPU's completion [ms].
    pub wall_ms: f64,
    /// Per-pass GPU times; empty where the adapter has no timestamp queries.
    pub passes: Vec<PassTime>,
}

/// Every pipeline, built once from the device (the disc gathers' on their first frame);
/// [`Renderer::render`] then draws any number of frames (of any size, scene and kernels).
pub struct Renderer {
    shadow: ShadowPass,
    gbuffer: GBufferPass,
    separable: Separable,
    area: AreaGather,
    splats: Splats,
    combine: Combine,
    disc: DiscPipelines,
    pool: FramePool,
}

/// A recorded frame's buffers, and its hold on the renderer's pool until they are read.
struct Recorded<'a> {
    gbuffer: crate::passes::gbuffer::GBuffer,
    scattered: wgpu::Buffer,
    combined: crate::passes::combine::Combined,
    surface: Option<wgpu::Buffer>,
    timer: Option<Timer>,
    _frame: std::sync::MutexGuard<'a, ()>,
}

impl Renderer {
    /// Compiles every pipeline (the disc gathers' on their first frame, and kept).
    pub fn new(gpu: &Gpu) -> Renderer {
        Renderer {
            shadow: ShadowPass::new(gpu),
            gbuffer: GBufferPass::new(gpu),
            separable: Separable::new(gpu),
            area: AreaGather::new(gpu),
            splats: Splats::new(gpu),
            combine: Combine::new(gpu),
            disc: DiscPipelines::new(gpu),
            pool: FramePool::default(),
        }
    }

    /// Renders `scene`, scattering the diffuse light of SSS surfaces as `scatter` says, and reads
    /// the images back. Buffers and textures are kept for the next frame, which reuses what did
    /// not change (its size, kernels, tables, mesh); frames from several threads take turns.
    pub fn render(
        &self,
        gpu: &Gpu,
        scene: &Scene,
        scatter: Scatter,
        params: &RenderParams,
    ) -> Result<Frame> {
        let r = self.record(gpu, scene, scatter, params)?;
        let n = (params.width * params.height) as usize;
        let read = |b: &wgpu::Buffer| -> Result<Vec<[f32; 4]>> {
            Ok(
                bytemuck::cast_slice::<u8, [f32; 4]>(&gpu.read_buffer(b, (n * 16) as u64)?)
                    .to_vec(),
            )
        };
        Ok(Frame {
            width: params.width,
            height: params.height,
            linear: read(&r.combined.linear)?,
            display: gpu.read_buffer(&r.combined.display, (n * 4) as u64)?,
            irradiance: read(&r.gbuffer.diffuse)?,
            scattered: read(&r.scattered)?,
            geometry: read(&r.gbuffer.geometry)?,
            surface: match &r.surface {
                Some(b) => read(b)?,
                None => Vec::new(),
            },
            times: match &r.timer {
                Some(t) => t.read(gpu)?,
                None => Vec::new(),
            },
        })
    }

    /// The GPU's area-kernel lookup at each (distance [cm], area [cm²]) of `points`, with width
    /// factor `scale`: what [`Scatter::AreaGather`] reads, for checking against
    /// [`crate::AreaKernel::lookup`].
    pub fn area_lookup(
        &self,
        gpu: &Gpu,
        kernel: &crate::AreaKernel,
        scale: f32,
        points: &[[f32; 2]],
    ) -> Result<Vec<[f32; 3]>> {
        self.area.lookup(gpu, kernel, scale, points)
    }

    /// Renders a frame as [`Renderer::render`] does but reads back only its pass times: what a
    /// frame costs on the GPU.
    pub fn time(
        &self,
        gpu: &Gpu,
        scene: &Scene,
        scatter: Scatter,
        params: &RenderParams,
    ) -> Result<FrameTime> {
        let start = std::time::Instant::now();
        let r = self.record(gpu, scene, scatter, params)?;
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(FrameTime {
            wall_ms,
            passes: match &r.timer {
                Some(t) => t.read(gpu)?,
                None => Vec::new(),
            },
        })
    }

    /// Checks the input, records every pass and submits them.
    fn record<'a>(
        &'a self,
        gpu: &'a Gpu,
        scene: &Scene,
        scatter: Scatter,
        params: &RenderParams,
    ) -> Result<Recorded<'a>> {
        let disc = scatter.gathers_lit_surface();
        check(gpu, scene, &scatter, params)?;
        let (w, h) = (params.width, params.height);
        let n = (w * h) as usize;
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let frame = self.pool.begin(&mut enc);
        let alloc = Alloc::pooled(gpu, &self.pool);
        let mesh = MeshBuffers::upload(alloc, &scene.mesh);
        let mut rec = Recording::timed(alloc, enc);
        // The disc gathers shade with their own physics (the scene pass's tables off): no back maps.
        let back = if disc {
            0
        } else {
            crate::passes::shadow::back_layers(scene, params)
        };
        let shadow_maps = self.shadow.encode(&mut rec, (scene, &mesh, back))?;
        let gbuffer = self
            .gbuffer
            .encode(&mut rec, (scene, &mesh, &shadow_maps, params, disc))?;
        let scattered = alloc.pixels(n, "scattered");
        let target = Target {
            scene,
            camera_view_proj: camera_view_proj(scene, (w, h)),
            size: (w, h),
            mesh: &mesh,
            gbuffer: &gbuffer,
            scattered: &scattered,
        };
        let mut surface = None;
        match scatter {
            Scatter::Separable(given) => {
                self.separable.encode(&mut rec, (&target, given, params))?
            }
            Scatter::DirectionalDipole(setup) => self
                .disc
                .encode(&mut rec, (&target, DiscModel::Dipole(setup)))?,
            Scatter::SurfaceGather(setup) => self
                .disc
                .encode(&mut rec, (&target, DiscModel::Surface(setup)))?,
            Scatter::AreaGather(setup) => {
                let width = params.sss_width;
                let g = self.area.encode(&mut rec, (&target, setup, width))?;
                let lighting = self.gbuffer.lighting(&gbuffer);
                self.splats
                    .encode(&mut rec, (&target, setup, width, lighting, &g))?;
                surface = Some(g.surface);
            }
            Scatter::None => {
                rec.enc
                    .copy_buffer_to_buffer(&gbuffer.diffuse, 0, &scattered, 0, (n * 16) as u64)
            }
        }
        let combined = self
            .combine
            .encode(&mut rec, (params, &scattered, &gbuffer))?;
        let timer = rec.submit();
        Ok(Recorded {
            gbuffer,
            scattered,
            combined,
            surface,
            timer,
            _frame: frame,
        })
    }
}

/// Refuses what the renderer cannot draw, naming the field: an image the adapter cannot hold,
/// invalid lights or too many of them (fewer for the disc gathers), invalid shading tables,
/// vertex materials beyond [`MAX_MATERIALS`], kernels that do not match the scene's materials, a
/// negative kernel scale.
fn check(gpu: &Gpu, scene: &Scene, scatter: &Scatter, params: &RenderParams) -> Result<()> {
    let disc = scatter.gathers_lit_surface();
    let (w, h) = (params.width, params.height);
    let max = gpu.device.limits().max_texture_dimension_2d;
    if w == 0 || h == 0 || w > max || h > max {
        return Err(GpuError::invalid(
            "image size",
            format!("{w}×{h}"),
            format!("each side must lie in 1..={max}"),
        ));
    }
    crate::request::check_lights(&scene.lights, disc)?;
    for s in &params.shading {
        s.validate()?;
    }
    if let Some(v) = scene
        .mesh
        .vertices
        .iter()
        .find(|v| v.material as usize >= MAX_MATERIALS)
    {
        return Err(GpuError::invalid(
            "vertex material",
            v.material,
            format!("must be below {MAX_MATERIALS}"),
        ));
    }
    let used = scene.material_count();
    match scatter {
        Scatter::Separable(kernels) if kernels.len() < used || kernels.len() > MAX_MATERIALS => {
            return Err(GpuError::invalid(
                "kernels",
                kernels.len(),
                format!("one per SSS material: the scene uses {used}, at most {MAX_MATERIALS}"),
            ));
        }
        Scatter::DirectionalDipole(_) | Scatter::AreaGather(_) | Scatter::SurfaceGather(_)
            if used > 1 =>
        {
            return Err(GpuError::invalid(
                "materials",
                used,
                "the directional dipole and the area and surface gathers render one SSS material per frame",
            ));
        }
        _ => {}
    }
    if !(params.sss_width.is_finite() && params.sss_width >= 0.0) {
        return Err(GpuError::invalid(
            "sss width",
            params.sss_width,
            "must be finite and ≥ 0",
        ));
    }
    let n = (w * h) as usize;
    let dev = &gpu.device;
    let limit = dev
        .limits()
        .max_storage_buffer_binding_size
        .min(dev.limits().max_buffer_size);
    if n as u64 * 16 > limit {
        return Err(GpuError::invalid(
            "image size",
            format!("{w}×{h}"),
            format!(
                "needs {} MB per buffer, the adapter allows {} MB",
                (n * 16) >> 20,
                limit >> 20
            ),
        ));
    }
    Ok(())
}

/// Renders one frame with a [`Renderer`] built for it (to render many, build one and keep it).
pub fn render(gpu: &Gpu, scene: &Scene, scatter: Scatter, params: &RenderParams) -> Result<Frame> {
    Renderer::new(gpu).render(gpu, scene, scatter, params)
}
