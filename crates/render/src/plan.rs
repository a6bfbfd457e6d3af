//! A checked request turned into everything a frame is drawn with: the scene, the renderer's
//! settings with each material's shading tables, the kernels or the gather's set-up. Building a
//! plan runs the Monte Carlo tables and fits the kernels; drawing it ([`Plan::render`]) only uses
//! the device.

use fit::taps::{ShaderKernel, TapSpec};
use fit::{KernelModel, Profile};
use gpu::{KernelTaps, Method, RenderParams, Scatter};

use crate::error::{RenderError, Result};
use crate::options::{Choice, DipoleEnergy};
use crate::progress::Progress;
use crate::request::{NamedMaterial, Request};
use crate::tables::MaterialTables;

/// Where a plan gets a material's Monte Carlo profile and tables: simulated, or read from a
/// cache (the caller's; see [`Simulated`] for the plain one).
pub trait Profiles {
    /// The profile of `m`.
    fn profile(&mut self, m: &NamedMaterial) -> Result<Profile>;

    /// The tables of `m` whose make-up is `key` ([`MaterialTables::key`]): kept ones made of
    /// the same, else `build()`'s. By default always built.
    fn tables(
        &mut self,
        m: &NamedMaterial,
        key: &str,
        build: &mut dyn FnMut() -> Result<MaterialTables>,
    ) -> Result<MaterialTables> {
        let _ = (m, key);
        build()
    }
}

/// Profiles simulated at the request's run settings (`config.photons` per channel) and seed,
/// reported to `progress`.
pub struct Simulated<'a> {
    /// Run settings and seed.
    pub tables: &'a crate::TableSettings,
    /// Where the runs are reported.
    pub progress: &'a dyn Progress,
}

impl Profiles for Simulated<'_> {
    fn profile(&mut self, m: &NamedMaterial) -> Result<Profile> {
        let t = self.tables;
        let spec = t
            .config
            .batch(&[&m.material], t.config.photons, t.seed, true)?;
        self.progress.begin(
            &format!("simulating {}", m.slug),
            spec.photons * spec.groups().len() as u64,
        );
        let p = shading::profile::simulate(&spec, &m.slug, &|k| self.progress.advance(k));
        self.progress.end();
        Ok(p?.profile)
    }
}

/// The set-up of a method that replaces the separable kernels.
#[derive(Clone, Debug)]
pub enum Gather {
    /// The directional dipole.
    Dipole(Box<gpu::DipoleSetup>),
    /// Maisch & Ropinski's area gather.
    Area(Box<gpu::AreaGatherSetup>),
    /// The Monte Carlo BSSRDF over the lit surface.
    Surface(Box<gpu::SurfaceGatherSetup>),
}

impl Gather {
    /// The directional dipole's and the area gather's set-ups of `gather` (what `--bench` times).
    pub fn timed(
        gather: &Option<Gather>,
    ) -> (Option<&gpu::DipoleSetup>, Option<&gpu::AreaGatherSetup>) {
        match gather {
            Some(Gather::Dipole(s)) => (Some(s.as_ref()), None),
            Some(Gather::Area(s)) => (None, Some(s.as_ref())),
            _ => (None, None),
        }
    }
}

/// How one kernel was chosen, for the caller to report.
#[derive(Clone, Debug)]
pub enum KernelChoice {
    /// Given by the request.
    Given,
    /// Pre-integration fitted to the material's profile.
    Fitted,
    /// The smallest rank meeting the image-error target: each rank tried with its image RMS,
    /// and whether the last met the target.
    Ladder(Vec<(usize, KernelModel, f64)>, bool),
}

/// A render ready to draw.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The scene with the request's overrides.
    pub scene: gpu::Scene,
    /// The materials, in the scene's order.
    pub materials: Vec<NamedMaterial>,
    /// The renderer's settings, each material's shading tables included.
    pub params: RenderParams,
    /// The separable method's kernels, one per material (empty for the other methods and
    /// without SSS), and how each was chosen.
    pub kernels: Vec<(ShaderKernel, KernelChoice)>,
    /// The kernels as uploaded.
    pub gpu_kernels: Vec<KernelTaps>,
    /// The set-up of a method that replaces the kernels.
    pub gather: Option<Gather>,
    /// The shading options as applied.
    pub shading: crate::ResolvedShading,
    /// Each material's tables.
    pub tables: Vec<MaterialTables>,
    /// What the caller should pass on: where a model is outside its domain, how a model was
    /// rescaled.
    pub notes: Vec<String>,
}

impl Plan {
    /// Checks `request` ([`Request::check`]), builds each material's tables and the method's
    /// kernels or set-up, reading profiles from `profiles` where the method needs them.
    pub fn build(
        request: &Request,
        profiles: &mut dyn Profiles,
        progress: &dyn Progress,
    ) -> Result<Plan> {
        let mut scene = request.check()?;
        let shading = request.resolved_shading();
        let mut notes = Vec::new();
        let gather = gather(request, profiles, progress, &mut notes)?;
        let mut params = params(request);
        let mut tables = Vec::new();
        for (s, m) in params.shading.iter_mut().zip(&request.materials) {
            let key = MaterialTables::key(m, &shading, &request.tables)?;
            let t = profiles.tables(m, &key, &mut || {
                MaterialTables::build(m, &shading, &request.tables, progress)
            })?;
            *s = t.shading(shading.exit, m.material.eta);
            tables.push(t);
        }
        // The curvature the shape tables are read at, per vertex (none without them).
        scene.mesh.bake_shape_curvature(&params.shading)?;
        if let Some(j) = request.frame.jitter {
            params.jitter = j;
        } else if let Some(k) = &request.kernel {
            params.jitter = k.jitter as f32;
        }
        let kernels = kernels(request, profiles)?;
        let gpu_kernels = kernels
            .iter()
            .map(|(k, _)| KernelTaps::from_shader_kernel(k))
            .collect::<std::result::Result<Vec<_>, _>>()?;
        Ok(Plan {
            scene,
            materials: request.materials.clone(),
            params,
            kernels,
            gpu_kernels,
            gather,
            shading,
            tables,
            notes,
        })
    }

    /// How the frame scatters light.
    pub fn scatter(&self) -> Scatter<'_> {
        match &self.gather {
            Some(Gather::Dipole(s)) => Scatter::DirectionalDipole(s),
            Some(Gather::Area(s)) => Scatter::AreaGather(s),
            Some(Gather::Surface(s)) => Scatter::SurfaceGather(s),
            None if self.gpu_kernels.is_empty() => Scatter::None,
            None => Scatter::Separable(&self.gpu_kernels),
        }
    }

    /// Draws the frame on `gpu`.
    pub fn render(&self, gpu: &gpu::Gpu) -> Result<gpu::Frame> {
        Ok(gpu::render(gpu, &self.scene, self.scatter(), &self.params)?)
    }
}

/// The renderer's settings from the request, shading tables not yet filled in.
fn params(r: &Request) -> RenderParams {
    RenderParams {
        width: r.frame.width,
        height: r.frame.height,
        albedo: r.albedo,
        sss_width: r.frame.sss_width,
        depth_mode: r.depth_test,
        tolerance_cm: r.frame.tolerance_cm,
        jitter: 0.0,
        fixed_depth: None,
        exposure: r.frame.exposure,
        skip_empty: true,
        skip_subpixel: true,
        half_res: r.half_res,
        fast: r.frame.fast_blur,
        ..RenderParams::default()
    }
}

/// One kernel per material for the separable method: the request's, or pre-integration (or the
/// smallest rank meeting the image-error target) fitted to each material's profile.
fn kernels(r: &Request, profiles: &mut dyn Profiles) -> Result<Vec<(ShaderKernel, KernelChoice)>> {
    if r.no_sss || r.method() != Method::Separable {
        return Ok(Vec::new());
    }
    if let Some(k) = &r.kernel {
        return Ok(vec![(k.clone(), KernelChoice::Given)]);
    }
    let taps = r.frame.taps;
    r.materials
        .iter()
        .map(|m| {
            let p = profiles.profile(m)?;
            Ok(match r.frame.error_target {
                Some(target) => {
                    let ladder =
                        fit::select::Judge::new(&p).smallest_rank(target, &m.slug, taps)?;
                    let tried = ladder
                        .tried
                        .iter()
                        .map(|(rank, s)| (*rank, s.model, s.error()))
                        .collect();
                    let kernel = ladder.chosen().kernel.clone();
                    (kernel, KernelChoice::Ladder(tried, ladder.met))
                }
                None => {
                    let truths = fit::ground_truths(&p);
                    let fitted = KernelModel::Preint.fit_truths(&truths, &m.slug)?;
                    let spec = TapSpec {
                        taps,
                        ..Default::default()
                    };
                    let k = ShaderKernel::from_fitted(&fitted, &m.slug, spec)?;
                    (k, KernelChoice::Fitted)
                }
            })
        })
        .collect()
}

/// The set-up of the method, if it replaces the kernels.
fn gather(
    r: &Request,
    profiles: &mut dyn Profiles,
    progress: &dyn Progress,
    notes: &mut Vec<String>,
) -> Result<Option<Gather>> {
    let m = &r.materials[0];
    let g = &r.gather;
    let sampling = |s: &mut gpu::Sampling| {
        s.samples = g.samples;
        s.frames = g.frames;
        s.map_size = g.light_map;
        s.denoise = g.denoise;
        s.seed = g.frame_seed.unwrap_or(r.tables.seed as u32);
        if let Some(radius) = g.radius_cm {
            s.radius_cm = radius;
        }
        s.validate()
    };
    let media = fit::analytic::Medium::channels(&m.material);
    Ok(Some(match r.method() {
        Method::Separable => return Ok(None),
        Method::AreaGather => {
            let pattern = gpu::GatherPattern {
                inner: g.inner,
                ring: 5,
                layers: g.layers,
                brighten: g.brighten,
            };
            pattern.validate().map_err(|e| {
                RenderError::invalid("gather_pattern", "inner/layers", e.to_string())
            })?;
            let p = profiles.profile(m)?;
            Gather::Area(Box::new(gpu::AreaGatherSetup {
                kernel: gpu::AreaKernel::for_material(&m.slug, &media, &p)?,
                pattern,
                splat_clamp: g.splat_clamp,
            }))
        }
        Method::DirectionalDipole => {
            let mut setup = gpu::DipoleSetup::new(&media)?;
            sampling(&mut setup.sampling)?;
            setup.validate()?;
            if g.dipole_energy == DipoleEnergy::MonteCarlo {
                let p = profiles.profile(m)?;
                setup = setup.renormalized(&media, [0, 1, 2].map(|c| p.total(c)))?;
                notes.push(format!(
                    "directional dipole rescaled to mc's total Rd: R ×{:.3}, G ×{:.3}, B ×{:.3}",
                    setup.scale[0], setup.scale[1], setup.scale[2]
                ));
            }
            for (c, medium) in media.iter().enumerate() {
                let albedo = medium.albedo_reduced();
                if albedo < 0.5 {
                    notes.push(format!(
                        "warning: {} channel {} has reduced albedo {albedo:.3}: the directional dipole is a high-albedo model and overestimates its reflectance there",
                        m.slug,
                        ["R", "G", "B"][c]
                    ));
                }
            }
            Gather::Dipole(Box::new(setup))
        }
        Method::SurfaceGather => {
            let p = profiles.profile(m)?;
            let spec = r.tables.config.batch(
                &[&m.material],
                r.tables.incidence_photons,
                r.tables.seed,
                true,
            )?;
            let runs = shading::gather_batch_runs(g.bssrdf);
            let total = r.tables.incidence_photons * spec.groups().len() as u64 * runs;
            progress.begin("surface gather tables", total);
            let r_max = gpu::SurfaceGatherSetup::table_radius_cm(&p);
            let tables = shading::gather_tables(&spec, g.bssrdf, r_max, &|k| progress.advance(k));
            progress.end();
            let t = tables?;
            let mut setup = gpu::SurfaceGatherSetup::new(&p, t.angles, t.directional)?;
            setup.shape = t.shape;
            setup.bssrdf = g.bssrdf;
            sampling(&mut setup.sampling)?;
            setup.validate()?;
            Gather::Surface(Box::new(setup))
        }
    }))
}

/// What the plan's method is, for a closing line: the gather with its sampling, the kernel with
/// its passes and taps, or no SSS.
pub fn describe(plan: &Plan) -> String {
    match (&plan.gather, plan.kernels.first()) {
        (Some(Gather::Surface(s)), _) => format!(
            "surface gather of the {} Monte Carlo BSSRDF ({} samples × {} frames per pixel and light, r* = {:.3} cm{})",
            s.bssrdf.name(),
            s.sampling.samples,
            s.sampling.frames,
            s.sampling.radius_cm,
            if s.sampling.denoise {
                let [r, g, b] = s.denoise_widths_cm();
                format!(", denoised at σ = {r:.3} / {g:.3} / {b:.3} cm")
            } else {
                String::new()
            }
        ),
        (Some(Gather::Area(s)), _) => format!(
            "area gather ({} taps reaching {:.0} px{})",
            s.pattern.taps().len(),
            s.pattern.reach_px(),
            if s.pattern.brighten {
                ", √i brightening"
            } else {
                ""
            }
        ),
        (Some(Gather::Dipole(d)), _) => format!(
            "directional dipole ({} samples × {} frames per pixel and light, r* = {:.3} cm)",
            d.sampling.samples, d.sampling.frames, d.sampling.radius_cm
        ),
        (None, Some((k, _))) => format!(
            "{} kernel ({} pass(es) × {} taps{}){}",
            k.model,
            k.pass.len(),
            k.taps,
            shading_of(&plan.shading),
            if plan.kernels.len() > 1 {
                format!(
                    " per material ({})",
                    plan.tables
                        .iter()
                        .map(|t| t.slug.as_str())
                        .collect::<Vec<_>>()
                        .join(",")
                )
            } else {
                String::new()
            }
        ),
        (None, None) => "no SSS".to_string(),
    }
}

/// The shading tables a separable render applies, for [`describe`]: "" when none.
fn shading_of(s: &crate::ResolvedShading) -> String {
    let mut parts = Vec::new();
    if s.incidence {
        parts.push("ρ(θ)/ρ(0)");
    }
    match s.exit {
        crate::ExitLaw::Entry => parts.push("h(θ_o; θ_i) at the entry angle"),
        crate::ExitLaw::Normal => parts.push("h(θ_o) of normal entry"),
        crate::ExitLaw::Lambertian => {}
    }
    if s.entry_shift {
        parts.push("entry shift δ(θ)");
    }
    if s.translucency {
        parts.push("translucency");
    }
    if s.shape {
        parts.push("shape E(κ, θ)");
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!("; {}", parts.join(", "))
    }
}
