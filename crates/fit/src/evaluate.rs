//! Evaluation of every kernel model on one material's profile: kernel-space RMS (raw and
//! L1-normalized by eq. 5.12), L1 error, image-space RMS per test signal, fit time; plus what the
//! plots need (kernel slices, singular values, every separable kernel for convolution images).
//!
//! Models ([`MODELS`]): `svd1`–`svd6`, `preint`, `guided-k0`/`k1`/`k2` (b = 0), `manual` (Table
//! A.1 when the material has a row, else the image-space fit; the row's `variant` says which),
//! `deon1`–`deon6`, `skin` (the original SSSS kernel with the demo's parameters, scaled in mm),
//! `skin-fit` (its strength and falloff fitted to the profile, eq. 4.13), `burley` (rank-1
//! pre-integration of the fitted Christensen–Burley kernel) and `burley-radial` (the same kernel
//! dense, convolved in 2D). Rows are keyed by [`KernelModel`]; find one with [`Evaluation::row`].

use std::time::Instant;

use rayon::prelude::*;

use crate::error::Result;
use crate::kernel2d::{Kernel2, SUPPORT_EPSILON, ground_truths};
use crate::manual::table_a1;
pub use crate::metrics::ImageSize;
use crate::metrics::{ImageEval, KernelMetrics};
use crate::model::{KernelModel, ManualParams, SkinParams};
use crate::separable::Separable;
use crate::signals::Signal;
use crate::skin::Skin;
use crate::{Burley, Gaussians, Profile, svd, top_eigen_to};

/// The four rank-1 models of thesis Table 6.3 and Figs. 6.3–6.10, in the thesis's order.
pub const RANK1: [KernelModel; 4] = [
    KernelModel::Svd {
        rank: 1,
        renormalize: false,
    },
    KernelModel::Preint,
    KernelModel::Guided { k: 1.0, b: 0.0 },
    KernelModel::Manual(ManualParams::Auto),
];

/// Every model [`evaluate`] measures, in row order (per channel).
pub const MODELS: [KernelModel; 21] = {
    const fn svd(rank: usize) -> KernelModel {
        KernelModel::Svd {
            rank,
            renormalize: false,
        }
    }
    const fn guided(k: f64) -> KernelModel {
        KernelModel::Guided { k, b: 0.0 }
    }
    const fn deon(n: usize) -> KernelModel {
        KernelModel::Deon { n }
    }
    [
        svd(1),
        svd(2),
        svd(3),
        svd(4),
        svd(5),
        svd(6),
        KernelModel::Preint,
        guided(0.0),
        guided(1.0),
        guided(2.0),
        KernelModel::Manual(ManualParams::Auto),
        deon(1),
        deon(2),
        deon(3),
        deon(4),
        deon(5),
        deon(6),
        KernelModel::Skin(SkinParams::Given(Skin::DEMO)),
        KernelModel::Skin(SkinParams::Fit),
        KernelModel::Burley { radial: false },
        KernelModel::Burley { radial: true },
    ]
};

/// The highest SVD rank and d'Eon Gaussian count in [`MODELS`].
const NESTED: usize = 6;

/// One model on one channel.
#[derive(Clone, Debug)]
pub struct Row {
    /// The model as evaluated; `manual` and `skin-fit` keep their unresolved names (the fitted
    /// parameters differ per material).
    pub model: KernelModel,
    /// Where `manual`'s parameters came from: `table A.1` or `image-space fit`; `None` for the
    /// other models.
    pub variant: Option<&'static str>,
    /// Channel index (R, G, B).
    pub channel: usize,
    /// Kernel-space RMS √(mean over the grid of (K − A)²) against the normalized ground truth K [-]
    /// (thesis §5.1).
    pub kernel_rms: f64,
    /// The same after scaling the model to ‖A‖₁ = ‖K‖₁ (eq. 5.12) [-].
    pub kernel_rms_normalized: f64,
    /// |‖A‖₁ − ‖K‖₁| / ‖K‖₁ before any renormalization [-].
    pub l1_error: f64,
    /// Image RMS per test signal against the ground truth's convolution, the model scaled to the
    /// truth's sum (energy conservation; images in [0, 1]) [-].
    pub image_rms: Vec<(Signal, f64)>,
    /// Fit time of this channel [s]; nested fits (SVD ranks, d'Eon counts) share one time.
    pub fit_seconds: f64,
    /// Main-axis slice A(x, 0) and diagonal slice A(x, x) of the (raw) model, x ≥ 0.
    pub axis: Vec<f64>,
    /// Diagonal slice A(x, x) of the (raw) model, x ≥ 0.
    pub diagonal: Vec<f64>,
}

impl Row {
    /// The row as `sss eval --json` prints it (and `sss.evaluate` returns it): the model, its
    /// family, variant, rank or k where it has one, the channel name, the kernel- and image-space
    /// errors (image RMS per test signal by name) and the fit time.
    pub fn json(&self) -> serde_json::Value {
        let (rank, k) = match self.model {
            KernelModel::Svd { rank, .. } => (Some(rank), None),
            KernelModel::Deon { n } => (Some(n), None),
            KernelModel::Guided { k, .. } => (None, Some(k)),
            _ => (None, None),
        };
        serde_json::json!({
            "model": self.model, "family": self.model.family().name(), "variant": self.variant,
            "rank": rank, "k": k, "channel": mc::CHANNELS[self.channel],
            "kernel_rms": self.kernel_rms, "kernel_rms_normalized": self.kernel_rms_normalized,
            "l1_error": self.l1_error,
            "image_rms": self.image_rms.iter().map(|(s, e)| (s.name().to_string(), serde_json::json!(e))).collect::<serde_json::Map<_, _>>(),
            "fit_seconds": self.fit_seconds,
        })
    }
}

impl Row {
    /// The row's name for tables: the model's name, with the manual model's source in
    /// parentheses (`svd1`, `guided-k1`, `manual (table A.1)`, `burley-radial`, …).
    pub fn label(&self) -> String {
        match self.variant {
            Some(v) => format!("{} ({v})", self.model),
            None => self.model.to_string(),
        }
    }

    /// The row's title for figures: [`KernelModel::title`] with the manual model's source.
    pub fn title(&self) -> String {
        match self.variant {
            Some(v) => format!("{} ({v})", self.model.title()),
            None => self.model.title(),
        }
    }
}

/// Everything measured for one material.
pub struct Evaluation {
    /// [`MODELS`] on channel R, then G, then B.
    pub rows: Vec<Row>,
    /// The first 30 singular values per channel (thesis Fig. 5.1).
    pub singular_values: [Vec<f64>; 3],
    /// Ground truth slices per channel (axis, diagonal), x ≥ 0, and the sample spacing [cm].
    pub truth_axis: [Vec<f64>; 3],
    /// Ground truth diagonal slice K(x, x) per channel, x ≥ 0.
    pub truth_diagonal: [Vec<f64>; 3],
    /// Sample spacing of the kernels and slices [cm].
    pub h: f64,
    /// Every separable model's kernel per channel, for convolution plots.
    pub kernels: Vec<(KernelModel, Vec<Separable>)>,
    /// The image evaluator per channel.
    pub images: Vec<ImageEval>,
}

impl Evaluation {
    /// The row of `model` on channel `c`, if it was evaluated.
    pub fn row(&self, model: KernelModel, c: usize) -> Option<&Row> {
        self.rows
            .iter()
            .find(|r| r.model == model && r.channel == c)
    }

    /// The kernel of a separable `model` on channel `c`, if it was evaluated.
    pub fn kernel(&self, model: KernelModel, c: usize) -> Option<&Separable> {
        self.kernels
            .iter()
            .find(|(m, _)| *m == model)
            .and_then(|(_, k)| k.get(c))
    }
}

fn slices(a: &Separable) -> (Vec<f64>, Vec<f64>) {
    let n = a.half();
    let axis = (0..=n)
        .map(|j| a.terms.iter().map(|t| t.sign * t.a[n + j] * t.a[n]).sum())
        .collect();
    let diag = (0..=n)
        .map(|j| {
            a.terms
                .iter()
                .map(|t| t.sign * t.a[n + j] * t.a[n + j])
                .sum()
        })
        .collect();
    (axis, diag)
}

fn dense_slices(k: &Kernel2) -> (Vec<f64>, Vec<f64>) {
    let n = k.half;
    (
        (0..=n).map(|j| k.at(n, n + j)).collect(),
        (0..=n).map(|j| k.at(n + j, n + j)).collect(),
    )
}

/// Evaluates every model of [`MODELS`] on every channel of a profile. `material` selects Table
/// A.1 rows for `manual`.
pub fn evaluate(p: &Profile, material: &str, image: ImageSize) -> Result<Evaluation> {
    let truths: Vec<Kernel2> = ground_truths(p);
    // (model, kernel per channel, fit seconds per channel) of every separable model, in MODELS
    // order. SVD rank N and d'Eon up to N Gaussians hold every lower rank: one fit each.
    let mut kernels: Vec<(KernelModel, Vec<Separable>, [f64; 3])> = Vec::new();
    // Channels in parallel (the d'Eon fits are sequential within a channel).
    let nested: Vec<_> = truths
        .par_iter()
        .map(|k| {
            let t = Instant::now();
            let svd_n = (svd(k, NESTED).0, t.elapsed().as_secs_f64());
            let t = Instant::now();
            // A channel that returns no light is the identity in every model (below): no fit.
            let gaussians = if k.is_delta() {
                Vec::new()
            } else {
                Gaussians::fit_up_to(k, NESTED)
            };
            let deon_n = (gaussians, t.elapsed().as_secs_f64());
            let spectrum: Vec<f64> = top_eigen_to(k, 30, 1e-6, 200, SUPPORT_EPSILON)
                .values
                .iter()
                .map(|v| v.abs())
                .collect();
            (svd_n, deon_n, spectrum)
        })
        .collect();
    let mut singular_values: [Vec<f64>; 3] = Default::default();
    let (mut svd_n, mut deon_n) = (Vec::new(), Vec::new());
    for (c, (s, d, spectrum)) in nested.into_iter().enumerate() {
        svd_n.push(s);
        deon_n.push(d);
        singular_values[c] = spectrum;
    }
    for model in MODELS {
        let (channels, seconds) = match model {
            KernelModel::Svd { rank, .. } => (
                svd_n
                    .iter()
                    .zip(&truths)
                    .map(|((a, _), k)| Separable {
                        h: k.h,
                        terms: a.terms[..rank.min(a.terms.len())].to_vec(),
                    })
                    .collect(),
                [0, 1, 2].map(|c| svd_n[c].1),
            ),
            KernelModel::Deon { n } => (
                deon_n
                    .iter()
                    .zip(&truths)
                    .map(|((g, _), k)| {
                        // A channel that returns no light: the identity, as every fit gives it.
                        if k.is_delta() {
                            Separable::identity(k.half, k.h)
                        } else {
                            g[n - 1].to_separable(k.half, k.h)
                        }
                    })
                    .collect(),
                [0, 1, 2].map(|c| deon_n[c].1),
            ),
            // Dense, not separable: evaluated below.
            KernelModel::Burley { radial: true } => continue,
            _ => {
                let fitted = model.fit_truths(&truths, material)?;
                (fitted.channels, [0, 1, 2].map(|c| fitted.seconds[c]))
            }
        };
        kernels.push((model, channels, seconds));
    }
    let manual_source = if table_a1(material).is_some() {
        "table A.1"
    } else {
        "image-space fit"
    };

    // Channels in parallel: each is independent (its image evaluation, its metrics, its dense
    // Burley kernel).
    type Channel = (Vec<Row>, (Vec<f64>, Vec<f64>), ImageEval);
    let per_channel: Vec<Channel> = truths
        .par_iter()
        .enumerate()
        .map(|(c, k)| {
            let eval = ImageEval::new(k, image.size, image.max_half);
            let metrics = KernelMetrics::new(k);
            let mut rows: Vec<Row> = kernels
                .iter()
                .map(|(model, channels, seconds)| {
                    let a = &channels[c];
                    let (axis, diagonal) = slices(a);
                    Row {
                        model: *model,
                        variant: matches!(model, KernelModel::Manual(_)).then_some(manual_source),
                        channel: c,
                        kernel_rms: metrics.rms(k, a),
                        kernel_rms_normalized: metrics.rms_normalized(k, a),
                        l1_error: metrics.l1_error(a),
                        image_rms: eval.rms(a),
                        fit_seconds: seconds[c],
                        axis,
                        diagonal,
                    }
                })
                .collect();
            rows.push(burley_radial(k, c, &eval));
            (rows, dense_slices(k), eval)
        })
        .collect();
    let mut rows = Vec::new();
    let mut truth_axis: [Vec<f64>; 3] = Default::default();
    let mut truth_diagonal: [Vec<f64>; 3] = Default::default();
    let mut images = Vec::new();
    for (c, (r, (axis, diagonal), eval)) in per_channel.into_iter().enumerate() {
        rows.extend(r);
        (truth_axis[c], truth_diagonal[c]) = (axis, diagonal);
        images.push(eval);
    }
    Ok(Evaluation {
        rows,
        singular_values,
        truth_axis,
        truth_diagonal,
        h: truths[0].h,
        kernels: kernels.into_iter().map(|(m, k, _)| (m, k)).collect(),
        images,
    })
}

/// Burley's kernel used radially: dense, non-separable, convolved in 2D; its image error with
/// ‖A‖₁ = ‖K‖₁ as for the separable models.
fn burley_radial(k: &Kernel2, c: usize, eval: &ImageEval) -> Row {
    let t = Instant::now();
    let mut dense = if k.is_delta() {
        k.clone()
    } else {
        Burley::fit(k).kernel(k.half, k.h)
    };
    let fit_seconds = t.elapsed().as_secs_f64();
    let kr = |d: &Kernel2| {
        (k.v.iter()
            .zip(&d.v)
            .map(|(p, q)| (p - q).powi(2))
            .sum::<f64>()
            / k.v.len() as f64)
            .sqrt()
    };
    let (axis, diagonal) = dense_slices(&dense);
    let kernel_rms = kr(&dense);
    let l1_error = (dense.l1() - k.l1()).abs() / k.l1();
    // Normalized in place (a second dense kernel is 0.5 GB on Ketchup's grid).
    let s = k.l1() / dense.l1();
    dense.v.iter_mut().for_each(|x| *x *= s);
    Row {
        model: KernelModel::Burley { radial: true },
        variant: None,
        channel: c,
        kernel_rms,
        kernel_rms_normalized: kr(&dense),
        l1_error,
        image_rms: eval.rms_dense(&dense),
        fit_seconds,
        axis,
        diagonal,
    }
}
