//! Christensen–Burley normalized diffusion (2015), the profile engines ship:
//! R(r) = A·(e^{−r/d} + e^{−r/(3d)}) / (8π d r), whose integral over the plane is A and whose
//! radial CDF is 1 − ¼e^{−r/d} − ¾e^{−r/(3d)}. Fitted to a ground truth by choosing d [cm] (and A)
//! that minimize the kernel-space squared error; used radially (a dense 2D
//! kernel, as engines do) or projected onto one axis (pre-integrated, rank 1).

use crate::kernel2d::Kernel2;
use crate::preint::preint;
use crate::separable::Separable;

/// A fitted Burley profile: shape d [cm] and total A.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Burley {
    /// Shape length d [cm] of R(r) ∝ (e^{−r/d} + e^{−r/(3d)})/r.
    pub d: f64,
    /// Total A [-]: R's integral over the plane.
    pub a: f64,
}

impl Burley {
    /// The profile Christensen & Burley (2015) give for a medium, from its transport coefficients:
    /// the multiple-scattering albedo A solves their van de Hulst fit
    /// α′ = 1 − (4.09712 + 4.20863A − √(9.59217 + 41.6808A + 17.7126A²))²
    /// ([`mc::artist::multiple_scattering_albedo`]), the searchlight shape factor is
    /// s = 1.85 − A + 7|A − 0.8|³ and d = ℓ/s with ℓ = 1/σt′. The total is A times the entry
    /// transmittance, per unit incident power as MC profiles are.
    pub fn from_medium(m: &crate::analytic::Medium) -> Burley {
        let albedo = m.albedo_reduced();
        // A medium that does not scatter has no diffuse profile.
        let a = mc::artist::multiple_scattering_albedo(albedo);
        let s = 1.85 - a + 7.0 * (a - 0.8).abs().powi(3);
        Burley {
            d: m.transport_mfp() / s,
            a: a * m.entry_transmittance(),
        }
    }

    /// Energy in the disc of radius r: A·(1 − ¼e^{−r/d} − ¾e^{−r/(3d)}).
    pub fn cdf(&self, r: f64) -> f64 {
        self.a * (1.0 - 0.25 * (-r / self.d).exp() - 0.75 * (-r / (3.0 * self.d)).exp())
    }

    /// Density R(r) per unit area [cm⁻²].
    pub fn density(&self, r: f64) -> f64 {
        self.a * ((-r / self.d).exp() + (-r / (3.0 * self.d)).exp())
            / (8.0 * std::f64::consts::PI * self.d * r)
    }

    /// The dense 2D kernel on the ground truth's grid: each sample is the profile's mass over its
    /// h×h cell, by midpoint sub-sampling (finer near the centre); the centre cell, where R has
    /// its integrable 1/r singularity, takes the exact mass of the disc of equal area.
    pub fn kernel(&self, half: usize, h: f64) -> Kernel2 {
        let m = 2 * half + 1;
        let mut v = vec![0.0; m * m];
        // The cell integrals are even in x and y: each of the quadrant's goes to its four mirror
        // images.
        for i in 0..=half {
            for j in 0..=half {
                let value = self.cell_mass(i, j, h);
                for row in [half + i, half - i] {
                    v[row * m + half + j] = value;
                    v[row * m + half - j] = value;
                }
            }
        }
        Kernel2 { half, h, v }
    }

    /// The profile's mass over the h×h cell centred at (j·h, i·h): midpoint sub-sampling, finer
    /// near the centre; the centre cell takes the exact mass of the disc of equal area.
    fn cell_mass(&self, i: usize, j: usize, h: f64) -> f64 {
        let (di, dj) = (i as f64, j as f64);
        let dist = (di * di + dj * dj).sqrt();
        if dist == 0.0 {
            return self.cdf(h / std::f64::consts::PI.sqrt());
        }
        let s = if dist < 4.0 {
            16
        } else if dist < 16.0 {
            4
        } else {
            1
        };
        let mut sum = 0.0;
        for u in 0..s {
            for w in 0..s {
                let x = (dj - 0.5 + (w as f64 + 0.5) / s as f64) * h;
                let y = (di - 0.5 + (u as f64 + 0.5) / s as f64) * h;
                sum += self.density((x * x + y * y).sqrt());
            }
        }
        sum * h * h / (s * s) as f64
    }

    /// Fits d to a ground truth's radial samples: its centre row, sample j at r = j·h holding
    /// the mass of its h×h cell ([`Burley::fit_radial`]).
    pub fn fit(k: &Kernel2) -> Burley {
        let (n, h) = (k.half, k.h);
        let rd: Vec<f64> = (0..=n).map(|j| k.at(n, n + j) / (h * h)).collect();
        Burley::fit_radial(&rd, h)
    }

    /// Fits d to channel `c` of a profile sampled at the radii j·dr of its own bins (what
    /// [`Burley::fit`] sees on [`crate::ground_truth`], without forming the 2D kernel).
    pub fn fit_profile(p: &crate::Profile, c: usize) -> Burley {
        let rd: Vec<f64> = (0..=p.len()).map(|j| p.at(c, j as f64 * p.dr)).collect();
        Burley::fit_radial(&rd, p.dr)
    }

    /// Fits d by golden-section search on log d against radial samples Rd(j·h) [any scale],
    /// weighted by annulus area 2πr·h as the plane's squared error; the model is its density at
    /// each radius and its mean over the disc of area h² at the centre. For each d the total A is
    /// the least-squares optimum (the model is linear in A).
    fn fit_radial(rd: &[f64], h: f64) -> Burley {
        let n = rd.len() - 1;
        let data: Vec<(f64, f64, f64)> = rd
            .iter()
            .enumerate()
            .map(|(j, &v)| {
                let r = j as f64 * h;
                (r, v, 2.0 * std::f64::consts::PI * r.max(0.25 * h) * h)
            })
            .collect();
        let unit_value = |d: f64, r: f64| {
            let b = Burley { d, a: 1.0 };
            if r == 0.0 {
                b.cdf(h / std::f64::consts::PI.sqrt()) / (h * h)
            } else {
                b.density(r)
            }
        };
        let with_best_a = |d: f64| {
            let m: Vec<f64> = data.iter().map(|&(r, _, _)| unit_value(d, r)).collect();
            let a = data
                .iter()
                .zip(&m)
                .map(|(&(_, v, w), p)| w * p * v)
                .sum::<f64>()
                / data
                    .iter()
                    .zip(&m)
                    .map(|(&(_, _, w), p)| w * p * p)
                    .sum::<f64>();
            let cost = data
                .iter()
                .zip(&m)
                .map(|(&(_, v, w), p)| w * (a * p - v).powi(2))
                .sum::<f64>();
            (Burley { d, a }, cost)
        };
        let cost = |ld: f64| with_best_a(ld.exp()).1;
        let (mut lo, mut hi) = ((0.05 * h).ln(), (n as f64 * h).ln());
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (mut f1, mut f2) = (cost(x1), cost(x2));
        for _ in 0..80 {
            if f1 < f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - g * (hi - lo);
                f1 = cost(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + g * (hi - lo);
                f2 = cost(x2);
            }
        }
        with_best_a((0.5 * (lo + hi)).exp()).0
    }

    /// The rank-1 projection of the radial kernel onto one axis (pre-integration).
    pub fn projected(&self, half: usize, h: f64) -> Separable {
        preint(&self.kernel(half, h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdf_integrates_to_a_and_the_kernel_conserves_it() {
        let b = Burley { d: 0.05, a: 0.8 };
        assert_eq!(b.cdf(0.0), 0.0);
        assert!((b.cdf(1e3) - 0.8).abs() < 1e-12);
        // The kernel's samples hold the CDF's mass up to the grid's inscribed disc.
        let k = b.kernel(200, 0.005);
        let inside: f64 = (0..k.side())
            .flat_map(|i| (0..k.side()).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                let (x, y) = (j as f64 - 200.0, i as f64 - 200.0);
                (x * x + y * y).sqrt() <= 150.0
            })
            .map(|(i, j)| k.at(i, j))
            .sum();
        assert!(
            (inside - b.cdf(150.0 * 0.005)).abs() < 2e-3 * b.a,
            "{inside} vs {}",
            b.cdf(0.75)
        );
    }

    #[test]
    fn fit_recovers_a_burley_ground_truth() {
        let truth = Burley { d: 0.03, a: 1.0 };
        let k = truth.kernel(120, 0.004);
        let b = Burley::fit(&k);
        // The radial fit compares cell averages with point densities: exact only to ~1e-4.
        assert!((b.d - 0.03).abs() < 1e-3 * 0.03, "{}", b.d);
    }
}
