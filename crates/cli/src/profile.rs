//! `sss profile` (an analytic model's Rd(r) as the CSV `simulate` writes) and
//! `sss compare-profiles` (every analytic model against the Monte Carlo profile).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use fit::analytic::Medium;
use fit::profile_compare::compare;
use render::profile_cache::ProfileModel;
use serde_json::json;

use crate::cache::ProfileSource;
use crate::files::{Outputs, out_file};
use crate::library;

#[derive(Args)]
pub struct ProfileArgs {
    /// Material (built-in name or material .toml path)
    material: String,

    /// Analytic model: dipole, better-dipole, directional-dipole, pbd, burley; or `table`, the
    /// Monte Carlo profile interpolated from --table (standard errors: the table's noise and
    /// the interpolation error estimate)
    #[arg(long)]
    model: ProfileModel,

    /// With --model table: a table file, or a folder of *.table.json, from `sss table`
    #[arg(long, value_name = "FILE|DIR")]
    table: Option<PathBuf>,

    /// Output CSV file, or a folder to write NAME.MODEL.profile.csv into
    /// [default: out/NAME.MODEL.profile.csv]
    #[arg(long, value_name = "FILE|DIR")]
    out: Option<PathBuf>,

    /// Run settings TOML for the grid rule [default: the thesis's]
    #[arg(long)]
    config: Option<PathBuf>,
}

/// Writes one analytic profile on the material's thesis grid.
pub fn profile(a: ProfileArgs) -> Result<()> {
    let n = library::material(&a.material)?;
    let config = library::config(a.config.as_deref())?;
    let bars = crate::common::Bars::default();
    let grid = config.grid_for(&n.material)?;
    let csv = (a.model.csv(&n, &config, a.table.as_deref(), &bars))
        .map_err(|e| e.renamed(|f| (f == "table").then(|| "--table".into())))?;
    let name = format!("{}.{}.profile.csv", n.slug, a.model.name());
    let out = match &a.out {
        Some(o) => out_file(o, &name),
        None => crate::common::default_out().join(name),
    };
    let mut files = Outputs::default();
    files.add(&out, csv);
    files.commit()?;
    eprintln!(
        "{} profile of {} ({} bins of {:.4e} cm) → {}",
        a.model.name(),
        n.slug,
        grid.nr,
        grid.dr,
        out.display()
    );
    Ok(())
}

#[derive(Args)]
pub struct CompareArgs {
    /// Materials (built-in names or material .toml paths)
    #[arg(required = true, value_name = "MATERIAL")]
    materials: Vec<String>,

    #[command(flatten)]
    source: ProfileSource,

    /// Output folder for the plots NAME.compare_profiles.png (written once every material has
    /// been compared)
    #[arg(long, value_name = "DIR", default_value = "out/plots")]
    plots: PathBuf,

    /// Print the measurements as JSON on stdout
    #[arg(long)]
    json: bool,
}

/// Tabulates and plots every analytic model against each material's MC profile.
pub fn compare_profiles(a: CompareArgs) -> Result<()> {
    let named = library::materials(&a.materials)?;
    let pool = crate::common::thread_pool(a.source.threads)?;
    let mut files = Outputs::default();
    let mut out = Vec::new();
    for n in &named {
        let mc = a.source.profile(n, &mut files)?;
        let models = pool.install(|| compare(&mc, &n.material))?;
        let mfp = [0, 1, 2].map(|c| Medium::channel(&n.material, c).transport_mfp());
        let plot = a.plots.join(format!("{}.compare_profiles.png", n.slug));
        let labelled: Vec<(&str, &fit::Profile)> = models
            .iter()
            .map(|m| (m.model.name(), &m.profile))
            .collect();
        files.add(
            &plot,
            report::plot::profile_comparison(&mc, &labelled, mfp, &n.slug)?,
        );
        if !a.json {
            report::profile_comparison::lines(&n.slug, &models)
                .iter()
                .for_each(|l| println!("{l}"));
        }
        let plot_name = plot.display().to_string();
        out.push(report::profile_comparison::json(
            &n.slug, &plot_name, &models,
        ));
    }
    files.commit()?;
    eprintln!("plots → {}", a.plots.display());
    if a.json {
        crate::common::print_json(&json!({ "materials": out }))?;
    }
    Ok(())
}
