//! `sss reproduce`: the thesis's tables and figures regenerated from scratch, written as a
//! self-contained HTML report (tables inline, PNG plots beside it) and a JSON file with every
//! number. Each result sits beside the published one; the "what agrees" section is generated
//! from the numbers.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow};
use clap::Args;
use report::reproduce::MitsubaImages;
use report::reproduction::{Asked, reproduce};

use crate::common::{Bars, parse_count};

#[derive(Args)]
pub struct ReproduceArgs {
    /// Output folder (index.html, report.json, PNG plots, profiles/ with their provenance),
    /// written once the whole report is done
    #[arg(long, value_name = "DIR", default_value = "report")]
    out: PathBuf,

    /// CI-sized run: 2·10⁴ photons per channel, a coarser grid (dr = min MFP/6, 10 max MFP) and
    /// 128-pixel test images; 8–15 s on 2 cores
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

pub fn run(a: ReproduceArgs) -> Result<()> {
    let start = Instant::now();
    mc::outputs::check_writable(&a.out)?;
    let pool = crate::common::thread_pool(a.threads)?;
    let references = a
        .references
        .iter()
        .map(|p| read_references(p))
        .collect::<Result<Vec<_>>>()?
        .concat();
    let asked = Asked {
        quick: a.quick,
        photons: a.photons,
        profiles: a.profiles.clone(),
        references,
    };
    let (files, json) = pool.install(|| reproduce(asked, &a.out, &Bars::default()))?;
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
