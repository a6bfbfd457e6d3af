//! `sss bench mc`: photon-tracer throughput, run time against error, and batch tracing against
//! channel-by-channel runs (`mc::bench`), printed. A benchmark, not a test: it asserts nothing.

use anyhow::Result;
use clap::{Args, Subcommand};

use crate::common::parse_count;

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
    let bars = crate::common::Bars::default();
    let v = report::tracer_bench::run(a.max_photons, a.library_photons, a.threads, &bars)?;
    if a.json {
        crate::common::print_json(&v)?;
    }
    Ok(())
}
