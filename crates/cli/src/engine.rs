//! Kernels where engines and artists use them: `sss kernel` (material → the best shader snippet
//! for a budget) and `sss engine-params` (material → Unreal, Unity, Blender or OpenPBR fields),
//! and `--from-artist` (an artist's colour and radius → a material).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use fit::engine::{Engine, materialx};
use fit::engine_report::EngineReport;
use fit::export::{OffsetUnit, ShaderFormat, export};
use fit::select::{Budget, Judge, Scored};
use serde_json::json;

use crate::cache::ProfileSource;
use crate::files::{Outputs, out_file};
use crate::library::{self, Named};

/// The material: a built-in name, a material file, or an artist's colour and radius.
#[derive(Args)]
pub struct MaterialArg {
    /// Material (built-in name or material .toml path; a file may give `color` and `radius`
    /// instead of `sigma_a` and `sigma_s`)
    #[arg(value_name = "MATERIAL", required_unless_present = "from_artist")]
    material: Option<String>,

    /// An artist's material instead: color=R,G,B (multiple-scattering albedo in [0, 1]) and
    /// radius=R,G,B[:cm|mm] (mean free path 1/σt, default cm), optionally g=G (default 0) and
    /// eta=N (default 1.3); inverted to σa, σs by van de Hulst's fit (as OpenPBR and pbrt do)
    #[arg(long, num_args = 2..=4, value_name = "KEY=VALUE", conflicts_with = "material")]
    from_artist: Option<Vec<String>>,
}

impl MaterialArg {
    pub fn resolve(&self) -> Result<Named> {
        match (&self.material, &self.from_artist) {
            (Some(m), _) => library::material(m),
            (None, Some(kv)) => {
                let (slug, material) = mc::Material::from_artist(kv)?;
                eprintln!(
                    "artist material: σa = {:.4?} cm⁻¹, σs = {:.4?} cm⁻¹ (van de Hulst inversion)",
                    material.sigma_a, material.sigma_s
                );
                Ok(Named { slug, material })
            }
            (None, None) => bail!("give a MATERIAL or --from-artist"),
        }
    }
}

#[derive(Args)]
pub struct KernelArgs {
    #[command(flatten)]
    material: MaterialArg,

    /// Output: hlsl, glsl, wgsl or json (SSSS layout, see `sss export`)
    #[arg(long)]
    format: ShaderFormat,

    /// Renderer budget PASSESxTAPS: 1D convolution passes (2 per separable term) × taps per pass
    #[arg(long, default_value = "2x17")]
    budget: Budget,

    /// Unit of the exported tap offsets: cm or mm
    #[arg(long, default_value = "cm")]
    unit: OffsetUnit,

    #[command(flatten)]
    source: ProfileSource,

    /// Output file for the snippet, or a folder to write NAME.FORMAT into [default: standard
    /// output]
    #[arg(long, value_name = "FILE|DIR")]
    out: Option<PathBuf>,

    /// Print the choice and every candidate's error as JSON on stdout (needs --out)
    #[arg(long)]
    json: bool,
}

pub fn kernel(a: KernelArgs) -> Result<()> {
    if a.json && a.out.is_none() {
        bail!("--json prints the summary on stdout: give --out FILE for the snippet");
    }
    let named = a.material.resolve()?;
    let mut files = Outputs::default();
    let p = a.source.profile(&named, &mut files)?;
    let judge = Judge::new(&p);
    let ranked = judge.rank(a.budget, &named.slug)?;
    eprintln!(
        "models within {} (1D passes × taps), image RMS on the test signals (images in [0, 1]):",
        a.budget
    );
    ranked.iter().for_each(|s| eprintln!("{}", s.line()));
    let best = &ranked[0];
    eprintln!(
        "chose {} for {}: mean image RMS {:.2e} ({} 1D passes × {} taps)",
        best.model,
        named.slug,
        best.error(),
        2 * best.kernel.pass.len(),
        best.kernel.taps
    );
    let snippet = export(&best.kernel, a.format, a.unit);
    let out = a
        .out
        .as_ref()
        .map(|o| out_file(o, &format!("{}.{}", named.slug, a.format)));
    if let Some(path) = &out {
        files.add(path, snippet.as_bytes());
    }
    files.commit()?;
    if out.is_none() {
        crate::common::print_raw(&snippet)?;
    }
    if a.json {
        let rows: Vec<_> = ranked.iter().map(Scored::json).collect();
        crate::common::print_json(
            &json!({"material": named.slug, "budget": a.budget.to_string(), "format": a.format.to_string(), "chosen": best.model.to_string(), "out": out, "candidates": rows}),
        )?;
    }
    Ok(())
}

#[derive(Args)]
pub struct EngineParamsArgs {
    #[command(flatten)]
    material: MaterialArg,

    /// Engine: unreal (Subsurface Profile, Burley), unity (HDRP Diffusion Profile), blender
    /// (Principled BSDF: the Christensen-Burley fit, and the Random Walk fields that make
    /// Cycles trace the material's own σa, σs and g, inverting the random walk of Blender 4.0–5.0),
    /// openpbr (OpenPBR Surface / MaterialX)
    #[arg(long)]
    engine: Engine,

    /// Budget of the separable kernel the engine's profile is compared with (PASSESxTAPS)
    #[arg(long, default_value = "2x17")]
    budget: Budget,

    #[command(flatten)]
    source: ProfileSource,

    /// openpbr: also write the material as a MaterialX document: a .mtlx file, or a folder to
    /// write NAME.mtlx into
    #[arg(long, value_name = "FILE|DIR")]
    mtlx: Option<PathBuf>,

    /// Print the parameters, the fit and its errors as JSON on stdout
    #[arg(long)]
    json: bool,
}

pub fn engine_params(a: EngineParamsArgs) -> Result<()> {
    if a.mtlx.is_some() && a.engine != Engine::OpenPbr {
        bail!(
            "invalid --mtlx for --engine {}: MaterialX is written for openpbr",
            a.engine
        );
    }
    let named = a.material.resolve()?;
    let mut files = Outputs::default();
    let p = a.source.profile(&named, &mut files)?;
    let r = EngineReport::new(&p, &named.material, &named.slug, a.engine, a.budget)?;
    let mtlx = a
        .mtlx
        .as_ref()
        .map(|o| out_file(o, &format!("{}.mtlx", named.slug)));
    if let Some(path) = &mtlx {
        files.add(path, materialx(&r.params, &named.slug));
    }
    files.commit()?;
    let mut text = r.text();
    if let Some(path) = &mtlx {
        text += &format!("wrote {}\n", path.display());
    }
    if a.json {
        eprint!("{text}");
        let mut v = serde_json::to_value(&r)?;
        v["mtlx"] = json!(mtlx);
        crate::common::print_json(&v)?;
    } else {
        print!("{text}");
    }
    Ok(())
}
