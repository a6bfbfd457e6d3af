//! The directional dipole (Frisvad, Hachisuka & Kjeldsen 2014; draft §3.5.8): a BSSRDF that
//! depends on the direction of the incident light, for arbitrary surface geometry.
//!
//! S(x_i, ω_i; x_o, ω_o) = T(η, ω_i)·[S_d(x_i, ω_i; x_o) + S_δE]·T(η, ω_o). The diffuse part is a
//! real ray source along the refracted direction ω₁₂ minus a virtual one:
//! S_d = S′_d(x_o − x_i, ω₁₂, d_r) − S′_d(x_o − x_v, ω_v, d_v), clamped at 0, with (eq. 3.7)
//! S′_d(x, ω, ρ) = 1/(4C_φ(1/η))·1/(4π²)·e^{−σtr ρ}/ρ³·[C_φ(η)(ρ²/D + 3(1 + σtr ρ)x·ω)
//!   − C_E(η)(3D(1 + σtr ρ)ω·n_o − ((1 + σtr ρ) + 3D(3(1 + σtr ρ) + (σtr ρ)²)/ρ²·x·ω)x·n_o)],
//! D = 1/(3σt′), σtr = √(σa/D), d_e = 2.131D/√α′, A = (1 − C_E(η))/(2C_φ(η)), and
//! - the modified tangent-plane normal n*_i = x̂ × (n_i × x)/|n_i × x| (n_i where x_o = x_i or
//!   x ∥ n_i), x = x_o − x_i;
//! - the virtual source x_v = x_i + 2A·d_e·n*_i with direction ω_v = ω₁₂ − 2(ω₁₂·n*_i)n*_i;
//! - the distance to the real source, with μ₀ = −ω₁₂·n_o:
//!   d_r² = r² + Dμ₀(Dμ₀ − 2d_e cos β) where μ₀ > 0 (front-lit),
//!   d_r² = r² + 1/(3σt)² otherwise (back-lit: light through a thin part), σt = σa + σs
//!   unreduced, and cos β = −√((r² − (x·ω₁₂)²)/(r² + d_e²)).
//!
//! Integrating T(ω_o) cos θ_o over the exit hemisphere gives 4πC_φ(1/η), so on a flat surface
//! the exitance per unit incident power is Rd = T(θ_i)·4πC_φ(1/η)·S_d ([`DirectionalDipole::rd_xy`]).
//!
//! S_δE is the δ-Eddington reduced intensity (Joseph, Wiscombe & Weinman 1976): the phase
//! function's forward peak (fraction g² of scattering events) is folded into the unscattered
//! beam, which then decays with σt* = σa + σs(1 − g²) along the refracted ray. It is a δ in
//! position and direction (the beam leaves only where the refracted ray meets the surface again,
//! along its own continuation), so [`DirectionalDipole::reduced_intensity`] gives its weight
//! e^{−σt* s} for a path of length s inside; renderers add it only where the view direction is
//! that continuation.
//!
//! Errors of the draft fixed here (each also checked in a test):
//! - §3.5.6 writes the fluence as Φ/(4πD)·e^{+σtr r}/r, growing without bound; the Green's
//!   function of the diffusion equation decays, e^{−σtr r}.
//! - Eq. 3.9 writes ∫R(n·ω)dω inside C_E, where eq. 3.8's (n·ω)² is meant
//!   ([`super::fresnel_moments::c_e`] uses the second moment).
//! - §4.3's importance-sampling weight: the text divides each sample by e^{−σtr r}, the
//!   equations multiply by it, and both keep the uniform disc's A_c/N. An unbiased estimator
//!   divides by the sampling density, here per unit area of the disc:
//!   σtr e^{−σtr r}/(2πr(1 − e^{−σtr r*})) (`gpu::dipole`, tested there against quadrature).
//! - Table 4.1 prints Apple's blue σa as 0.0046 mm⁻¹; Jensen et al. 2001 measured 0.046 mm⁻¹,
//!   the value that reproduces their measured total reflectance 0.53 (test
//!   `apple_blue_absorption_of_the_draft_is_a_misprint`).

use nalgebra::Vector3;

use super::Medium;
use super::fresnel_moments::{c_e, c_phi};
use std::f64::consts::PI;

/// A point on a surface with its unit outward normal (cm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Position [cm].
    pub x: Vector3<f64>,
    /// Unit outward normal.
    pub n: Vector3<f64>,
}

/// The directional dipole's constants for one channel: plain data, e.g. for a shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DipoleConstants {
    /// Diffusion coefficient D = 1/(3σt′) [cm].
    pub d: f64,
    /// Effective transport coefficient σtr = √(σa/D) [cm⁻¹].
    pub sigma_tr: f64,
    /// Extrapolation distance d_e = 2.131D/√α′ [cm].
    pub d_e: f64,
    /// Boundary factor A = (1 − C_E(η))/(2C_φ(η)) [-].
    pub a: f64,
    /// C_φ(η) [-].
    pub c_phi: f64,
    /// C_E(η) [-].
    pub c_e: f64,
    /// 1/(4C_φ(1/η)·4π²) (0 for a medium that does not scatter) [sr⁻¹].
    pub norm: f64,
    /// The back-lit source depth 1/(3σt), σt unreduced [cm].
    pub backlit_depth: f64,
    /// The δ-Eddington extinction σt* = σa + σs(1 − g²) [cm⁻¹].
    pub sigma_t_delta: f64,
    /// Relative index η [-].
    pub eta: f64,
}

/// The directional dipole for one channel.
#[derive(Clone, Debug)]
pub struct DirectionalDipole {
    k: DipoleConstants,
}

impl DirectionalDipole {
    /// Sets up the model for a medium.
    pub fn new(m: &Medium) -> Self {
        let d = 1.0 / (3.0 * m.sigma_t_reduced());
        let albedo = m.albedo_reduced();
        let (cp, ce) = (c_phi(m.eta), c_e(m.eta));
        DirectionalDipole {
            k: DipoleConstants {
                d,
                sigma_tr: (m.sigma_a / d).sqrt(),
                d_e: 2.131 * d / albedo.sqrt(),
                a: (1.0 - ce) / (2.0 * cp),
                c_phi: cp,
                c_e: ce,
                // A medium that does not scatter (α′ = 0) has no diffuse part.
                norm: if albedo > 0.0 {
                    1.0 / (4.0 * c_phi(1.0 / m.eta) * 4.0 * PI * PI)
                } else {
                    0.0
                },
                backlit_depth: 1.0 / (3.0 * (m.sigma_a + m.sigma_s)),
                sigma_t_delta: m.sigma_a + m.sigma_s * (1.0 - m.g * m.g),
                eta: m.eta,
            },
        }
    }

    /// The model's constants.
    pub fn constants(&self) -> DipoleConstants {
        self.k
    }

    /// S′_d(x, ω, ρ) of eq. 3.7 for a source at distance ρ [cm] with x·ω = `x_w`, ω·n_o = `w_n`,
    /// x·n_o = `x_n` [cm⁻² sr⁻¹], without the normalisation `norm`.
    fn source(&self, rho: f64, x_w: f64, w_n: f64, x_n: f64) -> f64 {
        let (d, s) = (self.k.d, self.k.sigma_tr * rho);
        let bracket = self.k.c_phi * (rho * rho / d + 3.0 * (1.0 + s) * x_w)
            - self.k.c_e
                * (3.0 * d * (1.0 + s) * w_n
                    - ((1.0 + s) + 3.0 * d * (3.0 * (1.0 + s) + s * s) / (rho * rho) * x_w) * x_n);
        (-s).exp() / (rho * rho * rho) * bracket
    }

    /// The refracted direction ω₁₂ of light arriving from unit direction `w_i` (pointing away
    /// from the surface, towards the light) at a surface with unit normal `n`, and the Fresnel
    /// transmittance T(η, ω_i). Light from below the tangent plane has T = 0.
    pub fn refract(&self, w_i: &Vector3<f64>, n: &Vector3<f64>) -> (Vector3<f64>, f64) {
        let cos_i = w_i.dot(n);
        if cos_i <= 0.0 {
            return (-n, 0.0);
        }
        let (f, cos_t) = mc::fresnel(1.0, self.k.eta, cos_i.min(1.0));
        let inv = 1.0 / self.k.eta;
        let w12 = (-w_i * inv + n * (inv * cos_i - cos_t)).normalize();
        (w12, 1.0 - f)
    }

    /// The diffuse BSSRDF S_d(x_i, ω_i; x_o) [cm⁻² sr⁻¹] for light from unit direction `w_i`
    /// (towards the light) entering at `i` and leaving at `o`, without the Fresnel factors.
    pub fn s_d(&self, i: &SurfacePoint, w_i: &Vector3<f64>, o: &SurfacePoint) -> f64 {
        if self.k.norm == 0.0 {
            return 0.0;
        }
        let (w12, _) = self.refract(w_i, &i.n);
        self.s_d_refracted(i, &w12, o)
    }

    /// S_d for the refracted direction `w12` already known.
    fn s_d_refracted(&self, i: &SurfacePoint, w12: &Vector3<f64>, o: &SurfacePoint) -> f64 {
        let k = &self.k;
        let x = o.x - i.x;
        let r2 = x.norm_squared();
        let r = r2.sqrt();
        // The modified tangent-plane normal n*_i.
        let side = i.n.cross(&x);
        let n_star = if r > 0.0 && side.norm() > 1e-9 * r {
            (x / r).cross(&(side / side.norm()))
        } else {
            i.n
        };
        let x_w = x.dot(w12);
        let mu0 = -w12.dot(&o.n);
        let d_r = if mu0 > 0.0 {
            let cos_beta = -((r2 - x_w * x_w).max(0.0) / (r2 + k.d_e * k.d_e)).sqrt();
            (r2 + k.d * mu0 * (k.d * mu0 - 2.0 * k.d_e * cos_beta)).sqrt()
        } else {
            (r2 + k.backlit_depth * k.backlit_depth).sqrt()
        };
        let real = self.source(d_r, x_w, w12.dot(&o.n), x.dot(&o.n));
        let x_v = i.x + n_star * (2.0 * k.a * k.d_e);
        let w_v = w12 - n_star * (2.0 * w12.dot(&n_star));
        let xv = o.x - x_v;
        let virt = self.source(xv.norm(), xv.dot(&w_v), w_v.dot(&o.n), xv.dot(&o.n));
        (k.norm * (real - virt)).max(0.0)
    }

    /// The full diffuse BSSRDF T(η, ω_i)·S_d·T(η, ω_o) [cm⁻² sr⁻¹]; `w_o` points from `o` towards
    /// the viewer.
    pub fn bssrdf(
        &self,
        i: &SurfacePoint,
        w_i: &Vector3<f64>,
        o: &SurfacePoint,
        w_o: &Vector3<f64>,
    ) -> f64 {
        let (w12, t_in) = self.refract(w_i, &i.n);
        let cos_o = w_o.dot(&o.n);
        if t_in == 0.0 || cos_o <= 0.0 || self.k.norm == 0.0 {
            return 0.0;
        }
        let t_out = 1.0 - mc::fresnel(1.0, self.k.eta, cos_o.min(1.0)).0;
        t_in * self.s_d_refracted(i, &w12, o) * t_out
    }

    /// The δ-Eddington reduced intensity's weight e^{−σt* s} after a straight path of `s` [cm]
    /// inside the medium (S_δE without its δ factors and Fresnel terms).
    pub fn reduced_intensity(&self, s: f64) -> f64 {
        (-self.k.sigma_t_delta * s).exp()
    }

    /// Total diffuse reflectance per unit incident power at incidence `theta_i_deg` [-]:
    /// ∫∫ Rd(x, y; θ) dx dy by the midpoint rule on a polar grid around the entry point, radii
    /// graded as t³ out to 10³ transport mean free paths (10³ × 64 cells; within 10⁻³ of the
    /// Gauss–Legendre total at normal incidence, tested).
    pub fn total_rd(&self, theta_i_deg: f64) -> f64 {
        if self.k.norm == 0.0 {
            return 0.0;
        }
        let r_max = 1e3 * 3.0 * self.k.d;
        let (nr, nphi) = (1000, 64);
        let mut sum = 0.0;
        for i in 0..nr {
            let (a, b) = (
                (i as f64 / nr as f64).powi(3),
                ((i + 1) as f64 / nr as f64).powi(3),
            );
            let (r, dr) = (0.5 * (a + b) * r_max, (b - a) * r_max);
            for j in 0..nphi {
                let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * PI;
                sum += self.rd_xy(r * phi.cos(), r * phi.sin(), theta_i_deg) * r * dr;
            }
        }
        sum * 2.0 * PI / nphi as f64
    }

    /// Rd(r) [cm⁻²] at normal incidence.
    pub fn rd(&self, r: f64) -> f64 {
        self.rd_xy(r, 0.0, 0.0)
    }

    /// Rd(x, y) [cm⁻²] per unit incident power on the flat surface z = 0 for a beam at polar
    /// angle `theta_i_deg` in the plane x–z, travelling towards +x, entering at the origin:
    /// T(θ_i)·4πC_φ(1/η)·S_d.
    pub fn rd_xy(&self, x: f64, y: f64, theta_i_deg: f64) -> f64 {
        let th = theta_i_deg.to_radians();
        let up = Vector3::z();
        let i = SurfacePoint {
            x: Vector3::zeros(),
            n: up,
        };
        let o = SurfacePoint {
            x: Vector3::new(x, y, 0.0),
            n: up,
        };
        let w_i = Vector3::new(-th.sin(), 0.0, th.cos());
        let (w12, t_in) = self.refract(&w_i, &up);
        t_in * 4.0 * PI * c_phi(1.0 / self.k.eta) * self.s_d_refracted(&i, &w12, &o)
    }
}
