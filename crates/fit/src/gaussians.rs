//! d'Eon & Luebke sums of Gaussians (thesis eq. 4.4): R_d(x, y) ≈ Σᵢ wᵢ G(x, y; vᵢ) with
//! G(x, y; v) = e^{−(x²+y²)/2v} / (2πv), wᵢ ≥ 0 and Σ wᵢ = ‖R_d‖₁ (the L1 constraint; 1 for a
//! normalized kernel). Each 2D Gaussian is separable, G(x,y;v) = g(x;v)·g(y;v), so N Gaussians are
//! applied as N separable pairs (2N passes).
//!
//! Fit: Nelder–Mead (argmin) over log vᵢ; for given variances the weights solve the constrained
//! non-negative least-squares problem exactly (equality by a Lagrange multiplier, non-negativity
//! by an active set). The objective is the kernel-space squared error over the plane,
//! Σ_r 2πr·dr·(R(r) − A(r))² on the profile's radii. N+1 starts from the N solution plus one new
//! variance at the best gap midpoint, so the error never grows with N.

use argmin::core::{CostFunction, Error, Executor};
use argmin::solver::neldermead::NelderMead;
use nalgebra::{DMatrix, DVector};

use crate::kernel2d::Kernel2;
use crate::separable::{Separable, Term};

/// A fitted sum of Gaussians: variances [cm²] and weights (Σw = the fitted L1 norm).
#[derive(Clone, Debug, PartialEq)]
pub struct Gaussians {
    /// Variances vᵢ [cm²].
    pub variances: Vec<f64>,
    /// Weights wᵢ ≥ 0 [-], one per variance.
    pub weights: Vec<f64>,
}

/// Radial samples of the normalized ground truth: r [cm], value per unit area (sum over the
/// plane = 1), and the annulus area 2πr·dr used as weight.
struct Radial {
    r: Vec<f64>,
    value: Vec<f64>,
    area: Vec<f64>,
}

impl Radial {
    fn from_kernel(k: &Kernel2) -> Self {
        // The centre row of the kernel (x ≥ 0) samples R(r) at r = j·h; values per unit area are
        // kernel samples / h².
        let n = k.half;
        let h = k.h;
        let r: Vec<f64> = (0..=n).map(|j| j as f64 * h).collect();
        let value = (0..=n).map(|j| k.at(n, n + j) / (h * h)).collect();
        let area = r
            .iter()
            .map(|&x| 2.0 * std::f64::consts::PI * x.max(0.25 * h) * h)
            .collect();
        Radial { r, value, area }
    }
}

fn g2(r: f64, v: f64) -> f64 {
    (-r * r / (2.0 * v)).exp() / (2.0 * std::f64::consts::PI * v)
}

impl Gaussians {
    /// Weights for fixed variances: argmin Σ area·(R − Σ wᵢGᵢ)², Σw = total, w ≥ 0.
    fn weights_for(radial: &Radial, variances: &[f64], total: f64) -> (Vec<f64>, f64) {
        let n = variances.len();
        let mut active: Vec<bool> = vec![true; n];
        loop {
            let idx: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
            let k = idx.len();
            // KKT system [2GᵀWG 1; 1ᵀ 0][w; λ] = [2GᵀWR; total].
            let mut a = DMatrix::<f64>::zeros(k + 1, k + 1);
            let mut b = DVector::<f64>::zeros(k + 1);
            for (p, &i) in idx.iter().enumerate() {
                for (q, &j) in idx.iter().enumerate() {
                    a[(p, q)] = radial
                        .r
                        .iter()
                        .zip(&radial.area)
                        .map(|(&r, &w)| w * g2(r, variances[i]) * g2(r, variances[j]))
                        .sum();
                }
                b[p] = radial
                    .r
                    .iter()
                    .zip(&radial.area)
                    .zip(&radial.value)
                    .map(|((&r, &w), &v)| w * g2(r, variances[i]) * v)
                    .sum();
                a[(p, k)] = 1.0;
                a[(k, p)] = 1.0;
            }
            b[k] = total;
            let sol = a
                .clone()
                .lu()
                .solve(&b)
                .or_else(|| a.pseudo_inverse(1e-14).ok().map(|pi| pi * &b))
                .unwrap_or_else(|| DVector::zeros(k + 1));
            let mut w = vec![0.0; n];
            for (p, &i) in idx.iter().enumerate() {
                w[i] = sol[p];
            }
            match idx
                .iter()
                .copied()
                .filter(|&i| w[i] < 0.0)
                .min_by(|&x, &y| w[x].total_cmp(&w[y]))
            {
                Some(worst) if k > 1 => active[worst] = false,
                _ => {
                    let w: Vec<f64> = w.into_iter().map(|x| x.max(0.0)).collect();
                    let err = Self::error(radial, variances, &w);
                    return (w, err);
                }
            }
        }
    }

    fn error(radial: &Radial, variances: &[f64], w: &[f64]) -> f64 {
        radial
            .r
            .iter()
            .zip(&radial.area)
            .zip(&radial.value)
            .map(|((&r, &a), &v)| {
                let m: f64 = variances
                    .iter()
                    .zip(w)
                    .map(|(&vi, &wi)| wi * g2(r, vi))
                    .sum();
                a * (v - m).powi(2)
            })
            .sum()
    }

    /// Fits 1…`n` Gaussians to a normalized ground truth; element i has i+1 Gaussians.
    pub fn fit_up_to(k: &Kernel2, n: usize) -> Vec<Gaussians> {
        let radial = Radial::from_kernel(k);
        let total = k.v.iter().sum::<f64>();
        let (v_min, v_max) = ((0.5 * k.h).powi(2), (k.half as f64 * k.h / 2.0).powi(2));
        let mut out: Vec<Gaussians> = Vec::new();
        let mut prev: Vec<f64> = Vec::new();
        for count in 1..=n {
            // Start: the previous variances plus one more, at whichever gap midpoint (between them
            // or beyond either end) gives the lowest error once the weights are re-solved.
            let prev_logs: Vec<f64> = prev.iter().map(|v| v.ln()).collect();
            let cost_of = |logs: &Vec<f64>| {
                Cost {
                    radial: &radial,
                    total,
                }
                .cost(logs)
                .unwrap_or(f64::INFINITY)
            };
            let logs = Self::candidates(&prev_logs, v_min.ln(), v_max.ln())
                .into_iter()
                .map(|l| {
                    let mut c = prev_logs.clone();
                    c.push(l);
                    c.sort_by(f64::total_cmp);
                    c
                })
                .min_by(|a, b| cost_of(a).total_cmp(&cost_of(b)))
                .expect("at least one candidate");
            let problem = Cost {
                radial: &radial,
                total,
            };
            let mut simplex = vec![logs.clone()];
            for i in 0..count {
                let mut p = logs.clone();
                p[i] += 0.7;
                simplex.push(p);
            }
            let best = NelderMead::new(simplex)
                .with_sd_tolerance(1e-12)
                .ok()
                .and_then(|s| {
                    Executor::new(problem, s)
                        .configure(|st| st.max_iters(400 * count as u64))
                        .run()
                        .ok()
                })
                .and_then(|r| r.state.best_param.clone())
                .unwrap_or(logs.clone());
            let start_cost = Cost {
                radial: &radial,
                total,
            }
            .cost(&logs)
            .unwrap_or(f64::INFINITY);
            let best_cost = Cost {
                radial: &radial,
                total,
            }
            .cost(&best)
            .unwrap_or(f64::INFINITY);
            let chosen = if best_cost <= start_cost { best } else { logs };
            let mut variances: Vec<f64> = chosen.iter().map(|l| l.exp()).collect();
            variances.sort_by(f64::total_cmp);
            let (weights, _) = Self::weights_for(&radial, &variances, total);
            prev = variances.clone();
            out.push(Gaussians { variances, weights });
        }
        out
    }

    /// Candidate log-variances for one more Gaussian: the midpoints of the gaps between the
    /// current ones and the ends of [lo, hi].
    fn candidates(logs: &[f64], lo: f64, hi: f64) -> Vec<f64> {
        let mut pts = vec![lo];
        pts.extend(logs.iter().copied());
        pts.push(hi);
        pts.sort_by(f64::total_cmp);
        pts.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
    }

    /// The separable pairs on the kernel's grid: aᵢ(x) ∝ g(x; vᵢ) with Σₓ aᵢ = √wᵢ, so each pair's
    /// discrete sum is exactly wᵢ.
    pub fn to_separable(&self, half: usize, h: f64) -> Separable {
        let terms = self
            .variances
            .iter()
            .zip(&self.weights)
            .filter(|(_, w)| **w > 0.0)
            .map(|(&v, &w)| {
                let g: Vec<f64> = (0..2 * half + 1)
                    .map(|i| (-((i as f64 - half as f64) * h).powi(2) / (2.0 * v)).exp())
                    .collect();
                let s: f64 = g.iter().sum();
                Term {
                    sign: 1.0,
                    a: g.into_iter().map(|x| x * w.sqrt() / s).collect(),
                }
            })
            .collect();
        Separable { h, terms }
    }
}

struct Cost<'a> {
    radial: &'a Radial,
    total: f64,
}

impl CostFunction for Cost<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, logs: &Self::Param) -> Result<f64, Error> {
        let v: Vec<f64> = logs.iter().map(|l| l.clamp(-60.0, 60.0).exp()).collect();
        Ok(Gaussians::weights_for(self.radial, &v, self.total).1)
    }
}
