//! `sss fit`: a shader-ready kernel (taps per separable pass) from a profile CSV.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use fit::taps::{ShaderKernel, TapSpec};
use fit::{KernelModel, Profile};
use serde_json::json;

use crate::files::{Outputs, out_file};

/// The kernel model and its parameters, as every command that builds a kernel takes them.
#[derive(Args, Clone)]
pub struct ModelArgs {
    /// Kernel model: svd, svdN, svdN-renorm, preint, guided[-kK][-bB], manual, deonN, skin,
    /// skin-fit (SSSS's strength and falloff fitted to the profile, thesis eq. 4.13), burley.
    /// Full grammar in ARCHITECTURE.md; --rank, --k, --b and the knobs below refine it
    #[arg(long, default_value = "preint")]
    pub model: KernelModel,

    /// Rank (svd) or number of Gaussians (deon): separable passes = 2·N
    #[arg(long)]
    pub rank: Option<usize>,

    /// Guided optimization: radial weight exponent k (0 centre … 2 falloff)
    #[arg(long)]
    pub k: Option<f64>,

    /// Guided optimization: axis suppression b on [−1, 1] (0 = none; the thesis uses 50)
    #[arg(long)]
    pub b: Option<f64>,

    /// SVD: rescale to ‖A‖₁ = ‖R_d‖₁ (thesis eq. 5.12)
    #[arg(long)]
    pub renormalize: bool,

    /// Manual model: weight w of the near Gaussian, in [0, 1] (one value or R,G,B); unset knobs
    /// come from Table A.1 or the image-space fit
    #[arg(long, value_parser = crate::common::parse_rgb, value_name = "W[,W,W]")]
    pub w: Option<[f64; 3]>,

    /// Manual model: variance τ_n of the near Gaussian [mm²] (one value or R,G,B)
    #[arg(long, value_parser = crate::common::parse_rgb, value_name = "MM2[,MM2,MM2]")]
    pub tau_near: Option<[f64; 3]>,

    /// Manual model: variance τ_f of the far Gaussian [mm²] (one value or R,G,B)
    #[arg(long, value_parser = crate::common::parse_rgb, value_name = "MM2[,MM2,MM2]")]
    pub tau_far: Option<[f64; 3]>,

    /// Skin model: SSSS strength t in [0, 1], the share of light scattered (one value or R,G,B)
    /// [default: the demo's 0.48,0.41,0.28]
    #[arg(long, value_parser = crate::common::parse_rgb, value_name = "T[,T,T]")]
    pub strength: Option<[f64; 3]>,

    /// Skin model: SSSS falloff f, each channel's radius stretch 0.001 + f (one value or R,G,B)
    /// [default: the demo's 1,0.37,0.3]
    #[arg(long, value_parser = crate::common::parse_rgb, value_name = "F[,F,F]")]
    pub falloff: Option<[f64; 3]>,

    /// Skin model: width w, multiplies the kernel's size (1 = the demo's profile in mm, taps to
    /// ±2 mm at 17 taps) [default: 1]
    #[arg(long)]
    pub width: Option<f64>,
}

impl ModelArgs {
    /// The model with the knobs applied (`fit::knobs`); a refusal names the flag.
    pub fn resolve(&self, truths: &[fit::Kernel2], material: &str) -> Result<KernelModel> {
        let knobs = fit::knobs::Knobs {
            rank: self.rank,
            k: self.k,
            b: self.b,
            renormalize: self.renormalize,
            w: self.w,
            tau_near: self.tau_near,
            tau_far: self.tau_far,
            strength: self.strength,
            falloff: self.falloff,
            width: self.width,
        };
        knobs
            .apply(self.model, truths, material)
            .map_err(|e| match e {
                fit::FitError::Invalid {
                    field,
                    value,
                    reason,
                } if fit::knobs::NAMES.contains(&field.as_str()) => {
                    anyhow::anyhow!("invalid --{} {value}: {reason}", field.replace('_', "-"))
                }
                e => e.into(),
            })
    }
}

/// Options of how a model is sampled into taps.
#[derive(Args, Clone)]
pub struct TapArgs {
    /// Taps per 1D pass (odd numbers include the centre)
    #[arg(long, default_value_t = 17)]
    pub taps: usize,

    /// Fraction of taps the renderer should jitter per pixel (stored in the kernel file)
    #[arg(long, default_value_t = 0.0)]
    pub jitter: f64,

    /// Fraction of the widest channel's 1D mass inside the tap range (0.95 balances the channels
    /// at 17 taps; the tail beyond still goes into the outer taps' weights)
    #[arg(long, default_value_t = 0.95)]
    pub coverage: f64,
}

impl TapArgs {
    pub fn spec(&self) -> TapSpec {
        TapSpec {
            taps: self.taps,
            coverage: self.coverage,
            jitter: self.jitter,
        }
    }
}

#[derive(Args)]
pub struct FitArgs {
    /// Profile CSV written by `sss simulate` (r_cm,R,G,B,R_se,G_se,B_se)
    profile: PathBuf,

    #[command(flatten)]
    model: ModelArgs,

    #[command(flatten)]
    taps: TapArgs,

    /// Material name (for Table A.1 lookup and the file's header) [default: from the file name]
    #[arg(long)]
    material: Option<String>,

    /// Output kernel file (TOML), or a folder to write MATERIAL.kernel.toml into
    #[arg(long, value_name = "FILE|DIR", default_value = "kernel.toml")]
    out: PathBuf,

    /// Print a machine-readable summary on stdout
    #[arg(long)]
    json: bool,
}

pub fn run(a: FitArgs) -> Result<()> {
    let text = crate::files::read_text(&a.profile)
        .with_context(|| format!("cannot read profile {}", a.profile.display()))?;
    let p = Profile::from_csv(&text, &a.profile.display().to_string())?;
    let file = a.profile.file_name().and_then(|n| n.to_str());
    let stem = file.and_then(|n| n.split('.').next());
    let material = a
        .material
        .clone()
        .unwrap_or(stem.unwrap_or("material").into());
    let start = std::time::Instant::now();
    let spec = a.taps.spec();
    spec.validate()?;
    let truths = fit::ground_truths(&p);
    let fitted = (a.model.resolve(&truths, &material)?).fit_truths(&truths, &material)?;
    let kernel = ShaderKernel::from_fitted(&fitted, &material, spec)?;
    let tap_rms = kernel.tap_error(&p, &fitted);
    eprintln!(
        "taps vs full-resolution kernel, worst image RMS over the test signals: R {:.2e}  G {:.2e}  B {:.2e} (images in [0, 1])",
        tap_rms[0], tap_rms[1], tap_rms[2]
    );
    let name = kernel.model;
    let out = out_file(&a.out, &format!("{material}.kernel.toml"));
    let mut files = Outputs::default();
    files.add(&out, kernel.file_text(&a.profile.display().to_string()));
    files.commit()?;
    let summary = json!({ "model": name.to_string(), "material": material, "out": out, "taps": kernel.taps, "passes": kernel.pass.len(), "range_cm": kernel.range, "taps_vs_full_image_rms": tap_rms, "seconds": start.elapsed().as_secs_f64() });
    if a.json {
        crate::common::print_json(&summary)?;
    } else {
        eprintln!(
            "wrote {} ({name}: {} pass(es) × {} taps, range {:.4} cm) in {:.2} s",
            out.display(),
            kernel.pass.len(),
            kernel.taps,
            kernel.range,
            start.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
