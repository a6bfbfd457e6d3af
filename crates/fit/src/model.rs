//! The kernel models as one type, [`KernelModel`], and the one entry point that fits any of them
//! to a profile ([`KernelModel::fit`]). Every place that names a model (the CLI's `--model`, the
//! kernel TOML's `model` field, model selection, exports) goes through this type.
//!
//! Names (`Display`, parsed back by `FromStr`, used by serde):
//!
//! | name | model |
//! |---|---|
//! | `svdN`, `svdN-renorm` | SVD rank-N (§5.1), optionally rescaled to ‖A‖₁ = ‖R_d‖₁ (eq. 5.12) |
//! | `preint` | pre-integration (§5.2) |
//! | `guided-kK`, `guided-kK-bB` | guided optimization (§5.3); bare `guided` is k = 1, b = 0 |
//! | `manual`, `manual(w=…,tn=…,tf=…)` | Jimenez's two Gaussians (§5.4): Table A.1 or an image-space fit, or given w and variances τ_n, τ_f [mm²] per channel (`a/b/c`) |
//! | `deonN` | d'Eon's sum of N Gaussians (eq. 4.4) |
//! | `skin`, `skin(t=…,f=…,w=…)`, `skin-fit` | the SSSS skin kernel (eq. 4.8): the demo's strength t and falloff f, given ones, or fitted to the profile (§4.6, eq. 4.13) |
//! | `burley`, `burley-radial` | Christensen–Burley fitted to the profile, projected to rank 1 or radial (dense 2D, not separable) |
//!
//! Lengths in cm unless a name says mm; every fit returns channel kernels on the ground truth's
//! grid with ‖A‖₁ as the model defines it (see each model's module).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use rayon::prelude::*;

use crate::error::{FitError, Result};
use crate::kernel2d::{Kernel2, ground_truths};
use crate::manual::{Manual, table_a1};
use crate::profile::Profile;
use crate::separable::Separable;
use crate::skin::Skin;
use crate::{Burley, Gaussians, Guided, preint, svd};

/// Where the manual model's parameters come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ManualParams {
    /// Table A.1 when the material has a row, else an image-space fit.
    Auto,
    /// Given per channel (w, τ_n, τ_f in cm²).
    Given([Manual; 3]),
}

/// Where the SSSS skin kernel's parameters come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SkinParams {
    /// Given (the demo's defaults are [`Skin::DEMO`]).
    Given(Skin),
    /// Fitted to the profile by eq. 4.13.
    Fit,
}

/// Every kernel model of the thesis and the baselines engines ship.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KernelModel {
    /// SVD rank-N (§5.1); `renormalize`: rescaled to ‖A‖₁ = ‖R_d‖₁ (eq. 5.12).
    Svd {
        /// Rank N: the number of rank-1 terms, 1 to 32.
        rank: usize,
        /// Rescale to ‖A‖₁ = ‖R_d‖₁ (eq. 5.12).
        renormalize: bool,
    },
    /// Pre-integration (§5.2).
    Preint,
    /// Guided optimization (§5.3): radial exponent k, axis suppression b on [−1, 1].
    Guided {
        /// Radial weight exponent k ≥ 0 ([`Guided::k`]).
        k: f64,
        /// Axis suppression b ≥ 0 on [−1, 1] ([`Guided::b`]; 0: none).
        b: f64,
    },
    /// Manual two-Gaussian model (§5.4).
    Manual(ManualParams),
    /// d'Eon sum of N Gaussians (eq. 4.4): N rank-1 terms.
    Deon {
        /// Number of Gaussians N, 1 to 6.
        n: usize,
    },
    /// The original SSSS skin kernel (eq. 4.8).
    Skin(SkinParams),
    /// Christensen–Burley normalized diffusion fitted to the profile; `radial`: the dense 2D
    /// kernel engines use (not separable), else its rank-1 projection.
    Burley {
        /// The dense 2D kernel instead of its rank-1 projection.
        radial: bool,
    },
}

/// A family of kernel models ([`KernelModel::family`]): plots colour and group models by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// SVD rank-N.
    Svd,
    /// Pre-integration.
    Preint,
    /// Guided optimization.
    Guided,
    /// The manual two-Gaussian model.
    Manual,
    /// d'Eon sums of Gaussians.
    Deon,
    /// The SSSS skin kernel.
    Skin,
    /// Christensen–Burley normalized diffusion.
    Burley,
}

impl Family {
    /// Every family, in the thesis's order.
    pub const ALL: [Family; 7] = [
        Family::Svd,
        Family::Preint,
        Family::Guided,
        Family::Manual,
        Family::Deon,
        Family::Skin,
        Family::Burley,
    ];

    /// The family's name, the stem of every model name of the family (and itself a model name):
    /// `svd`, `preint`, `guided`, `manual`, `deon`, `skin`, `burley`.
    pub fn name(self) -> &'static str {
        match self {
            Family::Svd => "svd",
            Family::Preint => "preint",
            Family::Guided => "guided",
            Family::Manual => "manual",
            Family::Deon => "deon",
            Family::Skin => "skin",
            Family::Burley => "burley",
        }
    }
}

/// A model fitted to the three channels of a profile.
#[derive(Clone, Debug)]
pub struct FittedKernel {
    /// The model as fitted, with parameters resolved (`manual` → its w, τ; `skin-fit` → its t, f, w).
    pub model: KernelModel,
    /// One separable kernel per channel on the channel's ground-truth grid.
    pub channels: Vec<Separable>,
    /// Per channel: wall-clock seconds of its fit (channels are fitted in parallel), plus a third
    /// of resolving parameters shared by the channels (`manual`'s image-space fit, `skin-fit`).
    pub seconds: Vec<f64>,
}

impl KernelModel {
    /// Rank-1 terms, i.e. horizontal + vertical pass pairs; `None` for the radial Burley kernel,
    /// which is not separable.
    pub fn terms(&self) -> Option<usize> {
        match *self {
            KernelModel::Svd { rank, .. } => Some(rank),
            KernelModel::Deon { n } => Some(n),
            KernelModel::Burley { radial: true } => None,
            _ => Some(1),
        }
    }

    /// The model's family: what it is before its parameters.
    pub fn family(&self) -> Family {
        match self {
            KernelModel::Svd { .. } => Family::Svd,
            KernelModel::Preint => Family::Preint,
            KernelModel::Guided { .. } => Family::Guided,
            KernelModel::Manual(_) => Family::Manual,
            KernelModel::Deon { .. } => Family::Deon,
            KernelModel::Skin(_) => Family::Skin,
            KernelModel::Burley { .. } => Family::Burley,
        }
    }

    /// A title for people (legends, panel labels, report tables): `SVD rank-1`,
    /// `pre-integration`, `guided, k = 1`, `d'Eon, 3 Gaussians`, … The name (`Display`) is what
    /// the CLI and files take; the title is only shown.
    pub fn title(&self) -> String {
        match *self {
            KernelModel::Svd { rank, renormalize } => format!(
                "SVD rank-{rank}{}",
                if renormalize { ", renormalized" } else { "" }
            ),
            KernelModel::Preint => "pre-integration".into(),
            KernelModel::Guided { k, b: 0.0 } => format!("guided, k = {k}"),
            KernelModel::Guided { k, b } => format!("guided, k = {k}, b = {b}"),
            KernelModel::Manual(ManualParams::Auto) => "manual".into(),
            KernelModel::Manual(ManualParams::Given(_)) => "manual, given w and τ".into(),
            KernelModel::Deon { n: 1 } => "d'Eon, 1 Gaussian".into(),
            KernelModel::Deon { n } => format!("d'Eon, {n} Gaussians"),
            KernelModel::Skin(SkinParams::Given(s)) if s == Skin::DEMO => {
                "SSSS skin, demo defaults".into()
            }
            KernelModel::Skin(SkinParams::Given(_)) => "SSSS skin, given t, f, w".into(),
            KernelModel::Skin(SkinParams::Fit) => "SSSS skin, fitted (eq. 4.13)".into(),
            KernelModel::Burley { radial: false } => "Burley, rank-1 projection".into(),
            KernelModel::Burley { radial: true } => "Burley, radial 2D".into(),
        }
    }

    /// 1D convolution passes a renderer runs: 2 per rank-1 term (thesis: rank N ⇒ 2N passes).
    pub fn passes(&self) -> Option<usize> {
        self.terms().map(|t| 2 * t)
    }

    /// Checks parameter ranges; the error names the field.
    pub fn validate(&self) -> Result<()> {
        match *self {
            KernelModel::Svd { rank, .. } if !(1..=32).contains(&rank) => {
                Err(FitError::invalid("rank", rank, "must be in 1..=32"))
            }
            KernelModel::Deon { n } if !(1..=6).contains(&n) => Err(FitError::invalid(
                "Gaussians",
                n,
                "d'Eon sums have 1 to 6 Gaussians",
            )),
            KernelModel::Guided { k, b }
                if !(k.is_finite() && k >= 0.0 && b.is_finite() && b >= 0.0) =>
            {
                Err(FitError::invalid(
                    "guided k, b",
                    format!("{k}, {b}"),
                    "must be non-negative and finite",
                ))
            }
            KernelModel::Manual(ManualParams::Given(m)) => m.iter().try_for_each(|c| c.validate()),
            KernelModel::Skin(SkinParams::Given(s)) => s.validate(),
            _ => Ok(()),
        }
    }

    /// Fits the model to every channel's normalized ground truth of `p`; `material` selects
    /// Table A.1 rows for `manual`.
    pub fn fit(&self, p: &Profile, material: &str) -> Result<FittedKernel> {
        self.validate()?;
        let truths: Vec<Kernel2> = ground_truths(p);
        self.fit_truths(&truths, material)
    }

    /// [`KernelModel::fit`] on given per-channel ground truths.
    pub fn fit_truths(&self, truths: &[Kernel2], material: &str) -> Result<FittedKernel> {
        self.fit_with(truths, None, material)
    }

    /// [`KernelModel::fit_truths`] on ground truths made from `p` on a grid of its own
    /// ([`crate::select::Judge`]'s): the models fit the truths, except Burley's d, which is fitted
    /// to the profile at its bins' radii as on `p`'s own grid ([`Burley::fit_profile`]), since a
    /// least-squares fit of its 1/r peak depends on how finely the centre is sampled, and the
    /// manual model's fit starts where it does on `p`'s grid ([`Manual::start_with`]).
    pub fn fit_judged(
        &self,
        p: &Profile,
        truths: &[Kernel2],
        material: &str,
    ) -> Result<FittedKernel> {
        self.fit_with(truths, Some(p), material)
    }

    fn fit_with(
        &self,
        truths: &[Kernel2],
        profile: Option<&Profile>,
        material: &str,
    ) -> Result<FittedKernel> {
        self.validate()?;
        let start = std::time::Instant::now();
        let model = match *self {
            KernelModel::Manual(ManualParams::Auto) => {
                KernelModel::Manual(ManualParams::Given(match table_a1(material) {
                    Some(t) => t,
                    None => {
                        let fitted: Vec<Manual> = truths
                            .par_iter()
                            .map(|k| {
                                let dr = profile.map_or(k.h, |p| p.dr);
                                Manual::fit_image_space(k, Manual::start_with(k, dr))
                            })
                            .collect();
                        [fitted[0], fitted[1], fitted[2]]
                    }
                }))
            }
            KernelModel::Skin(SkinParams::Fit) => {
                KernelModel::Skin(SkinParams::Given(Skin::fit([
                    &truths[0], &truths[1], &truths[2],
                ])))
            }
            m => m,
        };
        let shared = start.elapsed().as_secs_f64() / truths.len() as f64;
        let (channels, seconds) = truths
            .par_iter()
            .enumerate()
            .map(|(c, k)| {
                let t = std::time::Instant::now();
                // A channel that returns no light spreads nothing, whatever the model: the
                // identity (its weight, the channel's reflectance, is 0).
                let fitted = if k.is_delta() {
                    Separable::identity(k.half, k.h)
                } else {
                    model.fit_channel(k, c, profile)?
                };
                Ok((fitted, shared + t.elapsed().as_secs_f64()))
            })
            .collect::<Result<Vec<_>>>()?
            .into_iter()
            .unzip();
        Ok(FittedKernel {
            model,
            channels,
            seconds,
        })
    }

    /// Channel `c` of a model whose parameters are resolved.
    fn fit_channel(&self, k: &Kernel2, c: usize, profile: Option<&Profile>) -> Result<Separable> {
        Ok(match *self {
            KernelModel::Svd { rank, renormalize } => {
                let a = svd(k, rank).0;
                if renormalize {
                    a.renormalized(k.l1())
                } else {
                    a
                }
            }
            KernelModel::Preint => preint(k),
            KernelModel::Guided { k: kk, b } => {
                Guided {
                    k: kk,
                    b,
                    ..Guided::default()
                }
                .fit(k)
                .kernel
            }
            KernelModel::Manual(ManualParams::Given(m)) => m[c].separable(k.half, k.h),
            KernelModel::Deon { n } => Gaussians::fit_up_to(k, n)
                .pop()
                .ok_or_else(|| FitError::invalid("Gaussians", n, "no fit"))?
                .to_separable(k.half, k.h),
            KernelModel::Skin(SkinParams::Given(s)) => s.separable(c, k.half, k.h),
            KernelModel::Burley { radial: false } => match profile {
                Some(p) => Burley::fit_profile(p, c),
                None => Burley::fit(k),
            }
            .projected(k.half, k.h),
            KernelModel::Burley { radial: true } => {
                return Err(FitError::invalid(
                    "model",
                    self,
                    "the radial Burley kernel is not separable; use `burley` (its rank-1 projection)",
                ));
            }
            KernelModel::Manual(ManualParams::Auto) | KernelModel::Skin(SkinParams::Fit) => {
                unreachable!("parameters are resolved in fit_truths")
            }
        })
    }
}

/// A parameter with 6 significant digits (names stay readable; `FromStr` reads them back).
fn g6(x: f64) -> String {
    let r: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    format!("{r}")
}

/// `a/b/c` (three channels) or one value for all.
fn fmt3(v: [f64; 3]) -> String {
    let [a, b, c] = v.map(g6);
    if a == b && b == c {
        a
    } else {
        format!("{a}/{b}/{c}")
    }
}

fn parse3(key: &str, s: &str) -> std::result::Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split('/')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .map_err(|_| format!("{key}={s}: {x:?} is not a number"))
        })
        .collect::<std::result::Result<_, _>>()?;
    match v[..] {
        [a] => Ok([a; 3]),
        [a, b, c] => Ok([a, b, c]),
        _ => Err(format!("{key}={s}: give one value or three (R/G/B)")),
    }
}

/// (key, value) pairs of a parametrized name.
type Params<'a> = Vec<(&'a str, &'a str)>;

/// `name(key=value,…)` → (name, [(key, value)]).
fn split_params(s: &str) -> std::result::Result<(&str, Params<'_>), String> {
    let Some(open) = s.find('(') else {
        return Ok((s, Vec::new()));
    };
    let inner = s[open + 1..]
        .strip_suffix(')')
        .ok_or_else(|| format!("{s:?}: missing ')'"))?;
    let params = inner
        .split(',')
        .map(|kv| {
            kv.split_once('=')
                .map(|(k, v)| (k.trim(), v.trim()))
                .ok_or_else(|| format!("{s:?}: {kv:?} is not key=value"))
        })
        .collect::<std::result::Result<_, _>>()?;
    Ok((&s[..open], params))
}

impl fmt::Display for KernelModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            KernelModel::Svd { rank, renormalize } => {
                write!(f, "svd{rank}{}", if renormalize { "-renorm" } else { "" })
            }
            KernelModel::Preint => write!(f, "preint"),
            KernelModel::Guided { k, b: 0.0 } => write!(f, "guided-k{k}"),
            KernelModel::Guided { k, b } => write!(f, "guided-k{k}-b{b}"),
            KernelModel::Manual(ManualParams::Auto) => write!(f, "manual"),
            KernelModel::Manual(ManualParams::Given(m)) => write!(
                f,
                "manual(w={},tn={},tf={})",
                fmt3(m.map(|c| c.w)),
                fmt3(m.map(|c| c.tau_near * 100.0)),
                fmt3(m.map(|c| c.tau_far * 100.0))
            ),
            KernelModel::Deon { n } => write!(f, "deon{n}"),
            KernelModel::Skin(SkinParams::Fit) => write!(f, "skin-fit"),
            KernelModel::Skin(SkinParams::Given(s)) if s == Skin::DEMO => write!(f, "skin"),
            KernelModel::Skin(SkinParams::Given(s)) => write!(
                f,
                "skin(t={},f={},w={})",
                fmt3(s.strength),
                fmt3(s.falloff),
                g6(s.width)
            ),
            KernelModel::Burley { radial: false } => write!(f, "burley"),
            KernelModel::Burley { radial: true } => write!(f, "burley-radial"),
        }
    }
}

impl FromStr for KernelModel {
    type Err = String;

    fn from_str(text: &str) -> std::result::Result<Self, String> {
        parse_model(text).map_err(|e| {
            if e.contains(text) {
                e
            } else {
                format!("{text:?}: {e}")
            }
        })
    }
}

fn parse_model(text: &str) -> std::result::Result<KernelModel, String> {
    {
        let s = text.trim().to_ascii_lowercase();
        let (name, params) = split_params(&s)?;
        let count = |rest: &str, what: &str| -> std::result::Result<usize, String> {
            if rest.is_empty() {
                return Ok(1);
            }
            rest.parse()
                .map_err(|_| format!("{text:?}: {rest:?} is not a {what}"))
        };
        let model = if let Some(rest) = name.strip_prefix("svd") {
            let (n, renormalize) = match rest.strip_suffix("-renorm") {
                Some(n) => (n, true),
                None => (rest, false),
            };
            KernelModel::Svd {
                rank: count(n, "rank")?,
                renormalize,
            }
        } else if let Some(rest) = name.strip_prefix("deon") {
            KernelModel::Deon {
                n: count(rest, "number of Gaussians")?,
            }
        } else if name == "preint" {
            KernelModel::Preint
        } else if let Some(rest) = name.strip_prefix("guided") {
            let (mut k, mut b) = (1.0, 0.0);
            for part in rest.split('-').filter(|p| !p.is_empty()) {
                let num = |v: &str| {
                    v.parse::<f64>()
                        .map_err(|_| format!("{text:?}: {part:?} is not k<number> or b<number>"))
                };
                match part.split_at(part.chars().next().map_or(0, char::len_utf8)) {
                    ("k", v) => k = num(v)?,
                    ("b", v) => b = num(v)?,
                    _ => return Err(format!("{text:?}: {part:?} is not k<number> or b<number>")),
                }
            }
            KernelModel::Guided { k, b }
        } else if name == "manual" && params.is_empty() {
            KernelModel::Manual(ManualParams::Auto)
        } else if name == "manual" {
            let (mut w, mut tn, mut tf) = (None, None, None);
            for (key, v) in params {
                match key {
                    "w" => w = Some(parse3(key, v)?),
                    "tn" => tn = Some(parse3(key, v)?),
                    "tf" => tf = Some(parse3(key, v)?),
                    _ => {
                        return Err(format!(
                            "{text:?}: unknown manual parameter {key:?} (w, tn, tf)"
                        ));
                    }
                }
            }
            let (Some(w), Some(tn), Some(tf)) = (w, tn, tf) else {
                return Err(format!("{text:?}: manual(...) needs w, tn and tf"));
            };
            KernelModel::Manual(ManualParams::Given([0, 1, 2].map(|c| Manual {
                w: w[c],
                tau_near: tn[c] / 100.0,
                tau_far: tf[c] / 100.0,
            })))
        } else if name == "skin-fit" {
            KernelModel::Skin(SkinParams::Fit)
        } else if name == "skin" {
            let mut s = Skin::DEMO;
            for (key, v) in params {
                match key {
                    "t" => s.strength = parse3(key, v)?,
                    "f" => s.falloff = parse3(key, v)?,
                    "w" => {
                        s.width = v
                            .parse()
                            .map_err(|_| format!("{text:?}: w={v} is not a number"))?
                    }
                    _ => {
                        return Err(format!(
                            "{text:?}: unknown skin parameter {key:?} (t, f, w)"
                        ));
                    }
                }
            }
            KernelModel::Skin(SkinParams::Given(s))
        } else if name == "burley" {
            KernelModel::Burley { radial: false }
        } else if name == "burley-radial" {
            KernelModel::Burley { radial: true }
        } else {
            return Err(format!(
                "unknown kernel model {text:?} (svdN[-renorm], preint, guided[-kK][-bB], manual, deonN, skin, skin-fit, burley, burley-radial)"
            ));
        };
        model.validate().map_err(|e| format!("{text:?}: {e}"))?;
        Ok(model)
    }
}

impl Serialize for KernelModel {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for KernelModel {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        String::deserialize(d)?
            .parse()
            .map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        let models = [
            KernelModel::Svd {
                rank: 3,
                renormalize: true,
            },
            KernelModel::Svd {
                rank: 1,
                renormalize: false,
            },
            KernelModel::Preint,
            KernelModel::Guided { k: 1.55, b: 50.0 },
            KernelModel::Guided { k: 0.0, b: 0.0 },
            KernelModel::Manual(ManualParams::Auto),
            KernelModel::Manual(ManualParams::Given([
                Manual {
                    w: 0.5,
                    tau_near: 1e-4,
                    tau_far: 0.0123,
                },
                Manual {
                    w: 0.5,
                    tau_near: 2e-4,
                    tau_far: 0.01,
                },
                Manual {
                    w: 0.5,
                    tau_near: 3e-4,
                    tau_far: 0.02,
                },
            ])),
            KernelModel::Deon { n: 4 },
            KernelModel::Skin(SkinParams::Fit),
            KernelModel::Skin(SkinParams::Given(Skin::DEMO)),
            KernelModel::Skin(SkinParams::Given(Skin {
                strength: [0.9, 0.5, 0.25],
                falloff: [1.0, 0.5, 0.125],
                width: 3.5,
            })),
            KernelModel::Burley { radial: false },
            KernelModel::Burley { radial: true },
        ];
        for m in models {
            let name = m.to_string();
            let back: KernelModel = name.parse().unwrap();
            // Parameters print with 6 significant digits: the name is stable, and so is every
            // model whose parameters have no more digits.
            assert_eq!(back.to_string(), name);
            if !matches!(m, KernelModel::Manual(ManualParams::Given(_))) {
                assert_eq!(back, m, "{name}");
            }
            // The TOML field carries the same name.
            #[derive(Serialize, Deserialize)]
            struct F {
                model: KernelModel,
            }
            let t = toml::to_string(&F { model: m }).unwrap();
            assert_eq!(toml::from_str::<F>(&t).unwrap().model.to_string(), name);
            // A family's name is itself a name, of the same family.
            assert_eq!(
                m.family().name().parse::<KernelModel>().unwrap().family(),
                m.family()
            );
        }
        // Bare family names take the thesis's defaults.
        assert_eq!(
            "svd".parse::<KernelModel>().unwrap(),
            KernelModel::Svd {
                rank: 1,
                renormalize: false
            }
        );
        assert_eq!(
            "guided".parse::<KernelModel>().unwrap(),
            KernelModel::Guided { k: 1.0, b: 0.0 }
        );
        assert_eq!(
            "Deon".parse::<KernelModel>().unwrap(),
            KernelModel::Deon { n: 1 }
        );
    }

    #[test]
    fn bad_names_are_refused_with_the_value() {
        for bad in [
            "svd0",
            "svdx",
            "deon7",
            "guided-kx",
            "guided-k-1",
            "manual(w=1)",
            "skin(q=1)",
            "skin(t=2)",
            "gauss",
            "skin(t=1/2)",
        ] {
            let e = bad.parse::<KernelModel>().unwrap_err();
            assert!(
                e.contains(bad) || e.contains(&bad.to_ascii_lowercase()),
                "{bad}: {e}"
            );
        }
    }

    #[test]
    fn pass_counts_follow_the_rank() {
        assert_eq!(
            KernelModel::Svd {
                rank: 3,
                renormalize: false
            }
            .passes(),
            Some(6)
        );
        assert_eq!(KernelModel::Deon { n: 2 }.passes(), Some(4));
        assert_eq!(KernelModel::Preint.passes(), Some(2));
        assert_eq!(KernelModel::Burley { radial: true }.passes(), None);
    }
}
