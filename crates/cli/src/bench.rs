//! `sss bench mc`: photon-tracer throughput, run time against error, and batch tracing against
//! channel-by-channel runs. A benchmark, not a test: it asserts nothing and prints measurements.

use std::time::Instant;

use anyhow::Result;
use clap::{Args, Subcommand};
use mc::{BatchSpec, CHANNELS, ChannelSpec, Output, RunSpec, Sample, TallySet};
use serde_json::{Value, json};

use crate::{library, parse_count};

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
    let mut report = serde_json::Map::new();

    // 1. Single channel, one core: the MCML yardstick (full tallies) and profile-only.
    eprintln!("== single channel, 1 thread, thesis grid ==");
    let mut rows = Vec::new();
    for (name, photons) in [
        ("skin1", 200_000u64),
        ("wholemilk", 20_000),
        ("marble", 20_000),
    ] {
        let m = library::material(name)?.material;
        let grid = config.grid_for(&m)?;
        for rz in [true, false] {
            let spec = RunSpec {
                sample: Sample {
                    n_above: config.n_above,
                    n_below: config.n_below,
                    layers: vec![m.layer(0, config.thickness_cm)],
                },
                grid,
                photons,
                seed: 1,
                tallies: TallySet {
                    absorption_rz: rz,
                    surface_xy: 0,
                },
            };
            let t = Instant::now();
            let o = single.install(|| mc::run(&spec, &|_| {}))?;
            let s = t.elapsed().as_secs_f64();
            let row = json!({ "material": name, "channel": "R", "tallies": if rz { "full (MCML)" } else { "profile-only" }, "photons": photons, "seconds": s, "photons_per_s": photons as f64 / s, "events_per_s": o.interactions as f64 / s, "events_per_photon": o.interactions as f64 / photons as f64 });
            eprintln!(
                "{:<10} R  {:<13} {:>10.0} photons/s  {:>6.1} M events/s  ({:.0} events/photon)",
                name,
                row["tallies"].as_str().unwrap_or(""),
                photons as f64 / s,
                o.interactions as f64 / s / 1e6,
                o.interactions as f64 / photons as f64
            );
            rows.push(row);
        }
    }
    report.insert("single_channel_one_thread".into(), Value::Array(rows));

    // 2. Run time against error: the three channels of a material in one walk, profile-only.
    eprintln!(
        "\n== run time against error ({} threads, profile-only, thesis grid) ==",
        pool.current_num_threads()
    );
    eprintln!(
        "{:<10} {:>10} {:>9}  {:<3} {:>11} {:>13} {:>13}",
        "material", "photons", "seconds", "ch", "relSE(Rd)", "relSE Rd(1ℓ)", "relSE Rd(3ℓ)"
    );
    let mut rows = Vec::new();
    for name in ["skin1", "wholemilk"] {
        let named = library::material(name)?;
        let m = &named.material;
        let grid = config.grid_for(m)?;
        let mut photons = 10_000u64;
        while photons <= a.max_photons {
            let spec = BatchSpec {
                n_above: config.n_above,
                n_below: config.n_below,
                channels: (0..3)
                    .map(|c| ChannelSpec {
                        layer: m.layer(c, config.thickness_cm),
                        grid,
                    })
                    .collect(),
                photons,
                seed: 1,
                tallies: TallySet {
                    absorption_rz: false,
                    surface_xy: 0,
                },
            };
            let t = Instant::now();
            let out = pool.install(|| mc::run_batch(&spec, &|_| {}))?;
            let s = t.elapsed().as_secs_f64();
            for (c, o) in out.iter().enumerate() {
                let (e1, e3) = (rel_at(o, m.mfp(c)), rel_at(o, 3.0 * m.mfp(c)));
                eprintln!(
                    "{:<10} {:>10} {:>9.2}  {:<3} {:>11.2e} {:>13.2e} {:>13.2e}",
                    name,
                    photons,
                    s,
                    CHANNELS[c],
                    o.rd.se / o.rd.value,
                    e1,
                    e3
                );
                rows.push(json!({ "material": name, "photons": photons, "seconds": s, "channel": CHANNELS[c], "rel_se_rd": o.rd.se / o.rd.value, "rel_se_rd_r_1mfp": e1, "rel_se_rd_r_3mfp": e3 }));
            }
            photons *= 10;
        }
    }
    report.insert("time_vs_error".into(), Value::Array(rows));

    // 3. The whole library: one batch (walks shared by similarity) against one walk per channel.
    let all = library::all()?;
    let mut channels = Vec::new();
    for n in &all {
        let grid = config.grid_for(&n.material)?;
        channels.extend((0..3).map(|c| {
            ChannelSpec {
                layer: n
                    .material
                    .layer(c, n.material.thickness.unwrap_or(config.thickness_cm)),
                grid,
            }
        }));
    }
    let spec = BatchSpec {
        n_above: config.n_above,
        n_below: config.n_below,
        channels,
        photons: a.library_photons,
        seed: 1,
        tallies: TallySet {
            absorption_rz: false,
            surface_xy: 0,
        },
    };
    eprintln!(
        "\n== whole library ({} materials × 3 channels, {} photons each, profile-only) ==",
        all.len(),
        a.library_photons
    );
    let t = Instant::now();
    pool.install(|| mc::run_batch(&spec, &|_| {}))?;
    let batched = t.elapsed().as_secs_f64();
    let t = Instant::now();
    for c in &spec.channels {
        let one = BatchSpec {
            channels: vec![*c],
            ..spec.clone()
        };
        pool.install(|| mc::run_batch(&one, &|_| {}))?;
    }
    let separate = t.elapsed().as_secs_f64();
    eprintln!(
        "batched ({} walk groups): {batched:.2} s   channel by channel (48 walks): {separate:.2} s   speed-up {:.1}×",
        spec.groups().len(),
        separate / batched
    );
    eprintln!(
        "extrapolated to 10⁷ photons per channel: batched {:.0} s",
        batched * 1e7 / a.library_photons as f64
    );
    report.insert("library".into(), json!({ "photons": a.library_photons, "groups": spec.groups().len(), "batched_seconds": batched, "separate_seconds": separate, "threads": pool.current_num_threads() }));

    if a.json {
        println!("{}", serde_json::to_string_pretty(&Value::Object(report))?);
    }
    Ok(())
}

/// Relative standard error of Rd(r) in the bin containing radius `r` [cm].
fn rel_at(o: &Output, r: f64) -> f64 {
    let i = ((r / o.grid.dr) as usize).min(o.grid.nr - 1);
    if o.rd_r[i].value > 0.0 {
        o.rd_r[i].se / o.rd_r[i].value
    } else {
        f64::INFINITY
    }
}
