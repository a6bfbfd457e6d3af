//! Choosing a kernel for a renderer's budget: every model that fits in a number of 1D passes is
//! fitted, sampled into the budget's taps, and scored by its image-space error on the test
//! signals against the 2D ground-truth convolution (thesis §6.2's image-space RMS, with the
//! shader's sparse taps rather than the full-resolution kernel, since the taps are what ships).

use std::fmt;
use std::str::FromStr;

use rayon::prelude::*;

use crate::error::{FitError, Result};
use crate::kernel2d::{Kernel2, cell_ground_truth};
use crate::metrics::{ImageEval, eval_factor};
use crate::model::{KernelModel, ManualParams, SkinParams};
use crate::profile::Profile;
use crate::skin::Skin;
use crate::taps::{ShaderKernel, TapSpec};

/// A renderer's budget: 1D convolution passes (2 per rank-1 term) × taps per pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// 1D convolution passes: even (one horizontal and one vertical per rank-1 term), 2 to 12 when
    /// parsed.
    pub passes: usize,
    /// Taps per pass, 1 to 1025 when parsed.
    pub taps: usize,
}

impl Default for Budget {
    /// SSSS's budget: one horizontal and one vertical pass of 17 taps.
    fn default() -> Self {
        Budget {
            passes: 2,
            taps: 17,
        }
    }
}

impl fmt::Display for Budget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}x{}", self.passes, self.taps)
    }
}

impl FromStr for Budget {
    type Err = String;

    /// `PASSESxTAPS` (also `×` or `X`), e.g. `2x17`; passes even (H + V per term), 2..=12.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let t = s.trim().replace(['×', 'X'], "x");
        let (p, k) = t
            .split_once('x')
            .ok_or_else(|| format!("budget {s:?}: expected PASSESxTAPS, e.g. 2x17"))?;
        let num = |v: &str, what: &str| {
            v.trim()
                .parse::<usize>()
                .map_err(|_| format!("budget {s:?}: {what} {v:?} is not a whole number"))
        };
        let b = Budget {
            passes: num(p, "passes")?,
            taps: num(k, "taps")?,
        };
        if b.passes < 2 || !b.passes.is_multiple_of(2) || b.passes > 12 {
            return Err(format!(
                "budget {s:?}: passes must be even (one horizontal + one vertical per term), 2 to 12"
            ));
        }
        if !(1..=1025).contains(&b.taps) {
            return Err(format!("budget {s:?}: taps must be in 1..=1025"));
        }
        Ok(b)
    }
}

/// The models that fit in `passes` 1D passes: SVD rank-N rescaled to the kernel's energy and
/// d'Eon with N Gaussians for every N ≤ passes/2, and the rank-1 models.
pub fn candidates(passes: usize) -> Vec<KernelModel> {
    let terms = passes / 2;
    let mut m = vec![
        KernelModel::Preint,
        KernelModel::Guided { k: 1.0, b: 0.0 },
        KernelModel::Manual(ManualParams::Auto),
        KernelModel::Skin(SkinParams::Given(Skin::DEMO)),
        KernelModel::Skin(SkinParams::Fit),
        KernelModel::Burley { radial: false },
    ];
    for n in 1..=terms {
        m.push(KernelModel::Svd {
            rank: n,
            renormalize: true,
        });
        if n <= 6 {
            m.push(KernelModel::Deon { n });
        }
    }
    m
}

/// The highest rank an image-error target may climb to.
pub const MAX_RANK: usize = 6;

/// The model of rank `rank` on the ladder an image-error target climbs: 1 pre-integration, 2–6
/// SVD rescaled to the kernel's energy.
pub fn rank_model(rank: usize) -> KernelModel {
    match rank {
        1 => KernelModel::Preint,
        _ => KernelModel::Svd {
            rank,
            renormalize: true,
        },
    }
}

/// The ladder climbed by [`Judge::smallest_rank`]: each rung tried, and the kernel chosen.
#[derive(Clone, Debug)]
pub struct Ladder {
    /// Every rung tried, in order: the rank and its scored kernel.
    pub tried: Vec<(usize, Scored)>,
    /// Whether the last rung met the target (else it is rank [`MAX_RANK`], the best tried).
    pub met: bool,
}

impl Ladder {
    /// The chosen kernel: the last rung tried.
    pub fn chosen(&self) -> &Scored {
        &self.tried.last().expect("a ladder has a rung").1
    }
}

/// One scored candidate.
#[derive(Clone, Debug)]
pub struct Scored {
    /// The model as fitted (parameters resolved).
    pub model: KernelModel,
    /// The fitted kernel sampled into the budget's taps: what a renderer loads.
    pub kernel: ShaderKernel,
    /// Image RMS per channel: the root mean square over the test signals of each signal's RMS
    /// difference to the 2D ground-truth convolution (images in [0, 1]).
    pub image_rms: [f64; 3],
}

impl Scored {
    /// The mean over channels of [`Scored::image_rms`]: the ranking key.
    pub fn error(&self) -> f64 {
        self.image_rms.iter().sum::<f64>() / 3.0
    }

    /// One line of a ranking: the model and its image RMS per channel and mean.
    pub fn line(&self) -> String {
        let e = self.image_rms;
        format!(
            "  {:<34} R {:.2e}  G {:.2e}  B {:.2e}  mean {:.2e}",
            self.model.to_string(),
            e[0],
            e[1],
            e[2],
            self.error()
        )
    }

    /// As JSON: `{"model", "passes" (1D passes), "image_rms", "mean_image_rms"}`.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "model": self.model.to_string(), "passes": 2 * self.kernel.pass.len(),
            "image_rms": self.image_rms, "mean_image_rms": self.error(),
        })
    }
}

/// Ground-truth samples per pixel (per axis) on which [`Judge`] fits and scores the models.
pub const SAMPLES_PER_PIXEL: usize = 5;

/// Per-channel image evaluators of a profile's ground truths (built once, shared by models).
pub struct Judge {
    profile: Profile,
    truths: Vec<Kernel2>,
    evals: Vec<ImageEval>,
}

impl Judge {
    /// Builds the normalized ground truths of `p`'s three channels and their image evaluators
    /// (test signals of 256 px, kernels binned to a half-width of at most 128 px).
    ///
    /// A pixel is the odd number f of profile bins [`eval_factor`] gives, as on the profile's own
    /// grid ([`ground_truth`](crate::kernel2d::ground_truth)). The models are fitted and scored on
    /// a grid of at most [`SAMPLES_PER_PIXEL`] cells per pixel, each cell the mean of Rd over it
    /// from about one subsample per bin ([`cell_ground_truth`]): the same pixel integrals, on
    /// (f / 5)² fewer samples (a profile of 3,201 bins: 1,195² samples against 6,403²).
    pub fn new(p: &Profile) -> Self {
        let f = eval_factor(p.len(), 128);
        let s = f.min(SAMPLES_PER_PIXEL);
        let pixels = (p.len() + f / 2) / f;
        let (h, half, sub) = (
            p.dr * f as f64 / s as f64,
            s * pixels + s / 2,
            f.div_ceil(s),
        );
        let truths: Vec<Kernel2> = (0..3)
            .into_par_iter()
            .map(|c| cell_ground_truth(p, c, h, half, sub))
            .collect();
        let evals = truths
            .par_iter()
            .map(|k| ImageEval::with_factor(k, 256, s))
            .collect();
        Judge {
            profile: p.clone(),
            truths,
            evals,
        }
    }

    /// The normalized ground truths per channel.
    pub fn truths(&self) -> &[Kernel2] {
        &self.truths
    }

    /// Image RMS of channel `c` for a dense 2D kernel on the ground truth's grid (the RMS over the
    /// test signals, as [`Judge::score`]).
    pub fn image_rms_dense(&self, c: usize, k: &Kernel2) -> f64 {
        let e = self.evals[c].rms_dense(k);
        (e.iter().map(|(_, x)| x * x).sum::<f64>() / e.len() as f64).sqrt()
    }

    /// Per-channel image RMS of a shader kernel's taps.
    pub fn score(&self, kernel: &ShaderKernel) -> [f64; 3] {
        [0, 1, 2].map(|c| {
            let k = &self.truths[c];
            let sparse = kernel.to_separable(c, k.h, k.half);
            let e = self.evals[c].rms(&sparse);
            (e.iter().map(|(_, x)| x * x).sum::<f64>() / e.len() as f64).sqrt()
        })
    }

    /// Fits one model and samples it into `taps` taps per pass.
    pub fn kernel(&self, model: KernelModel, material: &str, taps: usize) -> Result<ShaderKernel> {
        let fitted = model.fit_judged(&self.profile, &self.truths, material)?;
        ShaderKernel::from_fitted(
            &fitted,
            material,
            TapSpec {
                taps,
                ..TapSpec::default()
            },
        )
    }

    /// Fits, samples and scores one model.
    pub fn fit_and_score(&self, model: KernelModel, material: &str, taps: usize) -> Result<Scored> {
        let kernel = self.kernel(model, material, taps)?;
        Ok(Scored {
            model: kernel.model,
            image_rms: self.score(&kernel),
            kernel,
        })
    }

    /// The smallest rank of the ladder ([`rank_model`]: 1 pre-integration, 2–[`MAX_RANK`] SVD)
    /// whose kernel of `taps` taps per pass meets the mean image RMS `target`; when none does,
    /// rank [`MAX_RANK`] with `met` false.
    pub fn smallest_rank(&self, target: f64, material: &str, taps: usize) -> Result<Ladder> {
        let mut tried = Vec::new();
        for rank in 1..=MAX_RANK {
            let scored = self.fit_and_score(rank_model(rank), material, taps)?;
            let met = scored.error() <= target;
            tried.push((rank, scored));
            if met {
                return Ok(Ladder { tried, met });
            }
        }
        Ok(Ladder { tried, met: false })
    }

    /// Every candidate for the budget, best (lowest mean image RMS) first.
    pub fn rank(&self, budget: Budget, material: &str) -> Result<Vec<Scored>> {
        let mut scored = candidates(budget.passes)
            .into_par_iter()
            .map(|m| self.fit_and_score(m, material, budget.taps))
            .collect::<Result<Vec<_>>>()?;
        scored.sort_by(|a, b| a.error().total_cmp(&b.error()));
        if scored.is_empty() {
            return Err(FitError::invalid("budget", budget, "no model fits"));
        }
        Ok(scored)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_parse_and_refuse() {
        assert_eq!(
            "2x17".parse::<Budget>().unwrap(),
            Budget {
                passes: 2,
                taps: 17
            }
        );
        assert_eq!(
            "6×33".parse::<Budget>().unwrap(),
            Budget {
                passes: 6,
                taps: 33
            }
        );
        for bad in ["3x17", "0x17", "2x0", "17", "2xq", "14x17"] {
            assert!(bad.parse::<Budget>().is_err(), "{bad}");
        }
    }

    #[test]
    fn candidates_fit_the_budget() {
        for passes in [2, 4, 6, 12] {
            for m in candidates(passes) {
                assert!(m.passes().unwrap() <= passes, "{m} in {passes}");
            }
        }
        assert_eq!(candidates(2).len(), 8);
    }

    /// A profile that is a single Gaussian is exactly separable: at any budget the winner's image
    /// error is far below SSSS's fixed skin kernel's, and more passes never make the best worse.
    #[test]
    fn ranking_prefers_exact_models() {
        let p = Profile::from_fn(0.005, 80, |_, r| (-r * r / (2.0 * 0.03f64.powi(2))).exp());
        let judge = Judge::new(&p);
        let r2 = judge
            .rank(
                Budget {
                    passes: 2,
                    taps: 33,
                },
                "test",
            )
            .unwrap();
        let skin = r2
            .iter()
            .find(|s| s.model == KernelModel::Skin(SkinParams::Given(Skin::DEMO)))
            .unwrap();
        assert!(
            r2[0].error() < 0.1 * skin.error(),
            "{} vs {}",
            r2[0].model,
            skin.error()
        );
        let r4 = judge
            .rank(
                Budget {
                    passes: 4,
                    taps: 33,
                },
                "test",
            )
            .unwrap();
        assert!(r4[0].error() <= r2[0].error() * (1.0 + 1e-9));
    }
}
