//! Guided optimization (thesis §5.3, eq. 5.19–5.20; supplement D):
//!
//!   argmin_a Σ_ij Γ_ij (K_ij − a_i a_j)²  subject to  ‖a‖₁² = ‖K‖₁,
//!   Γ(x, y; k, b) = (x̂² + ŷ²)^{k/2} (1 − e^{−b x̂²}) (1 − e^{−b ŷ²}),
//!
//! with x̂, ŷ the coordinates scaled to [−1, 1] over the kernel's half-width; b = 0 means no axis
//! suppression term (both factors are 1). For a ≥ 0 the constraint is linear, Σa = √‖K‖₁.
//!
//! Solver: alternating least squares on the asymmetric problem min Σ Γ (K − a bᵀ)², each half-step
//! exact: with b fixed, aᵢ = max(0, (Nᵢ − μ)/Dᵢ), Nᵢ = Σⱼ Γᵢⱼ Kᵢⱼ bⱼ, Dᵢ = Σⱼ Γᵢⱼ bⱼ², and the
//! multiplier μ found by bisection so that Σa = √‖K‖₁ holds to rounding. A fixed point a = H(a) of
//! this half-step map is a KKT point of the symmetric problem. Plain iteration converges linearly,
//! slowly for k = 0 on wide grids (hundreds of passes on Ketchup's), so the iterates are
//! extrapolated by Anderson acceleration ([`Anderson`]) and projected back onto a ≥ 0,
//! Σa = √‖K‖₁; an extrapolation that raises the objective is replaced by the plain step. The
//! objective comes free with each pass: F(a) = ΣΓK² − 2Σ aᵢNᵢ + Σ aᵢ²Dᵢ at b = a. Rows
//! whose weight is identically zero (the centre line when b > 0) are undetermined by the objective;
//! they take the mean of their neighbours.
//!
//! On a mirror-symmetric kernel (every rotated profile) Γ and the preint start are even, so every
//! iterate is even: the solver works on the kernel's quadrant with index multiplicities c
//! ([`Folded`]), Nᵢ = Σⱼ cⱼ Γᵢⱼ Qᵢⱼ bⱼ, Σa = Σ cᵢ aᵢ, a quarter of the memory traffic per pass for
//! the same iterates. It is not cut to the kernel's support (as the eigensolver is): the
//! multiplier μ < 0 of the L1 constraint gives a a floor −μ/Dᵢ across the whole grid, so the
//! solution depends on the grid's extent, not only on where K has its mass.

use std::time::Instant;

use rayon::prelude::*;

use crate::kernel2d::{Folded, Kernel2};
use crate::separable::Separable;

/// Parameters of the guided optimization.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guided {
    /// Radial weight exponent k (0: uniform, 1: default trade-off, 2: emphasize the falloff).
    pub k: f64,
    /// Axis suppression b on [−1, 1] (0: none; the thesis uses 50).
    pub b: f64,
    /// Enforce ‖a‖₁² = ‖K‖₁ (the model's definition); off only to compare with SVD.
    pub constrained: bool,
    /// Relative change of a below which the iteration stops.
    pub tolerance: f64,
    /// Most half-step passes before stopping with [`GuidedStop::MaxIterations`].
    pub max_iterations: usize,
}

impl Default for Guided {
    fn default() -> Self {
        Guided {
            k: 1.0,
            b: 0.0,
            constrained: true,
            tolerance: 1e-10,
            max_iterations: 2000,
        }
    }
}

/// Why the solver stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GuidedStop {
    /// One half-step changes a by less than the tolerance (relative): a fixed point.
    Converged,
    /// `max_iterations` passes ran first.
    MaxIterations,
}

/// The result with its solver report.
#[derive(Clone, Debug)]
pub struct GuidedFit {
    /// The rank-1 kernel a(x)a(y) on the input kernel's grid.
    pub kernel: Separable,
    /// Half-step passes run (each one pass over the kernel).
    pub iterations: usize,
    /// Why the solver stopped.
    pub stop: GuidedStop,
    /// Wall-clock time of the fit [s].
    pub seconds: f64,
    /// |‖a‖₁² − ‖K‖₁| / ‖K‖₁ of the result.
    pub constraint_error: f64,
    /// Weighted objective Σ Γ (K − a aᵀ)².
    pub objective: f64,
}

impl Guided {
    /// The axis-suppression factor 1 − e^{−b x̂²} (1 when b = 0).
    fn axis(&self, x: f64) -> f64 {
        if self.b == 0.0 {
            1.0
        } else {
            1.0 - (-self.b * x * x).exp()
        }
    }

    /// The weight Γ at scaled coordinates (x̂, ŷ) ∈ [−1, 1]².
    pub fn weight(&self, x: f64, y: f64) -> f64 {
        let radial = if self.k == 0.0 {
            1.0
        } else {
            (x * x + y * y).powf(self.k / 2.0)
        };
        radial * self.axis(x) * self.axis(y)
    }

    /// Fits to `k` the rank-1 kernel a(x)a(y) that minimizes the Γ-weighted error
    /// (eq. 5.19–5.20), under ‖a‖₁² = ‖K‖₁ when `constrained`, starting from the pre-integrated
    /// kernel.
    pub fn fit(&self, k: &Kernel2) -> GuidedFit {
        let start = Instant::now();
        let f = Folded::new(k);
        let (m, v, c) = (f.len, &f.v, &f.c);
        let n = f.half as f64;
        let scaled = |i: usize| if n > 0.0 { f.offset[i] / n } else { 0.0 };
        // Γ is never stored (it would double the memory traffic of every pass): it is evaluated
        // from per-index factors, Γᵢⱼ = radial(x̂ᵢ² + x̂ⱼ²)·sᵢ·sⱼ.
        let w = Weights::new(
            (0..m).map(|i| scaled(i).powi(2)).collect(),
            (0..m).map(|i| self.axis(scaled(i))).collect(),
            c,
            self.k,
        );
        let target = k.l1().sqrt();
        // Sums and norms of functions on the folded indices, as on the full grid.
        let norm = |x: &[f64]| x.iter().zip(c).map(|(x, c)| c * x * x).sum::<f64>().sqrt();
        let distance = |x: &[f64], y: &[f64]| {
            x.iter()
                .zip(y)
                .zip(c)
                .map(|((p, q), c)| c * (p - q).powi(2))
                .sum::<f64>()
                .sqrt()
        };

        // Start from the pre-integrated kernel: positive, meets the constraint.
        let mut x: Vec<f64> = f.fold(&crate::preint::preint(k).terms.remove(0).a);
        // Σᵢⱼ cᵢcⱼΓᵢⱼQᵢⱼ², the objective's constant part: F(x) = C − 2Σ cᵢxᵢNᵢ + Σ cᵢxᵢ²Dᵢ with
        // N, D the sums every half-step computes anyway, so each pass knows its own objective.
        let constant: f64 = (0..m)
            .into_par_iter()
            .map(|i| {
                let row = &v[i * m..(i + 1) * m];
                c[i] * w.row2(i, |j| (row[j] * row[j], 0.0)).0
            })
            .sum();
        let mut anderson = Anderson::new(ANDERSON_DEPTH);
        let mut stop = GuidedStop::MaxIterations;
        let mut iterations = 0;
        // The last iterate and its plain step, and whether the iterate was an extrapolation.
        let mut last: Option<(f64, Vec<f64>)> = None;
        let mut extrapolated = false;
        while iterations < self.max_iterations {
            iterations += 1;
            let (num, den) = self.sums(&w, v, &x, m);
            let objective = constant - 2.0 * (0..m).map(|i| c[i] * x[i] * num[i]).sum::<f64>()
                + (0..m).map(|i| c[i] * x[i] * x[i] * den[i]).sum::<f64>();
            // Safeguard: an extrapolation that raises the objective is dropped for the plain
            // step from the last iterate, and the history restarts.
            if let Some((f_last, g_last)) = &last
                && extrapolated
                && objective > *f_last + 1e-12 * constant.abs()
            {
                x = g_last.clone();
                anderson.clear();
                extrapolated = false;
                continue;
            }
            let mut g = self.solve(&w, &num, &den, target);
            if !self.constrained {
                // Without the constraint only the product a bᵀ is determined: the half-step maps
                // s·v to v/s, so the geometric mean of the two norms is the balanced one.
                let (nx, ng) = (norm(&x), norm(&g));
                if nx > 0.0 && ng > 0.0 {
                    let s = (nx / ng).sqrt();
                    g.iter_mut().for_each(|v| *v *= s);
                }
            }
            let scale = norm(&g).max(f64::MIN_POSITIVE);
            let change = distance(&g, &x) / scale;
            if change < self.tolerance {
                stop = GuidedStop::Converged;
                x = g;
                break;
            }
            // An extrapolation with no positive entry has no projection: take the plain step.
            let next = anderson
                .step(&x, &g, c)
                .filter(|y| !self.constrained || y.iter().any(|&v| v > 0.0))
                .map(|mut y| {
                    if self.constrained {
                        project(&mut y, c, target);
                    }
                    y
                });
            extrapolated = next.is_some();
            x = next.unwrap_or_else(|| g.clone());
            last = Some((objective, g));
        }
        // Stopped at max_iterations: the last plain step meets the constraint and was computed from
        // an evaluated point; an extrapolation after it was not evaluated.
        let a = match (stop, last) {
            (GuidedStop::MaxIterations, Some((_, g))) => g,
            _ => x,
        };
        let objective: f64 = (0..m)
            .into_par_iter()
            .map(|i| {
                let row = &v[i * m..(i + 1) * m];
                c[i] * w.row2(i, |j| ((row[j] - a[i] * a[j]).powi(2), 0.0)).0
            })
            .sum();
        let kernel = Separable::rank1(k.h, f.unfold(&a));
        let l1 = kernel.l1();
        let constraint_error = (l1 - k.l1()).abs() / k.l1();
        GuidedFit {
            kernel,
            iterations,
            stop,
            seconds: start.elapsed().as_secs_f64(),
            constraint_error,
            objective,
        }
    }

    /// The sums of the half-step for fixed `b`: Nᵢ = Σⱼ cⱼΓᵢⱼQᵢⱼbⱼ and Dᵢ = Σⱼ cⱼΓᵢⱼbⱼ², one pass
    /// over the kernel.
    fn sums(&self, w: &Weights, kv: &[f64], b: &[f64], m: usize) -> (Vec<f64>, Vec<f64>) {
        let b2: Vec<f64> = b.iter().map(|x| x * x).collect();
        (0..m)
            .into_par_iter()
            .map(|i| {
                let row = &kv[i * m..(i + 1) * m];
                w.row2(i, |j| (row[j] * b[j], b2[j]))
            })
            .unzip()
    }

    /// The exact minimizer over `a` for fixed `b` (see the module docs), from its sums.
    fn solve(&self, w: &Weights, num: &[f64], den: &[f64], target: f64) -> Vec<f64> {
        let (m, c) = (num.len(), &w.c);
        // Rows whose weight is identically zero are not determined by the objective.
        let free: Vec<bool> = w.s.iter().map(|&s| s == 0.0).collect();
        let solve = |mu: f64| -> Vec<f64> {
            let mut a: Vec<f64> = (0..m)
                .map(|i| {
                    if free[i] || den[i] == 0.0 {
                        0.0
                    } else {
                        (num[i] - mu) / den[i]
                    }
                })
                .collect();
            if self.constrained {
                a.iter_mut().for_each(|x| *x = x.max(0.0));
            }
            for i in (0..m).filter(|&i| free[i]) {
                let (l, r) = (i.checked_sub(1).map(|j| a[j]), a.get(i + 1).copied());
                a[i] = match (l, r) {
                    (Some(l), Some(r)) => 0.5 * (l + r),
                    (Some(v), None) | (None, Some(v)) => v,
                    (None, None) => 0.0,
                };
            }
            a
        };
        if !self.constrained {
            return solve(0.0);
        }
        // Σa(μ) is continuous and non-increasing in μ: bracket and bisect to the last bit.
        let total = |mu: f64| solve(mu).iter().zip(c).map(|(a, c)| c * a).sum::<f64>();
        // Σa(μ) → ∞ as μ → −∞ wherever some Dᵢ > 0, and → 0 as μ → ∞; the doublings are bounded
        // for the degenerate b = 0 (every Dᵢ = 0), where no μ meets the constraint.
        let (mut lo, mut hi) = (-1.0, 1.0);
        for _ in 0..2100 {
            if total(lo) >= target {
                break;
            }
            lo *= 2.0;
        }
        for _ in 0..2100 {
            if total(hi) <= target {
                break;
            }
            hi *= 2.0;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid == lo || mid == hi {
                break;
            }
            if total(mid) > target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let mut a = solve(0.5 * (lo + hi));
        // Remove the last rounding-level mismatch by scaling (relative change ~1e-16).
        let s: f64 = a.iter().zip(c).map(|(a, c)| c * a).sum();
        if s > 0.0 {
            a.iter_mut().for_each(|x| *x *= target / s);
        }
        a
    }
}

/// Γ in factored form: Γᵢⱼ = radial(qᵢ + qⱼ)·sᵢ·sⱼ with qᵢ = x̂ᵢ² and sᵢ the axis factor; sums
/// over j carry each index's multiplicity cⱼ ([`Folded`]).
struct Weights {
    q: Vec<f64>,
    s: Vec<f64>,
    /// Multiplicity of each index.
    c: Vec<f64>,
    /// sⱼ·cⱼ, the column factor of every sum.
    sc: Vec<f64>,
    k: f64,
}

impl Weights {
    fn new(q: Vec<f64>, s: Vec<f64>, c: &[f64], k: f64) -> Self {
        let sc = s.iter().zip(c).map(|(s, c)| s * c).collect();
        Weights {
            q,
            s,
            c: c.to_vec(),
            sc,
            k,
        }
    }

    /// (x̂² + ŷ²)^{k/2}, with the common exponents special-cased.
    #[inline(always)]
    fn radial(&self, r2: f64) -> f64 {
        if self.k == 0.0 {
            1.0
        } else if self.k == 1.0 {
            r2.sqrt()
        } else if self.k == 2.0 {
            r2
        } else {
            r2.powf(0.5 * self.k)
        }
    }

    /// (Σⱼ cⱼ Γᵢⱼ·f(j).0, Σⱼ cⱼ Γᵢⱼ·f(j).1) over row i, with four independent accumulators so the loop
    /// pipelines.
    #[inline(always)]
    fn row2<F: Fn(usize) -> (f64, f64)>(&self, i: usize, f: F) -> (f64, f64) {
        let (qi, m) = (self.q[i], self.q.len());
        let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
        let mut j = 0;
        while j + 4 <= m {
            for l in 0..4 {
                let g = self.radial(qi + self.q[j + l]) * self.sc[j + l];
                let (x, y) = f(j + l);
                a[l] += g * x;
                b[l] += g * y;
            }
            j += 4;
        }
        let (mut ta, mut tb) = (0.0, 0.0);
        while j < m {
            let g = self.radial(qi + self.q[j]) * self.sc[j];
            let (x, y) = f(j);
            ta += g * x;
            tb += g * y;
            j += 1;
        }
        (
            self.s[i] * (a.iter().sum::<f64>() + ta),
            self.s[i] * (b.iter().sum::<f64>() + tb),
        )
    }
}

/// Iterates kept by the Anderson extrapolation.
const ANDERSON_DEPTH: usize = 6;

/// Anderson acceleration of the half-step map H (Walker & Ni 2011, "type II"): from the last
/// iterates xᵢ and their plain steps gᵢ = H(xᵢ), the next iterate is g − ΔG·γ with γ the
/// least-squares coefficients that cancel the newest residual f = g − x against the residuals'
/// differences ΔF (in the folded grid's weighted norm Σ cᵢ·fᵢ²). The plain iteration converges
/// linearly, slowly for k = 0 on wide grids (hundreds of passes); the fixed point is the same.
struct Anderson {
    depth: usize,
    /// Oldest first.
    history: std::collections::VecDeque<Iterate>,
}

impl Anderson {
    fn new(depth: usize) -> Self {
        Anderson {
            depth,
            history: Default::default(),
        }
    }

    fn clear(&mut self) {
        self.history.clear();
    }

    /// Records (x, g = H(x)) and returns the extrapolated next iterate, or `None` while the
    /// history is too short or the least-squares problem is degenerate (take g then).
    fn step(&mut self, x: &[f64], g: &[f64], c: &[f64]) -> Option<Vec<f64>> {
        let f: Vec<f64> = g.iter().zip(x).map(|(g, x)| g - x).collect();
        self.history.push_back(Iterate { f, g: g.to_vec() });
        if self.history.len() > self.depth + 1 {
            self.history.pop_front();
        }
        let n = self.history.len() - 1;
        if n == 0 {
            return None;
        }
        let diff = |k: usize, part: fn(&Iterate) -> &Vec<f64>| {
            let (p, q) = (part(&self.history[k + 1]), part(&self.history[k]));
            p.iter().zip(q).map(|(p, q)| p - q).collect::<Vec<f64>>()
        };
        let df: Vec<Vec<f64>> = (0..n).map(|k| diff(k, |h| &h.f)).collect();
        let dot = |p: &[f64], q: &[f64]| -> f64 {
            p.iter().zip(q).zip(c).map(|((p, q), c)| c * p * q).sum()
        };
        let newest = &self.history[n].f;
        let normal = nalgebra::DMatrix::from_fn(n, n, |i, j| dot(&df[i], &df[j]));
        let rhs = nalgebra::DVector::from_fn(n, |i, _| dot(&df[i], newest));
        // A small ridge keeps nearly parallel differences from amplifying rounding.
        let ridge = 1e-12 * normal.trace().max(f64::MIN_POSITIVE);
        let gamma = (normal + nalgebra::DMatrix::identity(n, n) * ridge)
            .cholesky()?
            .solve(&rhs);
        if !gamma.iter().all(|v| v.is_finite()) {
            return None;
        }
        let mut next = self.history[n].g.clone();
        for (k, gk) in gamma.iter().enumerate() {
            let dg = diff(k, |h| &h.g);
            next.iter_mut().zip(&dg).for_each(|(v, d)| *v -= gk * d);
        }
        Some(next)
    }
}

/// One iterate of [`Anderson`]'s history.
struct Iterate {
    /// The residual gᵢ − xᵢ.
    f: Vec<f64>,
    /// The plain step gᵢ = H(xᵢ).
    g: Vec<f64>,
}

/// Projects onto the constraint set a ≥ 0, Σ cᵢaᵢ = `target` (clip, then rescale; `a` must have a
/// positive entry).
fn project(a: &mut [f64], c: &[f64], target: f64) {
    a.iter_mut().for_each(|v| *v = v.max(0.0));
    let s: f64 = a.iter().zip(c).map(|(a, c)| c * a).sum();
    a.iter_mut().for_each(|v| *v *= target / s);
}
