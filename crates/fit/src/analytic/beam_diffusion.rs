//! Photon beam diffusion (Habel, Christensen & Jarosz 2013) as pbrt evaluates it (pbrt-v3/v4
//! `BeamDiffusionMS`, `BeamDiffusionSS`), the profile Maisch & Ropinski tabulate (their §7.1).
//!
//! Multiple scattering: better-dipole sources (see `better_dipole`) spread along the refracted
//! beam with density σt′e^{−σt′z}, each of strength ρ′² (pbrt's weighting) and damped by Habel's
//! κ = 1 − e^{−2σt′(d_r + z)}; the depth integral is a midpoint rule on the quantiles
//! z_i = −ln(1 − (i + ½)/N)/σt′. Single scattering: the unreduced beam scattered once towards the
//! exit point, Σ ρe^{−σt(d + t_c)}p_HG(cos θ)(1 − F(cos θ))cos θ/d² over t = t_c + exponential
//! quantiles, with t_c = r√(η² − 1) the depth below which the exit would be totally internally
//! reflected.

use super::Medium;
use super::better_dipole::DipoleConstants;
use std::f64::consts::PI;

/// Photon beam diffusion for one channel.
#[derive(Clone, Debug)]
pub struct BeamDiffusion {
    k: DipoleConstants,
    sigma_t_reduced: f64,
    rho_reduced: f64,
    sigma_t: f64,
    rho: f64,
    g: f64,
    eta: f64,
    samples: usize,
    scale: f64,
}

impl BeamDiffusion {
    /// pbrt's quadrature size (100 depths for each term).
    pub const SAMPLES: usize = 100;

    /// Sets up the model with `samples` depths per term.
    pub fn new(m: &Medium, samples: usize) -> Self {
        let sigma_t = m.sigma_a + m.sigma_s;
        BeamDiffusion {
            k: DipoleConstants::new(m),
            sigma_t_reduced: m.sigma_t_reduced(),
            rho_reduced: m.albedo_reduced(),
            sigma_t,
            rho: if sigma_t > 0.0 {
                m.sigma_s / sigma_t
            } else {
                0.0
            },
            g: m.g,
            eta: m.eta,
            samples: samples.max(1),
            scale: m.entry_transmittance(),
        }
    }

    fn quantile(&self, i: usize) -> f64 {
        -(1.0 - (i as f64 + 0.5) / self.samples as f64).ln()
    }

    /// The multiple-scattering part [cm⁻²].
    pub fn multiple(&self, r: f64) -> f64 {
        let st = self.sigma_t_reduced;
        let sum: f64 = (0..self.samples)
            .map(|i| {
                let z = self.quantile(i) / st;
                let kappa = 1.0 - (-2.0 * st * ((r * r + z * z).sqrt() + z)).exp();
                kappa * self.k.exitance(r, z)
            })
            .sum();
        self.scale * self.rho_reduced * self.rho_reduced * sum / self.samples as f64
    }

    /// The single-scattering part [cm⁻²].
    pub fn single(&self, r: f64) -> f64 {
        if self.rho == 0.0 {
            return 0.0;
        }
        let t_c = if self.eta > 1.0 {
            r * (self.eta * self.eta - 1.0).sqrt()
        } else {
            0.0
        };
        let g = self.g;
        let sum: f64 = (0..self.samples)
            .map(|i| {
                let t = t_c + self.quantile(i) / self.sigma_t;
                let d = (r * r + t * t).sqrt();
                let cos_o = t / d;
                // Scattering angle between the downward beam and the path up to the exit point.
                let phase = (1.0 - g * g) / (4.0 * PI * (1.0 + g * g + 2.0 * g * cos_o).powf(1.5));
                let transmit = 1.0 - mc::fresnel(self.eta, 1.0, cos_o).0;
                self.rho * (-self.sigma_t * (d + t_c)).exp() / (d * d) * phase * transmit * cos_o
            })
            .sum();
        self.scale * sum / self.samples as f64
    }

    /// Rd(r) = multiple + single [cm⁻²].
    pub fn rd(&self, r: f64) -> f64 {
        self.multiple(r) + self.single(r)
    }
}
