//! The original SSSS skin kernel (Jimenez et al., thesis eq. 4.8), built exactly as the public
//! demo does: the red column of d'Eon & Luebke's six-Gaussian skin profile without its 0.0064 mm²
//! term (carried by the strength t instead), per-channel falloff f stretching the radius,
//! r → r/(0.001 + f); taps at quadratic offsets RANGE·sign(o)·o²/RANGE² (RANGE = 2 mm for ≤ 20 taps,
//! 3 above); weights = profile × the width of each tap's interval, normalized per channel; then
//! the strength: centre tap → lerp(1, w₀, t), others × t. Offsets of [`kernel`] are in mm, as in
//! the demo.
//!
//! The width w: eq. 4.8 writes p(w·r/(0.001 + f)), which would *shrink* the kernel as w grows;
//! the demo's shader and the thesis's text ("controls the global size") multiply the tap offsets
//! by the width instead. Here w multiplies the kernel's size, p(r/(w·(0.001 + f))), and w = 1 is
//! the demo's profile read in physical millimetres. Since w and f enter only through
//! w·(0.001 + f), a fit (§4.6, eq. 4.13) chooses each channel's scale and then reports the width
//! that makes the widest channel's falloff 1, as the demo's red channel is.

use argmin::core::{CostFunction, Error, Executor};
use argmin::solver::neldermead::NelderMead;

use crate::error::{FitError, Result};
use crate::kernel2d::Kernel2;
use crate::metrics::{bin_kernel, bin_separable, eval_factor};
use crate::separable::Separable;

/// d'Eon & Luebke (GPU Gems 3) red-channel variances [mm²] and weights, without the 0.0064 term.
const PROFILE: [(f64, f64); 5] = [
    (0.0484, 0.100),
    (0.187, 0.118),
    (0.567, 0.113),
    (1.99, 0.358),
    (7.41, 0.078),
];

/// The SSSS skin model's artist parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Skin {
    /// Strength t per channel in [0, 1]: the share of light the profile spreads (the rest stays
    /// in the centre tap).
    pub strength: [f64; 3],
    /// Falloff f per channel (> −0.001): stretches that channel's profile by 0.001 + f.
    pub falloff: [f64; 3],
    /// Width w (> 0): multiplies every channel's size; 1 = the profile in mm.
    pub width: f64,
}

impl Skin {
    /// The public demo's defaults.
    pub const DEMO: Skin = Skin {
        strength: [0.48, 0.41, 0.28],
        falloff: [1.0, 0.37, 0.3],
        width: 1.0,
    };

    /// Checks the ranges; the error names the field.
    pub fn validate(&self) -> Result<()> {
        for c in 0..3 {
            let (t, f) = (self.strength[c], self.falloff[c]);
            if !(t.is_finite() && (0.0..=1.0).contains(&t)) {
                return Err(FitError::invalid(
                    format!("strength[{c}]"),
                    t,
                    "must lie in [0, 1]",
                ));
            }
            if !(f.is_finite() && f > -0.001) {
                return Err(FitError::invalid(
                    format!("falloff[{c}]"),
                    f,
                    "must be finite and > −0.001",
                ));
            }
        }
        if !(self.width.is_finite() && self.width > 0.0) {
            return Err(FitError::invalid(
                "width",
                self.width,
                "must be positive and finite",
            ));
        }
        Ok(())
    }

    /// Channel `c`'s radius scale w·(0.001 + f) [-].
    fn scale(&self, c: usize) -> f64 {
        self.width * (0.001 + self.falloff[c])
    }

    /// The 1D kernel of channel `c` on a grid of half-width `half` and spacing `h` [cm]: the
    /// profile point-sampled and normalized to Σ = 1, times t, plus (1 − t) in the centre (the
    /// demo's construction with one tap per sample).
    pub fn separable(&self, c: usize, half: usize, h: f64) -> Separable {
        Separable::rank1(h, skin_taps(self.strength[c], self.scale(c), half, h))
    }

    /// The demo's shader kernel: (offset [mm], RGB weight) with the centre tap first, then
    /// increasing offset. Offsets are the demo's (RANGE = 2 or 3 mm) times the width.
    pub fn kernel(&self, taps: usize) -> Vec<(f64, [f64; 3])> {
        let range = if taps > 20 { 3.0 } else { 2.0 };
        let offs = crate::separable::offsets(taps, range);
        let mut k: Vec<(f64, [f64; 3])> = (0..taps)
            .map(|i| {
                let w0 = if i > 0 {
                    (offs[i] - offs[i - 1]).abs()
                } else {
                    0.0
                };
                let w1 = if i + 1 < taps {
                    (offs[i] - offs[i + 1]).abs()
                } else {
                    0.0
                };
                let area = 0.5 * (w0 + w1);
                let p = [0, 1, 2].map(|c| area * profile(offs[i] / (0.001 + self.falloff[c])));
                (offs[i] * self.width, p)
            })
            .collect();
        let centre = k.remove(taps / 2);
        k.insert(0, centre);
        for c in 0..3 {
            let (sum, t): (f64, f64) = (k.iter().map(|t| t.1[c]).sum(), self.strength[c]);
            k.iter_mut().for_each(|x| x.1[c] /= sum);
            k[0].1[c] = (1.0 - t) + t * k[0].1[c];
            k[1..].iter_mut().for_each(|x| x.1[c] *= t);
        }
        k
    }

    /// Fits the model to three channels' normalized ground truths by eq. 4.13: per channel, the
    /// strength t and scale w·(0.001 + f) minimizing ∫(R_d − a_s(x)a_s(y))² (Nelder–Mead over
    /// logit t and log scale, on the kernel binned to a half-width ≤ 100 samples so each cost is
    /// cheap); then w = the largest scale / 1.001 so that the widest channel has f = 1.
    pub fn fit(truths: [&Kernel2; 3]) -> Skin {
        let fits = truths.map(fit_channel);
        let width = fits.iter().map(|f| f.1).fold(0.0, f64::max) / 1.001;
        Skin {
            strength: fits.map(|f| f.0),
            falloff: fits.map(|f| f.1 / width - 0.001),
            width,
        }
    }
}

/// SSSS's internal profile p(r) at radius `r` [mm] (eq. 4.8's Gaussian mixture).
pub fn profile(r: f64) -> f64 {
    PROFILE
        .iter()
        .map(|&(v, w)| w * (-(r * r) / (2.0 * v)).exp() / (2.0 * std::f64::consts::PI * v))
        .sum()
}

/// t·p(10|x|/scale) normalized to Σ = 1 plus (1 − t) at the centre, x on the grid [cm].
fn skin_taps(t: f64, scale: f64, half: usize, h: f64) -> Vec<f64> {
    let a: Vec<f64> = (0..2 * half + 1)
        .map(|i| profile(10.0 * (i as f64 - half as f64).abs() * h / scale))
        .collect();
    let s: f64 = a.iter().sum();
    let mut a: Vec<f64> = a
        .into_iter()
        .map(|x| if s > 0.0 { t * x / s } else { 0.0 })
        .collect();
    a[half] += 1.0 - t;
    a
}

/// (strength, scale) of one channel by eq. 4.13.
fn fit_channel(k: &Kernel2) -> (f64, f64) {
    let factor = eval_factor(k.half, 100);
    let binned = bin_kernel(k, factor);
    let problem = SkinCost {
        k,
        binned: &binned,
        factor,
    };
    // Start: full strength, the scale whose p matches the ground truth's mean radius.
    // (over the quadrant with each sample's multiplicity: the ground truth is mirror-symmetric)
    let n = k.half;
    let multiplicity = |p: usize| if p == 0 { 1.0 } else { 2.0 };
    let mean_r_mm = 10.0
        * (0..=n)
            .flat_map(|p| (0..=n).map(move |q| (p, q)))
            .map(|(p, q)| {
                multiplicity(p)
                    * multiplicity(q)
                    * k.at(n + p, n + q)
                    * k.coord(n + p).hypot(k.coord(n + q))
            })
            .sum::<f64>()
        / k.l1();
    // ∫ r·p(r)·r dr / ∫ p(r)·r dr of the internal profile [mm] (midpoint rule to 30 mm).
    let (num, den) = (0..30_000).fold((0.0, 0.0), |(n, d), i| {
        let r = (i as f64 + 0.5) * 1e-3;
        (n + r * r * profile(r), d + r * profile(r))
    });
    let p_mean_r = num / den;
    let x0 = vec![2.0, (mean_r_mm / p_mean_r).max(1e-4).ln()];
    let simplex = vec![
        x0.clone(),
        vec![x0[0] - 1.5, x0[1]],
        vec![x0[0], x0[1] + 0.7],
    ];
    let best = NelderMead::new(simplex)
        .with_sd_tolerance(1e-10)
        .ok()
        .and_then(|s| {
            Executor::new(problem, s)
                .configure(|st| st.max_iters(300))
                .run()
                .ok()
        })
        .and_then(|r| r.state.best_param.clone())
        .unwrap_or(x0);
    (
        1.0 / (1.0 + (-best[0]).exp()),
        best[1].clamp(-20.0, 20.0).exp(),
    )
}

struct SkinCost<'a> {
    k: &'a Kernel2,
    binned: &'a Kernel2,
    factor: usize,
}

impl CostFunction for SkinCost<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    /// ‖K − a aᵀ‖² on the binned grid (binning commutes with the outer product).
    fn cost(&self, p: &Self::Param) -> std::result::Result<f64, Error> {
        let t = 1.0 / (1.0 + (-p[0]).exp());
        let scale = p[1].clamp(-20.0, 20.0).exp();
        let a = Separable::rank1(self.k.h, skin_taps(t, scale, self.k.half, self.k.h));
        let b = &bin_separable(&a, self.factor).terms[0].a;
        let m = self.binned.side();
        Ok((0..m)
            .flat_map(|i| (0..m).map(move |j| (i, j)))
            .map(|(i, j)| (self.binned.at(i, j) - b[i] * b[j]).powi(2))
            .sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Golden values of the public demo's kernel with its defaults, 17 taps
    /// (shared/reference/thesis_tables.md).
    #[test]
    fn matches_the_public_demo() {
        let k = Skin::DEMO.kernel(17);
        let golden = [
            (0.0, [0.536343, 0.624624, 0.748867]),
            (-2.0, [0.00317394, 0.000134823, 3.77269e-05]),
            (-1.53125, [0.0100386, 0.000914679, 0.000275702]),
            (-1.125, [0.0144609, 0.00317269, 0.00106399]),
        ];
        for (i, (o, w)) in golden.iter().enumerate() {
            assert!((k[i].0 - o).abs() < 1e-12, "offset {i}: {} vs {o}", k[i].0);
            for c in 0..3 {
                assert!(
                    (k[i].1[c] - w[c]).abs() <= 1e-5 * w[c],
                    "tap {i} channel {c}: {} vs {}",
                    k[i].1[c],
                    w[c]
                );
            }
        }
        // Symmetric, and the weights of a channel sum to 1 (the strength lerp keeps the sum).
        for c in 0..3 {
            assert!((k.iter().map(|t| t.1[c]).sum::<f64>() - 1.0).abs() < 1e-12);
        }
        assert!((k[1].1[0] - k[16].1[0]).abs() < 1e-15);
    }

    /// A ground truth made by the skin model itself is recovered by the eq. 4.13 fit.
    #[test]
    fn fit_recovers_a_skin_ground_truth() {
        let truth = Skin {
            strength: [0.9, 0.6, 0.3],
            falloff: [1.0, 0.5, 0.25],
            width: 2.0,
        };
        let (half, h) = (150, 0.004);
        let ks: Vec<Kernel2> = (0..3)
            .map(|c| truth.separable(c, half, h).to_dense())
            .collect();
        let fit = Skin::fit([&ks[0], &ks[1], &ks[2]]);
        for c in 0..3 {
            assert!(
                (fit.strength[c] - truth.strength[c]).abs() < 0.02,
                "t[{c}] {fit:?}"
            );
            let rel = fit.scale(c) / truth.scale(c) - 1.0;
            assert!(rel.abs() < 0.02, "scale[{c}] {fit:?}");
        }
        assert!((fit.falloff[0] - 1.0).abs() < 1e-9);
    }
}
