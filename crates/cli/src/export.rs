//! `sss export`: a kernel file (KERNEL.toml) as HLSL, GLSL or WGSL source or JSON, in SSSS's
//! layout (see `fit::export`).

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use fit::export::{OffsetUnit, ShaderFormat, export};
use fit::taps::ShaderKernel;

use crate::files::{Outputs, out_file};

#[derive(Args)]
pub struct ExportArgs {
    /// Kernel file written by `sss fit` (KERNEL.toml, offsets in cm or mm)
    pub kernel: PathBuf,

    /// Output format: hlsl, glsl, wgsl (constants, per-pass float4 arrays and a reference blur
    /// function) or json
    #[arg(long)]
    pub format: ShaderFormat,

    /// Unit of the exported tap offsets and KERNEL_RANGE: cm or mm
    #[arg(long, default_value = "cm")]
    pub unit: OffsetUnit,

    /// Output file, or a folder to write KERNEL.FORMAT into (KERNEL: the kernel file's stem)
    /// [default: standard output]
    #[arg(long, value_name = "FILE|DIR")]
    pub out: Option<PathBuf>,
}

pub fn run(a: ExportArgs) -> Result<()> {
    let text = crate::files::read_text(&a.kernel)
        .with_context(|| format!("cannot read kernel {}", a.kernel.display()))?;
    let k = ShaderKernel::from_toml(&text, &a.kernel.display().to_string())?;
    let source = export(&k, a.format, a.unit);
    match &a.out {
        Some(out) => {
            let stem = a
                .kernel
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("kernel");
            let path = out_file(out, &format!("{stem}.{}", a.format));
            let mut files = Outputs::default();
            files.add(&path, source);
            files.commit()?;
            eprintln!(
                "wrote {} ({}: {} pass(es) × {} taps, offsets in {})",
                path.display(),
                a.format,
                k.pass.len(),
                k.taps,
                a.unit
            );
        }
        None => std::io::stdout()
            .write_all(source.as_bytes())
            .context("cannot write to standard output")?,
    }
    Ok(())
}
