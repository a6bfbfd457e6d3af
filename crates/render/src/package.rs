//! The shading model of one material as a package an engine loads without our code: the kernel's
//! taps per pass, every table with its grid, units and standard errors, the bytes a renderer
//! uploads, and the lookups in WGSL, GLSL and HLSL — the functions our scene pass runs
//! (`shading::LOOKUPS_WGSL`, translated by naga) — with a README that says which pass each
//! belongs in. [`Package::build`] plans the material as `sss render` would (the request's
//! method must be the separable one); [`Package::files`] gives the files' names and bytes, for the
//! caller to write.

use fit::export::{OffsetUnit, ShaderFormat, export};
use fit::taps::ShaderKernel;
use shading::{INCIDENCE_STEPS, PACKED_SHADING_SIZE, PackedShading, ShaderSources, Shading};

use crate::error::{RenderError, Result};
use crate::options::ExitLaw;
use crate::plan::{Plan, Profiles};
use crate::progress::Progress;
use crate::request::{Request, ResolvedShading};
use crate::tables::MaterialTables;

/// The version of the package's layout, written into `tables.json`.
pub const PACKAGE_FORMAT: &str = "sss-package-1";

/// One material's shading model, ready to be written as files.
#[derive(Clone, Debug)]
pub struct Package {
    /// The material's short name.
    pub slug: String,
    /// The separable kernel (pre-integration fitted to the material, or the request's).
    pub kernel: ShaderKernel,
    /// Its tables as simulated, with their standard errors.
    pub tables: MaterialTables,
    /// The shading options they were built for.
    pub shading: ResolvedShading,
    /// What the renderer reads (the exit law applied, the boundary's η): `tables.bin`.
    pub rendered: Shading,
    /// The tables' provenance ([`MaterialTables::key`]): what they were simulated from.
    pub provenance: serde_json::Value,
    /// The lookups in the three languages.
    pub shaders: ShaderSources,
    /// What the caller should pass on (from the plan: a channel that does not scatter, …).
    pub notes: Vec<String>,
}

impl Package {
    /// Plans `request` (one SSS material, the separable method) and keeps what an engine needs;
    /// profiles and tables come from `profiles` (a cache, or simulated), reported to `progress`.
    /// A package carries the shape table unless the request turns it off (`shading.shape`
    /// `Some(false)`): whether the scene pass reads it is the engine's choice.
    pub fn build(
        request: &Request,
        profiles: &mut dyn Profiles,
        progress: &dyn Progress,
    ) -> Result<Package> {
        if request.materials.len() != 1 {
            return Err(RenderError::invalid(
                "materials",
                request.materials.len(),
                "a package holds one material",
            ));
        }
        if request.no_sss || request.method() != gpu::Method::Separable {
            return Err(RenderError::invalid(
                "method",
                format!("{:?}", request.method()),
                "a package holds the separable method's kernel and tables",
            ));
        }
        let mut request = request.clone();
        request.shading.shape = request.shading.shape.or(Some(true));
        let plan = Plan::build(&request, profiles, progress)?;
        Package::from_plan(&request, &plan)
    }

    /// The package of a plan already built for `request` (checked as [`Package::build`] does).
    pub fn from_plan(request: &Request, plan: &Plan) -> Result<Package> {
        if plan.materials.len() != 1 || plan.kernels.is_empty() {
            return Err(RenderError::invalid(
                "method",
                format!("{:?}", request.method()),
                "a package holds one material's separable kernel and tables",
            ));
        }
        let m = &plan.materials[0];
        let key = MaterialTables::key(m, &plan.shading, &request.tables)?;
        let mut notes = plan.notes.clone();
        let dark: Vec<&str> = (0..3)
            .filter(|&c| m.material.sigma_s[c] == 0.0)
            .map(|c| ["R", "G", "B"][c])
            .collect();
        if !dark.is_empty() {
            notes.push(format!(
                "{}: channel(s) {} do not scatter (σs = 0): no scattered light there. Their kernel \
                 is the identity (weights summing to 1 on the taps nearest the centre) and their tables \
                 neutral (ρ(θ)/ρ(0) = h = 1, δ = 0, Tt/ρ = 0): the albedo, which is the total \
                 diffuse reflectance ρ = 0 there, makes them black.",
                m.slug,
                dark.join(", ")
            ));
        }
        Ok(Package {
            slug: m.slug.clone(),
            kernel: plan.kernels[0].0.clone(),
            tables: plan.tables[0].clone(),
            shading: plan.shading,
            rendered: plan.params.shading[0],
            provenance: serde_json::from_str(&key).expect("a tables key is JSON"),
            shaders: ShaderSources::new()?,
            notes,
        })
    }

    /// The package's files, names relative to its folder: `README.md`, `tables.json`,
    /// `tables.bin`, `kernel.{json,wgsl,glsl,hlsl}` and `sss_lookups.{wgsl,glsl,hlsl}`.
    pub fn files(&self) -> Vec<(String, Vec<u8>)> {
        let packed = PackedShading::new(&self.rendered);
        let mut files = vec![
            ("README.md".to_string(), self.readme().into_bytes()),
            ("tables.json".to_string(), self.tables_json().into_bytes()),
            (
                "tables.bin".to_string(),
                bytemuck::bytes_of(&packed).to_vec(),
            ),
        ];
        for f in ShaderFormat::ALL {
            files.push((
                format!("kernel.{f}"),
                export(&self.kernel, f, OffsetUnit::Cm).into_bytes(),
            ));
        }
        for (ext, src) in [
            ("wgsl", &self.shaders.wgsl),
            ("glsl", &self.shaders.glsl),
            ("hlsl", &self.shaders.hlsl),
        ] {
            files.push((format!("sss_lookups.{ext}"), src.clone().into_bytes()));
        }
        files
    }

    /// `tables.json`: every table with its standard errors, grids and units, what `tables.bin`
    /// holds, and the provenance.
    pub fn tables_json(&self) -> String {
        let t = &self.tables;
        let angles: Vec<u32> = (0..INCIDENCE_STEPS as u32).map(|k| 10 * k).collect();
        let rgb = |v: [f32; 3]| serde_json::json!(v);
        let json = serde_json::json!({
            "format": PACKAGE_FORMAT,
            "material": self.slug,
            "eta": self.rendered.eta,
            "units": {
                "length": "cm",
                "angle": "degrees, from the surface normal",
                "incidence": "ρ(θ)/ρ(0) [-]",
                "exit": "h(θ_o; θ_i): radiance over a Lambertian surface's of the same total reflectance [-]",
                "entry_shift": "δ(θ) [cm]",
                "translucency": "Tt(d)/ρ [-]; exit h_T(θ_o; d) [-]",
                "shape": "E(κ, θ) [-] (a curved body's returned light within 8/σ_tr of its entry over a half-space's), shift ⟨x⟩ and width ⟨s⟩ [cm]; κ = curvature/σ_tr, σ_tr [cm⁻¹]",
            },
            "grids": {
                "angle_deg": angles,
                "thickness_cm": t.translucency.map(|(tr, _)| {
                    (0..shading::TRANSLUCENCY_STEPS).map(|k| tr.thickness_cm(k)).collect::<Vec<_>>()
                }),
            },
            "options": {
                "incidence": self.shading.incidence,
                "exit": match self.shading.exit {
                    ExitLaw::Entry => "entry: h(θ_o; θ_i) at the entry angle",
                    ExitLaw::Normal => "normal: every row the normal-entry one",
                    ExitLaw::Lambertian => "lambertian: all ones",
                },
                "entry_shift": self.shading.entry_shift,
                "translucency": self.shading.translucency,
                "shape": self.shading.shape,
            },
            "incidence": {
                "value": t.angles.incidence.map(rgb),
                "se": t.angles.incidence_se.map(rgb),
                "index": "[θ_i][channel]",
            },
            "exit": {
                "value": t.angles.exit,
                "se": t.angles.exit_se,
                "index": "[θ_i][θ_o][channel]",
            },
            "entry_shift": t.entry_shift.map(|s| serde_json::json!({
                "value_cm": s.shift_cm,
                "se_cm": s.shift_se_cm,
                "index": "[θ_i][channel]",
            })),
            "translucency": t.translucency.map(|(tr, rho)| serde_json::json!({
                "first_cm": tr.first_cm,
                "ratio": tr.ratio,
                "tt_over_rho": tr.table,
                "exit": tr.exit,
                "rho": rho.map(|r| serde_json::json!({"value": r.value, "se": r.se})),
                "index": "tt_over_rho[d][channel], exit[d][θ_o][channel]",
            })),
            "shape": t.shape.map(|s| serde_json::json!({
                "sigma_tr_per_cm": s.sigma_tr,
                "curvature_nodes": shading::SHAPE_CURVATURES,
                "thickness_nodes": shading::SHAPE_THICKNESSES,
                "curvature": s.curvature,
                "thickness": s.thickness,
                "index": "curvature[κ node][θ_i][channel], thickness[τ node][θ_i][channel]: {energy, shift_cm, width_cm} each {value, se}",
            })),
            "tables_bin": {
                "layout": format!("SssMaterial of sss_lookups.wgsl: {} vec4<f32>, little-endian", shading::PACKED_SHADING_VEC4),
                "bytes": PACKED_SHADING_SIZE,
                "as_rendered": self.rendered,
            },
            "kernel": "kernel.json",
            "provenance": self.provenance,
            "notes": self.notes,
        });
        serde_json::to_string_pretty(&json).expect("the tables serialize")
    }

    /// The package's README: what each file and function is, where it belongs in a frame, what
    /// it reads.
    pub fn readme(&self) -> String {
        let k = &self.kernel;
        let on = |b: bool| if b { "on" } else { "off" };
        let notes = if self.notes.is_empty() {
            String::new()
        } else {
            format!(
                "\n## Notes\n\n{}\n",
                self.notes
                    .iter()
                    .map(|n| format!("- {n}"))
                    .collect::<Vec<_>>()
                    .join("\n")
            )
        };
        format!(
            include_str!("package_readme.md"),
            slug = self.slug,
            eta = self.rendered.eta,
            model = k.model,
            taps = k.taps,
            passes = k.pass.len(),
            range = k.range,
            incidence = on(self.shading.incidence),
            exit = match self.shading.exit {
                ExitLaw::Entry => "at the entry angle",
                ExitLaw::Normal => "the normal-entry row",
                ExitLaw::Lambertian => "off (all ones)",
            },
            shift = on(self.shading.entry_shift),
            translucency = on(self.shading.translucency),
            shape = on(self.shading.shape),
            bytes = PACKED_SHADING_SIZE,
            vec4 = shading::PACKED_SHADING_VEC4,
            notes = notes,
        )
    }
}
