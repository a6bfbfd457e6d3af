//! `sss`: from measured optical coefficients to real-time subsurface-scattering kernels.
//!
//! Thin glue over the library crates: argument parsing, progress bars, files and exit codes.
//! Every error is printed as one line on stderr and exits with code 2; nothing is written then.

mod area_table;
mod bench;
mod cache;
mod engine;
mod eval;
mod export;
mod files;
mod fit;
mod library;
mod materials;
mod profile;
mod progress;
mod render;
mod reproduce;
mod shard;
mod simulate;
mod table;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "sss",
    version,
    about = "Measured optical coefficients → Monte Carlo profiles → separable SSS kernels",
    long_about = None,
    after_help = "Outputs are written whole or not at all, when a command has succeeded. --out is a folder \
for commands that write several files, and a file (or a folder to hold the default name) for those \
that write one. Monte Carlo profiles are cached in --profiles with their provenance \
(NAME.profile.json) and reused only when they match what was asked (see each command's --help)."
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
    Merge(simulate::MergeArgs),
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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Simulate(a) => simulate::simulate(a),
        Command::Merge(a) => simulate::merge(a),
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

/// Parses a positive count written as an integer or in scientific notation (`1e6`).
pub fn parse_count(s: &str) -> Result<u64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    if !(v.is_finite() && v >= 1.0 && v.fract() == 0.0 && v < u64::MAX as f64) {
        return Err(format!("{s:?} must be a positive whole number"));
    }
    Ok(v as u64)
}

/// Default output folder.
pub fn default_out() -> PathBuf {
    PathBuf::from("out")
}
