//! `sss area-table`: a kernel averaged over circular areas, R′(r, A), for screen-space lookups
//! (Maisch & Ropinski 2020 §3.2, §7.2), with a plot of the zoom-dependent shift it removes.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use fit::Profile;
use fit::analytic::{Medium, Model, Radial};
use fit::area_table::AreaTable;
use serde_json::json;

use crate::files::Outputs;
use crate::library;

#[derive(Args)]
pub struct AreaTableArgs {
    /// Material (built-in name or material .toml path); sets r_max and the analytic model's inputs
    material: String,

    /// Analytic profile: dipole, better-dipole, directional-dipole, pbd, burley
    #[arg(long, default_value = "pbd", value_parser = |s: &str| Model::parse(s).map_err(|e| e.to_string()))]
    model: Model,

    /// Use this profile CSV (e.g. from `sss simulate`) instead of an analytic model
    #[arg(long, value_name = "CSV", conflicts_with = "model")]
    profile: Option<PathBuf>,

    /// Texels along r and along the disc radius
    #[arg(long, default_value_t = 512)]
    size: usize,

    /// Cut-off of the source term Q(r) = α′σt′e^{−σt′r} [1/cm] that sets r_max
    #[arg(long, default_value_t = 1e-7)]
    q_min: f64,

    /// Output folder: NAME.area.f32, NAME.area.json, NAME.area_effect.png
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
}

/// Rd [1/cm²] at r [cm] of one channel.
type RadialFn = Box<dyn Fn(f64) -> f64 + Sync>;

pub fn run(a: AreaTableArgs) -> Result<()> {
    if !(2..=8192).contains(&a.size) {
        bail!("invalid --size = {}: must lie in 2..=8192", a.size);
    }
    if !(a.q_min.is_finite() && a.q_min > 0.0) {
        bail!("invalid --q-min = {}: must be positive", a.q_min);
    }
    let n = library::material(&a.material)?;
    let media = [0, 1, 2].map(|c| Medium::channel(&n.material, c));
    let r_max = fit::area_table::r_max(&media, a.q_min);
    if r_max <= 0.0 {
        bail!(
            "invalid --q-min = {}: the source term of {} never exceeds it",
            a.q_min,
            n.slug
        );
    }
    let (source, rd): (String, [RadialFn; 3]) = match &a.profile {
        Some(path) => {
            let text = crate::files::read_text(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            let p = std::sync::Arc::new(Profile::from_csv(&text, &path.display().to_string())?);
            let f = |c: usize| -> RadialFn {
                let p = p.clone();
                Box::new(move |r| p.at(c, r))
            };
            (path.display().to_string(), [f(0), f(1), f(2)])
        }
        None => {
            let [r, g, b] = media.each_ref().map(|m| a.model.radial(m));
            let f = |r: Radial| -> RadialFn { Box::new(move |x| r.rd(x.max(1e-12))) };
            (a.model.name().to_string(), [f(r?), f(g?), f(b?)])
        }
    };
    let start = std::time::Instant::now();
    let table = AreaTable::build([&*rd[0], &*rd[1], &*rd[2]], r_max, a.size, a.size);
    let seconds = start.elapsed().as_secs_f64();

    let curves = fit::area_table::zoom_effect(&table, [&*rd[0], &*rd[1], &*rd[2]], &media);

    let table_path = a.out.join(format!("{}.area.f32", n.slug));
    let header_path = a.out.join(format!("{}.area.json", n.slug));
    let mut header = table.header(&n.slug, &source, a.q_min, &curves);
    header["build_seconds"] = json!(seconds);
    let plot = a.out.join(format!("{}.area_effect.png", n.slug));
    let mut files = Outputs::default();
    files.add(&table_path, table.f32_bytes());
    files.add(&header_path, serde_json::to_string_pretty(&header)?);
    files.add(&plot, report::plot::area_effect(&curves, &n.slug)?);
    files.commit()?;
    eprintln!(
        "{}×{} area table of {} ({source}, r_max {r_max:.3} cm) built in {seconds:.2} s → {}, {}, {}",
        a.size,
        a.size,
        n.slug,
        table_path.display(),
        header_path.display(),
        plot.display()
    );
    Ok(())
}
