//! `sss fit`: a shader-ready kernel (taps per separable pass) from a profile CSV.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use fit::metrics::ImageEval;
use fit::taps::{Pass, ShaderKernel, Tap};
use fit::{Burley, Gaussians, Guided, Manual, Profile, Separable, ground_truth, preint, svd};
use serde_json::json;

use crate::files::write_atomic;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModelName {
    /// SVD rank-N (thesis §5.1); --rank N
    Svd,
    /// Pre-integration (thesis §5.2)
    Preint,
    /// Guided optimization (thesis §5.3); --k, --b
    Guided,
    /// Manual two-Gaussian model (§5.4): Table A.1 if the material has a row, else an image-space fit
    Manual,
    /// d'Eon sum of N Gaussians; --rank N
    Deon,
    /// The original SSSS skin kernel (eq. 4.8) with the demo's defaults
    Skin,
    /// Christensen–Burley normalized diffusion fitted to the profile, projected onto one axis
    Burley,
}

#[derive(Args)]
pub struct FitArgs {
    /// Profile CSV written by `sss simulate` (r_cm,R,G,B,R_se,G_se,B_se)
    profile: PathBuf,

    /// Kernel model
    #[arg(long, value_enum)]
    model: ModelName,

    /// Rank (svd) or number of Gaussians (deon): separable passes = 2·N
    #[arg(long, default_value_t = 1)]
    rank: usize,

    /// Guided optimization: radial weight exponent k (0 centre … 2 falloff)
    #[arg(long, default_value_t = 1.0)]
    k: f64,

    /// Guided optimization: axis suppression b on [−1, 1] (0 = none; the thesis uses 50)
    #[arg(long, default_value_t = 0.0)]
    b: f64,

    /// SVD: rescale to ‖A‖₁ = ‖R_d‖₁ (thesis eq. 5.12)
    #[arg(long)]
    renormalize: bool,

    /// Taps per 1D pass (odd numbers include the centre)
    #[arg(long, default_value_t = 17)]
    taps: usize,

    /// Fraction of taps the renderer should jitter per pixel (stored in the kernel file)
    #[arg(long, default_value_t = 0.0)]
    jitter: f64,

    /// Fraction of the widest channel's 1D mass inside the tap range (0.95 balances the channels
    /// at 17 taps; the tail beyond still goes into the outer taps' weights)
    #[arg(long, default_value_t = 0.95)]
    coverage: f64,

    /// Material name (for Table A.1 lookup and the file's header) [default: from the file name]
    #[arg(long)]
    material: Option<String>,

    /// Output kernel file (TOML)
    #[arg(long, default_value = "kernel.toml")]
    out: PathBuf,

    /// Print a machine-readable summary on stdout
    #[arg(long)]
    json: bool,
}

/// Fits one model to every channel's normalized ground truth.
fn fit_channels(
    p: &Profile,
    model: ModelName,
    rank: usize,
    k: f64,
    b: f64,
    renormalize: bool,
    material: &str,
) -> Result<Vec<Separable>> {
    (0..3)
        .map(|c| {
            let gt = ground_truth(p, c, None);
            Ok(match model {
                ModelName::Svd if renormalize => svd(&gt, rank).0.renormalized(gt.l1()),
                ModelName::Svd => svd(&gt, rank).0,
                ModelName::Preint => preint(&gt),
                ModelName::Guided => {
                    Guided {
                        k,
                        b,
                        ..Guided::default()
                    }
                    .fit(&gt)
                    .kernel
                }
                ModelName::Manual => {
                    let m = match fit::table_a1(material) {
                        Some(t) => t[c],
                        None => Manual::fit_image_space(
                            &gt,
                            Manual {
                                w: 0.5,
                                tau_near: (2.0 * gt.h).powi(2),
                                tau_far: (gt.half as f64 * gt.h / 8.0).powi(2),
                            },
                        ),
                    };
                    m.separable(gt.half, gt.h)
                }
                ModelName::Deon => Gaussians::fit_up_to(&gt, rank)
                    .pop()
                    .expect("rank ≥ 1")
                    .to_separable(gt.half, gt.h),
                ModelName::Burley => Burley::fit(&gt).projected(gt.half, gt.h),
                ModelName::Skin => bail!("the skin kernel is not fitted"),
            })
        })
        .collect()
}

/// What a kernel is built from, besides the profile.
pub struct KernelSpec<'a> {
    pub model: ModelName,
    pub rank: usize,
    pub k: f64,
    pub b: f64,
    pub renormalize: bool,
    pub material: &'a str,
    pub taps: usize,
    pub coverage: f64,
    pub jitter: f64,
}

/// The shader kernel of one model, and each channel's full-resolution separable fit (empty for
/// the skin kernel, which is not fitted).
pub fn build_kernel(p: &Profile, s: &KernelSpec) -> Result<(ShaderKernel, Vec<Separable>)> {
    let name = format!("{:?}", s.model).to_lowercase();
    if s.model == ModelName::Skin {
        // The demo's own taps, offsets converted from mm to cm.
        let k = fit::skin::kernel(s.taps, fit::skin::FALLOFF, fit::skin::STRENGTH);
        let mut tap: Vec<Tap> = k
            .iter()
            .map(|&(o, w)| Tap {
                offset: 0.1 * o,
                weight: w,
            })
            .collect();
        tap.sort_by(|x, y| x.offset.total_cmp(&y.offset));
        let kernel = ShaderKernel {
            model: name,
            material: s.material.to_string(),
            unit: "cm".into(),
            taps: s.taps,
            range: if s.taps > 20 { 0.3 } else { 0.2 },
            jitter: s.jitter,
            pass: vec![Pass {
                sign: [1.0; 3],
                tap,
            }],
        };
        return Ok((kernel, Vec::new()));
    }
    let chans = fit_channels(p, s.model, s.rank, s.k, s.b, s.renormalize, s.material)?;
    let shader = ShaderKernel::from_separable(
        &name,
        s.material,
        [&chans[0], &chans[1], &chans[2]],
        s.taps,
        s.coverage,
        s.jitter,
    );
    Ok((shader, chans))
}

pub fn run(a: FitArgs) -> Result<()> {
    if a.taps == 0 || a.taps > 1025 {
        bail!("invalid --taps {}: must be in 1..=1025", a.taps);
    }
    if !(0.0..=1.0).contains(&a.jitter) {
        bail!("invalid --jitter {}: must be in [0, 1]", a.jitter);
    }
    if !(a.coverage > 0.0 && a.coverage <= 1.0) {
        bail!("invalid --coverage {}: must be in (0, 1]", a.coverage);
    }
    if a.rank == 0 || a.rank > 32 {
        bail!("invalid --rank {}: must be in 1..=32", a.rank);
    }
    if !a.k.is_finite() || a.k < 0.0 || !a.b.is_finite() || a.b < 0.0 {
        bail!("invalid --k {} / --b {}: must be non-negative", a.k, a.b);
    }
    let text = std::fs::read_to_string(&a.profile)
        .with_context(|| format!("cannot read profile {}", a.profile.display()))?;
    let p = Profile::from_csv(&text, &a.profile.display().to_string())?;
    let material = a.material.clone().unwrap_or_else(|| {
        a.profile
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.split('.').next())
            .unwrap_or("material")
            .to_string()
    });
    let start = std::time::Instant::now();
    let name = format!("{:?}", a.model).to_lowercase();
    let mut tap_rms = Vec::new();
    let (kernel, chans) = build_kernel(
        &p,
        &KernelSpec {
            model: a.model,
            rank: a.rank,
            k: a.k,
            b: a.b,
            renormalize: a.renormalize,
            material: &material,
            taps: a.taps,
            coverage: a.coverage,
            jitter: a.jitter,
        },
    )?;
    // How far the sparse taps are from the full-resolution kernel, on the test signals.
    for (c, full) in chans.iter().enumerate() {
        let gt = ground_truth(&p, c, None);
        let eval = ImageEval::new(&gt, 256, 128);
        let sparse = kernel.to_separable(c, gt.h, gt.half);
        let worst = fit::signals::Signal::ALL
            .iter()
            .map(|&s| {
                let (_, _, f) = eval.images(s, full);
                let (_, _, t) = eval.images(s, &sparse);
                f.rms_diff(&t)
            })
            .fold(0.0, f64::max);
        tap_rms.push(worst);
    }
    if !chans.is_empty() {
        eprintln!(
            "taps vs full-resolution kernel, worst image RMS over the test signals: R {:.2e}  G {:.2e}  B {:.2e} (images in [0, 1])",
            tap_rms[0], tap_rms[1], tap_rms[2]
        );
    }
    let header = format!(
        "# sss fit: model {name}, material {material}, profile {}\n# offsets in cm; each [[pass]] is one horizontal + one vertical 1D convolution; sum the passes' results\n",
        a.profile.display()
    );
    write_atomic(&a.out, (header + &kernel.to_toml()).as_bytes())?;
    let summary = json!({ "model": name, "material": material, "out": a.out, "taps": a.taps, "passes": kernel.pass.len(), "range_cm": kernel.range, "taps_vs_full_image_rms": tap_rms, "seconds": start.elapsed().as_secs_f64() });
    if a.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        eprintln!(
            "wrote {} ({} pass(es) × {} taps, range {:.4} cm) in {:.2} s",
            a.out.display(),
            kernel.pass.len(),
            a.taps,
            kernel.range,
            start.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
