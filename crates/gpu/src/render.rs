//! One frame: shadow maps, the scene pass, the SSS passes and recombination, read back as images.

use glam::Mat4;
use wgpu::util::DeviceExt;

use crate::blur::{Blur, BlurParams, DepthMode, GpuKernel, pixels};
use crate::context::{Gpu, cleared_depth, compute_pipeline, depth_test};
use crate::dipole::{DipoleSetup, MeshBuffers};
use crate::error::{GpuError, Result};
use crate::mesh::Vertex;
use crate::scene::{AlbedoMode, Light, Scene};
use crate::timing::{PassTime, Timer};

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
    Separable(&'a [GpuKernel]),
    /// The directional dipole evaluated per pixel over lit surface points ([`crate::dipole`]);
    /// the albedo split and incidence table of [`RenderParams`] do not apply (the colour and the
    /// dependence on incidence come from the model).
    DirectionalDipole(&'a DipoleSetup),
}

/// Render settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderParams {
    /// Image width [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// How the albedo is split around the scattering; [`Scatter::DirectionalDipole`] ignores it.
    pub albedo: AlbedoMode,
    /// Kernel width multiplier (1 = physical size).
    pub sss_width: f32,
    /// How the blur treats samples across depth discontinuities.
    pub depth_mode: DepthMode,
    /// Depth tolerance [cm]; None: the kernel's range × `sss_width`.
    pub tolerance_cm: Option<f32>,
    /// Per-pixel random scale of the kernel's offsets in [1 − j/2, 1 + j/2] (see
    /// [`BlurParams::jitter`]); 0: off.
    pub jitter: f32,
    /// Fixed view depth [cm] for the kernel scale (see [`BlurParams::fixed_depth`]).
    pub fixed_depth: Option<f32>,
    /// Exposure before tone mapping.
    pub exposure: f32,
    /// Pixels without SSS do no blur work (they keep their unscattered light either way; off
    /// only to measure what the skip saves).
    pub skip_empty: bool,
    /// Per SSS material (the vertices' `material` index): how its surfaces are shaded.
    pub shading: [Shading; MAX_MATERIALS],
}

/// The most SSS materials one frame holds (each with its kernel and [`Shading`]).
pub const MAX_MATERIALS: usize = 4;

/// How the surfaces of one SSS material are shaded around the scattering; the default is off
/// (plain Lambertian entry and exit, no light through thin parts).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// Incidence-aware shading: the material's total diffuse reflectance at incidence
    /// θ = 0°, 10°, …, 80° relative to normal incidence, ρ(θ)/ρ(0) per channel (beyond 80° the
    /// last value). The scene pass multiplies each light's irradiance on SSS surfaces by it, and
    /// the ambient light by its cosine-weighted hemispherical mean. All ones: off.
    pub incidence: [[f32; 3]; INCIDENCE_STEPS],
    /// Exit-angle-aware shading: the radiance leaving the SSS material at polar angle
    /// θ = 0°, 10°, …, 80° relative to that of a Lambertian surface with the same total
    /// reflectance, h(θ) per channel (`mc::exitance`; beyond 80° the last value). The scattered
    /// light of each SSS pixel is multiplied by h at the pixel's view angle. All ones: off
    /// (Lambertian exit).
    pub exit: [[f32; 3]; INCIDENCE_STEPS],
    /// Light through thin parts of SSS surfaces (None: off).
    pub translucency: Option<Translucency>,
}

impl Shading {
    /// Checks the tables; the error names the field.
    pub fn validate(&self) -> Result<()> {
        if let Some(t) = &self.translucency {
            t.validate()?;
        }
        // Exit factors reach the shader through pack_albedo's 8-bit shared scale of at most 4:
        // with albedos ≤ 1, h up to 4 is exact to 8 bits.
        for (what, table, max) in [
            ("incidence table", &self.incidence, None),
            ("exit table", &self.exit, Some(4.0)),
        ] {
            if let Some(v) = table
                .iter()
                .flatten()
                .find(|v| !(v.is_finite() && **v >= 0.0 && max.is_none_or(|m| **v <= m)))
            {
                let reason = match max {
                    Some(m) => format!("entries must be finite, ≥ 0 and ≤ {m}"),
                    None => "entries must be finite and ≥ 0".into(),
                };
                return Err(GpuError::invalid(what, v, reason));
            }
        }
        Ok(())
    }
}

impl Default for Shading {
    fn default() -> Self {
        Shading {
            incidence: [[1.0; 3]; INCIDENCE_STEPS],
            exit: [[1.0; 3]; INCIDENCE_STEPS],
            translucency: None,
        }
    }
}

/// Entries of [`Shading::incidence`] and [`Shading::exit`]: θ = 0°, 10°, …, 80°.
pub const INCIDENCE_STEPS: usize = 9;

/// Entries of a [`Translucency`] table.
pub const TRANSLUCENCY_STEPS: usize = 16;

/// Light through thin parts (thesis §4.2's first pass; the SSSS supplement's transmittance), from
/// the material itself: a table of its slab transmittance against thickness.
///
/// For an SSS pixel facing away from a light with a shadow map, the shadow map gives the surface
/// where that light enters; the thickness d is the distance between the two along the light ray,
/// and the scene pass adds E·|n·l|·T(|n·l|)/T(1)·table(d) to the irradiance before the blur,
/// T the Fresnel transmittance into the material. Along the ray is
/// exact for light crossing a slab along its normal; at incidence θ it reads t/cos θ where the
/// refracted path inside is t/cos θt (8 % longer than that at 30° and η = 1.3). Measuring the
/// slab along the normal instead (d·|n·l|) would be exact for slabs but sends d → 0 at every
/// terminator of a thick part, where Tt(0)/ρ (up to 1/ρ) paints a bright band: the light
/// entering next to a terminator is the front-lit light the blur already spreads (there, too,
/// the Fresnel factor of grazing entry fades the rest). The table holds Tt(d)/ρ per channel: the slab's total
/// transmittance (`mc::slab`, normal incidence, per unit incident power) over the material's
/// total diffuse reflectance ρ, because the pipeline multiplies the blurred irradiance by the
/// object's albedo, which for a material is ρ; so a back-lit slab leaves with exitance E·Tt(d).
/// The entering face's normal is not known from a depth map: it is taken as −n (a parallel
/// face). Thicknesses are geometric, d_k = first·ratio^k, interpolated linearly in ln d, held
/// below the first and beyond the last.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Translucency {
    /// The first tabulated thickness [cm].
    pub first_cm: f32,
    /// The ratio between successive thicknesses (> 1).
    pub ratio: f32,
    /// Tt(d_k)/ρ per channel.
    pub table: [[f32; 3]; TRANSLUCENCY_STEPS],
    /// The material's relative index η: light entering the back face at incidence θ is scaled
    /// by the Fresnel transmittance T(θ)/T(0) (the table holds normal incidence).
    pub eta: f32,
}

impl Translucency {
    /// The geometric thicknesses of a table from `first_cm` to `last_cm` [cm].
    pub fn thicknesses(first_cm: f64, last_cm: f64) -> [f64; TRANSLUCENCY_STEPS] {
        let q = (last_cm / first_cm).powf(1.0 / (TRANSLUCENCY_STEPS - 1) as f64);
        std::array::from_fn(|k| first_cm * q.powi(k as i32))
    }

    /// Tt(d)/ρ at thickness `d_cm` (what the scene shader evaluates).
    pub fn at(&self, d_cm: f32) -> [f32; 3] {
        let t = (d_cm.max(1e-30) / self.first_cm).ln() / self.ratio.ln();
        if t.is_nan() || t <= 0.0 {
            return self.table[0];
        }
        let i = t.floor() as usize;
        if i + 1 >= TRANSLUCENCY_STEPS {
            return self.table[TRANSLUCENCY_STEPS - 1];
        }
        let f = t - i as f32;
        [0, 1, 2].map(|c| self.table[i][c] * (1.0 - f) + self.table[i + 1][c] * f)
    }

    /// Checks the table; the error names the field.
    pub fn validate(&self) -> Result<()> {
        if !(self.first_cm.is_finite() && self.first_cm > 0.0) {
            return Err(GpuError::invalid(
                "translucency first thickness",
                self.first_cm,
                "must be positive [cm]",
            ));
        }
        if !(self.ratio.is_finite() && self.ratio > 1.0) {
            return Err(GpuError::invalid(
                "translucency ratio",
                self.ratio,
                "must exceed 1",
            ));
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(GpuError::invalid(
                "translucency eta",
                self.eta,
                "must be positive",
            ));
        }
        if let Some(v) = self
            .table
            .iter()
            .flatten()
            .find(|v| !(v.is_finite() && **v >= 0.0))
        {
            return Err(GpuError::invalid(
                "translucency table",
                v,
                "entries must be finite and ≥ 0",
            ));
        }
        Ok(())
    }
}

/// ρ(θ)/ρ(0) at cos θ = `cos_i` from an incidence table (or h(θ) from an exit table), linear in θ
/// between entries (what the scene shader evaluates).
pub fn incidence_ratio(table: &[[f32; 3]; INCIDENCE_STEPS], cos_i: f32) -> [f32; 3] {
    let t = cos_i.clamp(0.0, 1.0).acos().to_degrees() / 10.0;
    let i = (t.floor() as usize).min(INCIDENCE_STEPS - 1);
    if i + 1 >= INCIDENCE_STEPS {
        return table[INCIDENCE_STEPS - 1];
    }
    let f = t - i as f32;
    [0, 1, 2].map(|c| table[i][c] * (1.0 - f) + table[i + 1][c] * f)
}

/// The cosine-weighted hemispherical mean 2∫₀^{π/2} f(θ) cos θ sin θ dθ of an incidence table:
/// the factor for diffuse (ambient) light.
pub fn incidence_hemispherical(table: &[[f32; 3]; INCIDENCE_STEPS]) -> [f32; 3] {
    let n = 900;
    let mut acc = [0.0f64; 3];
    for k in 0..n {
        let theta = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
        let f = incidence_ratio(table, theta.cos() as f32);
        let w = 2.0 * theta.cos() * theta.sin() * std::f64::consts::FRAC_PI_2 / n as f64;
        for c in 0..3 {
            acc[c] += w * f[c] as f64;
        }
    }
    acc.map(|x| x as f32)
}

impl Default for RenderParams {
    fn default() -> Self {
        RenderParams {
            width: 1920,
            height: 1080,
            albedo: AlbedoMode::PrePost,
            sss_width: 1.0,
            depth_mode: DepthMode::Lerp,
            tolerance_cm: None,
            jitter: 0.0,
            fixed_depth: None,
            exposure: 1.0,
            skip_empty: true,
            shading: [Shading::default(); MAX_MATERIALS],
        }
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
    /// Per-pass GPU times; empty where the adapter has no timestamp queries.
    pub times: Vec<PassTime>,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct LightU {
    view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    pos_or_dir: [f32; 4],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    view: [[f32; 4]; 4],
    camera_pos: [f32; 4],
    params: [f32; 4],
    ambient: [f32; 4],
    lights: [LightU; 4],
    /// Per SSS material.
    materials: [MaterialU; MAX_MATERIALS],
}

/// One material's [`Shading`] as scene.wgsl's `Material` holds it.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MaterialU {
    /// ρ(θ)/ρ(0) at θ = 0°, 10°, …, 80° (rgb).
    incidence: [[f32; 4]; INCIDENCE_STEPS],
    /// The ambient light's factor (rgb).
    incidence_ambient: [f32; 4],
    /// Tt(d)/ρ at the geometric thicknesses of [`Translucency`] (rgb).
    translucency: [[f32; 4]; TRANSLUCENCY_STEPS],
    /// x: first thickness [cm], y: ln ratio, z: 1 on / 0 off, w: η.
    translucency_params: [f32; 4],
    /// h(θ) at θ = 0°, 10°, …, 80° (rgb).
    exit: [[f32; 4]; INCIDENCE_STEPS],
}

impl MaterialU {
    /// The material's tables; `plain`: all off (the dipole brings its own physics).
    fn new(s: &Shading, plain: bool) -> MaterialU {
        let s = if plain { &Shading::default() } else { s };
        let rgb = |r: [f32; 3]| [r[0], r[1], r[2], 0.0];
        MaterialU {
            incidence: s.incidence.map(rgb),
            incidence_ambient: rgb(incidence_hemispherical(&s.incidence)),
            translucency: match &s.translucency {
                Some(t) => t.table.map(rgb),
                None => [[0.0; 4]; TRANSLUCENCY_STEPS],
            },
            translucency_params: match &s.translucency {
                Some(t) => [t.first_cm, t.ratio.ln(), 1.0, t.eta],
                None => [1.0, 1.0, 0.0, 1.0],
            },
            exit: s.exit.map(rgb),
        }
    }
}

/// The scene shader with the shared Fresnel function prepended.
pub(crate) const SCENE_WGSL: &str = concat!(
    include_str!("shaders/fresnel.wgsl"),
    include_str!("shaders/scene.wgsl")
);

/// The size of scene.wgsl's `Globals`: 2 mat4 + 3 vec4 + 4 lights × 160 + per material 10 vec4
/// of incidence, 17 vec4 of translucency and 9 vec4 of exit (checked against naga's layout in a
/// test).
pub(crate) const GLOBALS_SIZE: usize =
    2 * 64 + 3 * 16 + 4 * 160 + MAX_MATERIALS * (10 * 16 + 17 * 16 + 9 * 16);
const _: () = assert!(std::mem::size_of::<Globals>() == GLOBALS_SIZE);

/// Scene targets: diffuse; specular + strength; view depth + packed post-scatter albedo.
const FORMATS: [wgpu::TextureFormat; 3] = [
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rg32Float,
];
const SHADOW_SIZE: u32 = 2048;
const NEAR: f32 = 1.0;
const FAR: f32 = 500.0;

/// Renders `scene`, scattering the diffuse light of SSS surfaces as `scatter` says.
pub fn render(gpu: &Gpu, scene: &Scene, scatter: Scatter, params: &RenderParams) -> Result<Frame> {
    let dipole = matches!(scatter, Scatter::DirectionalDipole(_));
    let (w, h) = (params.width, params.height);
    let max = gpu.device.limits().max_texture_dimension_2d;
    if w == 0 || h == 0 || w > max || h > max {
        return Err(GpuError::invalid(
            "image size",
            format!("{w}×{h}"),
            format!("each side must lie in 1..={max}"),
        ));
    }
    if scene.lights.len() > 4 {
        return Err(GpuError::invalid("lights", scene.lights.len(), "at most 4"));
    }
    for s in &params.shading {
        s.validate()?;
    }
    if let Some(v) = scene
        .mesh
        .vertices
        .iter()
        .find(|v| v.strength > 0.0 && v.material as usize >= MAX_MATERIALS)
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
        Scatter::DirectionalDipole(_) if used > 1 => {
            return Err(GpuError::invalid(
                "materials",
                used,
                "the directional dipole renders one SSS material per frame",
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
    let vbuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("vertices"),
        contents: bytemuck::cast_slice(&scene.mesh.vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let ibuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("indices"),
        contents: bytemuck::cast_slice(&scene.mesh.indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    let index_count = scene.mesh.indices.len() as u32;

    // Shadow maps: one layer per light (at least one, so the binding exists).
    let layers = scene.lights.len().max(1) as u32;
    let shadow_tex = dev.create_texture(&wgpu::TextureDescriptor {
        label: Some("shadow maps"),
        size: wgpu::Extent3d {
            width: SHADOW_SIZE,
            height: SHADOW_SIZE,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let shadow_module = dev.create_shader_module(wgpu::include_wgsl!("shaders/shadow.wgsl"));
    let vertex_layout = Vertex::layout();
    let shadow_pipeline = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("shadow"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &shadow_module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(vertex_layout.clone())],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(depth_test()),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    });
    let mut lights = [LightU {
        view_proj: Mat4::IDENTITY.to_cols_array_2d(),
        inv_view_proj: Mat4::IDENTITY.to_cols_array_2d(),
        pos_or_dir: [0.0; 4],
        color: [0.0; 4],
    }; 4];
    let mut enc = dev.create_command_encoder(&Default::default());
    for (i, light) in scene.lights.iter().enumerate() {
        let vp = scene.light_view_proj(light);
        let (pos_or_dir, color, shadow) = match *light {
            Light::Directional {
                towards,
                irradiance,
                shadow,
            } => (towards.normalize().extend(0.0), irradiance, shadow),
            Light::Point {
                position,
                intensity,
                shadow,
            } => (position.extend(1.0), intensity, shadow),
        };
        lights[i] = LightU {
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            pos_or_dir: pos_or_dir.into(),
            color: color.extend(if shadow { i as f32 } else { -1.0 }).into(),
        };
        let ubuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light"),
            contents: bytemuck::bytes_of(&vp.to_cols_array_2d()),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &shadow_pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: ubuf.as_entire_binding(),
            }],
        });
        let view = shadow_tex.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: i as u32,
            array_layer_count: Some(1),
            ..Default::default()
        });
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow"),
            color_attachments: &[],
            depth_stencil_attachment: Some(cleared_depth(&view)),
            ..Default::default()
        });
        if shadow {
            pass.set_pipeline(&shadow_pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.set_vertex_buffer(0, vbuf.slice(..));
            pass.set_index_buffer(ibuf.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..index_count, 0, 0..1);
        }
    }

    // Scene pass.
    let cam = &scene.camera;
    let view = cam.view();
    let proj = cam.projection(w as f32 / h as f32, NEAR, FAR);
    let globals = Globals {
        view_proj: (proj * view).to_cols_array_2d(),
        view: view.to_cols_array_2d(),
        camera_pos: cam.position.extend(1.0).into(),
        params: [
            scene.lights.len() as f32,
            // The dipole's output carries its own colour: no post-scatter albedo.
            match params.albedo {
                _ if dipole => 0.0,
                AlbedoMode::Pre => 0.0,
                AlbedoMode::Post => 1.0,
                AlbedoMode::PrePost => 2.0,
            },
            scene.specular,
            scene.shininess,
        ],
        ambient: scene.ambient.extend(0.0).into(),
        lights,
        materials: params.shading.map(|s| MaterialU::new(&s, dipole)),
    };
    let gbuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("globals"),
        contents: bytemuck::bytes_of(&globals),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let scene_module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("scene"),
        source: wgpu::ShaderSource::Wgsl(SCENE_WGSL.into()),
    });
    let targets: Vec<Option<wgpu::ColorTargetState>> =
        FORMATS.iter().map(|&f| Some(f.into())).collect();
    let scene_pipeline = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("scene"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &scene_module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(vertex_layout)],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(depth_test()),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &scene_module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    });
    let shadow_view = shadow_tex.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let sampler = dev.create_sampler(&wgpu::SamplerDescriptor {
        compare: Some(wgpu::CompareFunction::LessEqual),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    let scene_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &scene_pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: gbuf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&shadow_view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
        ],
    });
    let size = wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    };
    let target = |label: &str, format| {
        dev.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
    };
    let tex: Vec<wgpu::Texture> = ["diffuse", "specular", "geometry"]
        .iter()
        .zip(FORMATS)
        .map(|(l, f)| target(l, f))
        .collect();
    let views: Vec<wgpu::TextureView> = tex
        .iter()
        .map(|t| t.create_view(&Default::default()))
        .collect();
    let depth = target("depth", wgpu::TextureFormat::Depth32Float);
    let depth_view = depth.create_view(&Default::default());
    {
        // Background: no light, no strength, far depth; its albedo bits are 0 (black), and it
        // has no diffuse light to scale anyway.
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
            ..Default::default()
        });
        pass.set_pipeline(&scene_pipeline);
        pass.set_bind_group(0, &scene_bind, &[]);
        pass.set_vertex_buffer(0, vbuf.slice(..));
        pass.set_index_buffer(ibuf.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..index_count, 0, 0..1);
    }

    // Unpack the targets into storage buffers.
    let bufs: Vec<wgpu::Buffer> = ["diffuse", "specular", "geometry", "albedo"]
        .iter()
        .map(|l| pixels(gpu, n, l))
        .collect();
    let unpack = compute_pipeline(dev, wgpu::include_wgsl!("shaders/unpack.wgsl"), "unpack");
    let mut entries: Vec<wgpu::BindGroupEntry> = views
        .iter()
        .enumerate()
        .map(|(i, v)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: wgpu::BindingResource::TextureView(v),
        })
        .collect();
    entries.extend(bufs.iter().enumerate().map(|(i, b)| wgpu::BindGroupEntry {
        binding: 3 + i as u32,
        resource: b.as_entire_binding(),
    }));
    let unpack_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &unpack.get_bind_group_layout(0),
        entries: &entries,
    });
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&unpack);
        pass.set_bind_group(0, &unpack_bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }

    // SSS.
    let scattered = pixels(gpu, n, "scattered");
    let tmp = pixels(gpu, n, "tmp");
    let mut timer = Timer::new(gpu);
    match scatter {
        Scatter::Separable(kernels) => {
            let blur_params = BlurParams {
                px_per_cm_at_unit_depth: cam.px_per_cm_at_unit_depth(h),
                sss_width: params.sss_width,
                depth_mode: params.depth_mode,
                tolerance_cm: params.tolerance_cm,
                jitter: params.jitter,
                fixed_depth: params.fixed_depth,
                skip_empty: params.skip_empty,
            };
            Blur::new(gpu).encode(
                gpu,
                &mut enc,
                kernels,
                &blur_params,
                (w, h),
                &bufs[0],
                &bufs[2],
                &tmp,
                &scattered,
                &mut timer.as_mut(),
            );
        }
        Scatter::DirectionalDipole(setup) => crate::dipole::encode(
            gpu,
            &mut enc,
            scene,
            setup,
            proj * view,
            (w, h),
            &MeshBuffers {
                vertices: &vbuf,
                indices: &ibuf,
                count: index_count,
            },
            &scattered,
            &mut timer.as_mut(),
        )?,
        Scatter::None => enc.copy_buffer_to_buffer(&bufs[0], 0, &scattered, 0, (n * 16) as u64),
    }

    // Recombine.
    let linear = pixels(gpu, n, "linear");
    let display = dev.create_buffer(&wgpu::BufferDescriptor {
        label: Some("display"),
        size: (n * 4) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let combine = compute_pipeline(dev, wgpu::include_wgsl!("shaders/combine.wgsl"), "combine");
    let cu = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("combine params"),
        contents: bytemuck::cast_slice(&[w, h, params.exposure.to_bits(), 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let combine_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &combine.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: cu.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: scattered.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: bufs[1].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: bufs[3].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: linear.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: display.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 6,
                resource: bufs[0].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 7,
                resource: bufs[2].as_entire_binding(),
            },
        ],
    });
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&combine);
        pass.set_bind_group(0, &combine_bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    gpu.queue.submit([enc.finish()]);

    let read = |b: &wgpu::Buffer| -> Result<Vec<[f32; 4]>> {
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&gpu.read_buffer(b, (n * 16) as u64)?).to_vec())
    };
    Ok(Frame {
        width: w,
        height: h,
        linear: read(&linear)?,
        display: gpu.read_buffer(&display, (n * 4) as u64)?,
        irradiance: read(&bufs[0])?,
        scattered: read(&scattered)?,
        geometry: read(&bufs[2])?,
        times: match &timer {
            Some(t) => t.read(gpu)?,
            None => Vec::new(),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn incidence_table_lookup_and_hemispherical_mean() {
        // A constant table is that constant everywhere; 2∫cos θ sin θ dθ = 1.
        let ones = [[1.0f32; 3]; INCIDENCE_STEPS];
        assert_eq!(incidence_ratio(&ones, 0.3), [1.0; 3]);
        for h in incidence_hemispherical(&ones) {
            assert!((h - 1.0).abs() < 1e-5, "{h}");
        }
        // A table linear in θ is reproduced between entries and held beyond 80°.
        let table: [[f32; 3]; INCIDENCE_STEPS] =
            std::array::from_fn(|k| [1.0 + 0.1 * k as f32, 1.0, 2.0 - 0.1 * k as f32]);
        let r = incidence_ratio(&table, 35f32.to_radians().cos());
        assert!(
            (r[0] - 1.35).abs() < 1e-4 && (r[2] - 1.65).abs() < 1e-4,
            "{r:?}"
        );
        assert_eq!(incidence_ratio(&table, 0.0), table[8]);
        // Hemispherical mean of f(θ) = 1 + θ/100 rad⁻¹… checked against direct quadrature of the
        // interpolant: for R, 2∫(1 + 0.01·θ°)cos θ sin θ dθ with θ° clamped at 80.
        let n = 20_000;
        let direct: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
                let deg = t.to_degrees().min(80.0);
                (1.0 + 0.01 * deg) * 2.0 * t.cos() * t.sin() * std::f64::consts::FRAC_PI_2
                    / n as f64
            })
            .sum();
        let h = incidence_hemispherical(&table);
        assert!((h[0] as f64 - direct).abs() < 1e-4, "{} vs {direct}", h[0]);
    }
}
