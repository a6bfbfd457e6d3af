//! `sss eval`: every kernel model against the ground truth of each material, in kernel space and
//! image space, as a table or JSON, with optional comparison plots.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use fit::evaluate::evaluate;
use fit::pareto::Pareto;
use serde_json::json;

use crate::cache::ProfileSource;
use crate::files::Outputs;
use crate::library;

#[derive(Args)]
pub struct EvalArgs {
    /// Materials (built-in names or material .toml paths)
    #[arg(required = true, value_name = "MATERIAL")]
    materials: Vec<String>,

    #[command(flatten)]
    source: ProfileSource,

    /// Also write comparison plots (PNG) to this folder (with the profiles, once every material
    /// has been evaluated)
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,

    /// Print the measurements as JSON on stdout
    #[arg(long)]
    json: bool,
}

pub fn run(a: EvalArgs) -> Result<()> {
    let named = library::materials(&a.materials)?;
    let pool = crate::common::thread_pool(a.source.threads)?;
    let mut out = Outputs::checked(a.plots.as_ref().unwrap_or(&a.source.folder()))?;
    let mut materials = Vec::new();
    for n in &named {
        let p = a.source.profile(n, &mut out)?;
        eprintln!(
            "fitting and evaluating every model for {} (kernel side {} samples) …",
            n.slug,
            2 * p.len() + 1
        );
        let ev = pool.install(|| evaluate(&p, &n.slug, fit::evaluate::ImageSize::default()))?;
        // Costs at the shaders' taps per pass.
        let pareto = Pareto::of(&ev, fit::taps::TapSpec::default().taps)?;
        if let Some(dir) = &a.plots {
            out.add_in(dir, report::plot::evaluation(&p, &ev, &n.slug)?);
            out.add(
                dir.join(format!("{}.pareto.png", n.slug)),
                report::pareto::plot(&pareto, &n.slug)?,
            );
        }
        if !a.json {
            let table = report::evaluation::table_lines(&n.slug, &ev.rows);
            let front = report::evaluation::pareto_lines(&n.slug, &pareto);
            table.iter().chain(&front).for_each(|l| println!("{l}"));
        }
        materials.push(report::evaluation::json(&n.slug, &ev, &pareto));
    }
    out.commit()?;
    if let Some(dir) = &a.plots {
        eprintln!("plots → {}", dir.display());
    }
    if a.json {
        crate::common::print_json(&json!({ "materials": materials }))?;
    }
    Ok(())
}
