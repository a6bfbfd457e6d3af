//! `sss table`: Monte Carlo profile tables per (g, η) (`mc::table`), on one machine or as
//! shards of a job array merged by `sss merge`; and reading tables back (`--table`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use clap::Args;
use mc::table::{self, Table, TableShard, TableSpec};
use serde_json::json;

use crate::common::{self, parse_count};
use crate::files::Outputs;

#[derive(Args)]
pub struct TableArgs {
    /// Henyey–Greenstein anisotropies g [-], one table per (g, η), e.g. 0,0.5,0.9
    #[arg(
        long,
        required = true,
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    g: Vec<f64>,

    /// Refractive indices η of the medium relative to the one above it [-], one table per (g, η), e.g. 1.3,1.4
    #[arg(long, required = true, value_delimiter = ',')]
    eta: Vec<f64>,

    /// Albedos per table, spaced as pbrt-v4's BSSRDFTable ((1 − e^{−8i/(n−1)})/(1 − e^{−8}), dense towards 1) up to --max-albedo
    #[arg(long, default_value_t = table::DEFAULT_ALBEDOS)]
    albedos: usize,

    /// Largest albedo σs/σt of the tables [-]; materials above it are refused (at 1 a half-space walk has no finite mean length)
    #[arg(long, default_value_t = table::DEFAULT_MAX_ALBEDO)]
    max_albedo: f64,

    /// Photon packets per albedo; accepts 1e6
    #[arg(long, value_parser = parse_count, default_value = "1e6")]
    photons: u64,

    /// `on`: every albedo from one walk, the largest albedo's, each exit reweighted by (α/α_max)ⁿ after n interactions ("white" Monte Carlo); `off`: one walk per albedo (the check: the same tables within noise, many times slower)
    #[arg(long, value_name = "on|off", value_parser = common::on_off(), action = clap::ArgAction::Set, default_value = "on")]
    white: bool,

    /// Seed of all random streams; same seed ⇒ same tables for any --threads or --shard
    #[arg(long, default_value_t = 1)]
    seed: u64,

    /// Output folder: gG_etaE.table.json per (g, η), or with --shard the shard file table-shard-I-of-N.json
    #[arg(long, value_name = "DIR", default_value = "out/tables")]
    out: PathBuf,

    /// Trace only the I-th of N deterministic slices of every table's photon chunks and write a shard file; combine all N with `sss merge` (bit-identical to the unsharded tables). `auto` takes I and N from a job array (Slurm's SLURM_ARRAY_TASK_ID/_MIN/_COUNT, AWS Batch's AWS_BATCH_JOB_ARRAY_INDEX/_SIZE); `auto/N` also reads a Kubernetes Indexed Job's JOB_COMPLETION_INDEX
    #[arg(long, value_name = "I/N|auto|auto/N")]
    shard: Option<String>,

    /// Worker threads [default: all cores]
    #[arg(long)]
    threads: Option<usize>,

    /// Where the walks are traced: cpu (every core) or gpu (wgpu compute, the same tables within noise; not with --shard)
    #[arg(long, value_parser = ["cpu", "gpu"], default_value = "cpu", conflicts_with = "shard")]
    device: String,

    /// Print a machine-readable summary on stdout
    #[arg(long)]
    json: bool,
}

fn specs(a: &TableArgs) -> Result<Vec<TableSpec>> {
    let albedos = (a.albedos, a.max_albedo);
    TableSpec::grid(&a.g, &a.eta, albedos, a.photons, a.seed, a.white).map_err(|e| match e {
        mc::McError::InvalidValue {
            field,
            value,
            reason,
        } if ["g", "eta", "albedos", "max_albedo", "photons"].contains(&field.as_str()) => {
            anyhow::anyhow!("invalid --{} {value}: {reason}", field.replace('_', "-"))
        }
        e => e.into(),
    })
}

pub fn run(a: TableArgs) -> Result<()> {
    let specs = specs(&a)?;
    mc::outputs::check_writable(&a.out)?;
    let pool = crate::common::thread_pool(a.threads)?;
    let (i, n) = match &a.shard {
        Some(s) => mc::job_array::slice(s, &|k| std::env::var(k).ok())?,
        None => (1, 1),
    };
    let start = Instant::now();
    let label = match &a.shard {
        Some(_) => format!("table shard {i}/{n}"),
        None => format!("{} table(s)", specs.len()),
    };
    let bar = common::photons(TableShard::photons(&specs, i, n), &label);
    if a.device == "gpu" {
        let (tables, events) = mc_gpu::tables(&gpu::Gpu::new()?, &specs, &|k| bar.inc(k))?;
        bar.finish_and_clear();
        return write(&tables, &a.out, a.json, start, Some(events));
    }
    let shard = pool.install(|| TableShard::trace(&specs, i, n, &|k| bar.inc(k)))?;
    bar.finish_and_clear();
    let events = shard.interactions();
    if a.shard.is_some() {
        let path = a.out.join(format!("table-shard-{i}-of-{n}.json"));
        let timing = (start.elapsed().as_secs_f64(), Some(events));
        return common::write_shard(&path, shard.to_json(), (i, n), timing, a.json);
    }
    let tables = table::merge_tables(&[(String::new(), shard)])?;
    write(&tables, &a.out, a.json, start, Some(events))
}

/// `sss merge` of table shards, given each file's name and text.
pub fn merge(texts: &[(String, String)], out: &Path, json: bool) -> Result<()> {
    let start = Instant::now();
    let shards = texts
        .iter()
        .map(|(name, text)| Ok((name.clone(), TableShard::from_json(text, name)?)))
        .collect::<Result<Vec<_>>>()?;
    let tables = table::merge_tables(&shards)?;
    write(&tables, out, json, start, None)
}

/// Writes the tables built since `start` and reports them.
fn write(
    tables: &[Table],
    out: &Path,
    json: bool,
    start: Instant,
    events: Option<u64>,
) -> Result<()> {
    let seconds = start.elapsed().as_secs_f64();
    let mut files = Outputs::default();
    let mut rows = Vec::new();
    for t in tables {
        let path = out.join(t.file_name());
        files.add(&path, t.to_json());
        let (line, row) = t.summary(&path);
        if !json {
            eprintln!("{line}");
        }
        rows.push(row);
    }
    files.commit()?;
    if json {
        crate::common::print_json(&json!({
            "tables": rows, "seconds": seconds, "events": events,
            "events_per_second": events.map(|e| e as f64 / seconds),
        }))?;
    } else if let Some(e) = events {
        let (count, rate) = (tables.len(), e as f64 / seconds);
        eprintln!("{count} table(s) in {seconds:.1} s ({rate:.3e} events/s)");
    }
    Ok(())
}
