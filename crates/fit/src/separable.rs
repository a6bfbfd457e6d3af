//! Separable kernels: a sum of N rank-1 terms s_i·a_i(x)·a_i(y), each applied as one horizontal
//! and one vertical 1D pass (two passes per term). Rank-1 models have one term with s = +1.

use rayon::prelude::*;

use crate::kernel2d::Kernel2;

/// One rank-1 term s·a(x)a(y) on the kernel's grid (length 2n+1, centred).
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// +1 or −1: a symmetric kernel's eigenvalues can be negative.
    pub sign: f64,
    /// The 1D function a on the kernel's grid, 2n+1 samples centred at index n [-].
    pub a: Vec<f64>,
}

/// A separable (sum of rank-1 terms) approximation of one channel's 2D kernel.
#[derive(Clone, Debug, PartialEq)]
pub struct Separable {
    /// Sample spacing [cm].
    pub h: f64,
    /// The rank-1 terms, summed; every term's `a` has the same length.
    pub terms: Vec<Term>,
}

impl Separable {
    /// The rank-1 kernel a(x)a(y) (sign +1) with sample spacing `h` [cm].
    pub fn rank1(h: f64, a: Vec<f64>) -> Self {
        Separable {
            h,
            terms: vec![Term { sign: 1.0, a }],
        }
    }

    /// The identity a(x)a(y) = δ: a unit sample at the centre, half-width `half`, spacing `h`
    /// [cm]. Every model's kernel for a channel that returns no light (it spreads nothing).
    pub fn identity(half: usize, h: f64) -> Self {
        let mut a = vec![0.0; 2 * half + 1];
        a[half] = 1.0;
        Separable::rank1(h, a)
    }

    /// Half-width n of the 1D functions (length 2n+1).
    pub fn half(&self) -> usize {
        self.terms.first().map(|t| t.a.len() / 2).unwrap_or(0)
    }

    /// The dense 2D kernel Σ sᵢ aᵢ aᵢᵀ.
    pub fn to_dense(&self) -> Kernel2 {
        let n = self.half();
        let m = 2 * n + 1;
        let mut v = vec![0.0; m * m];
        for t in &self.terms {
            for i in 0..m {
                let ai = t.sign * t.a[i];
                for j in 0..m {
                    v[i * m + j] += ai * t.a[j];
                }
            }
        }
        Kernel2 {
            half: n,
            h: self.h,
            v,
        }
    }

    /// ‖A‖₁ of the dense kernel, computed without forming it (in closed form for rank 1, row by
    /// row otherwise).
    pub fn l1(&self) -> f64 {
        if let [t] = &self.terms[..] {
            let s: f64 = t.a.iter().map(|x| x.abs()).sum();
            return s * s;
        }
        let n = self.half();
        (0..2 * n + 1)
            .into_par_iter()
            .map(|i| {
                (0..2 * n + 1)
                    .map(|j| {
                        self.terms
                            .iter()
                            .map(|t| t.sign * t.a[i] * t.a[j])
                            .sum::<f64>()
                            .abs()
                    })
                    .sum::<f64>()
            })
            .sum()
    }

    /// Scales the kernel so ‖A‖₁ = `target` (thesis eq. 5.12).
    pub fn renormalized(mut self, target: f64) -> Self {
        let s = (target / self.l1()).sqrt();
        for t in &mut self.terms {
            t.a.iter_mut().for_each(|x| *x *= s);
        }
        self
    }

    /// Scales the kernel so its samples sum to `target` (energy conservation, what SSSS's weight
    /// normalization does; equals eq. 5.12 for non-negative kernels).
    pub fn rescaled_to_sum(mut self, target: f64) -> Self {
        let s = self.sum();
        if s > 0.0 {
            let f = (target / s).sqrt();
            for t in &mut self.terms {
                t.a.iter_mut().for_each(|x| *x *= f);
            }
        }
        self
    }

    /// The kernel's samples sum Σ A(x, y) (= its integral over the grid).
    pub fn sum(&self) -> f64 {
        self.terms
            .iter()
            .map(|t| t.sign * t.a.iter().sum::<f64>().powi(2))
            .sum()
    }
}

/// SSSS's quadratic offsets for `n` taps over [−range, range], centre tap included for odd n.
pub fn offsets(n: usize, range: f64) -> Vec<f64> {
    if n == 1 {
        return vec![0.0];
    }
    let step = 2.0 * range / (n - 1) as f64;
    (0..n)
        .map(|i| {
            let o = -range + i as f64 * step;
            o.signum() * o * o / range
        })
        .collect()
}
