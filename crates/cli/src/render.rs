//! `sss render`: the kernels applied in wgpu screen-space passes on a scene, written as PNG (and
//! linear PFM); `--compare-models` renders every kernel model beside the CPU 2D ground-truth
//! convolution; `--bench` times the SSS passes.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use fit::taps::ShaderKernel;
use fit::{KernelModel, Profile};
use glam::Vec3;
use gpu::{
    AlbedoMode, DepthMode, DipoleSetup, Gpu, GpuKernel, Light, RenderParams, Scatter, Scene,
};
use serde_json::{Value, json};
use shading::Shading;

use crate::cache::ProfileSource;
use crate::files::Outputs;
use crate::fit::{build_kernel, plain};
use crate::library;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

/// Which exit law exit-angle-aware shading applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ExitAware {
    /// h(θ_o) of light that entered along the normal, at every pixel
    On,
    /// h(θ_o; θ_i) at the entry angle of the pixel's lights
    Entry,
    /// Lambertian exit
    Off,
}

/// A profile-only batch of `named` for the tables of the shading: the profiles' run settings
/// (`--config`) and seed, `photons` per channel.
fn table_spec(
    named: &library::Named,
    photons: u64,
    source: &ProfileSource,
) -> Result<mc::BatchSpec> {
    let config = library::config(source.config.as_deref())?;
    Ok(config.batch(&[&named.material], photons, source.seed_in(&config), true)?)
}

/// The material's angle tables (`shading::AngleTables::from_mc`, printed on stderr): the incidence
/// table if `incidence`, the exit table if `exit`, `photons` per channel and angle, with the
/// profiles' seed and run settings (`source`).
fn angle_tables(
    named: &library::Named,
    photons: u64,
    source: &ProfileSource,
    incidence: bool,
    exit: bool,
) -> Result<shading::AngleTables> {
    let angles = shading::AngleTables::angles(incidence, exit).len() as u64;
    if angles == 0 {
        return Ok(shading::AngleTables::ONES);
    }
    let spec = table_spec(named, photons, source)?;
    let bar = crate::common::photons(
        photons * spec.groups().len() as u64 * angles,
        "angle tables",
    );
    let t = shading::AngleTables::from_mc(&spec, incidence, exit, &|k| bar.inc(k))
        .with_context(|| format!("--incidence-aware/--exit-aware: {}", named.slug))?;
    bar.finish_and_clear();
    let rgb = |v: [f32; 3]| format!("{:.3} {:.3} {:.3}", v[0], v[1], v[2]);
    if incidence {
        eprintln!("incidence table of {} (ρ(θ)/ρ(0), R G B):", named.slug);
        for (k, row) in t.incidence.iter().enumerate() {
            eprintln!("  {:>4}°  {}", 10 * k, rgb(*row));
        }
    }
    if exit {
        eprintln!(
            "exit table of {} (h(θ_o; θ_i): radiance over a Lambertian surface's, R G B, ± SE; \
             entering at 0°, 40° and 80° of the 0°…80° it holds):",
            named.slug
        );
        for k in 0..shading::INCIDENCE_STEPS {
            let row = |i: usize| format!("{}  ± {}", rgb(t.exit[i][k]), rgb(t.exit_se[i][k]));
            eprintln!("  {:>4}°  {}  |  {}  |  {}", 10 * k, row(0), row(4), row(8));
        }
    }
    Ok(t)
}

/// The material's entry shift (`shading::EntryShift::from_mc`, printed on stderr): the centroid of
/// the light a half-space returns at each incidence table angle, `photons` per channel and angle,
/// with the profiles' seed and run settings.
fn entry_shift_table(
    named: &library::Named,
    photons: u64,
    source: &ProfileSource,
) -> Result<shading::EntryShift> {
    let spec = table_spec(named, photons, source)?;
    let bar = crate::common::photons(
        photons * spec.groups().len() as u64 * shading::INCIDENCE_STEPS as u64,
        "entry shift",
    );
    let t = shading::EntryShift::from_mc(&spec, &|k| bar.inc(k))
        .with_context(|| format!("--entry-shift: {}", named.slug))?;
    bar.finish_and_clear();
    eprintln!(
        "entry shift of {} (centroid of the returned light ahead of the entry, δ(θ) [mm], R G B ± SE):",
        named.slug
    );
    for k in 0..shading::INCIDENCE_STEPS {
        let mm = |v: [f32; 3]| format!("{:.3} {:.3} {:.3}", 10.0 * v[0], 10.0 * v[1], 10.0 * v[2]);
        eprintln!(
            "  {:>4}°  {}  ± {}",
            10 * k,
            mm(t.shift_cm[k]),
            mm(t.shift_se_cm[k])
        );
    }
    Ok(t)
}

/// The material's translucency table (`shading::Translucency::from_mc`, printed on stderr), `photons`
/// per channel and thickness, with the profiles' seed and run settings; ρ from a half-space run
/// of `shading::RHO_PHOTONS` (`Translucency::rho_of`), not from a whole profile.
fn translucency_table(
    named: &library::Named,
    photons: u64,
    source: &ProfileSource,
) -> Result<shading::Translucency> {
    let spec = table_spec(named, photons, source)?;
    let context = || format!("--translucency: {}", named.slug);
    let bar = crate::common::photons(
        (shading::RHO_PHOTONS + photons * shading::TRANSLUCENCY_STEPS as u64)
            * spec.groups().len() as u64,
        "translucency table",
    );
    let rho = shading::Translucency::rho_of(&spec, &|k| bar.inc(k)).with_context(context)?;
    let t = shading::Translucency::from_mc(&spec, rho.map(|r| r.value), &|k| bar.inc(k))
        .with_context(context)?;
    bar.finish_and_clear();
    eprintln!(
        "translucency table of {} (slab Tt(d) / ρ; ρ = {:.3} {:.3} {:.3} ± {:.3} {:.3} {:.3}):",
        named.slug, rho[0].value, rho[1].value, rho[2].value, rho[0].se, rho[1].se, rho[2].se
    );
    for (k, row) in t.table.iter().enumerate() {
        let d = t.thickness_cm(k);
        eprintln!("  {d:>8.4} cm  {:.4} {:.4} {:.4}", row[0], row[1], row[2]);
    }
    Ok(t)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// A separable screen-space kernel (thesis §4.2–4.4): --kernel, or pre-integration fitted here
    Separable,
    /// The directional dipole (Frisvad et al. 2014) integrated per pixel over lit surface points
    /// found through light-space position maps, progressive over --frames (draft §4.2–4.3);
    /// colours come from the material's coefficients, ambient light is not scattered
    DirectionalDipole,
    /// Maisch & Ropinski 2020 for long mean free paths (milk, marble, jade): the material's Monte
    /// Carlo profile averaged over discs, R′(r, A) (512×512), gathered per pixel over their
    /// layered sampling pattern from a pyramid of the irradiance (--gather-inner, --gather-layers)
    AreaGather,
    /// The material's own Monte Carlo BSSRDF integrated per pixel over lit surface points as the
    /// directional dipole is (--bssrdf radial: the MC profile at the 3-D distance with the
    /// incidence and exit tables; directional: mc's Rd(x, y; θ) at oblique incidence): the
    /// reference a real-time method is measured against on the same geometry and visibility;
    /// progressive over --frames, ambient light is not scattered
    SurfaceGather,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BssrdfArg {
    /// Rd(|x_o − x_i|) of the Monte Carlo profile × ρ(θ_i)/ρ(0), leaving with h(θ_o; θ_i): the
    /// best any radial-profile method can reach
    Radial,
    /// mc's Rd(x, y; θ_i) at 0°, 10°, …, 80°, 85° (385 × 193 cells per channel and angle, reaching
    /// ln(10⁸)/σtr), laid on the modified tangent plane (Frisvad et al. 2014: through x_i,
    /// holding x_o) with the entry angle's total reflectance, leaving with h(θ_o; θ_i)
    Directional,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DipoleEnergy {
    /// Frisvad et al.'s model unchanged
    Published,
    /// Each channel scaled so its total diffuse reflectance equals `mc`'s (the profile of
    /// --material, simulated or read from --profiles)
    MonteCarlo,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Albedo {
    /// Albedo applied before scattering (blurs texture detail)
    Pre,
    /// Albedo applied after scattering (keeps texture detail sharp)
    Post,
    /// √albedo before and after (SSSS's default)
    PrePost,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BlurPath {
    /// Storage buffers, two f32 reads per tap
    Exact,
    /// One bilinearly filtered rgba16float fetch per tap
    Fast,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Resolution {
    /// The image's resolution
    Full,
    /// Half in each direction
    Half,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DepthTest {
    /// Lerp towards the centre sample as the depth difference grows (thesis eq. 4.12)
    Lerp,
    /// Reject samples across depth discontinuities and renormalize per channel
    Reject,
    /// No depth test (light bleeds across silhouettes)
    None,
    /// Weight each sample by e^{−Δz²/(2τ)} (SSSS supplement §E), τ = --tolerance² or the
    /// kernel's largest variance, renormalized per channel (a soft reject)
    Gaussian,
}

#[derive(Args)]
pub struct RenderArgs {
    /// Scene: sphere (sphere on a floor), fin (sphere with two thin fins), pair (two spheres side
    /// by side, two SSS materials) or a Wavefront .obj path
    #[arg(long, default_value = "sphere")]
    scene: String,

    /// Material whose profile the default kernel (and --compare-models) is fitted to; for a scene
    /// of several SSS materials one per material, separated by commas (pair: left,right, e.g.
    /// skin1,marble). A material's kernel takes no light from another material's pixels
    #[arg(long, default_value = "skin1")]
    material: String,

    /// Kernel file from `sss fit` [default: pre-integration with --taps taps fitted to the material]
    #[arg(long, value_name = "KERNEL.toml")]
    kernel: Option<PathBuf>,

    /// Taps per 1D pass for kernels fitted here
    #[arg(long, default_value_t = 17)]
    taps: usize,

    /// Image-error target: per material, the smallest rank (1: pre-integration, 2–6: SVD rescaled
    /// to the kernel's energy) whose image RMS on `fit`'s test signals against the 2D ground
    /// truth (images in [0, 1], mean over R, G, B) is at most this; higher ranks are not run
    /// [default: pre-integration]
    #[arg(long, value_name = "RMS", conflicts_with = "kernel")]
    error_target: Option<f64>,

    /// Image width [px]
    #[arg(long, default_value_t = 1920)]
    width: u32,

    /// Image height [px]
    #[arg(long, default_value_t = 1080)]
    height: u32,

    /// Where the albedo is applied relative to the scattering
    #[arg(long, value_enum, default_value_t = Albedo::PrePost)]
    albedo: Albedo,

    /// Depth-discontinuity handling
    #[arg(long, value_enum, default_value_t = DepthTest::Lerp)]
    depth_test: DepthTest,

    /// Depth difference [cm] at which a sample is fully replaced/rejected [default: the kernel's range]
    #[arg(long)]
    tolerance: Option<f32>,

    /// Fraction of taps jittered per pixel, 0–1 (SSSS supplement Fig. S.6–S.7: each picked tap
    /// samples a random position within its cell; trades banding for noise) [default: the
    /// kernel file's jitter, else 0]
    #[arg(long)]
    jitter: Option<f32>,

    /// Resolution of the separable passes: full, or half (2×2 blocks averaged, blurred, then
    /// brought back by a depth- and material-aware bilinear upsampling; a quarter of the work)
    #[arg(long, value_enum, default_value_t = Resolution::Full)]
    resolution: Resolution,

    /// How the separable passes read their samples: exact (two f32 reads per tap, several
    /// materials) or fast (one filtered fetch per tap from an rgba16float texture of light and
    /// depth, as SSSS; one material; 0.1 % from exact on the sphere)
    #[arg(long, value_enum, default_value_t = BlurPath::Exact)]
    blur: BlurPath,

    /// Kernel width multiplier (1 = the material's physical scale)
    #[arg(long, default_value_t = 1.0)]
    sss_width: f32,

    /// Exposure before tone mapping
    #[arg(long, default_value_t = 1.0)]
    exposure: f32,

    /// Camera position X,Y,Z [cm]
    #[arg(long, value_parser = parse_vec3)]
    camera: Option<Vec3>,

    /// Camera target X,Y,Z [cm]
    #[arg(long, value_parser = parse_vec3)]
    target: Option<Vec3>,

    /// Vertical field of view [degrees]
    #[arg(long)]
    fov: Option<f32>,

    /// Lights (repeatable): dir:X,Y,Z[:IRRADIANCE] (towards the light; default 1.2),
    /// point:X,Y,Z[:INTENSITY] (position [cm], intensity = irradiance × cm²; default 1200) or
    /// area:X,Y,Z:AX,AY,AZ:SIDE[:RADIANCE] (a square of SIDE [cm] centred at X,Y,Z facing the
    /// point AX,AY,AZ, in Mitsuba's look_at frame with +y up; radiance default 5, a surface
    /// facing a large one gets π × it). All cast shadows. An area light is drawn as 64 point
    /// lights (its 8×8 cells), at most 64 in all; SSS surfaces reflect it in mirror with the
    /// Fresnel reflectance of the material's η
    #[arg(long = "light", value_parser = parse_light)]
    lights: Vec<Light>,

    /// Diffuse albedo R,G,B of the SSS objects (e.g. the material's total diffuse reflectance);
    /// given once for every material, or once per material in --material's order
    #[arg(long, value_parser = parse_vec3)]
    object_albedo: Vec<Vec3>,

    /// Diffuse albedo R,G,B of the floor
    #[arg(long, value_parser = parse_vec3)]
    floor_albedo: Option<Vec3>,

    /// Blinn–Phong specular intensity (0: none)
    #[arg(long)]
    specular: Option<f32>,

    /// Constant ambient irradiance (0: none)
    #[arg(long)]
    ambient: Option<f32>,

    /// Add a black, non-scattering box (an occluder that casts hard shadows), repeatable:
    /// MIN_X,MIN_Y,MIN_Z:MAX_X,MAX_Y,MAX_Z [cm]
    #[arg(long = "box", value_parser = parse_box)]
    boxes: Vec<(Vec3, Vec3)>,

    /// Incidence-aware shading: scale each light's irradiance on SSS surfaces by the material's
    /// total diffuse reflectance at that incidence angle relative to normal incidence,
    /// ρ(θ)/ρ(0) per channel, from `mc` at θ = 0°, 10°, …, 80° (Fresnel entry included)
    #[arg(long, value_enum, default_value = "off")]
    incidence_aware: OnOff,

    /// Exit-angle-aware shading: multiply the scattered light of SSS pixels by the material's
    /// reflected radiance at the pixel's view angle relative to a Lambertian surface's,
    /// h(θ_o; θ_i) = π·Rd_a(θ_o)/(Rd·cos θ_o) per channel, from `mc` at each entry angle
    /// θ_i = 0°, 10°, …, 80° in 10° exit bins: `on` reads the row of light that entered along
    /// the normal, `entry` the row at the entry angle of the pixel's lights (weighted by the
    /// irradiance each brings); its cosine-weighted mean is 1: it moves light between view
    /// angles, it adds none
    #[arg(long, value_enum, default_value = "off")]
    exit_aware: ExitAware,

    /// Entry-shifted shading: light entering a half-space at θ leaves, on average, δ(θ) ahead of
    /// its entry along its propagation over the surface (mc's centroid at θ = 0°, 10°, …, 80°,
    /// about 0.6 transport mean free paths at grazing entry); each SSS pixel is shaded with the
    /// light that entered δ behind it (that point's shadow, and its normal from the surface's
    /// curvature) before the kernel spreads it
    #[arg(long, value_enum, default_value = "off")]
    entry_shift: OnOff,

    /// Photons per channel and angle for the tables of --incidence-aware, --exit-aware and
    /// --entry-shift (and the surface gather's angle and directional tables)
    #[arg(long, value_parser = crate::common::parse_count, default_value = "100000")]
    incidence_photons: u64,

    /// Light through thin parts: on SSS surfaces facing away from a light, add the light the
    /// material transmits through the part's thickness (read from the light's shadow map), from
    /// `mc` slab simulations of --material at 16 thicknesses (exact when --object-albedo is the
    /// material's total diffuse reflectance) [default: on for the separable method; the
    /// directional dipole and the area gather's splats carry this light themselves]
    #[arg(long, value_enum)]
    translucency: Option<OnOff>,

    /// Photons per channel and thickness for the table of --translucency on
    #[arg(long, value_parser = crate::common::parse_count, default_value = "20000")]
    translucency_photons: u64,

    /// How SSS surfaces scatter light
    #[arg(long, value_enum, default_value_t = Method::Separable)]
    method: Method,

    /// surface-gather: the Monte Carlo BSSRDF integrated
    #[arg(long, value_enum, default_value_t = BssrdfArg::Directional)]
    bssrdf: BssrdfArg,

    /// directional-dipole, surface-gather: samples per pixel, light and frame
    #[arg(long, default_value_t = 16)]
    samples: u32,

    /// directional-dipole, surface-gather: frames accumulated (the image is their mean)
    #[arg(long, default_value_t = 16)]
    frames: u32,

    /// directional-dipole, surface-gather: seed of the frames' per-pixel random numbers
    /// [default: --seed, or 1]; another seed gives an independent image from the same tables
    #[arg(long)]
    frame_seed: Option<u32>,

    /// directional-dipole, surface-gather: radius r* [cm] of the disc of lit points around each
    /// pixel [default: the dipole ln(1000)/σtr of the material's slowest-decaying channel; the
    /// surface gather the Monte Carlo profile's extent]
    #[arg(long)]
    dipole_radius: Option<f32>,

    /// directional-dipole: its energy, as published (overestimates total reflectance, e.g.
    /// Skin1's by 1.5–2.5× at its η = 1.3, 1.6–2.3× at η = 1, R to B) or rescaled per channel to
    /// the Monte Carlo profile's total Rd
    #[arg(long, value_enum, default_value_t = DipoleEnergy::MonteCarlo)]
    dipole_energy: DipoleEnergy,

    /// directional-dipole, surface-gather: side of each light's position/normal map [texels]
    #[arg(long, default_value_t = 1024)]
    light_map: u32,

    /// area-gather: half-width n [px] of the inner block of (2n+1)² taps at full resolution
    #[arg(long, default_value_t = 2)]
    gather_inner: u32,

    /// area-gather: layers of 16 taps around the inner block, each 5/3 times wider than the
    /// previous (10 reach ≈ 413 px); 0 with a large --gather-inner is the brute-force 2D gather
    #[arg(long, default_value_t = 10)]
    gather_layers: u32,

    /// area-gather: weight the taps of layer i by √i, as the paper's §6.1 does for curved
    /// geometry (it adds up to 40 % of light on a flat, evenly lit surface)
    #[arg(long)]
    gather_brighten: bool,

    /// area-gather: read each splat (the light entering where the camera does not see, one per
    /// triangle) at the point their eq. 9 moves towards the pixel instead of at the triangle's
    /// centre (it counts the kernel's peak once per nearby triangle: 1.5× under a thin slab)
    #[arg(long)]
    splat_clamp: bool,

    /// Plain Lambertian shading: no scattering at all (a baseline); SSS surfaces still mirror
    /// area lights with the material's η, as a Lambertian surface under a clear coat would
    #[arg(long, conflicts_with_all = ["kernel", "compare_models", "bench"])]
    no_sss: bool,

    /// Render every kernel model and compare with the CPU 2D ground-truth convolution
    #[arg(long)]
    compare_models: bool,

    /// Time the SSS passes at --width × --height instead of rendering, on a renderer built once,
    /// with this command's other settings (depth test, jitter, shading tables): 11/17/25/33 taps ×
    /// rank 1 (pre-integration), 2, 3 (SVD) × full and half resolution × exact and fast path,
    /// and what skipping pixels without SSS and sub-pixel kernels saves (with --json:
    /// {"configs": […], "skips": {…}} only)
    #[arg(long)]
    bench: bool,

    #[command(flatten)]
    source: ProfileSource,

    /// Output folder: render.png, render.pfm; with --compare-models MODEL.png, compare_sheet.png
    /// and compare.json; and the profiles simulated here, unless --profiles names another folder.
    /// Written once the whole run has succeeded
    #[arg(long, value_name = "DIR", default_value = "out/render")]
    out: PathBuf,

    /// Print a machine-readable summary on stdout
    #[arg(long)]
    json: bool,
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f32>()
                .map_err(|_| format!("{s:?}: expected X,Y,Z"))
        })
        .collect::<Result<_, _>>()?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("{s:?}: expected three finite numbers X,Y,Z")),
    }
}

fn parse_box(s: &str) -> Result<(Vec3, Vec3), String> {
    let (a, b) = s.split_once(':').ok_or(format!(
        "{s:?}: expected MIN_X,MIN_Y,MIN_Z:MAX_X,MAX_Y,MAX_Z"
    ))?;
    let (lo, hi) = (parse_vec3(a)?, parse_vec3(b)?);
    if lo.cmplt(hi).all() {
        Ok((lo, hi))
    } else {
        Err(format!("{s:?}: every MIN must be below its MAX"))
    }
}

fn parse_light(s: &str) -> Result<Light, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let number = |t: &str, what: &str| -> Result<f32, String> {
        let v: f32 = t
            .parse()
            .map_err(|_| format!("{s:?}: {what} {t:?} is not a number"))?;
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(format!("{s:?}: {what} must be finite and ≥ 0"))
        }
    };
    match parts[..] {
        ["area", at, aim, side, ref rest @ ..] if rest.len() <= 1 => {
            let radiance = match rest.first() {
                Some(t) => number(t, "radiance")?,
                None => 5.0,
            };
            let side = number(side, "side")?;
            Light::square(
                parse_vec3(at)?,
                parse_vec3(aim)?,
                side,
                Vec3::splat(radiance),
                true,
            )
            .map_err(|e| format!("{s:?}: {e}"))
        }
        [kind @ ("dir" | "point"), v, ref rest @ ..] if rest.len() <= 1 => {
            let v = parse_vec3(v)?;
            let i = match rest.first() {
                Some(t) => number(t, "intensity")?,
                None if kind == "dir" => 1.2,
                None => 1200.0,
            };
            if kind == "dir" {
                if v.length() == 0.0 {
                    return Err(format!("{s:?}: the direction must not be zero"));
                }
                Ok(Light::Directional {
                    towards: v.normalize(),
                    irradiance: Vec3::splat(i),
                    shadow: true,
                })
            } else {
                Ok(Light::Point {
                    position: v,
                    intensity: Vec3::splat(i),
                    shadow: true,
                })
            }
        }
        _ => Err(format!(
            "{s:?}: expected dir:X,Y,Z[:I], point:X,Y,Z[:I] or area:X,Y,Z:AX,AY,AZ:SIDE[:L]"
        )),
    }
}

/// The kernels compared by --compare-models: (label, model). SVD is rescaled to the kernel's
/// energy (‖A‖₁ = ‖R_d‖₁) for images, as `eval` does.
const MODELS: [(&str, KernelModel); 8] = [
    ("preint", KernelModel::Preint),
    (
        "svd1",
        KernelModel::Svd {
            rank: 1,
            renormalize: true,
        },
    ),
    (
        "svd3",
        KernelModel::Svd {
            rank: 3,
            renormalize: true,
        },
    ),
    ("deon3", KernelModel::Deon { n: 3 }),
    ("guided", KernelModel::Guided { k: 1.0, b: 0.0 }),
    ("manual", KernelModel::Manual(fit::ManualParams::Auto)),
    (
        "skin",
        KernelModel::Skin(fit::SkinParams::Given(fit::skin::Skin::DEMO)),
    ),
    ("burley", KernelModel::Burley { radial: false }),
];

fn kernel_of(p: &Profile, slug: &str, model: KernelModel, taps: usize) -> Result<ShaderKernel> {
    let spec = fit::taps::TapSpec {
        taps,
        ..Default::default()
    };
    Ok(build_kernel(p, &plain(model), slug, spec)?.0)
}

/// The kernel of the smallest rank (1: pre-integration, 2–6: SVD, renormalized) whose image RMS
/// meets `target` (see `--error-target`), else rank 6 with a warning; prints each rank tried.
fn kernel_for_target(p: &Profile, slug: &str, taps: usize, target: f64) -> Result<ShaderKernel> {
    let ladder = fit::select::Judge::new(p).smallest_rank(target, slug, taps)?;
    for (i, (rank, scored)) in ladder.tried.iter().enumerate() {
        let chosen = ladder.met && i + 1 == ladder.tried.len();
        eprintln!(
            "{slug}: rank {rank} ({}, {taps} taps) image RMS {:.5}{}",
            scored.model,
            scored.error(),
            if chosen { " ≤ target: chosen" } else { "" }
        );
    }
    if !ladder.met {
        eprintln!(
            "warning: {slug}: no rank up to {} meets --error-target {target}: using rank {}",
            fit::select::MAX_RANK,
            fit::select::MAX_RANK
        );
    }
    Ok(ladder.chosen().kernel.clone())
}

/// The request's fields by the flags that set them, so that a refusal names the flag.
const FLAGS: [(&str, &str); 19] = [
    ("width", "--width"),
    ("height", "--height"),
    ("taps", "--taps"),
    ("error_target", "--error-target"),
    ("jitter", "--jitter"),
    ("sss_width", "--sss-width"),
    ("exposure", "--exposure"),
    ("tolerance_cm", "--tolerance"),
    ("specular", "--specular"),
    ("ambient", "--ambient"),
    ("fov_deg", "--fov"),
    ("object_albedo", "--object-albedo"),
    ("floor_albedo", "--floor-albedo"),
    ("lights", "--light"),
    ("materials", "--material"),
    ("fast_blur", "--blur fast"),
    ("method", "--method"),
    ("camera", "--camera/--target"),
    ("scene", "--scene"),
];

/// A `gpu` refusal with the request's field replaced by the flag that set it.
fn flagged(e: gpu::GpuError) -> anyhow::Error {
    match e {
        gpu::GpuError::Invalid {
            field,
            value,
            reason,
        } => {
            let flag = FLAGS
                .iter()
                .find(|(f, _)| *f == field)
                .map_or(field.as_str(), |(_, flag)| flag);
            anyhow::anyhow!("invalid {flag} {value}: {reason}")
        }
        e => e.into(),
    }
}

/// The render the flags ask for, as `gpu` checks it.
fn request(a: &RenderArgs, materials: usize) -> gpu::RenderRequest {
    gpu::RenderRequest {
        scene: a.scene.clone(),
        width: a.width,
        height: a.height,
        taps: a.taps,
        error_target: a.error_target,
        jitter: a.jitter,
        sss_width: a.sss_width,
        exposure: a.exposure,
        tolerance_cm: a.tolerance,
        method: match a.method {
            Method::Separable => gpu::Method::Separable,
            Method::DirectionalDipole => gpu::Method::DirectionalDipole,
            Method::AreaGather => gpu::Method::AreaGather,
            Method::SurfaceGather => gpu::Method::SurfaceGather,
        },
        materials,
        fast_blur: a.blur == BlurPath::Fast,
        lights: a.lights.clone(),
        camera: a.camera,
        target: a.target,
        fov_deg: a.fov,
        object_albedo: a.object_albedo.clone(),
        floor_albedo: a.floor_albedo,
        boxes: a.boxes.clone(),
        specular: a.specular,
        ambient: a.ambient,
    }
}

/// The set-up of a method that replaces the separable kernels, if one is asked for.
enum Gather {
    Dipole(Box<gpu::DipoleSetup>),
    Area(Box<gpu::AreaGatherSetup>),
    Surface(Box<gpu::SurfaceGatherSetup>),
}

impl Gather {
    fn of(named: &library::Named, a: &RenderArgs, files: &mut Outputs) -> Result<Option<Gather>> {
        Ok(match a.method {
            Method::Separable => None,
            Method::DirectionalDipole => {
                Some(Gather::Dipole(Box::new(dipole_setup(named, a, files)?)))
            }
            Method::AreaGather => Some(Gather::Area(Box::new(area_setup(named, a, files)?))),
            Method::SurfaceGather => {
                Some(Gather::Surface(Box::new(surface_setup(named, a, files)?)))
            }
        })
    }

    fn scatter(&self) -> Scatter<'_> {
        match self {
            Gather::Dipole(s) => Scatter::DirectionalDipole(s),
            Gather::Area(s) => Scatter::AreaGather(s),
            Gather::Surface(s) => Scatter::SurfaceGather(s),
        }
    }

    /// What the method is, for the closing line.
    fn describe(&self) -> String {
        match self {
            Gather::Surface(s) => format!(
                "surface gather of the {} Monte Carlo BSSRDF ({} samples × {} frames per pixel and light, r* = {:.3} cm)",
                bssrdf_name(s.bssrdf),
                s.sampling.samples,
                s.sampling.frames,
                s.sampling.radius_cm
            ),
            Gather::Area(s) => format!(
                "area gather ({} taps reaching {:.0} px{})",
                s.pattern.taps().len(),
                s.pattern.reach_px(),
                if s.pattern.brighten {
                    ", √i brightening"
                } else {
                    ""
                }
            ),
            Gather::Dipole(d) => format!(
                "directional dipole ({} samples × {} frames per pixel and light, r* = {:.3} cm)",
                d.sampling.samples, d.sampling.frames, d.sampling.radius_cm
            ),
        }
    }

    /// The method's settings for the JSON summary.
    fn json(&self) -> Value {
        match self {
            Gather::Area(s) => {
                json!({"area_gather": {"inner": s.pattern.inner, "layers": s.pattern.layers, "taps": s.pattern.taps().len(), "reach_px": s.pattern.reach_px(), "brighten": s.pattern.brighten, "r_max_cm": s.kernel.r_max_cm(), "table": gpu::area_gather::AREA_TABLE_SIZE}})
            }
            Gather::Surface(s) => {
                json!({"surface_gather": {"bssrdf": bssrdf_name(s.bssrdf), "samples": s.sampling.samples, "frames": s.sampling.frames, "radius_cm": s.sampling.radius_cm, "light_map": s.sampling.map_size, "seed": s.sampling.seed}})
            }
            Gather::Dipole(d) => {
                json!({"dipole": {"samples": d.sampling.samples, "frames": d.sampling.frames, "radius_cm": d.sampling.radius_cm, "light_map": d.sampling.map_size, "scale": d.scale}})
            }
        }
    }
}

fn bssrdf_name(b: shading::Bssrdf) -> &'static str {
    match b {
        shading::Bssrdf::Radial => "radial",
        shading::Bssrdf::Directional => "directional",
    }
}

/// The renderer's settings: image, albedo, depth test, blur path and each material's shading
/// tables (incidence and exit tables, translucency, η).
fn params(
    a: &RenderArgs,
    all_named: &[library::Named],
    kernel_file: Option<&ShaderKernel>,
) -> Result<RenderParams> {
    let mut shading = [Shading::default(); gpu::MAX_MATERIALS];
    for (s, n) in shading.iter_mut().zip(all_named) {
        let tables = angle_tables(
            n,
            a.incidence_photons,
            &a.source,
            a.incidence_aware == OnOff::On && !a.no_sss,
            a.exit_aware != ExitAware::Off && !a.no_sss,
        )?;
        let translucency = match a.translucency.unwrap_or(OnOff::On) {
            OnOff::On if a.method == Method::Separable && !a.no_sss => {
                Some(translucency_table(n, a.translucency_photons, &a.source)?)
            }
            _ => None,
        };
        let entry_shift = if a.entry_shift == OnOff::On && !a.no_sss {
            entry_shift_table(n, a.incidence_photons, &a.source)?
        } else {
            shading::EntryShift::NONE
        };
        *s = Shading {
            incidence: tables.incidence,
            entry_shift,
            // `on`: every row the normal-entry one, whatever angle the light enters at.
            exit: match a.exit_aware {
                ExitAware::Entry => tables.exit,
                _ => [tables.exit[0]; shading::INCIDENCE_STEPS],
            },
            translucency,
            eta: n.material.eta as f32,
        };
    }
    Ok(RenderParams {
        width: a.width,
        height: a.height,
        albedo: match a.albedo {
            Albedo::Pre => AlbedoMode::Pre,
            Albedo::Post => AlbedoMode::Post,
            Albedo::PrePost => AlbedoMode::PrePost,
        },
        sss_width: a.sss_width,
        depth_mode: match a.depth_test {
            DepthTest::Lerp => DepthMode::Lerp,
            DepthTest::Reject => DepthMode::Reject,
            DepthTest::None => DepthMode::None,
            DepthTest::Gaussian => DepthMode::Gaussian,
        },
        tolerance_cm: a.tolerance,
        jitter: a
            .jitter
            .or(kernel_file.map(|k| k.jitter as f32))
            .unwrap_or(0.0),
        fixed_depth: None,
        exposure: a.exposure,
        skip_empty: true,
        skip_subpixel: true,
        half_res: a.resolution == Resolution::Half,
        fast: a.blur == BlurPath::Fast,
        shading,
    })
}

/// One kernel per material for the separable method: --kernel, or pre-integration (or the
/// smallest rank meeting --error-target) fitted to each material's profile.
fn kernels(
    a: &RenderArgs,
    all_named: &[library::Named],
    kernel_file: Option<ShaderKernel>,
    files: &mut Outputs,
) -> Result<Vec<ShaderKernel>> {
    match kernel_file {
        _ if a.no_sss || a.method != Method::Separable => Ok(Vec::new()),
        Some(k) => Ok(vec![k]),
        None => all_named
            .iter()
            .map(|n| {
                let p = a.source.profile(n, files)?;
                match a.error_target {
                    Some(t) => kernel_for_target(&p, &n.slug, a.taps, t),
                    None => kernel_of(&p, &n.slug, KernelModel::Preint, a.taps),
                }
            })
            .collect(),
    }
}

/// A kernel file named by --kernel.
fn read_kernel(path: &std::path::Path) -> Result<ShaderKernel> {
    let text =
        crate::files::read_text(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(ShaderKernel::from_toml(&text, &path.display().to_string())?)
}

/// What scattered the light, for the closing line.
fn describe(gather: Option<&Gather>, kernels: &[ShaderKernel], materials: &str) -> String {
    match (gather, kernels.first()) {
        (Some(g), _) => g.describe(),
        (None, Some(k)) => format!(
            "{} kernel ({} pass(es) × {} taps){}",
            k.model,
            k.pass.len(),
            k.taps,
            if kernels.len() > 1 {
                format!(" per material ({materials})")
            } else {
                String::new()
            }
        ),
        (None, None) => "no SSS".to_string(),
    }
}

/// The JSON summary's settings of the method: the kernels, each gather's (null when not used)
/// and the materials' translucency tables.
fn settings_json(gather: Option<&Gather>, kernels: &[ShaderKernel], shading: &[Shading]) -> Value {
    let mut v = json!({
        "kernel": kernels.first().map(|k| k.model.to_string()),
        "kernels": kernels.iter().map(|k| json!({"model": k.model.to_string(), "passes": k.pass.len(), "taps": k.taps})).collect::<Vec<_>>(),
        "area_gather": null, "surface_gather": null, "dipole": null,
        "translucency": shading.iter().map(|s| s.translucency.as_ref().map(|t| json!({"first_cm": t.first_cm, "ratio": t.ratio, "tt_over_rho": t.table}))).collect::<Vec<_>>(),
    });
    if let (Some(m), Some(Value::Object(g))) = (v.as_object_mut(), gather.map(Gather::json)) {
        m.extend(g);
    }
    v
}

pub fn run(mut a: RenderArgs) -> Result<()> {
    let names: Vec<&str> = a.material.split(',').map(str::trim).collect();
    let scene = request(&a, names.len()).scene().map_err(flagged)?;
    if names.len() > 1 && (a.kernel.is_some() || a.compare_models || a.bench) {
        bail!(
            "--kernel, --compare-models and --bench take a scene of one SSS material (--scene {} has {})",
            a.scene,
            names.len()
        );
    }
    let all_named = names
        .iter()
        .map(|n| library::material(n))
        .collect::<Result<Vec<_>>>()?;
    let named = &all_named[0];
    // Nothing is written outside --out unless --profiles says where.
    a.source.profiles.get_or_insert_with(|| a.out.clone());
    let kernel_file = match &a.kernel {
        Some(path) => Some(read_kernel(path)?),
        None => None,
    };
    let mut files = Outputs::default();
    let gather = Gather::of(named, &a, &mut files)?;
    let gpu = Gpu::new()?;
    eprintln!("GPU: {}", gpu.adapter_name);
    let params = params(&a, &all_named, kernel_file.as_ref())?;
    if a.bench {
        match &gather {
            Some(Gather::Dipole(setup)) => bench_dipole(&gpu, &scene, setup, &named.slug, &a)?,
            _ => {
                let p = a.source.profile(named, &mut files)?;
                let area = match &gather {
                    Some(Gather::Area(s)) => Some(s.as_ref()),
                    _ => None,
                };
                bench(&gpu, &scene, (&p, &named.slug), &params, area, &a)?
            }
        }
        return files.commit();
    }
    let kernels = kernels(&a, &all_named, kernel_file, &mut files)?;
    let gpu_kernels = kernels
        .iter()
        .map(GpuKernel::from_shader_kernel)
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let start = std::time::Instant::now();
    let scatter = match &gather {
        Some(g) => g.scatter(),
        None if gpu_kernels.is_empty() => Scatter::None,
        None => Scatter::Separable(&gpu_kernels),
    };
    let frame = gpu::render(&gpu, &scene, scatter, &params)?;
    let seconds = start.elapsed().as_secs_f64();
    let png_path = a.out.join("render.png");
    files.add(
        &png_path,
        report::image::png_rgba(frame.width, frame.height, &frame.display)?,
    );
    files.add(
        a.out.join("render.pfm"),
        report::image::pfm(frame.width, frame.height, &frame.linear),
    );
    let what = describe(gather.as_ref(), &kernels, &a.material);
    let mut summary = json!({
        "adapter": gpu.adapter_name, "scene": a.scene, "method": a.method.to_possible_value().map(|v| v.get_name().to_string()),
        "materials": all_named.iter().map(|n| &n.slug).collect::<Vec<_>>(), "width": a.width, "height": a.height,
        "seconds": seconds, "png": png_path, "pass_ms": frame.times.iter().map(|t| json!({"pass": t.label, "ms": t.ms})).collect::<Vec<_>>(),
    });
    let settings = settings_json(
        gather.as_ref(),
        &kernels,
        &params.shading[..all_named.len()],
    );
    if let (Some(m), Value::Object(extra)) = (summary.as_object_mut(), settings) {
        m.extend(extra);
    }
    if a.compare_models {
        let p = a.source.profile(named, &mut files)?;
        summary["compare"] = compare(&gpu, &scene, &params, &p, named, &a, &mut files)?;
    }
    files.commit()?;
    eprintln!(
        "{what} on {} at {}×{} in {seconds:.2} s → {}",
        a.scene,
        a.width,
        a.height,
        png_path.display()
    );
    if a.compare_models {
        let sheet = a.out.join("compare_sheet.png");
        eprintln!("comparison sheet → {}", sheet.display());
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    }
    Ok(())
}

/// Every model rendered against the CPU 2D ground truth (`gpu::compare_models`): the table on
/// stdout, each model's PNG, the sheet of cut-outs with difference images, and compare.json.
fn compare(
    gpu: &Gpu,
    scene: &Scene,
    base: &RenderParams,
    p: &Profile,
    named: &library::Named,
    a: &RenderArgs,
    files: &mut Outputs,
) -> Result<serde_json::Value> {
    let slug = &named.slug;
    let scale = gpu::compare::kernel_scale(scene, base.height, p, a.sss_width);
    eprintln!(
        "comparing models at {:.4} cm/px (profile bins of {:.4} cm × {}) …",
        scale.cm_per_px, p.dr, scale.bin
    );
    let models: Vec<KernelModel> = MODELS.iter().map(|(_, m)| *m).collect();
    let spec = fit::taps::TapSpec {
        taps: a.taps,
        ..Default::default()
    };
    let cmp = gpu::compare_models(gpu, scene, base, p, slug, &models, spec)?;
    // With --json the table stays off stdout.
    let table = |line: String| {
        if !a.json {
            println!("{line}");
        }
    };
    table(format!(
        "{slug} on {}: image RMS of the scattered diffuse against the 2D ground truth (SSS pixels, relative to their mean)",
        a.scene
    ));
    table(format!(
        "  {:<11} {:>9} {:>8} {:>8} {:>8}",
        "model", "RGB", "R", "G", "B"
    ));
    let line = |label: &str, e: &gpu::compare::ImageError| {
        let pct = |x: f64| format!("{:.3}%", 100.0 * x);
        format!(
            "  {label:<11} {:>9} {:>8} {:>8} {:>8}",
            pct(e.rms_rel_all),
            pct(e.rms_rel[0]),
            pct(e.rms_rel[1]),
            pct(e.rms_rel[2])
        )
    };
    let l = &cmp.lambert;
    table(line("lambert", &l.error));
    let mut rows = vec![
        json!({"model": "lambert", "image_rms_rel": l.error.rms_rel_all, "image_rms_rel_rgb": l.error.rms_rel}),
    ];
    // The area gather with the paper's pattern, at the pixels' true depths.
    let area = cmp.area_gather(
        gpu,
        scene,
        base,
        &gpu::AreaGatherSetup::new(
            gpu::AreaKernel::for_material(
                slug,
                &fit::analytic::Medium::channels(&named.material),
                p,
            )
            .with_context(|| format!("the area gather of {slug}"))?,
        ),
    )?;
    let labels = MODELS.iter().map(|(l, _)| *l).chain(["area-gather"]);
    let shown: Vec<(&str, &gpu::compare::Shown)> =
        labels.zip(cmp.kernels.iter().chain([&area])).collect();
    for &(label, k) in &shown {
        let e = k.error.rms_rel_all;
        table(line(label, &k.error));
        let png = a.out.join(format!("{label}.png"));
        files.add(
            &png,
            report::image::png_rgba(base.width, base.height, &k.display)?,
        );
        rows.push(json!({"model": label, "image_rms_rel": e, "image_rms_rel_rgb": k.error.rms_rel, "png": png}));
    }
    let sheet = a.out.join("compare_sheet.png");
    let title = vec![
        format!(
            "{slug} on {}: each kernel model against the CPU 2D ground truth (scattered diffuse light)",
            a.scene
        ),
        format!(
            "cut-out of {0}×{0} px around the strongest shadow edge; {1:.4} cm per pixel",
            cmp.crop.side, cmp.scale.cm_per_px
        ),
    ];
    let lambert = [("no SSS (Lambert)", l)];
    let all: Vec<_> = lambert.into_iter().chain(shown).collect();
    files.add(
        &sheet,
        report::sheet::comparison_sheet(&cmp, title, &all, a.exposure)?,
    );
    let v = json!({ "cm_per_px": cmp.scale.cm_per_px, "models": rows, "sheet": sheet });
    files.add(
        a.out.join("compare.json"),
        serde_json::to_string_pretty(&v)?,
    );
    Ok(v)
}

/// The area gather's kernel, from the material's Monte Carlo profile averaged over discs out to
/// r_max, where the source term α′σt′e^{−σt′r} falls to 10⁻⁷ cm⁻¹ (Maisch & Ropinski 2020 §7.1),
/// and the pattern from the flags.
fn area_setup(
    named: &library::Named,
    a: &RenderArgs,
    files: &mut Outputs,
) -> Result<gpu::AreaGatherSetup> {
    if a.kernel.is_some() || a.compare_models || a.no_sss {
        bail!("--method area-gather does not use --kernel, --compare-models or --no-sss");
    }
    if a.translucency == Some(OnOff::On) {
        bail!(
            "--translucency is for the separable method: the area gather's splats carry light through thin parts"
        );
    }
    let pattern = gpu::GatherPattern {
        inner: a.gather_inner,
        ring: 5,
        layers: a.gather_layers,
        brighten: a.gather_brighten,
    };
    pattern
        .validate()
        .context("invalid --gather-inner/--gather-layers")?;
    let p = a.source.profile(named, files)?;
    Ok(gpu::AreaGatherSetup {
        kernel: gpu::AreaKernel::for_material(
            &named.slug,
            &fit::analytic::Medium::channels(&named.material),
            &p,
        )
        .with_context(|| format!("--method area-gather: {}", named.slug))?,
        pattern,
        splat_clamp: a.splat_clamp,
    })
}

/// The directional-dipole settings from the material and the flags; warns where the model is
/// outside its domain.
fn dipole_setup(
    named: &library::Named,
    a: &RenderArgs,
    files: &mut Outputs,
) -> Result<DipoleSetup> {
    if a.kernel.is_some() || a.compare_models || a.no_sss {
        bail!("--method directional-dipole does not use --kernel, --compare-models or --no-sss");
    }
    if a.incidence_aware == OnOff::On
        || a.exit_aware != ExitAware::Off
        || a.entry_shift == OnOff::On
    {
        bail!(
            "--incidence-aware, --exit-aware and --entry-shift are for the separable method: the directional dipole depends on both angles itself"
        );
    }
    if a.translucency == Some(OnOff::On) {
        bail!(
            "--translucency is for the separable method: the directional dipole carries light through thin parts itself"
        );
    }
    let media = fit::analytic::Medium::channels(&named.material);
    let mut setup = DipoleSetup::new(&media)?;
    sampling(&mut setup.sampling, a)?;
    setup
        .validate()
        .context("invalid --samples/--frames/--dipole-radius/--light-map")?;
    if a.dipole_energy == DipoleEnergy::MonteCarlo {
        let p = a.source.profile(named, files)?;
        setup = setup.renormalized(&media, [0, 1, 2].map(|c| p.total(c)))?;
        eprintln!(
            "directional dipole rescaled to mc's total Rd: R ×{:.3}, G ×{:.3}, B ×{:.3}",
            setup.scale[0], setup.scale[1], setup.scale[2]
        );
    }
    for (c, m) in media.iter().enumerate() {
        let albedo = m.albedo_reduced();
        if albedo < 0.5 {
            eprintln!(
                "warning: {} channel {} has reduced albedo {albedo:.3}: the directional dipole is a high-albedo model and overestimates its reflectance there",
                named.slug,
                ["R", "G", "B"][c]
            );
        }
    }
    Ok(setup)
}

/// The disc gathers' sampling flags (--samples, --frames, --light-map, --frame-seed or --seed,
/// --dipole-radius where given) over a method's defaults.
fn sampling(s: &mut gpu::Sampling, a: &RenderArgs) -> Result<()> {
    s.samples = a.samples;
    s.frames = a.frames;
    s.map_size = a.light_map;
    s.seed = match a.frame_seed {
        Some(seed) => seed,
        None => a.source.seed()? as u32,
    };
    if let Some(r) = a.dipole_radius {
        s.radius_cm = r;
    }
    Ok(())
}

/// The surface gather's Monte Carlo tables for the material (`gpu::SurfaceGatherSetup::from_mc`:
/// its profile, the angle tables and, for --bssrdf directional, mc's Rd(x, y; θ) tables at
/// --incidence-photons per channel and angle) and the sampling flags.
fn surface_setup(
    named: &library::Named,
    a: &RenderArgs,
    files: &mut Outputs,
) -> Result<gpu::SurfaceGatherSetup> {
    if a.kernel.is_some() || a.compare_models || a.no_sss || a.bench {
        bail!(
            "--method surface-gather does not use --kernel, --compare-models, --no-sss or --bench"
        );
    }
    if a.incidence_aware == OnOff::On
        || a.exit_aware != ExitAware::Off
        || a.entry_shift == OnOff::On
        || a.translucency == Some(OnOff::On)
    {
        bail!(
            "--incidence-aware, --exit-aware, --entry-shift and --translucency are for the separable method: the surface gather brings the angle tables, the entry direction and the light through thin parts itself"
        );
    }
    let profile = a.source.profile(named, files)?;
    let spec = table_spec(named, a.incidence_photons, &a.source)?;
    let bssrdf = match a.bssrdf {
        BssrdfArg::Radial => shading::Bssrdf::Radial,
        BssrdfArg::Directional => shading::Bssrdf::Directional,
    };
    let bar = crate::common::photons(
        a.incidence_photons * spec.groups().len() as u64 * shading::gather_batch_runs(bssrdf),
        "surface gather tables",
    );
    let context = || format!("--method surface-gather: {}", named.slug);
    let r_max = gpu::SurfaceGatherSetup::table_radius_cm(&profile);
    let (angles, directional) =
        shading::gather_tables(&spec, bssrdf, r_max, &|k| bar.inc(k)).with_context(context)?;
    let mut setup =
        gpu::SurfaceGatherSetup::new(&profile, angles, directional).with_context(context)?;
    bar.finish_and_clear();
    sampling(&mut setup.sampling, a)?;
    setup
        .validate()
        .context("invalid --samples/--frames/--dipole-radius/--light-map")?;
    Ok(setup)
}

/// `--bench` with the directional dipole (`gpu::bench::dipole`): its table (stdout, or stderr
/// with --json) and with --json the rows on stdout.
fn bench_dipole(
    gpu: &Gpu,
    scene: &Scene,
    base: &DipoleSetup,
    slug: &str,
    a: &RenderArgs,
) -> Result<()> {
    let table = |line: String| {
        if a.json {
            eprintln!("{line}")
        } else {
            println!("{line}")
        }
    };
    if !gpu.timestamps {
        eprintln!(
            "this adapter has no timestamp queries: reporting whole-render wall time instead"
        );
    }
    let rows = gpu::bench::dipole(gpu, scene, base)?;
    table(format!(
        "directional dipole at 1920×1080 on {} ({slug}, {} frames per render, median of 3 renders)",
        gpu.adapter_name, base.sampling.frames
    ));
    table(format!(
        "  {:>6} {:>8} {:>18} {:>18}",
        "lights", "samples", "dipole ms/frame", "render wall ms"
    ));
    for r in &rows {
        table(format!(
            "  {:>6} {:>8} {:>18} {:>18.1}",
            r.lights,
            r.samples,
            ms(r.dipole_ms_per_frame),
            r.render_wall_ms
        ));
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({"adapter": gpu.adapter_name, "rows": rows}))?
        );
    }
    Ok(())
}

/// A time [ms] with three decimals, or "-" where there is none.
fn ms(v: Option<f64>) -> String {
    v.map_or("-".to_string(), |v| format!("{v:.3}"))
}

/// `--bench` with the separable passes (`gpu::bench::separable`, at --width × --height): every
/// configuration and what each skip saves, as a table (stdout, or stderr with --json) and with
/// --json as JSON on stdout.
fn bench(
    gpu: &Gpu,
    scene: &Scene,
    (p, slug): (&Profile, &str),
    params: &RenderParams,
    area: Option<&gpu::AreaGatherSetup>,
    a: &RenderArgs,
) -> Result<()> {
    let table = |line: String| {
        if a.json {
            eprintln!("{line}")
        } else {
            println!("{line}")
        }
    };
    if !gpu.timestamps {
        eprintln!("this adapter has no timestamp queries: GPU times are null, frame times remain");
    }
    let cpu_adapter = gpu.adapter_name.contains("Cpu");
    if cpu_adapter {
        eprintln!(
            "{} runs on the CPU: its timestamps do not measure the work; compare the frame-time ratios",
            gpu.adapter_name
        );
    }
    let b = gpu::bench::separable(gpu, scene, (p, slug), params, area)?;
    table(format!(
        "SSS passes at {}×{} on {} ({slug} on {}, renderer built once, median of 5 frames)",
        a.width, a.height, gpu.adapter_name, a.scene
    ));
    table(format!(
        "  {:<12} {:>5} {:>5} {:>10} {:>6} {:>12} {:>10} {:>14}",
        "kernel", "taps", "rank", "resolution", "path", "SSS GPU ms", "frame ms", "÷ preint 17"
    ));
    for c in &b.configs {
        table(format!(
            "  {:<12} {:>5} {:>5} {:>10} {:>6} {:>12} {:>10.1} {:>14.2}",
            c.kernel,
            c.taps,
            c.rank.map_or("-".into(), |r| r.to_string()),
            c.resolution,
            c.path,
            ms(c.gpu_ms),
            c.frame_ms,
            c.frame_ratio_to_preint17
        ));
    }
    let s = &b.skips;
    let (e, f, r) = (&s.empty_pixels, &s.subpixel_kernels, &s.rank_target);
    table("skips (preint, 17 taps; SSS GPU ms on / off, frame ms on / off):".into());
    table(format!(
        "  pixels without SSS ({:.0} % of the image has SSS): {} / {}, {:.1} / {:.1}",
        100.0 * e.sss_pixel_fraction,
        ms(e.saving.gpu_ms_on),
        ms(e.saving.gpu_ms_off),
        e.saving.frame_ms_on,
        e.saving.frame_ms_off
    ));
    table(format!(
        "  sub-pixel kernels (the scene {:.1}× as far, footprint {:.1} → {:.2} px): {} / {}, {:.1} / {:.1}",
        f.distance_factor,
        f.near_footprint_px,
        f.footprint_px,
        ms(f.saving.gpu_ms_on),
        ms(f.saving.gpu_ms_off),
        f.saving.frame_ms_on,
        f.saving.frame_ms_off
    ));
    table(format!(
        "  ranks beyond an image-error target ({:.5}, 1.05 × the best of ranks 1–3): rank {} chosen, frame ms {:.1} / {:.1} (rank 3)",
        r.target_image_rms, r.rank_chosen, r.saving.frame_ms_on, r.saving.frame_ms_off
    ));
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "adapter": gpu.adapter_name, "width": a.width, "height": a.height,
                "scene": a.scene, "material": slug, "timestamps": gpu.timestamps,
                "cpu_adapter": cpu_adapter, "configs": b.configs, "skips": b.skips,
            }))?
        );
    }
    Ok(())
}
