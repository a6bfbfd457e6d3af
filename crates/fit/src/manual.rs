//! Manual approximation (Jimenez; thesis §5.4, eq. 5.21): A_m = a_m(x) a_m(y) with
//! a_m = w·G(τ_n) + (1−w)·G(τ_f), G(τ) the zero-mean 1D Gaussian of variance τ, per channel.
//! Parameters come from the thesis's Table A.1 (√τ in mm) or from an automatic fit that minimizes
//! the image-space error on the test signals. On the grid each sample is the Gaussian mixture
//! integrated over its cell (erf), so narrow near-field Gaussians keep their mass.
//!
//! [`WSweep`] is thesis Fig. 5.17: w moves the kernel from far (w = 0) to near scattering (w = 1).
//! The draft calls the mixture "linearly interpolated via w", which holds for a_m; the 2D kernel
//! a_m(x)a_m(y) is quadratic in w: the near pair carries w², the far pair (1−w)² and the cross
//! terms (near along one axis, far along the other) 2w(1−w), so "balanced" w = ½ is a quarter
//! near, a quarter far and half cross.

use argmin::core::{CostFunction, Error, Executor};
use argmin::solver::neldermead::NelderMead;
use serde::Deserialize;

use crate::kernel2d::Kernel2;
use crate::metrics::ImageSize;
use crate::metrics::{ImageEval, edge_response, edge_width};
use crate::separable::Separable;

/// Parameters of one channel: w, and variances τ_n, τ_f [cm²].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Manual {
    /// Weight w of the near Gaussian [-], in [0, 1]; the far one has 1 − w.
    pub w: f64,
    /// Variance τ_n of the near Gaussian [cm²].
    pub tau_near: f64,
    /// Variance τ_f of the far Gaussian [cm²].
    pub tau_far: f64,
}

#[derive(Deserialize)]
struct Row {
    sqrt_tau_near_mm: [f64; 3],
    sqrt_tau_far_mm: [f64; 3],
    w: f64,
}

const TABLE_A1: &str = include_str!("../../../configs/manual_table_a1.toml");

/// The thesis's Table A.1 parameters for a material (apple, ketchup, marble, skin1, wholemilk).
pub fn table_a1(material: &str) -> Option<[Manual; 3]> {
    let table: std::collections::BTreeMap<String, Row> =
        toml::from_str(TABLE_A1).expect("Table A.1 parses");
    let row = table.get(&material.to_lowercase())?;
    Some([0, 1, 2].map(|c| Manual {
        w: row.w,
        tau_near: (0.1 * row.sqrt_tau_near_mm[c]).powi(2),
        tau_far: (0.1 * row.sqrt_tau_far_mm[c]).powi(2),
    }))
}

impl Manual {
    /// Where the image-space fit starts: equal weights, a near Gaussian two samples wide and a
    /// far one an eighth of the kernel's half-width.
    pub fn start(k: &Kernel2) -> Manual {
        Manual::start_with(k, k.h)
    }

    /// [`Manual::start`] with the near Gaussian two bins of width `dr` [cm] wide: on a ground
    /// truth coarser than the profile's bins, the start the bins' own grid gives (the Nelder–Mead
    /// fit finds the minimum nearest its start).
    pub fn start_with(k: &Kernel2, dr: f64) -> Manual {
        Manual {
            w: 0.5,
            tau_near: (2.0 * dr).powi(2),
            tau_far: (k.half as f64 * k.h / 8.0).powi(2),
        }
    }

    /// Checks the ranges; the error names the field.
    pub fn validate(&self) -> crate::Result<()> {
        if !(self.w.is_finite() && (0.0..=1.0).contains(&self.w)) {
            return Err(crate::FitError::invalid("w", self.w, "must lie in [0, 1]"));
        }
        for (field, v) in [("tau_near", self.tau_near), ("tau_far", self.tau_far)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(crate::FitError::invalid(
                    field,
                    v,
                    "variance must be positive and finite",
                ));
            }
        }
        Ok(())
    }

    /// The 1D function on a grid of half-width `half` and spacing `h` [cm], cell-integrated, with
    /// Σ a = 1 (so ‖A‖₁ = 1, the normalized ground truth's).
    pub fn separable(&self, half: usize, h: f64) -> Separable {
        let cdf = |x: f64, tau: f64| 0.5 * (1.0 + libm::erf(x / (2.0 * tau).sqrt()));
        let a: Vec<f64> = (0..2 * half + 1)
            .map(|i| {
                let x = (i as f64 - half as f64) * h;
                let cell = |tau: f64| cdf(x + 0.5 * h, tau) - cdf(x - 0.5 * h, tau);
                self.w * cell(self.tau_near) + (1.0 - self.w) * cell(self.tau_far)
            })
            .collect();
        let s: f64 = a.iter().sum();
        Separable::rank1(h, a.into_iter().map(|x| x / s).collect())
    }

    /// Fits (w, τ_n, τ_f) to minimize Σ over the test signals of the image-space MSE (Nelder–Mead
    /// over (logit w, log τ_n, log τ_f)), starting from `start`.
    pub fn fit_image_space(k: &Kernel2, start: Manual) -> Manual {
        // A coarse evaluation grid keeps each cost evaluation cheap.
        let eval = ImageEval::new(k, 128, 48);
        let problem = ManualCost {
            eval: &eval,
            half: k.half,
            h: k.h,
        };
        let x0 = vec![
            (start.w / (1.0 - start.w)).ln(),
            start.tau_near.ln(),
            start.tau_far.ln(),
        ];
        let mut simplex = vec![x0.clone()];
        for (i, d) in [0.8, 0.8, 0.8].iter().enumerate() {
            let mut p = x0.clone();
            p[i] += d;
            simplex.push(p);
        }
        let best = NelderMead::new(simplex)
            .with_sd_tolerance(1e-8)
            .ok()
            .and_then(|s| {
                Executor::new(problem, s)
                    .configure(|st| st.max_iters(120))
                    .run()
                    .ok()
            })
            .and_then(|r| r.state.best_param.clone())
            .unwrap_or(x0);
        from_params(&best)
    }
}

fn from_params(p: &[f64]) -> Manual {
    let w = 1.0 / (1.0 + (-p[0]).exp());
    let (a, b) = (p[1].clamp(-60.0, 10.0).exp(), p[2].clamp(-60.0, 10.0).exp());
    Manual {
        w,
        tau_near: a.min(b),
        tau_far: a.max(b),
    }
}

struct ManualCost<'a> {
    eval: &'a ImageEval,
    half: usize,
    h: f64,
}

impl CostFunction for ManualCost<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, p: &Self::Param) -> Result<f64, Error> {
        let s = from_params(p).separable(self.half, self.h);
        Ok(self.eval.rms(&s).iter().map(|(_, e)| e * e).sum())
    }
}

/// Thesis Fig. 5.17: the manual model with fixed τ_n, τ_f per channel and w swept over [0, 1].
/// The thesis's claim: raising w moves the kernel "from emphasised far scattering, which offers a
/// more pronounced falloff" to "predominant near scattering, which preserves sharper features".
/// Measured per w and channel: the image-space error against the 2D ground truth and the 10–90 %
/// width of the light across a shadow edge, beside the ground truth's own edge width (exact by
/// pre-integration, eq. 5.15).
#[derive(Clone, Debug)]
pub struct WSweep {
    /// The swept parameters' τ_n, τ_f [cm²] per channel (their w is replaced by each swept w).
    pub params: [Manual; 3],
    /// The swept w, ascending.
    pub w: Vec<f64>,
    /// Per w: RMS over the five test signals of the image-space RMS error per channel (the
    /// images' units: irradiance 1 = white).
    pub image_rms: Vec<[f64; 3]>,
    /// Per w: the 10–90 % edge width [cm] per channel.
    pub edge_width: Vec<[f64; 3]>,
    /// The ground truth's 10–90 % edge width [cm] per channel.
    pub truth_edge_width: [f64; 3],
    /// Edge responses shown in the figure: (w, M(x) per channel on the kernel grid, x from −X to
    /// X with spacing [`WSweep::h`]); dimensionless.
    pub edges: Vec<(f64, [Vec<f64>; 3])>,
    /// The ground truth's edge response per channel (same grid).
    pub truth_edge: [Vec<f64>; 3],
    /// Sample spacing [cm].
    pub h: f64,
}

impl WSweep {
    /// Sweeps `w` (each in [0, 1]) with the τ of `params` on the three channels' normalized
    /// ground truths, with test images of `image`'s size; `shown` are the w whose edge responses
    /// the figure draws.
    pub fn measure(
        truths: &[Kernel2],
        params: [Manual; 3],
        w: &[f64],
        shown: &[f64],
        image: ImageSize,
    ) -> crate::Result<WSweep> {
        let at = |c: usize, w: f64| -> crate::Result<Separable> {
            let m = Manual { w, ..params[c] };
            m.validate()?;
            Ok(m.separable(truths[c].half, truths[c].h))
        };
        let evals: Vec<ImageEval> = truths
            .iter()
            .map(|k| ImageEval::new(k, image.size, image.max_half))
            .collect();
        let mut w = w.to_vec();
        w.sort_by(f64::total_cmp);
        let (mut image_rms, mut widths) = (Vec::new(), Vec::new());
        for &wi in &w {
            let mut e = [0.0; 3];
            let mut width = [0.0; 3];
            for c in 0..3 {
                let s = at(c, wi)?;
                let r = evals[c].rms(&s);
                e[c] = (r.iter().map(|(_, x)| x * x).sum::<f64>() / r.len() as f64).sqrt();
                width[c] = edge_width(&edge_response(&s.terms[0].a), s.h);
            }
            image_rms.push(e);
            widths.push(width);
        }
        let edges = shown
            .iter()
            .map(|&wi| {
                let m = [0, 1, 2].map(|c| at(c, wi).map(|s| edge_response(&s.terms[0].a)));
                let [r, g, b] = m;
                Ok((wi, [r?, g?, b?]))
            })
            .collect::<crate::Result<Vec<_>>>()?;
        // The ground truth's edge is pre-integration's (eq. 5.15): a_p is the column sum of K.
        let truth_edge = [0, 1, 2].map(|c| edge_response(&crate::preint(&truths[c]).terms[0].a));
        Ok(WSweep {
            params,
            truth_edge_width: [0, 1, 2].map(|c| edge_width(&truth_edge[c], truths[c].h)),
            w,
            image_rms,
            edge_width: widths,
            edges,
            truth_edge,
            h: truths[0].h,
        })
    }

    /// The swept w with the lowest image-space error, per channel.
    pub fn best_w(&self) -> [f64; 3] {
        [0, 1, 2].map(|c| {
            let i = (0..self.w.len())
                .min_by(|&i, &j| self.image_rms[i][c].total_cmp(&self.image_rms[j][c]))
                .expect("at least one w is swept");
            self.w[i]
        })
    }
}
