//! `sss reproduce`: the thesis's tables and figures regenerated from scratch, written as a
//! self-contained HTML report (tables inline, PNG plots beside it) and a JSON file with every
//! number. Each result sits beside the published one; the "what agrees" section is generated
//! from the numbers.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use fit::Profile;
use fit::evaluate::{ImageSize, evaluate};
use mc::provenance::{self, Explicit, Provenance, Reuse, provenance_path};
use report::reproduce::{MAIN, MitsubaImages, Published, RenderedTables, Report};

use crate::common::{self, parse_count};
use crate::files::Outputs;
use crate::library;

#[derive(Args)]
pub struct ReproduceArgs {
    /// Output folder (index.html, report.json, PNG plots, profiles/ with their provenance),
    /// written once the whole report is done
    #[arg(long, value_name = "DIR", default_value = "report")]
    out: PathBuf,

    /// CI-sized run: 2·10⁴ photons per channel, a coarser grid (dr = min MFP/6, 10 max MFP) and
    /// 128-pixel test images; minutes on 2 cores
    #[arg(long)]
    quick: bool,

    /// Photons per channel [default: 1e7, or 2e4 with --quick]
    #[arg(long, value_parser = parse_count)]
    photons: Option<u64>,

    /// Worker threads [default: all cores]
    #[arg(long)]
    threads: Option<usize>,

    /// Read the 16 profiles from this folder (NAME.profile.csv, e.g. a previous report's
    /// profiles/) instead of simulating them. Where a profile has its provenance
    /// (NAME.profile.json) it must be of the built-in material, and of --photons when given; a
    /// profile without one is refused when --photons is given
    #[arg(long, value_name = "DIR")]
    profiles: Option<PathBuf>,

    /// Include the rendered-scene comparisons against Mitsuba 3: an images.json that
    /// `python3 scripts/references/images.py` wrote, or the summary.json of `run.py` (every scene
    /// and material it ran, the long-mean-free-path ones included); repeatable. Each entry must
    /// have the fields the page shows (a file missing one is refused, naming it); report.json
    /// keeps every field
    #[arg(long, value_name = "JSON")]
    references: Vec<PathBuf>,

    /// Also print the report's numbers (report.json) on stdout
    #[arg(long)]
    json: bool,
}

/// The image comparisons against Mitsuba in a `--references` file.
fn read_references(path: &std::path::Path) -> Result<Vec<MitsubaImages>> {
    let text = crate::files::read_text(path)
        .with_context(|| format!("cannot read --references {}", path.display()))?;
    MitsubaImages::parse(&text).map_err(|e| anyhow!("--references {}: {e}", path.display()))
}

/// A profile of `--profiles` and its provenance, if it has one: one that is not of the built-in
/// material, or not of the --photons given, is refused (the user named these files), as is one
/// without provenance when --photons is given.
fn read_profile(
    csv: &std::path::Path,
    asked: &Provenance,
    explicit: Explicit,
) -> Result<(String, Option<Provenance>)> {
    let text =
        crate::files::read_text(csv).with_context(|| format!("cannot read {}", csv.display()))?;
    let sidecar = provenance_path(csv);
    let have = sidecar
        .exists()
        .then(|| crate::cache::read_provenance(&sidecar))
        .transpose()?;
    let name = csv.display().to_string();
    match provenance::reuse(&name, &sidecar, have.as_ref(), asked, explicit) {
        Reuse::Use(_) => Ok((text, have)),
        Reuse::Replace(why) if have.is_none() => {
            bail!("{why}: it cannot stand for --photons {}", asked.photons)
        }
        Reuse::Replace(why) => bail!("{why}"),
    }
}

/// Every built-in material's profile CSV with its provenance: read from `--profiles` (each must
/// match what was asked) or simulated in one batch of `photons` per channel.
fn library_profiles(
    a: &ReproduceArgs,
    config: &mc::SimConfig,
    photons: u64,
    pool: &rayon::ThreadPool,
    all: &[library::Named],
) -> Result<(Vec<String>, Vec<Option<Provenance>>)> {
    let materials: Vec<&mc::Material> = all.iter().map(|n| &n.material).collect();
    let spec = config.batch(&materials, photons, config.seed, true)?;
    Ok(match &a.profiles {
        Some(dir) => {
            let explicit = Explicit {
                photons: a.photons.is_some(),
                ..Explicit::default()
            };
            all.iter()
                .enumerate()
                .map(|(i, n)| {
                    let asked = Provenance::of(&spec, i, &n.slug, None);
                    read_profile(
                        &dir.join(format!("{}.profile.csv", n.slug)),
                        &asked,
                        explicit,
                    )
                })
                .collect::<Result<Vec<_>>>()?
                .into_iter()
                .unzip()
        }
        None => {
            let bar = common::photons(
                photons * spec.groups().len() as u64,
                "simulating the library",
            );
            let outputs = pool.install(|| mc::run_batch(&spec, &|k| bar.inc(k)))?;
            bar.finish_and_clear();
            all.iter()
                .enumerate()
                .map(|(i, n)| {
                    let o = &outputs[3 * i..3 * i + 3];
                    (
                        Profile::csv_from_mc([&o[0], &o[1], &o[2]]),
                        Some(Provenance::of(&spec, i, &n.slug, None)),
                    )
                })
                .unzip()
        }
    })
}

/// Tables 6.4 and 6.5 rendered on our scenes with the library's profiles, or skipped (saying
/// why) without an adapter.
fn rendered(
    all: &[library::Named],
    profiles: &[Profile],
    quick: bool,
    published: &Published,
) -> Result<RenderedTables> {
    Ok(match gpu::Gpu::new() {
        Err(e) => {
            eprintln!("rendered Tables 6.4 and 6.5 skipped: {e}");
            RenderedTables::Skipped {
                reason: e.to_string(),
            }
        }
        Ok(gpu) => {
            eprintln!("rendering Tables 6.4 and 6.5 on our scenes …");
            let with: Vec<(&str, &Profile)> = all
                .iter()
                .zip(profiles)
                .map(|(n, p)| (n.slug.as_str(), p))
                .collect();
            let r = report::rendered::rendered_tables(&gpu, &with, quick, published)?;
            eprintln!("rendered Tables 6.4 and 6.5 in {:.1} s", r.seconds);
            RenderedTables::Rendered(Box::new(r))
        }
    })
}

pub fn run(a: ReproduceArgs) -> Result<()> {
    let start = Instant::now();
    let published = Published::thesis();
    let pool = crate::common::thread_pool(a.threads)?;
    let mut config = library::config(None)?;
    let extent_mfp = config.grid.r_max_mfp;
    let image = if a.quick {
        config.grid.dr_per_min_mfp = 6.0;
        config.grid.r_max_mfp = 10.0;
        ImageSize {
            size: 128,
            max_half: 48,
        }
    } else {
        ImageSize::default()
    };
    let photons = a
        .photons
        .unwrap_or(if a.quick { 20_000 } else { config.photons });
    let references = a
        .references
        .iter()
        .map(|p| read_references(p))
        .collect::<Result<Vec<_>>>()?
        .concat();
    let mut files = Outputs::default();

    // 1. Profiles of the whole library, one batch.
    let all = library::all()?;
    let t = Instant::now();
    let (csvs, provenance) = library_profiles(&a, &config, photons, &pool, &all)?;
    let simulate_seconds = t.elapsed().as_secs_f64();
    // The photons behind the report: those asked, or those every profile read says it has.
    let counts: Vec<Option<u64>> = provenance
        .iter()
        .map(|p| {
            p.as_ref()
                .filter(|p| p.target_error.is_none())
                .map(|p| p.photons)
        })
        .collect();
    let photons = match &counts[..] {
        [Some(first), rest @ ..] if rest.iter().all(|c| *c == Some(*first)) => Some(*first),
        _ => None,
    };
    let mut profiles = Vec::new();
    for ((n, csv), prov) in all.iter().zip(&csvs).zip(&provenance) {
        let path = a
            .out
            .join("profiles")
            .join(format!("{}.profile.csv", n.slug));
        let p = Profile::parse_csv(csv, &path.display().to_string())?;
        if let Some(prov) = prov {
            files.add(provenance_path(&path), prov.to_json());
        }
        files.add(path, csv.as_str());
        profiles.push(p);
    }
    let profile_of = |slug: &str| {
        let i = all
            .iter()
            .position(|n| n.slug == slug)
            .expect("the report's materials are built in");
        (&all[i], &profiles[i])
    };

    // 2. Every model on the five main materials, with their plots.
    let mut evals = Vec::new();
    for name in MAIN {
        let (_, p) = profile_of(name);
        eprintln!("fitting and evaluating every model for {name} …");
        let ev = pool.install(|| evaluate(p, name, image))?;
        files.add_in(&a.out, report::plot::evaluation(p, &ev, name)?);
        evals.push(ev);
    }
    for (n, p) in all.iter().zip(&profiles) {
        if !MAIN.contains(&n.slug.as_str()) {
            files.add(
                a.out.join(format!("{}.profile.png", n.slug)),
                report::plot::profile(p, &n.slug)?,
            );
        }
    }
    let slugs: Vec<(&str, &mc::Material)> =
        all.iter().map(|n| (n.slug.as_str(), &n.material)).collect();
    let tables = report::reproduce::tables(&slugs, &evals, &published);

    // 3. Tables 6.4 and 6.5 rendered on our scenes (skipped, saying why, without an adapter).
    let rendered_tables = rendered(&all, &profiles, a.quick, &published)?;

    // 4. Fig. 5.15 and 5.17 on Skin1: their plots, numbers and claims.
    eprintln!("guided k = 1.55, b = 50 against pre-integration, and the manual w sweep (skin1) …");
    let (n, p) = profile_of(report::reproduce::CHAPTER5_MATERIAL);
    let chapter5 = report::reproduce::chapter5(&n.material, p, image, extent_mfp)?;
    for (name, png) in chapter5.plots()? {
        files.add(a.out.join(name), png);
    }
    let report = Report::new(
        a.quick,
        photons,
        simulate_seconds,
        tables,
        &chapter5,
        rendered_tables,
        references,
    );
    let json = serde_json::to_string_pretty(&report)?;
    files.add(a.out.join("report.json"), json.as_str());
    files.add(a.out.join("index.html"), report.html());
    files.commit()?;
    if a.json {
        println!("{json}");
    }
    eprintln!(
        "wrote {} in {:.0} s",
        a.out.join("index.html").display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
