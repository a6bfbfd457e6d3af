//! `sss eval`: every kernel model against the ground truth of each material, in kernel space and
//! image space, as a table or JSON, with optional comparison plots.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use fit::evaluate::{Row, evaluate};
use fit::pareto::{Pareto, Point};
use fit::signals::Signal;
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
    let mut out = Outputs::default();
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
            print_table(&n.slug, &ev.rows);
            print_pareto(&n.slug, &pareto);
        }
        materials.push(json!({
            "name": n.slug,
            "models": ev.rows.iter().map(Row::json).collect::<Vec<_>>(),
            "pareto": pareto,
        }));
    }
    out.commit()?;
    if let Some(dir) = &a.plots {
        eprintln!("plots → {}", dir.display());
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({ "materials": materials }))?
        );
    }
    Ok(())
}

fn print_table(slug: &str, rows: &[Row]) {
    println!("{slug}: kernel-space RMS (raw / L1-normalized), image RMS (edge, shaded), fit time");
    println!(
        "  {:<24} {:>3} {:>11} {:>11} {:>9} {:>10} {:>10} {:>8}",
        "model", "ch", "kernel", "kernel(N)", "L1 err", "edge", "shaded", "fit [s]"
    );
    for r in rows {
        let img = |s: Signal| {
            r.image_rms
                .iter()
                .find(|(x, _)| *x == s)
                .map(|(_, e)| *e)
                .unwrap_or(f64::NAN)
        };
        println!(
            "  {:<24} {:>3} {:>11.3e} {:>11.3e} {:>9.2e} {:>10.3e} {:>10.3e} {:>8.3}",
            r.label(),
            ["R", "G", "B"][r.channel],
            r.kernel_rms,
            r.kernel_rms_normalized,
            r.l1_error,
            img(Signal::Edge),
            img(Signal::Shaded),
            r.fit_seconds
        );
    }
}

/// The Pareto front of GPU cost against mean image RMS and the best separable model per pass
/// budget; dense kernels on a line of their own.
fn print_pareto(slug: &str, p: &Pareto) {
    let t = p.taps_per_pass;
    println!(
        "{slug}: Pareto front of GPU cost (T = {t} taps per 1D pass) against image RMS (mean over \
         signals and channels; worst channel)"
    );
    println!(
        "  {:<24} {:>6} {:>8} {:>10} {:>10}",
        "model", "passes", "taps/px", "mean RMS", "worst ch."
    );
    for q in &p.front {
        println!(
            "  {:<24} {:>6} {:>8} {:>10.3e} {:>10.3e}",
            q.label, q.cost.passes, q.cost.taps, q.mean_image_rms, q.worst_channel_rms
        );
    }
    let error = |q: &Point| {
        format!(
            "mean image RMS {:.3e}, worst channel {:.3e}",
            q.mean_image_rms, q.worst_channel_rms
        )
    };
    for r in &p.recommended {
        match &r.best {
            Some(q) => println!(
                "  recommended for {} passes: {} ({} passes, {} taps/px; {})",
                r.budget,
                q.label,
                q.cost.passes,
                q.cost.taps,
                error(q)
            ),
            None => println!("  recommended for {} passes: none fits", r.budget),
        }
    }
    for q in &p.dense {
        println!(
            "  dense: {} (1 pass of {t}×{t} = {} taps/px; {})",
            q.label,
            q.cost.taps,
            error(q)
        );
    }
}
