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
//!
//! At oblique incidence ([`DirectionalDipole::rd_xy`]) the beam refracts to
//! ω₁₂ = (sin θt, 0, −cos θt), μ₀ = cos θt, cos β = −√((r² − (x·ω₁₂)²)/(r² + d_e²)), the virtual
//! source's direction is ω_v = (sin θt, 0, cos θt), and T(0) becomes T(θi) = 1 − F(θi). On a flat
//! surface the modified tangent-plane normal n* equals n.

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
    /// 4πC_φ(1/η)/(4C_φ(1/η)·4π²) = 1/(4π): everything outside the bracket but e/ρ³ and T(θi)
    /// (0 for a medium that does not scatter).
    scale: f64,
    /// Relative index η.
    eta: f64,
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
                4.0 * PI * c_phi(1.0 / m.eta) / (4.0 * c_phi(1.0 / m.eta) * 4.0 * PI * PI)
            } else {
                0.0
            },
            eta: m.eta,
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

    /// Rd(r) [cm⁻²] at normal incidence.
    pub fn rd(&self, r: f64) -> f64 {
        self.rd_xy(r, 0.0, 0.0)
    }

    /// Rd(x, y) [cm⁻²] per unit incident power for a beam at polar angle `theta_i_deg` in the
    /// plane x–z, travelling towards +x, entering at the origin.
    pub fn rd_xy(&self, x: f64, y: f64, theta_i_deg: f64) -> f64 {
        if self.scale == 0.0 {
            return 0.0;
        }
        let cos_i = theta_i_deg.to_radians().cos();
        let (f, cos_t) = mc::fresnel(1.0, self.eta, cos_i);
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let (d, de) = (self.d, self.d_e);
        let r2 = x * x + y * y;
        let x_w = x * sin_t; // (x_o − x_i)·ω₁₂
        let cos_beta = -((r2 - x_w * x_w).max(0.0) / (r2 + de * de)).sqrt();
        let mu0 = cos_t;
        let d_r = (r2 + d * mu0 * (d * mu0 - 2.0 * de * cos_beta)).sqrt();
        let real = self.source(d_r, x_w, -cos_t, 0.0);
        let zv = 2.0 * self.a * de;
        let d_v = (r2 + zv * zv).sqrt();
        let virt = self.source(d_v, x_w - zv * cos_t, cos_t, -zv);
        (1.0 - f) * self.scale * (real - virt).max(0.0)
    }
}
