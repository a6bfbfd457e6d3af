//! The classical dipole (Jensen et al. 2001; draft §3.5.7): a real source one transport mean free
//! path below the surface and a negative image above the extrapolated boundary.
//!
//! Rd(r) = α′/(4π)·[z_r(1 + σtr d_r)e^{−σtr d_r}/d_r³ + z_v(1 + σtr d_v)e^{−σtr d_v}/d_v³],
//! D = 1/(3σt′), σtr = √(3σaσt′), z_r = 1/σt′, z_v = z_r + 4AD, A = (1 + F_dr)/(1 − F_dr).

use super::Medium;
use super::fresnel_moments::f_dr;

/// Jensen's dipole for one channel.
#[derive(Clone, Debug)]
pub struct Dipole {
    albedo: f64,
    sigma_tr: f64,
    z_r: f64,
    z_v: f64,
    a: f64,
    scale: f64,
}

impl Dipole {
    /// Sets up the dipole for a medium.
    pub fn new(m: &Medium) -> Self {
        let st = m.sigma_t_reduced();
        let d = 1.0 / (3.0 * st);
        let fdr = f_dr(m.eta);
        let a = (1.0 + fdr) / (1.0 - fdr);
        Dipole {
            albedo: m.albedo_reduced(),
            sigma_tr: (3.0 * m.sigma_a * st).sqrt(),
            z_r: 1.0 / st,
            z_v: 1.0 / st + 4.0 * a * d,
            a,
            scale: m.entry_transmittance(),
        }
    }

    /// Rd(r) [cm⁻²].
    pub fn rd(&self, r: f64) -> f64 {
        let term = |z: f64| {
            let d = (z * z + r * r).sqrt();
            z * (1.0 + self.sigma_tr * d) * (-self.sigma_tr * d).exp() / (d * d * d)
        };
        self.scale * self.albedo / (4.0 * std::f64::consts::PI) * (term(self.z_r) + term(self.z_v))
    }

    /// The closed-form total diffuse reflectance (Jensen et al. 2001, eq. 5 integrated):
    /// (α′/2)(1 + e^{−(4/3)A√(3(1−α′))})e^{−√(3(1−α′))}, times the entry transmittance.
    pub fn total(&self) -> f64 {
        let s = (3.0 * (1.0 - self.albedo)).sqrt();
        self.scale * 0.5 * self.albedo * (1.0 + (-4.0 / 3.0 * self.a * s).exp()) * (-s).exp()
    }
}
