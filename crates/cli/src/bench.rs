//! `sss bench mc`: photon-tracer throughput, run time against error, and batch tracing against
//! channel-by-channel runs (`mc::bench`), printed. A benchmark, not a test: it asserts nothing.

use anyhow::Result;
use clap::{Args, Subcommand};
use report::tracer_bench;

use crate::common::parse_count;
use crate::library;

#[derive(Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    what: BenchWhat,
}

#[derive(Subcommand)]
enum BenchWhat {
    /// Monte Carlo tracer: photons/s and events/s per core, run time against error, --all against channel by channel
    Mc(McBench),
}

#[derive(Args)]
struct McBench {
    /// Largest photon count of the run-time-against-error table (10⁴, 10⁵, … up to this)
    #[arg(long, default_value = "1e6", value_parser = parse_count)]
    max_photons: u64,

    /// Photons per channel for the whole-library comparison (batched vs channel by channel)
    #[arg(long, default_value = "1e5", value_parser = parse_count)]
    library_photons: u64,

    /// Worker threads for the multi-threaded parts [default: all cores]
    #[arg(long)]
    threads: Option<usize>,

    /// Print the measurements as JSON on stdout
    #[arg(long)]
    json: bool,
}

pub fn run(args: BenchArgs) -> Result<()> {
    let BenchWhat::Mc(a) = args.what;
    let config = library::config(None)?;
    let single = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()?;

    // 1. Single channel, one core: the MCML yardstick (full tallies, summed as .mci runs keep
    // them, and with per-photon standard errors of A(r, z)) and profile-only.
    eprintln!("== single channel, 1 thread, thesis grid ==");
    let named = ["skin1", "wholemilk", "marble"]
        .map(library::material)
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
    let cases: Vec<(&str, &mc::Material, u64)> = named
        .iter()
        .zip([200_000, 20_000, 20_000])
        .map(|(n, photons)| (n.slug.as_str(), &n.material, photons))
        .collect();
    let throughput = single.install(|| mc::bench::throughput(&cases, &config))?;
    tracer_bench::throughput_lines(&throughput)
        .iter()
        .for_each(|l| eprintln!("{l}"));

    // 2. Run time against error: the three channels of a material in one walk, profile-only.
    eprintln!(
        "\n== run time against error ({} threads, profile-only, thesis grid) ==",
        pool.current_num_threads()
    );
    let two: Vec<(&str, &mc::Material)> = named[..2]
        .iter()
        .map(|n| (n.slug.as_str(), &n.material))
        .collect();
    let errors = pool.install(|| mc::bench::time_vs_error(&two, &config, a.max_photons))?;
    tracer_bench::error_lines(&errors)
        .iter()
        .for_each(|l| eprintln!("{l}"));

    // 3. The whole library: one batch (walks shared by similarity) against one walk per channel.
    let all = library::all()?;
    eprintln!(
        "\n== whole library ({} materials × 3 channels, {} photons each, profile-only) ==",
        all.len(),
        a.library_photons
    );
    let materials: Vec<&mc::Material> = all.iter().map(|n| &n.material).collect();
    let b = pool.install(|| mc::bench::batching(&materials, &config, a.library_photons))?;
    tracer_bench::batching_lines(&b)
        .iter()
        .for_each(|l| eprintln!("{l}"));
    if a.json {
        let v = tracer_bench::json(&throughput, &errors, &b, pool.current_num_threads());
        println!("{}", serde_json::to_string_pretty(&v)?);
    }
    Ok(())
}
