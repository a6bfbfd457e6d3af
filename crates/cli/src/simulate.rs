//! `sss simulate` and `sss merge`: run the photon tracer for materials (batched by similarity)
//! or for an MCML `.mci` file, and write profiles, summaries and MCML `.mco` files; with
//! `--incidence-angles`, also total Rd against the incidence angle per material (CSV, plot).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use report::simulation::{self, Finished};
use report::simulation_run::{Simulated, Simulation};
use serde_json::json;

use crate::common::{Bars, parse_count};
use crate::library::{self, Named};

#[derive(Args)]
pub struct SimulateArgs {
    /// Materials: built-in names (see `sss materials`) or paths to material .toml files
    #[arg(value_name = "MATERIAL", conflicts_with_all = ["all", "mci"])]
    materials: Vec<String>,

    /// Simulate every built-in material (each material's results are the same as when simulated alone)
    #[arg(long, conflicts_with = "mci")]
    all: bool,

    /// Run every run of an MCML input file (.mci) and write one .mco per run
    #[arg(long, value_name = "FILE.mci")]
    mci: Option<PathBuf>,

    /// Photon packets per channel [default: from the config, 1e7 for the thesis settings]; accepts 1e6
    #[arg(long, value_parser = parse_count)]
    photons: Option<u64>,

    /// Seed of all random streams [default: from the config]; same seed ⇒ same results for any --threads, --shard, or other materials on the command line
    #[arg(long)]
    seed: Option<u64>,

    /// Worker threads [default: all cores]
    #[arg(long)]
    threads: Option<usize>,

    /// Run settings TOML (photons, seed, grid rule, thickness, ambient η) [default: built-in configs/thesis.toml]
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,

    /// Output folder: per material NAME.profile.csv, its provenance NAME.profile.json (what later
    /// commands check before reusing the profile), NAME.summary.json, and with --full
    /// NAME.R/G/B.mco
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,

    /// Stop each walk group once the relative standard error of total Rd and of r·Rd(r) within 3 MFP is ≤ E (e.g. 0.01); --photons is then the cap
    #[arg(long, value_name = "E", conflicts_with_all = ["shard", "mci"])]
    target_error: Option<f64>,

    /// Also tally the absorption A(r, z) and write NAME.R/G/B.mco in MCML's format, tracing
    /// exactly as MCML does (no importance roulette); 5–7× the time of the default in a batch of
    /// materials, where every channel deposits its own absorption at every interaction
    #[arg(long)]
    full: bool,

    /// Tally only what profiles need (no A(r, z), no .mco files): the default, accepted for
    /// scripts written before --full existed
    #[arg(long = "profile-only", conflicts_with = "full")]
    _profile_only: bool,

    /// Run only the I-th of N deterministic slices of the photon chunks and write a shard file; combine with `sss merge`. `auto` takes I and N from a job array (Slurm's SLURM_ARRAY_TASK_ID/_MIN/_COUNT, AWS Batch's AWS_BATCH_JOB_ARRAY_INDEX/_SIZE); `auto/N` also reads a Kubernetes Indexed Job's JOB_COMPLETION_INDEX
    #[arg(long, value_name = "I/N|auto|auto/N", conflicts_with = "mci")]
    shard: Option<String>,

    /// Also measure total Rd(θ) per material for a beam at these polar angles [degrees, each in [0, 90)], e.g. 0,15,30,45,60,75,85: NAME.incidence.csv, .png and the summary's "incidence"
    #[arg(long, value_name = "DEG[,DEG…]", value_delimiter = ',', value_parser = parse_angle, allow_negative_numbers = true, conflicts_with_all = ["mci", "shard"])]
    incidence_angles: Vec<f64>,

    /// Photon packets per channel and angle for --incidence-angles; separate from --photons, since only total Rd is needed; accepts 1e5
    #[arg(long, value_name = "N", default_value = "1e5", value_parser = parse_count)]
    incidence_photons: u64,

    /// Where the profiles are traced: cpu (every core) or gpu (wgpu compute, one channel at a
    /// time; not with --full, --target-error, --shard or --mci; Rd(θ) stays on the CPU)
    #[arg(long, value_parser = ["cpu", "gpu"], default_value = "cpu", conflicts_with_all = ["mci", "shard", "target_error"])]
    device: String,

    /// Print a machine-readable summary on stdout
    #[arg(long)]
    json: bool,
}

pub fn simulate(args: SimulateArgs) -> Result<()> {
    let pool = crate::common::thread_pool(args.threads)?;
    mc::outputs::check_writable(&args.out)?;
    if let Some(mci) = &args.mci {
        return pool.install(|| run_mci(mci, &args));
    }
    let named: Vec<Named> = if args.all {
        library::all()?
    } else if args.materials.is_empty() {
        bail!("no material given: name one (e.g. `sss simulate skin1`), use --all, or --mci FILE");
    } else {
        args.materials
            .iter()
            .map(|m| library::material(m))
            .collect::<Result<_>>()?
    };
    let config = library::config(args.config.as_deref())?;
    let gpu = (args.device == "gpu").then(gpu::Gpu::new).transpose()?;
    let sim = Simulation {
        materials: named
            .iter()
            .map(|n| (n.slug.as_str(), &n.material))
            .collect(),
        config: &config,
        photons: args.photons.unwrap_or(config.photons),
        seed: args.seed.unwrap_or(config.seed),
        full: args.full,
        target_error: args.target_error,
        incidence_angles: args.incidence_angles.clone(),
        incidence_photons: args.incidence_photons,
        gpu: gpu.as_ref(),
    };
    let bars = Bars::default();
    let Some(s) = &args.shard else {
        let run = pool.install(|| sim.run(&bars))?;
        return finish(
            &run.finished(pool.current_num_threads()),
            &args.out,
            args.json,
        );
    };
    let start = Instant::now();
    let (i, n) = mc::job_array::slice(s, &|k| std::env::var(k).ok())?;
    let sh = pool.install(|| sim.shard(i, n, &bars))?;
    let path = args.out.join(format!("shard-{i}-of-{n}.json"));
    let seconds = start.elapsed().as_secs_f64();
    crate::common::write_shard(&path, sh.to_json(), (i, n), (seconds, None), args.json)
}

pub fn merge(texts: &[(String, String)], out: &Path, json: bool) -> Result<()> {
    finish(&Simulated::merge(texts)?.finished(1), out, json)
}

/// Writes each material's files (`report::simulation`) and reports.
fn finish(run: &Finished, out: &Path, json_out: bool) -> Result<()> {
    let (files, mut summaries) = run.files(out)?;
    let written = files.len();
    files.commit()?;
    if json_out {
        let v = if summaries.len() == 1 {
            summaries.remove(0)
        } else {
            json!({ "materials": summaries, "seconds": run.seconds })
        };
        crate::common::print_json(&v)?;
    } else {
        for s in &summaries {
            print!("{}", simulation::summary_text(s));
            eprint!("{}", simulation::incidence_text(s));
        }
        eprintln!(
            "wrote {written} file(s) to {} in {:.1} s",
            out.display(),
            run.seconds
        );
    }
    Ok(())
}

fn run_mci(path: &Path, args: &SimulateArgs) -> Result<()> {
    let text =
        crate::files::read_text(path).with_context(|| format!("cannot read {}", path.display()))?;
    let runs = mc::mci::parse(&text, &path.display().to_string(), args.seed.unwrap_or(1))?;
    let bars = Bars::default();
    let (files, report) = simulation::run_mci(runs, args.photons, &args.out, &bars)?;
    files.commit()?;
    if args.json {
        crate::common::print_json(&json!({ "runs": report }))?;
    } else {
        for r in &report {
            println!("{}", simulation::mci_run_text(r));
        }
    }
    Ok(())
}

/// One incidence angle [degrees] in [0, 90).
fn parse_angle(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number (angles in degrees, e.g. 0,30,60)"))?;
    if !(v.is_finite() && (0.0..90.0).contains(&v)) {
        return Err(format!("{s:?} must be in [0, 90) degrees"));
    }
    Ok(v)
}
