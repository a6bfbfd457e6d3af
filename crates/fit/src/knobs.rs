//! A kernel model refined by the knobs a user sets beside it (`sss fit --rank 3`, `--k`, `--b`,
//! `--renormalize`, the manual model's `--w`, `--tau-near`, `--tau-far`, the skin model's
//! `--strength`, `--falloff`, `--width`): each knob belongs to one family, and one set on a
//! model of another family is refused by name.

use crate::error::{FitError, Result};
use crate::kernel2d::Kernel2;
use crate::manual::Manual;
use crate::model::{KernelModel, ManualParams, SkinParams};
use crate::skin::Skin;

/// The knobs' names, as errors name them.
pub const NAMES: [&str; 10] = [
    "rank",
    "k",
    "b",
    "renormalize",
    "w",
    "tau_near",
    "tau_far",
    "strength",
    "falloff",
    "width",
];

/// The knobs, each `None` (or false) when not set.
#[derive(Clone, Copy, Debug, Default)]
pub struct Knobs {
    /// Rank (svd) or number of Gaussians (deon).
    pub rank: Option<usize>,
    /// Guided optimization: radial weight exponent k.
    pub k: Option<f64>,
    /// Guided optimization: axis suppression b.
    pub b: Option<f64>,
    /// SVD: rescale to ‖A‖₁ = ‖R_d‖₁ (thesis eq. 5.12).
    pub renormalize: bool,
    /// Manual model: weight of the near Gaussian per channel [-].
    pub w: Option<[f64; 3]>,
    /// Manual model: variance of the near Gaussian per channel [mm²].
    pub tau_near: Option<[f64; 3]>,
    /// Manual model: variance of the far Gaussian per channel [mm²].
    pub tau_far: Option<[f64; 3]>,
    /// Skin model: SSSS strength per channel [-].
    pub strength: Option<[f64; 3]>,
    /// Skin model: SSSS falloff per channel [-].
    pub falloff: Option<[f64; 3]>,
    /// Skin model: width multiplier [-].
    pub width: Option<f64>,
}

impl Knobs {
    /// The first knob set of those named, as (name, value) for an error.
    fn first_set(&self, names: &[&'static str]) -> Option<(&'static str, String)> {
        let rgb = |v: Option<[f64; 3]>| v.map(|v| format!("{v:?}"));
        names.iter().find_map(|&n| {
            let v = match n {
                "rank" => self.rank.map(|r| r.to_string()),
                "k" => self.k.map(|x| x.to_string()),
                "b" => self.b.map(|x| x.to_string()),
                "renormalize" => self.renormalize.then(|| "on".to_string()),
                "w" => rgb(self.w),
                "tau_near" => rgb(self.tau_near),
                "tau_far" => rgb(self.tau_far),
                "strength" => rgb(self.strength),
                "falloff" => rgb(self.falloff),
                _ => self.width.map(|x| x.to_string()),
            };
            v.map(|v| (n, v))
        })
    }

    /// `model` with the knobs applied, validated. Manual knobs on a manual model without given
    /// parameters start from its image-space fit to `truths` (the ground truths of `material`).
    pub fn apply(&self, m: KernelModel, truths: &[Kernel2], material: &str) -> Result<KernelModel> {
        const MANUAL: [&str; 3] = ["w", "tau_near", "tau_far"];
        const SKIN: [&str; 3] = ["strength", "falloff", "width"];
        let wrong = |names: &[&'static str], family: &str| -> Result<KernelModel> {
            let (field, value) = self.first_set(names).expect("a knob of the family is set");
            let reason = format!("model {m} takes none (it applies to {family} only)");
            Err(FitError::invalid(field, value, reason))
        };
        let manual_knobs = self.first_set(&MANUAL).is_some();
        let skin_knobs = self.first_set(&SKIN).is_some();
        let model = match m {
            KernelModel::Svd { rank, renormalize } => KernelModel::Svd {
                rank: self.rank.unwrap_or(rank),
                renormalize: renormalize || self.renormalize,
            },
            KernelModel::Deon { n } => KernelModel::Deon {
                n: self.rank.unwrap_or(n),
            },
            KernelModel::Guided { k, b } => KernelModel::Guided {
                k: self.k.unwrap_or(k),
                b: self.b.unwrap_or(b),
            },
            _ if self.rank.is_some() => return wrong(&["rank"], "svd and deon"),
            _ if self.k.is_some() || self.b.is_some() => return wrong(&["k", "b"], "guided"),
            KernelModel::Manual(p) if manual_knobs => {
                let base = match p {
                    ManualParams::Given(g) => g,
                    ManualParams::Auto => match m.fit_truths(truths, material)?.model {
                        KernelModel::Manual(ManualParams::Given(g)) => g,
                        _ => unreachable!("manual resolves to manual"),
                    },
                };
                // Variances are given in mm² and kept in cm².
                KernelModel::Manual(ManualParams::Given([0, 1, 2].map(|c| Manual {
                    w: self.w.map_or(base[c].w, |w| w[c]),
                    tau_near: self.tau_near.map_or(base[c].tau_near, |t| t[c] / 100.0),
                    tau_far: self.tau_far.map_or(base[c].tau_far, |t| t[c] / 100.0),
                })))
            }
            KernelModel::Skin(SkinParams::Given(s)) if skin_knobs => {
                KernelModel::Skin(SkinParams::Given(Skin {
                    strength: self.strength.unwrap_or(s.strength),
                    falloff: self.falloff.unwrap_or(s.falloff),
                    width: self.width.unwrap_or(s.width),
                }))
            }
            m => m,
        };
        if self.renormalize && !matches!(model, KernelModel::Svd { .. }) {
            return wrong(&["renormalize"], "svd");
        }
        if manual_knobs && !matches!(model, KernelModel::Manual(_)) {
            return wrong(&MANUAL, "manual");
        }
        if skin_knobs && !matches!(model, KernelModel::Skin(SkinParams::Given(_))) {
            return wrong(&SKIN, "skin");
        }
        model.validate()?;
        Ok(model)
    }
}
