//! What a body run takes: the body, its medium's coefficients, the beam's angle, the surface grid,
//! photons and seed; plain serializable data, checked with errors that name the field and value.
//!
//! Units: lengths in cm, coefficients in cm⁻¹, the beam's angle in degrees.

use serde::{Deserialize, Serialize};

use super::shape::Body;
use crate::error::{McError, Result};
use crate::layer::Incidence;

/// The largest number of surface bins a run tallies (as MCML's 2D tallies in [`crate::Grid`]).
pub const MAX_SURFACE_BINS: usize = 50_000_000;

/// The homogeneous medium of a body, in air (n = 1) outside it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Coefficients {
    /// Refractive index η [-].
    pub n: f64,
    /// Absorption coefficient σa [cm⁻¹].
    pub mu_a: f64,
    /// Scattering coefficient σs [cm⁻¹].
    pub mu_s: f64,
    /// Henyey–Greenstein anisotropy g = ⟨cos θ⟩ [-], in [−1, 1].
    pub g: f64,
}

impl Coefficients {
    /// Total interaction coefficient σt = σa + σs [cm⁻¹].
    pub fn mu_t(&self) -> f64 {
        self.mu_a + self.mu_s
    }

    /// Diffusion's effective attenuation σ_tr = √(3σa(σa + σs(1 − g))) [cm⁻¹]; 1/σ_tr is the
    /// diffusion length the body's size is compared with.
    pub fn sigma_tr(&self) -> f64 {
        (3.0 * self.mu_a * (self.mu_a + self.mu_s * (1.0 - self.g))).sqrt()
    }
}

/// The grid exits are tallied on, over the body's own surface: radial bins of width `dr` in the
/// distance from the entry point along the surface (the last also collects everything beyond,
/// as MCML's), azimuth bins over [0, π] about the entry normal (the plane of incidence folds
/// ±φ), and exit-angle bins over [0, π/2] to the local normal.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SurfaceGrid {
    /// Radial bin width [cm].
    pub dr: f64,
    /// Number of radial bins.
    pub nr: usize,
    /// Number of azimuth bins over [0, π].
    pub n_azimuth: usize,
    /// Number of exit-angle bins over [0, π/2].
    pub n_exit: usize,
}

impl SurfaceGrid {
    /// Azimuth bin width [rad].
    pub fn d_azimuth(&self) -> f64 {
        std::f64::consts::PI / self.n_azimuth as f64
    }

    /// Exit-angle bin width [rad].
    pub fn d_exit(&self) -> f64 {
        std::f64::consts::FRAC_PI_2 / self.n_exit as f64
    }
}

/// One body run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodySpec {
    /// The body's shape and size.
    pub body: Body,
    /// Its medium.
    pub coefficients: Coefficients,
    /// The beam's angle to the inward normal at the entry point, in air.
    pub incidence: Incidence,
    /// Where exits are tallied.
    pub grid: SurfaceGrid,
    /// Number of photon packets.
    pub photons: u64,
    /// Seed of every random stream of the run.
    pub seed: u64,
}

impl BodySpec {
    /// Checks every field; the error names the first offending one and its value.
    pub fn validate(&self) -> Result<()> {
        let size = self.body.size_cm();
        let field = match self.body {
            Body::Slab { .. } => "thickness_cm",
            Body::Sphere { .. } | Body::Cavity { .. } => "radius_cm",
        };
        if !(size.is_finite() && size > 0.0) {
            return Err(McError::invalid(
                field,
                McError::number(size),
                "must be positive and finite [cm]",
            ));
        }
        let c = &self.coefficients;
        if !(c.n.is_finite() && c.n > 0.0) {
            return Err(McError::invalid(
                "n",
                c.n,
                "refractive index must be positive and finite",
            ));
        }
        for (name, v) in [("mu_a", c.mu_a), ("mu_s", c.mu_s)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(McError::invalid(name, v, "must be non-negative and finite"));
            }
        }
        if !(c.g.is_finite() && (-1.0..=1.0).contains(&c.g)) {
            return Err(McError::invalid("g", c.g, "must lie in [-1, 1]"));
        }
        if matches!(self.body, Body::Cavity { .. }) && c.mu_a == 0.0 {
            // Around a cavity the medium is unbounded: light that does not come back wanders off
            // for ever, and only absorption ends its walk.
            return Err(McError::invalid(
                "mu_a",
                c.mu_a,
                "must be positive around a cavity (an infinite medium)",
            ));
        }
        let theta = self.incidence.theta_deg;
        if !(theta.is_finite() && (0.0..90.0).contains(&theta)) {
            return Err(McError::invalid(
                "theta_deg",
                theta,
                "must be in [0, 90) degrees",
            ));
        }
        self.validate_grid()?;
        crate::job::check_photons(self.photons)
    }

    fn validate_grid(&self) -> Result<()> {
        let g = &self.grid;
        if !(g.dr.is_finite() && g.dr > 0.0) {
            return Err(McError::invalid(
                "dr",
                McError::number(g.dr),
                "grid spacing must be positive and finite [cm]",
            ));
        }
        for (name, n) in [
            ("nr", g.nr),
            ("n_azimuth", g.n_azimuth),
            ("n_exit", g.n_exit),
        ] {
            if n == 0 || n > 1_000_000 {
                return Err(McError::invalid(
                    name,
                    n,
                    "number of bins must be in 1..=1000000",
                ));
            }
        }
        if g.nr.saturating_mul(g.n_azimuth) > MAX_SURFACE_BINS {
            return Err(McError::invalid(
                "nr",
                g.nr,
                "nr × n_azimuth would exceed 5e7 bins",
            ));
        }
        Ok(())
    }
}
