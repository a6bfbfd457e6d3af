//! The better dipole (d'Eon 2012): Grosjean's diffusion coefficient D = (2σa + σs′)/(3σt′²), the
//! extrapolation distance z_b = 2AD with A = (1 + 3C₂)/(1 − 2C₁), and the exitance
//! C_φ·φ + C_E·E, which counts both the fluence and the flux through the boundary.
//!
//! For a source of unit power at depth z_r with its image at z_v = −z_r − 2z_b:
//! φ(r) = (e^{−σtr d_r}/d_r − e^{−σtr d_v}/d_v)/(4πD),
//! E(r) = (z_r(1 + σtr d_r)e^{−σtr d_r}/d_r³ − z_v(1 + σtr d_v)e^{−σtr d_v}/d_v³)/(4π),
//! σtr = √(σa/D). The better dipole puts a source of strength α′ at z_r = 1/σt′.

use super::Medium;
use super::fresnel_moments::{c_e, c_phi, c1, c2};
use std::f64::consts::PI;

/// The boundary and diffusion constants shared by the better dipole and photon beam diffusion.
#[derive(Clone, Copy, Debug)]
pub struct DipoleConstants {
    /// Grosjean's D [cm].
    pub d: f64,
    /// σtr = √(σa/D) [cm⁻¹].
    pub sigma_tr: f64,
    /// Extrapolation distance z_b = 2AD [cm].
    pub z_b: f64,
    /// C_φ(η), C_E(η).
    pub c_phi: f64,
    pub c_e: f64,
}

impl DipoleConstants {
    /// The constants of a medium.
    pub fn new(m: &Medium) -> Self {
        let st = m.sigma_t_reduced();
        let d = (2.0 * m.sigma_a + m.sigma_s_reduced()) / (3.0 * st * st);
        let a = (1.0 + 3.0 * c2(m.eta)) / (1.0 - 2.0 * c1(m.eta));
        DipoleConstants {
            d,
            sigma_tr: (m.sigma_a / d).sqrt(),
            z_b: 2.0 * a * d,
            c_phi: c_phi(m.eta),
            c_e: c_e(m.eta),
        }
    }

    /// Exitance C_φφ + C_E E [cm⁻²] at r [cm] of a unit source at depth `z_r` [cm].
    pub fn exitance(&self, r: f64, z_r: f64) -> f64 {
        let z_v = -z_r - 2.0 * self.z_b;
        let (d_r, d_v) = ((r * r + z_r * z_r).sqrt(), (r * r + z_v * z_v).sqrt());
        let (e_r, e_v) = ((-self.sigma_tr * d_r).exp(), (-self.sigma_tr * d_v).exp());
        let phi = (e_r / d_r - e_v / d_v) / (4.0 * PI * self.d);
        let flux = (z_r * (1.0 + self.sigma_tr * d_r) * e_r / (d_r * d_r * d_r)
            - z_v * (1.0 + self.sigma_tr * d_v) * e_v / (d_v * d_v * d_v))
            / (4.0 * PI);
        self.c_phi * phi + self.c_e * flux
    }

    /// ∫ exitance dA over the plane for a unit source at depth `z_r`, in closed form:
    /// C_φ(e^{−σtr z_r} − e^{−σtr|z_v|})/(2Dσtr) + C_E(e^{−σtr z_r} + e^{−σtr|z_v|})/2.
    pub fn exitance_total(&self, z_r: f64) -> f64 {
        let z_v = z_r + 2.0 * self.z_b;
        let (e_r, e_v) = ((-self.sigma_tr * z_r).exp(), (-self.sigma_tr * z_v).exp());
        let phi = if self.sigma_tr > 0.0 {
            (e_r - e_v) / (2.0 * self.d * self.sigma_tr)
        } else {
            (z_v - z_r) / (2.0 * self.d)
        };
        self.c_phi * phi + self.c_e * 0.5 * (e_r + e_v)
    }
}

/// d'Eon's better dipole for one channel.
#[derive(Clone, Debug)]
pub struct BetterDipole {
    k: DipoleConstants,
    z_r: f64,
    scale: f64,
}

impl BetterDipole {
    /// Sets up the better dipole for a medium.
    pub fn new(m: &Medium) -> Self {
        BetterDipole {
            k: DipoleConstants::new(m),
            z_r: m.transport_mfp(),
            scale: m.entry_transmittance() * m.albedo_reduced(),
        }
    }

    /// Rd(r) [cm⁻²].
    pub fn rd(&self, r: f64) -> f64 {
        self.scale * self.k.exitance(r, self.z_r)
    }

    /// The closed-form total diffuse reflectance.
    pub fn total(&self) -> f64 {
        self.scale * self.k.exitance_total(self.z_r)
    }
}
