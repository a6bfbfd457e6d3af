//! `sss eval`: every kernel model against the ground truth of each material, in kernel space and
//! image space, as a table or JSON, with optional comparison plots.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use fit::KernelModel;
use fit::Profile;
use fit::evaluate::{RANK1, Row, evaluate};
use fit::signals::Signal;
use serde_json::{Value, json};

use crate::files::write_atomic;
use crate::library::{self, Named};
use crate::{parse_count, progress, simulate};

#[derive(Args)]
pub struct EvalArgs {
    /// Materials (built-in names or material .toml paths)
    #[arg(required = true, value_name = "MATERIAL")]
    materials: Vec<String>,

    #[command(flatten)]
    source: ProfileSource,

    /// Write comparison plots (PNG) to this folder
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,

    /// Print the measurements as JSON on stdout
    #[arg(long)]
    json: bool,
}

/// Where MC profiles come from: a folder, with missing ones simulated there.
#[derive(Args)]
pub struct ProfileSource {
    /// Folder of profiles NAME.profile.csv; missing ones are simulated and written there
    #[arg(long, default_value = "out")]
    pub profiles: PathBuf,

    /// Photons per channel for profiles simulated on demand [default: the thesis's 1e7]
    #[arg(long, value_parser = parse_count)]
    pub photons: Option<u64>,

    /// Seed for profiles simulated on demand
    #[arg(long, default_value_t = 1)]
    pub seed: u64,

    /// Worker threads [default: all cores]
    #[arg(long)]
    pub threads: Option<usize>,
}

impl ProfileSource {
    /// The profile of a material, on a pool of the requested threads.
    pub fn profile(&self, n: &Named) -> Result<Profile> {
        simulate::thread_pool(self.threads)?
            .install(|| profile_for(n, &self.profiles, self.photons, self.seed))
    }
}

/// The profile of a material: read from `dir`, or simulated (profile-only batch run) and saved.
pub fn profile_for(n: &Named, dir: &Path, photons: Option<u64>, seed: u64) -> Result<Profile> {
    let path = dir.join(format!("{}.profile.csv", n.slug));
    if !path.exists() {
        let config = library::config(None)?;
        let photons = photons.unwrap_or(config.photons);
        let spec = simulate::batch_spec(std::slice::from_ref(n), &config, photons, seed, true)?;
        let bar = progress::photons(
            photons * spec.groups().len() as u64,
            &format!("simulating {}", n.slug),
        );
        let out = mc::run_batch(&spec, &|k| bar.inc(k))?;
        bar.finish_and_clear();
        write_atomic(
            &path,
            simulate::profile_csv(&out.iter().collect::<Vec<_>>()).as_bytes(),
        )?;
        eprintln!(
            "simulated {} ({photons} photons/channel) → {}",
            n.slug,
            path.display()
        );
    } else {
        eprintln!("reusing {} (delete it to simulate again)", path.display());
    }
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    Ok(Profile::from_csv(&text, &path.display().to_string())?)
}

fn row_json(r: &Row) -> Value {
    let (rank, k) = match r.model {
        KernelModel::Svd { rank, .. } => (Some(rank), None),
        KernelModel::Deon { n } => (Some(n), None),
        KernelModel::Guided { k, .. } => (None, Some(k)),
        _ => (None, None),
    };
    json!({
        "model": r.model, "family": r.model.family(), "variant": r.variant, "rank": rank, "k": k, "channel": mc::CHANNELS[r.channel],
        "kernel_rms": r.kernel_rms, "kernel_rms_normalized": r.kernel_rms_normalized, "l1_error": r.l1_error,
        "image_rms": r.image_rms.iter().map(|(s, e)| (s.name().to_string(), json!(e))).collect::<serde_json::Map<_, _>>(),
        "fit_seconds": r.fit_seconds,
    })
}

pub fn run(a: EvalArgs) -> Result<()> {
    let named = library::materials(&a.materials)?;
    let pool = simulate::thread_pool(a.source.threads)?;
    let mut materials = Vec::new();
    for n in &named {
        let p = a.source.profile(n)?;
        eprintln!(
            "fitting and evaluating every model for {} (kernel side {} samples) …",
            n.slug,
            2 * p.len() + 1
        );
        let ev = pool.install(|| evaluate(&p, &n.slug, fit::evaluate::ImageSize::default()))?;
        if let Some(dir) = &a.plots {
            write_plots(&p, &ev, &n.slug, dir)?;
        }
        if !a.json {
            print_table(&n.slug, &ev.rows);
        }
        materials.push(
            json!({ "name": n.slug, "models": ev.rows.iter().map(row_json).collect::<Vec<_>>() }),
        );
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({ "materials": materials }))?
        );
    }
    Ok(())
}

pub fn write_plots(
    p: &Profile,
    ev: &fit::evaluate::Evaluation,
    slug: &str,
    dir: &Path,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    // Render to temporary names, then rename: no half-written PNG is ever visible.
    let render = |name: String, f: &dyn Fn(&Path) -> fit::Result<()>| -> Result<()> {
        let tmp = dir.join(format!(".{name}.tmp.png"));
        f(&tmp)?;
        std::fs::rename(&tmp, dir.join(&name))?;
        Ok(())
    };
    render(format!("{slug}.profile.png"), &|path| {
        fit::plot::profile(p, slug, path)
    })?;
    render(format!("{slug}.slices_rank1.png"), &|path| {
        fit::plot::slices(ev, &RANK1, slug, path)
    })?;
    render(format!("{slug}.slices_multipass.png"), &|path| {
        let multipass = [
            KernelModel::Svd {
                rank: 3,
                renormalize: false,
            },
            KernelModel::Deon { n: 3 },
            KernelModel::Burley { radial: true },
        ];
        fit::plot::slices(ev, &multipass, slug, path)
    })?;
    render(format!("{slug}.singular_values.png"), &|path| {
        fit::plot::singular_values(ev, slug, path)
    })?;
    for s in [Signal::Edge, Signal::CircleSquares] {
        render(format!("{slug}.conv_{}.png", s.name()), &|path| {
            fit::plot::convolutions(ev, &RANK1, s, 10.0, slug, path)
        })?;
    }
    eprintln!("plots for {slug} → {}", dir.display());
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
