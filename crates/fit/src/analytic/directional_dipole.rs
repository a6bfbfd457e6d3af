//! The directional dipole (Frisvad, Hachisuka & Kjeldsen 2014; draft §3.5.8) evaluated at normal
//! incidence, where it becomes a radial profile.
//!
//! With x_i at the origin, n = +z, the refracted beam ω₁₂ = −z and x_o = (r, 0, 0):
//! S_d = S′_d(x_o − x_i, ω₁₂, d_r) − S′_d(x_o − x_v, ω_v, d_v), clamped at 0, where
//! S′_d(x, ω, ρ) = 1/(4C_φ(1/η))·1/(4π²)·e^{−σtr ρ}/ρ³·[C_φ(η)(ρ²/D + 3(1 + σtr ρ)x·ω)
//!   − C_E(η)(3D(1 + σtr ρ)ω·n − ((1 + σtr ρ) + 3D(3(1 + σtr ρ) + (σtr ρ)²)/ρ²·x·ω)x·n)],
//! D = 1/(3σt′), σtr = √(σa/D), d_e = 2.131D/√α′, A = (1 − C_E(η))/(2C_φ(η)),
//! d_r² = r² + Dμ₀(Dμ₀ − 2d_e cos β) with μ₀ = 1 and cos β = −√(r²/(r² + d_e²)),
//! x_v = x_i + 2Ad_e n, ω_v = ω₁₂ − 2(ω₁₂·n)n. The BSSRDF is T(ω_i)·S_d·T(ω_o); integrating T(ω_o)
//! cos θ_o over the exit hemisphere gives 4πC_φ(1/η), so Rd(r) = T(0)·4πC_φ(1/η)·S_d.
//! (The draft's eq. 3.9 writes ∫R(n·ω)dω in C_E where (n·ω)² is meant.)

use super::Medium;
use super::fresnel_moments::{c_e, c_phi};
use std::f64::consts::PI;

/// The directional dipole's normal-incidence profile for one channel.
#[derive(Clone, Debug)]
pub struct DirectionalDipole {
    d: f64,
    sigma_tr: f64,
    d_e: f64,
    a: f64,
    c_phi: f64,
    c_e: f64,
    /// T(0)·4πC_φ(1/η)/(4C_φ(1/η)·4π²) = T(0)/(4π): everything outside the bracket but e/ρ³.
    scale: f64,
}

impl DirectionalDipole {
    /// Sets up the model for a medium.
    pub fn new(m: &Medium) -> Self {
        let d = 1.0 / (3.0 * m.sigma_t_reduced());
        let albedo = m.albedo_reduced();
        let (cp, ce) = (c_phi(m.eta), c_e(m.eta));
        DirectionalDipole {
            d,
            sigma_tr: (m.sigma_a / d).sqrt(),
            d_e: 2.131 * d / albedo.sqrt(),
            a: (1.0 - ce) / (2.0 * cp),
            c_phi: cp,
            c_e: ce,
            // A medium that does not scatter (α′ = 0) has no diffuse profile.
            scale: if albedo > 0.0 {
                m.entry_transmittance() * 4.0 * PI * c_phi(1.0 / m.eta)
                    / (4.0 * c_phi(1.0 / m.eta) * 4.0 * PI * PI)
            } else {
                0.0
            },
        }
    }

    /// S′_d's bracket times e^{−σtr ρ}/ρ³ for x·ω = `x_w`, ω·n = `w_n`, x·n = `x_n`.
    fn source(&self, rho: f64, x_w: f64, w_n: f64, x_n: f64) -> f64 {
        let (d, s) = (self.d, self.sigma_tr * rho);
        let bracket = self.c_phi * (rho * rho / d + 3.0 * (1.0 + s) * x_w)
            - self.c_e
                * (3.0 * d * (1.0 + s) * w_n
                    - ((1.0 + s) + 3.0 * d * (3.0 * (1.0 + s) + s * s) / (rho * rho) * x_w) * x_n);
        (-s).exp() / (rho * rho * rho) * bracket
    }

    /// Rd(r) [cm⁻²].
    pub fn rd(&self, r: f64) -> f64 {
        if self.scale == 0.0 {
            return 0.0;
        }
        let (d, de) = (self.d, self.d_e);
        let cos_beta = -(r * r / (r * r + de * de)).sqrt();
        let d_r = (r * r + d * (d - 2.0 * de * cos_beta)).sqrt();
        let real = self.source(d_r, 0.0, -1.0, 0.0);
        let zv = 2.0 * self.a * de;
        let d_v = (r * r + zv * zv).sqrt();
        let virt = self.source(d_v, -zv, 1.0, -zv);
        self.scale * (real - virt).max(0.0)
    }
}
