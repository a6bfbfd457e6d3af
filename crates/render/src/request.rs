//! What a render asks for, as a whole: the frame (`gpu`'s request: scene, image, camera, lights,
//! method), the materials, the kernel, the shading model around it, the Monte Carlo tables' run
//! settings and the gathers' sampling. [`Request::default`] is the method the references measure
//! closest to path tracing: pre-integration with the incidence table, the exit law at the entry
//! angle, the entry shift and light through thin parts (the bust at 13.1 % of Mitsuba against
//! 47.9 % for the kernel alone, docs/measurements.md). [`Request::check`] refuses what does not go
//! together, naming the field.

use fit::taps::ShaderKernel;

use crate::error::{RenderError, Result};
use crate::options::{DipoleEnergy, ExitLaw};

/// A material with the short name its files and messages use.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedMaterial {
    /// Short name, e.g. `skin1`.
    pub slug: String,
    /// Its coefficients per channel.
    pub material: mc::Material,
}

impl NamedMaterial {
    /// A built-in material by name (case-insensitive).
    pub fn builtin(name: &str) -> Result<NamedMaterial> {
        Ok(NamedMaterial {
            slug: name.to_lowercase(),
            material: mc::Material::builtin(name)?,
        })
    }
}

/// The shading model around the separable kernel; `None` takes the method's default: on (and
/// the exit law at the entry angle) for the separable method, off for the others, which bring
/// their own dependence on the angles and their own light through thin parts.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadingOptions {
    /// Scale each light's irradiance by ρ(θ)/ρ(0) from `mc` at θ = 0°, 10°, …, 80°.
    pub incidence: Option<bool>,
    /// Which exit law h(θ_o; θ_i) multiplies the scattered light.
    pub exit: Option<ExitLaw>,
    /// Shade each pixel with the light that entered δ(θ_i) behind it and δ(θ_o) along the view
    /// ray's propagation over the surface.
    pub entry_shift: Option<bool>,
    /// Add the light the material transmits through thin parts (separable method only).
    pub translucency: Option<bool>,
    /// Multiply the light entering SSS surfaces by the shape table's E(κ, θ) at the surface's
    /// curvature at the scale the light travels (baked per vertex), and by what a slab as thin as the body's chord along the light keeps
    /// where it is thinner than its curvature makes it (separable method only; default off).
    pub shape: Option<bool>,
}

/// The shading options as applied: each default resolved for the method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvedShading {
    /// Incidence table on.
    pub incidence: bool,
    /// The exit law.
    pub exit: ExitLaw,
    /// Entry shift on.
    pub entry_shift: bool,
    /// Translucency table on.
    pub translucency: bool,
    /// Shape table on (`shading::ShapeTable`: what curved and thin bodies return against the
    /// half-space), read by the scene pass at the vertices' baked curvature.
    pub shape: bool,
}

/// How the tables of the shading model are simulated.
#[derive(Clone, Debug, PartialEq)]
pub struct TableSettings {
    /// Run settings (grid rule, ambient index) of every table and profile.
    pub config: mc::SimConfig,
    /// Seed of every table's runs.
    pub seed: u64,
    /// Photons per channel and angle of the incidence, exit, entry-shift and directional tables.
    pub incidence_photons: u64,
    /// Photons per channel and thickness of the translucency table.
    pub translucency_photons: u64,
}

impl Default for TableSettings {
    /// The thesis's settings and seed, 10⁵ photons per angle, 2·10⁴ per thickness.
    fn default() -> Self {
        let config = mc::SimConfig::thesis().expect("the built-in thesis settings parse");
        TableSettings {
            seed: config.seed,
            config,
            incidence_photons: 100_000,
            translucency_photons: 20_000,
        }
    }
}

/// The sampling of the methods that replace the separable kernel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GatherOptions {
    /// Surface gather: the Monte Carlo BSSRDF integrated.
    pub bssrdf: shading::Bssrdf,
    /// Directional dipole, surface gather: samples per pixel, light and frame.
    pub samples: u32,
    /// Directional dipole, surface gather: frames accumulated (the image is their mean).
    pub frames: u32,
    /// Directional dipole, surface gather: seed of the frames' random numbers [default: the
    /// tables' seed].
    pub frame_seed: Option<u32>,
    /// Directional dipole, surface gather: radius r* [cm] of the disc of lit points [default:
    /// the method's].
    pub radius_cm: Option<f32>,
    /// Directional dipole: its energy.
    pub dipole_energy: DipoleEnergy,
    /// Directional dipole, surface gather: side of each light's position/normal map [texels].
    pub light_map: u32,
    /// Surface gather: the frames' mean through the edge-aware denoiser
    /// (`gpu`'s passes/denoise.rs) over what the samples add to the control variate, its width
    /// per channel half the profile's median exit radius.
    pub denoise: bool,
    /// Area gather: half-width n [px] of the inner block of (2n+1)² taps.
    pub inner: u32,
    /// Area gather: layers of 16 taps around the inner block.
    pub layers: u32,
    /// Area gather: weight the taps of layer i by √i (the paper's §6.1).
    pub brighten: bool,
    /// Area gather: read each splat at the point the paper's eq. 9 moves towards the pixel.
    pub splat_clamp: bool,
}

impl Default for GatherOptions {
    fn default() -> Self {
        GatherOptions {
            bssrdf: shading::Bssrdf::Directional,
            samples: 16,
            frames: 16,
            frame_seed: None,
            radius_cm: None,
            dipole_energy: DipoleEnergy::MonteCarlo,
            light_map: 1024,
            denoise: false,
            inner: 2,
            layers: 10,
            brighten: false,
            splat_clamp: false,
        }
    }
}

/// A render as asked for.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// Scene, image, camera, lights, method and kernel sampling, as `gpu` checks them; its
    /// `materials` count is set from [`Request::materials`].
    pub frame: gpu::RenderRequest,
    /// One material per SSS material of the scene.
    pub materials: Vec<NamedMaterial>,
    /// A kernel to apply instead of pre-integration fitted to the material (separable method,
    /// one material).
    pub kernel: Option<ShaderKernel>,
    /// Where the albedo is applied relative to the scattering.
    pub albedo: gpu::AlbedoMode,
    /// Depth-discontinuity handling of the separable passes.
    pub depth_test: gpu::DepthMode,
    /// The separable passes at half resolution.
    pub half_res: bool,
    /// The shading model around the kernel.
    pub shading: ShadingOptions,
    /// How its tables are simulated.
    pub tables: TableSettings,
    /// The gathers' sampling.
    pub gather: GatherOptions,
    /// Plain Lambertian shading: no scattering at all (a baseline).
    pub no_sss: bool,
}

impl Default for Request {
    /// Skin1 on the built-in sphere at 1920×1080, pre-integration (17 taps) with every shading
    /// table on.
    fn default() -> Self {
        Request {
            frame: gpu::RenderRequest::default(),
            materials: vec![NamedMaterial::builtin("skin1").expect("skin1 is built in")],
            kernel: None,
            albedo: gpu::AlbedoMode::PrePost,
            depth_test: gpu::DepthMode::Lerp,
            half_res: false,
            shading: ShadingOptions::default(),
            tables: TableSettings::default(),
            gather: GatherOptions::default(),
            no_sss: false,
        }
    }
}

impl Request {
    /// The method the request scatters with.
    pub fn method(&self) -> gpu::Method {
        self.frame.method
    }

    /// The shading options with each default resolved for the method (all off without SSS).
    pub fn resolved_shading(&self) -> ResolvedShading {
        let separable = self.method() == gpu::Method::Separable && !self.no_sss;
        let s = &self.shading;
        let on = |v: Option<bool>| !self.no_sss && v.unwrap_or(separable);
        ResolvedShading {
            incidence: on(s.incidence),
            exit: match s.exit {
                _ if self.no_sss => ExitLaw::Lambertian,
                Some(e) => e,
                None if separable => ExitLaw::Entry,
                None => ExitLaw::Lambertian,
            },
            entry_shift: on(s.entry_shift),
            translucency: separable && s.translucency.unwrap_or(true),
            shape: separable && s.shape == Some(true),
        }
    }

    /// Checks the request as a whole: `gpu`'s checks and the scene ([`gpu::RenderRequest::scene`]),
    /// then what the method takes. Every refusal names the field.
    pub fn check(&self) -> Result<gpu::Scene> {
        let mut frame = self.frame.clone();
        frame.materials = self.materials.len();
        if self.materials.is_empty() {
            return Err(RenderError::invalid("materials", 0, "name at least one"));
        }
        let scene = frame.scene()?;
        let method = self.method();
        let given = |v: Option<bool>| v == Some(true);
        if self.kernel.is_some() && self.materials.len() > 1 {
            return Err(RenderError::invalid(
                "kernel",
                "a kernel file",
                format!(
                    "takes a scene of one SSS material ({} has {})",
                    self.frame.scene,
                    self.materials.len()
                ),
            ));
        }
        if method != gpu::Method::Separable {
            if self.kernel.is_some() || self.no_sss {
                return Err(RenderError::invalid(
                    if self.no_sss { "no_sss" } else { "kernel" },
                    describe(method),
                    "is for the separable method: the other methods bring their own scattering",
                ));
            }
            if given(self.shading.translucency) {
                return Err(RenderError::invalid(
                    "translucency",
                    "on",
                    format!(
                        "is for the separable method: the {} carries light through thin parts itself",
                        describe(method)
                    ),
                ));
            }
            if given(self.shading.shape) {
                return Err(RenderError::invalid(
                    "shape",
                    "on",
                    format!(
                        "is for the separable method: the {} does not read the shape table",
                        describe(method)
                    ),
                ));
            }
        }
        if method.gathers_lit_surface() {
            let s = &self.shading;
            for (field, on) in [
                ("incidence", given(s.incidence)),
                ("exit", s.exit.is_some_and(|e| e != ExitLaw::Lambertian)),
                ("entry_shift", given(s.entry_shift)),
            ] {
                if on {
                    return Err(RenderError::invalid(
                        field,
                        "on",
                        format!(
                            "is for the separable method: the {} depends on both angles and on the entry point itself",
                            describe(method)
                        ),
                    ));
                }
            }
        }
        if self.gather.denoise && method != gpu::Method::SurfaceGather {
            return Err(RenderError::invalid(
                "denoise",
                "on",
                format!(
                    "is for the surface gather: its widths come from the Monte Carlo profile, which the {} does not read",
                    describe(method)
                ),
            ));
        }
        if method.gathers_lit_surface() {
            let g = &self.gather;
            gpu::Sampling {
                samples: g.samples,
                frames: g.frames,
                radius_cm: g.radius_cm.unwrap_or(1.0),
                map_size: g.light_map,
                seed: 0,
                denoise: g.denoise,
            }
            .validate()?;
        }
        let t = &self.tables;
        for (field, v) in [
            ("incidence_photons", t.incidence_photons),
            ("translucency_photons", t.translucency_photons),
        ] {
            if v == 0 {
                return Err(RenderError::invalid(field, v, "must be at least 1"));
            }
        }
        Ok(scene)
    }
}

/// What a method is called in messages.
fn describe(method: gpu::Method) -> &'static str {
    match method {
        gpu::Method::Separable => "separable method",
        gpu::Method::DirectionalDipole => "directional dipole",
        gpu::Method::AreaGather => "area gather",
        gpu::Method::SurfaceGather => "surface gather",
    }
}
