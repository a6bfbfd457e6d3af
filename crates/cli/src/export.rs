//! `sss export`: a kernel file (KERNEL.toml) as HLSL, GLSL or WGSL source or JSON, in SSSS's
//! layout (see `fit::export`); or, with `--format package`, a material's whole shading model as
//! a folder an engine loads (`render::Package`).

use std::path::PathBuf;
use std::str::FromStr;

use anyhow::{Context, Result, bail};
use clap::Args;
use fit::export::{OffsetUnit, ShaderFormat, export};
use fit::taps::ShaderKernel;

use crate::cache::{ProfileSource, TableFlags};
use crate::files::{Outputs, out_file};
use crate::library;

/// What `--format` asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Format {
    /// A kernel file as shader code or JSON.
    Kernel(ShaderFormat),
    /// A material's shading model as a folder.
    Package,
}

impl FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        if s.trim().eq_ignore_ascii_case("package") {
            return Ok(Format::Package);
        }
        ShaderFormat::from_str(s)
            .map(Format::Kernel)
            .map_err(|_| format!("{s:?} is not a format: hlsl, glsl, wgsl, json or package"))
    }
}

#[derive(Args)]
pub struct ExportArgs {
    /// Kernel file written by `sss fit` (KERNEL.toml, offsets in cm or mm); with --format
    /// package a material (built-in name or material .toml path)
    #[arg(value_name = "KERNEL|MATERIAL")]
    pub input: String,

    /// Output format: hlsl, glsl, wgsl (constants, per-pass float4 arrays and a reference blur
    /// function) or json; or package: the material's kernel (pre-integration, --taps taps) and
    /// shading tables (incidence, exit, entry shift, translucency, as `sss render` uses them),
    /// with the lookups that read them in WGSL, GLSL and HLSL and a README, into the folder --out
    #[arg(long)]
    pub format: Format,

    /// Unit of the exported tap offsets and KERNEL_RANGE: cm or mm (a package's are cm)
    #[arg(long, default_value = "cm")]
    pub unit: OffsetUnit,

    /// Output file, or a folder to write KERNEL.FORMAT into (KERNEL: the kernel file's stem)
    /// [default: standard output]; with --format package the package's folder [default:
    /// out/MATERIAL.package]
    #[arg(long, value_name = "FILE|DIR")]
    pub out: Option<PathBuf>,

    #[command(flatten)]
    pub tables: TableFlags,

    /// package: where its profile and tables come from
    #[command(flatten)]
    pub source: ProfileSource,
}

pub fn run(a: ExportArgs) -> Result<()> {
    match a.format {
        Format::Kernel(format) => kernel(&a, format),
        Format::Package => package(a),
    }
}

fn kernel(a: &ExportArgs, format: ShaderFormat) -> Result<()> {
    let path = PathBuf::from(&a.input);
    let text = crate::files::read_text(&path)
        .with_context(|| format!("cannot read kernel {}", path.display()))?;
    let k = ShaderKernel::from_toml(&text, &path.display().to_string())?;
    let source = export(&k, format, a.unit);
    match &a.out {
        Some(out) => {
            let stem = path.file_stem().and_then(|s| s.to_str());
            let path = out_file(out, &format!("{}.{format}", stem.unwrap_or("kernel")));
            let mut files = Outputs::default();
            files.add(&path, source);
            files.commit()?;
            eprintln!(
                "wrote {} ({format}: {} pass(es) × {} taps, offsets in {})",
                path.display(),
                k.pass.len(),
                k.taps,
                a.unit
            );
        }
        None => crate::common::print_raw(&source)?,
    }
    Ok(())
}

fn package(a: ExportArgs) -> Result<()> {
    if a.unit != OffsetUnit::Cm {
        bail!("invalid --unit {}: a package's lengths are cm", a.unit);
    }
    let named = library::material(&a.input)?;
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| crate::common::default_out().join(format!("{}.package", named.slug)));
    let request = a.source.request(named, &a.tables)?;
    let mut files = Outputs::checked(&out)?;
    let package = (a.source).build(&mut files, |p, bars| {
        render::Package::build(&request, p, bars)
    })?;
    for note in &package.notes {
        eprintln!("{note}");
    }
    files.add_in(&out, package.files());
    files.commit()?;
    eprintln!(
        "wrote the shading model of {} to {} (README.md says what each file is; {} pass(es) × {} taps)",
        package.slug,
        out.display(),
        package.kernel.pass.len(),
        package.kernel.taps
    );
    Ok(())
}
