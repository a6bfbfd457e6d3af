//! `sss`: from measured optical coefficients to real-time subsurface-scattering kernels.
//!
//! Thin glue over the library crates: argument parsing, progress bars, files and exit codes.
//! Every error is printed as one line on stderr and exits with code 2; nothing is written then.

mod area_table;
mod bench;
mod cache;
mod common;
mod engine;
mod eval;
mod export;
mod files;
mod fit;
mod library;
mod materials;
mod profile;
mod render;
mod reproduce;
mod simulate;
mod table;
mod view;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "sss",
    version,
    about = "Measured optical coefficients → Monte Carlo profiles → separable SSS kernels",
    long_about = None,
    after_help = "Outputs are written whole or not at all, when a command has succeeded. --out is a folder for commands that \
write several files, and a file (or a folder to hold the default name) for those that write one. Monte Carlo profiles are \
cached in --profiles with their provenance (NAME.profile.json) and reused only when they match what was asked (see each command's --help)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate diffuse reflectance profiles Rd(r) with MCML physics (materials or an .mci file)
    Simulate(simulate::SimulateArgs),
    /// Fit a separable kernel model to a profile and write shader-ready taps (KERNEL.toml)
    Fit(fit::FitArgs),
    /// Evaluate every kernel model against the ground truth (kernel and image space), with plots
    Eval(eval::EvalArgs),
    /// Export a kernel file as shader code (HLSL, GLSL, WGSL) or JSON in SSSS's layout
    Export(export::ExportArgs),
    /// Regenerate the thesis's tables and figures as an HTML report (use --quick for a CI-sized run)
    Reproduce(reproduce::ReproduceArgs),
    /// Write an analytic profile (dipole, better-dipole, directional-dipole, pbd, burley) as a profile CSV
    Profile(profile::ProfileArgs),
    /// Compare every analytic profile with the Monte Carlo profile: table, JSON and a plot per material
    CompareProfiles(profile::CompareArgs),
    /// Tabulate a kernel averaged over circular areas R′(r, A) for screen-space lookups (Maisch & Ropinski 2020)
    AreaTable(area_table::AreaTableArgs),
    /// Apply a kernel in wgpu screen-space passes on a scene (PNG + linear PFM); --compare-models, --bench
    Render(render::RenderArgs),
    /// Merge shard files of one `simulate --shard` run or one `table --shard` build into its outputs
    Merge(MergeArgs),
    /// Build Monte Carlo profile tables R̂(ρ; albedo) per (g, η): any material's profile then by interpolation, in milliseconds
    Table(table::TableArgs),
    /// List the built-in materials with σa, σs, g, η, albedo and mean free path per channel
    Materials(materials::MaterialsArgs),
    /// Fit every model that fits a budget, pick the one with the lowest image error and write it as shader code
    Kernel(engine::KernelArgs),
    /// Burley parameters for Unreal, Unity, Blender or OpenPBR (MaterialX) fitted to the Monte Carlo profile, with their error
    EngineParams(engine::EngineParamsArgs),
    /// Benchmarks (run time against error); measurements only, never pass/fail
    Bench(bench::BenchArgs),
    /// Write the browser page (WebGPU) with a material's shading model and scenes, to serve and open
    View(view::ViewArgs),
}

fn main() -> ExitCode {
    // SAFETY: first thing in main, before any other thread starts.
    unsafe { gpu::quiet_headless_vulkan() };
    // A negative count reaches its parser, which names it, not clap's "unexpected argument".
    let command = Cli::command().mut_subcommands(|c| c.allow_negative_numbers(true));
    let cli = Cli::from_arg_matches(&command.get_matches()).unwrap_or_else(|e| e.exit());
    let result = match cli.command {
        Command::Simulate(a) => simulate::simulate(a),
        Command::Merge(a) => merge(a),
        Command::Table(a) => table::run(a),
        Command::Render(a) => render::run(a),
        Command::Profile(a) => profile::profile(a),
        Command::CompareProfiles(a) => profile::compare_profiles(a),
        Command::AreaTable(a) => area_table::run(a),
        Command::Fit(a) => fit::run(a),
        Command::Eval(a) => eval::run(a),
        Command::Export(a) => export::run(a),
        Command::Reproduce(a) => reproduce::run(a),
        Command::Materials(a) => materials::list(a),
        Command::Bench(a) => bench::run(a),
        Command::Kernel(a) => engine::kernel(a),
        Command::EngineParams(a) => engine::engine_params(a),
        Command::View(a) => view::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let chain: Vec<String> = e.chain().map(|c| c.to_string()).collect();
            eprintln!("error: {}", chain.join(": "));
            ExitCode::from(2)
        }
    }
}

#[derive(Args)]
struct MergeArgs {
    /// Shard files written by `sss simulate --shard` (all of one run), or by `sss table --shard` (all of one build)
    #[arg(required = true, value_name = "SHARD.json")]
    shards: Vec<PathBuf>,

    /// Output folder (the same files as `simulate` or `table` writes)
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,

    /// Print a machine-readable summary on stdout
    #[arg(long)]
    json: bool,
}

/// `sss merge`: a table build's shards or a profile run's, told apart by the first file's format.
fn merge(a: MergeArgs) -> Result<()> {
    let texts = files::read_named(&a.shards, "shard")?;
    match texts.first() {
        Some((_, text)) if mc::table::TableShard::is_shard(text) => {
            table::merge(&texts, &a.out, a.json)
        }
        _ => simulate::merge(&texts, &a.out, a.json),
    }
}
