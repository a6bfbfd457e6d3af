//! `sss render`'s flags and how they map onto a `render::Request`; a refusal of the library's
//! names the flag that set the field.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use fit::taps::ShaderKernel;
use glam::Vec3;
use gpu::Light;
use render::{RenderError, Request};

use crate::cache::ProfileSource;
use crate::common::{choice, on_off, parse_count};
use crate::library;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene: sphere (sphere on a floor), fin (sphere with two thin fins), pair (two spheres side
    /// by side, two SSS materials) or a Wavefront .obj path
    #[arg(long, default_value = "sphere")]
    pub scene: String,

    /// Material whose profile the default kernel (and --compare-models) is fitted to; for a scene
    /// of several SSS materials one per material, separated by commas (pair: left,right, e.g.
    /// skin1,marble). A material's kernel takes no light from another material's pixels
    #[arg(long, default_value = "skin1")]
    pub material: String,

    /// Kernel file from `sss fit` [default: pre-integration with --taps taps fitted to the material]
    #[arg(long, value_name = "KERNEL.toml")]
    pub kernel: Option<PathBuf>,

    /// Taps per 1D pass for kernels fitted here
    #[arg(long, default_value_t = 17)]
    pub taps: usize,

    /// Image-error target: per material, the smallest rank (1: pre-integration, 2–6: SVD rescaled
    /// to the kernel's energy) whose image RMS on `fit`'s test signals against the 2D ground
    /// truth (images in [0, 1], mean over R, G, B) is at most this; higher ranks are not run
    /// [default: pre-integration]
    #[arg(long, value_name = "RMS", conflicts_with = "kernel")]
    pub error_target: Option<f64>,

    /// Image width [px]
    #[arg(long, default_value_t = 1920)]
    pub width: u32,

    /// Image height [px]
    #[arg(long, default_value_t = 1080)]
    pub height: u32,

    /// Where the albedo is applied relative to the scattering
    #[arg(long, value_parser = choice::<gpu::AlbedoMode>(), default_value = "pre-post")]
    pub albedo: gpu::AlbedoMode,

    /// Depth-discontinuity handling
    #[arg(long, value_parser = choice::<gpu::DepthMode>(), default_value = "lerp")]
    pub depth_test: gpu::DepthMode,

    /// Depth difference [cm] at which a sample is fully replaced/rejected [default: the kernel's range]
    #[arg(long)]
    pub tolerance: Option<f32>,

    /// Fraction of taps jittered per pixel, 0–1 (SSSS supplement Fig. S.6–S.7: each picked tap
    /// samples a random position within its cell; trades banding for noise) [default: the
    /// kernel file's jitter, else 0]
    #[arg(long)]
    pub jitter: Option<f32>,

    /// Resolution of the separable passes: full, or half (2×2 blocks averaged, blurred, then
    /// brought back by a depth- and material-aware bilinear upsampling; a quarter of the work)
    #[arg(long, value_parser = ["full", "half"], default_value = "full")]
    pub resolution: String,

    /// How the separable passes read their samples: exact (two f32 reads per tap, several
    /// materials) or fast (one filtered fetch per tap from an rgba16float texture of light and
    /// depth, as SSSS; one material; 0.1 % from exact on the sphere)
    #[arg(long, value_parser = ["exact", "fast"], default_value = "exact")]
    pub blur: String,

    /// Kernel width multiplier (1 = the material's physical scale)
    #[arg(long, default_value_t = 1.0)]
    pub sss_width: f32,

    /// Exposure before tone mapping
    #[arg(long, default_value_t = 1.0)]
    pub exposure: f32,

    /// Camera position X,Y,Z [cm]
    #[arg(long, value_parser = render::parse::vec3)]
    pub camera: Option<Vec3>,

    /// Camera target X,Y,Z [cm]
    #[arg(long, value_parser = render::parse::vec3)]
    pub target: Option<Vec3>,

    /// Vertical field of view [degrees]
    #[arg(long)]
    pub fov: Option<f32>,

    /// Lights (repeatable): dir:X,Y,Z[:IRRADIANCE] (towards the light; default 1.2),
    /// point:X,Y,Z[:INTENSITY] (position [cm], intensity = irradiance × cm²; default 1200) or
    /// area:X,Y,Z:AX,AY,AZ:SIDE[:RADIANCE] (a square of SIDE [cm] centred at X,Y,Z facing the
    /// point AX,AY,AZ, in Mitsuba's look_at frame with +y up; radiance default 5, a surface
    /// facing a large one gets π × it). All cast shadows. An area light is drawn as 64 point
    /// lights (its 8×8 cells), at most 64 in all; SSS surfaces reflect it in mirror with the
    /// Fresnel reflectance of the material's η
    #[arg(long = "light", value_parser = render::parse::light)]
    pub lights: Vec<Light>,

    /// Diffuse albedo R,G,B of the SSS objects (e.g. the material's total diffuse reflectance);
    /// given once for every material, or once per material in --material's order
    #[arg(long, value_parser = render::parse::vec3)]
    pub object_albedo: Vec<Vec3>,

    /// Diffuse albedo R,G,B of the floor
    #[arg(long, value_parser = render::parse::vec3)]
    pub floor_albedo: Option<Vec3>,

    /// Blinn–Phong specular intensity (0: none)
    #[arg(long)]
    pub specular: Option<f32>,

    /// Constant ambient irradiance (0: none)
    #[arg(long)]
    pub ambient: Option<f32>,

    /// Add a black, non-scattering box (an occluder that casts hard shadows), repeatable:
    /// MIN_X,MIN_Y,MIN_Z:MAX_X,MAX_Y,MAX_Z [cm]
    #[arg(long = "box", value_parser = render::parse::cuboid)]
    pub boxes: Vec<(Vec3, Vec3)>,

    /// Incidence-aware shading: scale each light's irradiance on SSS surfaces by the material's
    /// total diffuse reflectance at that incidence angle relative to normal incidence,
    /// ρ(θ)/ρ(0) per channel, from `mc` at θ = 0°, 10°, …, 80° (Fresnel entry included)
    /// [default: on for the separable method, off for the others]
    #[arg(long, value_parser = on_off())]
    pub incidence_aware: Option<bool>,

    /// Exit-angle-aware shading: multiply the scattered light of SSS pixels by the material's
    /// reflected radiance at the pixel's view angle relative to a Lambertian surface's,
    /// h(θ_o; θ_i) = π·Rd_a(θ_o)/(Rd·cos θ_o) per channel, from `mc` at each entry angle
    /// θ_i = 0°, 10°, …, 80° in 10° exit bins: `on` reads the row of light that entered along
    /// the normal, `entry` the row at the entry angle of the pixel's lights (weighted by the
    /// irradiance each brings); its cosine-weighted mean is 1: it moves light between view
    /// angles, it adds none [default: entry for the separable method, off for the others]
    #[arg(long, value_parser = choice::<render::ExitLaw>())]
    pub exit_aware: Option<render::ExitLaw>,

    /// Entry-shifted shading: light entering a half-space at θ leaves δ(θ) ahead of its entry on
    /// average (mc's centroid); each SSS pixel is shaded with the light that entered δ behind it
    /// (that point's shadow and normal) [default: on for the separable method, off for others]
    #[arg(long, value_parser = on_off())]
    pub entry_shift: Option<bool>,

    /// Photons per channel and angle for the tables of --incidence-aware, --exit-aware and
    /// --entry-shift (and the surface gather's angle and directional tables)
    #[arg(long, value_parser = parse_count, default_value = "100000")]
    pub incidence_photons: u64,

    /// Light through thin parts: on SSS surfaces facing away from a light, add the light the
    /// material transmits through the part's thickness (read from the light's shadow map), from
    /// `mc` slab simulations of --material at 16 thicknesses (exact when --object-albedo is the
    /// material's total diffuse reflectance) [default: on for the separable method; the
    /// directional dipole and the area gather's splats carry this light themselves]
    #[arg(long, value_parser = on_off())]
    pub translucency: Option<bool>,

    /// Shape-aware shading: entering light × E(κ, θ) of a sphere or cavity of the surface's
    /// curvature (mc), less where the body is thin along the light [default: off; separable only]
    #[arg(long, value_parser = on_off())]
    pub shape: Option<bool>,

    /// Photons per channel and thickness for the table of --translucency on
    #[arg(long, value_parser = parse_count, default_value = "20000")]
    pub translucency_photons: u64,

    /// How SSS surfaces scatter light
    #[arg(long, value_parser = choice::<gpu::Method>(), default_value = "separable")]
    pub method: gpu::Method,

    /// surface-gather: the Monte Carlo BSSRDF integrated
    #[arg(long, value_parser = choice::<shading::Bssrdf>(), default_value = "directional")]
    pub bssrdf: shading::Bssrdf,

    /// directional-dipole, surface-gather: samples per pixel, light and frame
    #[arg(long, default_value_t = 16)]
    pub samples: u32,

    /// directional-dipole, surface-gather: frames accumulated (the image is their mean)
    #[arg(long, default_value_t = 16)]
    pub frames: u32,

    /// directional-dipole, surface-gather: seed of the frames' per-pixel random numbers
    /// [default: --seed, or 1]; another seed gives an independent image from the same tables
    #[arg(long)]
    pub frame_seed: Option<u32>,

    /// directional-dipole, surface-gather: radius r* [cm] of the disc of lit points around each
    /// pixel [default: the dipole ln(1000)/σtr of the material's slowest-decaying channel; the
    /// surface gather the Monte Carlo profile's extent]
    #[arg(long)]
    pub dipole_radius: Option<f32>,

    /// directional-dipole: its energy, as published (overestimates total reflectance, e.g.
    /// Skin1's by 1.5–2.5× at its η = 1.3, 1.6–2.3× at η = 1, R to B) or rescaled per channel to
    /// the Monte Carlo profile's total Rd
    #[arg(long, value_parser = choice::<render::DipoleEnergy>(), default_value = "monte-carlo")]
    pub dipole_energy: render::DipoleEnergy,

    /// directional-dipole, surface-gather: side of each light's position/normal map [texels]
    #[arg(long, default_value_t = 1024)]
    pub light_map: u32,

    /// surface-gather: an edge-aware denoiser over the frames' mean, of world widths half the
    /// profile's median exit radius per channel [cm], for few samples a frame [default: off]
    #[arg(long, value_parser = on_off())]
    pub denoise: Option<bool>,

    /// area-gather: half-width n [px] of the inner block of (2n+1)² taps at full resolution
    #[arg(long, default_value_t = 2)]
    pub gather_inner: u32,

    /// area-gather: layers of 16 taps around the inner block, each 5/3 times wider than the
    /// previous (10 reach ≈ 413 px); 0 with a large --gather-inner is the brute-force 2D gather
    #[arg(long, default_value_t = 10)]
    pub gather_layers: u32,

    /// area-gather: weight the taps of layer i by √i, as the paper's §6.1 does for curved
    /// geometry (it adds up to 40 % of light on a flat, evenly lit surface)
    #[arg(long)]
    pub gather_brighten: bool,

    /// area-gather: read each splat (the light entering where the camera does not see, one per
    /// triangle) at the point their eq. 9 moves towards the pixel instead of at the triangle's
    /// centre (it counts the kernel's peak once per nearby triangle: 1.5× under a thin slab)
    #[arg(long)]
    pub splat_clamp: bool,

    /// Plain Lambertian shading: no scattering at all (a baseline); SSS surfaces still mirror
    /// area lights with the material's η, as a Lambertian surface under a clear coat would
    #[arg(long, conflicts_with_all = ["kernel", "compare_models", "bench"])]
    pub no_sss: bool,

    /// Render every kernel model and compare with the CPU 2D ground-truth convolution
    #[arg(long)]
    pub compare_models: bool,

    /// Time instead of rendering, at --width × --height on a renderer built once: `frame` (the
    /// surface gather's only) this command's frame [ms]; `all` (the default) with the separable
    /// method 11/17/25/33 taps × rank 1 (pre-integration), 2, 3 (SVD) × full and half resolution
    /// × exact and fast path with this command's other settings, and what skipping pixels
    /// without SSS and sub-pixel kernels saves (with --json: {"configs": […], "skips": {…}})
    #[arg(long, value_name = "WHAT", num_args = 0..=1, default_missing_value = "all",
          value_parser = ["all", "frame"])]
    pub bench: Option<String>,

    #[command(flatten)]
    pub source: ProfileSource,

    /// Output folder: render.png, render.pfm, render.json (the summary); with --compare-models
    /// MODEL.png, compare_sheet.png and compare.json; and the profiles simulated here, unless
    /// --profiles names another folder. Checked first (writable, no other scene's render in it),
    /// written once the whole run has succeeded
    #[arg(long, value_name = "DIR", default_value = "out/render")]
    pub out: PathBuf,

    /// Replace a render of another scene or material in --out
    #[arg(long)]
    pub overwrite: bool,

    /// Print a machine-readable summary on stdout
    #[arg(long)]
    pub json: bool,
}

/// The request's fields whose flag is not `--` and the field's name with dashes (those are
/// found among the flags), so that a refusal names the flag.
const FLAGS: [(&str, &str); 10] = [
    ("tolerance_cm", "--tolerance"),
    ("fov_deg", "--fov"),
    ("lights", "--light"),
    ("materials", "--material"),
    ("fast_blur", "--blur fast"),
    ("camera", "--camera/--target"),
    ("incidence", "--incidence-aware"),
    ("exit", "--exit-aware"),
    ("gather_pattern", "--gather-inner/--gather-layers"),
    ("disc radius", "--dipole-radius"),
];

/// The request the flags describe.
pub fn request(a: &RenderArgs, materials: Vec<render::NamedMaterial>) -> Result<Request> {
    let config = library::config(a.source.config.as_deref())?;
    let kernel = match &a.kernel {
        Some(path) => {
            let text = crate::files::read_text(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            Some(ShaderKernel::from_toml(&text, &path.display().to_string())?)
        }
        None => None,
    };
    Ok(Request {
        frame: gpu::RenderRequest {
            scene: a.scene.clone(),
            width: a.width,
            height: a.height,
            taps: a.taps,
            error_target: a.error_target,
            jitter: a.jitter,
            sss_width: a.sss_width,
            exposure: a.exposure,
            tolerance_cm: a.tolerance,
            method: a.method,
            materials: materials.len(),
            fast_blur: a.blur == "fast",
            lights: a.lights.clone(),
            camera: a.camera,
            target: a.target,
            fov_deg: a.fov,
            object_albedo: a.object_albedo.clone(),
            floor_albedo: a.floor_albedo,
            boxes: a.boxes.clone(),
            specular: a.specular,
            ambient: a.ambient,
        },
        materials,
        kernel,
        albedo: a.albedo,
        depth_test: a.depth_test,
        half_res: a.resolution == "half",
        shading: render::ShadingOptions {
            incidence: a.incidence_aware,
            exit: a.exit_aware,
            entry_shift: a.entry_shift,
            translucency: a.translucency,
            shape: a.shape,
        },
        tables: render::TableSettings {
            seed: a.source.seed_in(&config),
            config,
            incidence_photons: a.incidence_photons,
            translucency_photons: a.translucency_photons,
        },
        gather: render::GatherOptions {
            bssrdf: a.bssrdf,
            samples: a.samples,
            frames: a.frames,
            frame_seed: a.frame_seed,
            radius_cm: a.dipole_radius,
            dipole_energy: a.dipole_energy,
            light_map: a.light_map,
            denoise: a.denoise.unwrap_or(false),
            inner: a.gather_inner,
            layers: a.gather_layers,
            brighten: a.gather_brighten,
            splat_clamp: a.splat_clamp,
        },
        no_sss: a.no_sss,
    })
}

/// A library refusal with the request's field replaced by the flag that set it.
pub fn flagged(e: RenderError) -> anyhow::Error {
    let flag = |field: &str| match FLAGS.iter().find(|(f, _)| *f == field) {
        Some((_, flag)) => Some(flag.to_string()),
        None => {
            let long = field.replace('_', "-");
            let command = RenderArgs::augment_args(clap::Command::new("render"));
            let known = command.get_arguments().any(|a| a.get_long() == Some(&long));
            known.then(|| format!("--{long}"))
        }
    };
    match e.renamed(flag) {
        RenderError::Invalid {
            field,
            value,
            reason,
        } => anyhow::anyhow!("invalid {field} {value}: {reason}"),
        e => e.into(),
    }
}
