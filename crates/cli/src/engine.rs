//! Kernels where engines and artists use them: `sss kernel` (material → the best shader snippet
//! for a budget) and `sss engine-params` (material → Unreal, Unity, Blender or OpenPBR fields),
//! and `--from-artist` (an artist's colour and radius → a material).

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use fit::engine::{BurleyProfileFit, Engine, burley_engine, materialx, openpbr, random_walk};
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

fn print_ranking(ranked: &[Scored], budget: Budget) {
    eprintln!(
        "models within {budget} (1D passes × taps), image RMS on the test signals (images in [0, 1]):"
    );
    for s in ranked {
        eprintln!(
            "  {:<34} R {:.2e}  G {:.2e}  B {:.2e}  mean {:.2e}",
            s.model.to_string(),
            s.image_rms[0],
            s.image_rms[1],
            s.image_rms[2],
            s.error()
        );
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
    print_ranking(&ranked, a.budget);
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
        std::io::stdout()
            .write_all(snippet.as_bytes())
            .context("cannot write to standard output")?;
    }
    if a.json {
        let rows: Vec<_> = ranked
            .iter()
            .map(|s| json!({"model": s.model.to_string(), "passes": 2 * s.kernel.pass.len(), "image_rms": s.image_rms, "mean_image_rms": s.error()}))
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(
                &json!({"material": named.slug, "budget": a.budget.to_string(), "format": a.format.to_string(), "chosen": best.model.to_string(), "out": out, "candidates": rows})
            )?
        );
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
    let judge = Judge::new(&p);
    let fit = BurleyProfileFit::new(&p, &judge);
    let best = judge.rank(a.budget, &named.slug)?.swap_remove(0);
    let params = match a.engine {
        Engine::OpenPbr => openpbr(&named.material),
        e => burley_engine(e, &fit).expect("Burley engines map the fit"),
    };
    // Blender's random walk traces the medium itself: its fields come from the coefficients.
    let walk = (a.engine == Engine::Blender).then(|| random_walk(&named.material));
    let mtlx = a
        .mtlx
        .as_ref()
        .map(|o| out_file(o, &format!("{}.mtlx", named.slug)));
    if let Some(path) = &mtlx {
        files.add(path, materialx(&params, &named.slug));
    }
    files.commit()?;
    let ch = mc::CHANNELS;
    let mut text = params.text(&named.slug);
    if let Some(w) = &walk {
        text += &w.text(&named.slug);
    }
    text += &format!(
        "Burley fit to the Monte Carlo profile: albedo {:.4?}, d {:.4e}/{:.4e}/{:.4e} cm\n",
        fit.albedo, fit.d_cm[0], fit.d_cm[1], fit.d_cm[2]
    );
    text += "what the engine's profile costs (images in [0, 1]):\n";
    for (c, ch) in ch.iter().enumerate() {
        text += &format!(
            "  {}: Burley kernel RMS {:.1}% of the MC kernel; image RMS Burley {:.2e}, best separable ({}) {:.2e}\n",
            ch,
            100.0 * fit.kernel_rms_rel[c],
            fit.image_rms[c],
            best.model,
            best.image_rms[c]
        );
    }
    if a.engine == Engine::OpenPbr {
        text += "  (OpenPBR renderers path-trace the medium itself; the Burley line is what a Burley-based real-time approximation of it costs)\n";
    }
    if let Some(path) = &mtlx {
        text += &format!("wrote {}\n", path.display());
    }
    if a.json {
        eprint!("{text}");
        println!(
            "{}",
            serde_json::to_string_pretty(
                &json!({"material": named.slug, "params": params, "random_walk": walk, "burley_fit": fit, "best_separable": {"model": best.model.to_string(), "budget": a.budget.to_string(), "image_rms": best.image_rms}, "mtlx": mtlx})
            )?
        );
    } else {
        print!("{text}");
    }
    Ok(())
}
