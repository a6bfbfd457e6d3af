//! Analytic diffuse reflectance profiles Rd(r) from optical coefficients, beside the Monte Carlo
//! ground truth.
//!
//! Conventions: one colour channel of a homogeneous half-space (σa, σs [cm⁻¹], Henyey–Greenstein
//! g, relative index η = n_material / n_outside) under a normally incident, infinitely narrow beam
//! of unit power. Rd(r) [cm⁻²] is the angle-integrated exitance at distance r [cm] per unit
//! *incident* power, without the specular reflection Rsp: MCML's `Rd_r`. Diffusion models are
//! derived per unit power entering the medium, so they are multiplied by the entry transmittance
//! 1 − Rsp. They use the similarity relation σs′ = σs(1 − g), σt′ = σa + σs′, α′ = σs′/σt′, and
//! the transport mean free path ℓ = 1/σt′ is the unit "MFP" of comparisons.

mod beam_diffusion;
mod better_dipole;
pub mod burley;
mod dipole;
mod directional_dipole;
pub mod fresnel_moments;

pub use beam_diffusion::BeamDiffusion;
pub use better_dipole::BetterDipole;
pub use dipole::Dipole;
pub use directional_dipole::{DipoleConstants, DirectionalDipole, SurfacePoint};

use crate::error::{FitError, Result};
use crate::profile::Profile;
use burley::Burley;

/// One channel's optical coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    /// Absorption coefficient σa [cm⁻¹].
    pub sigma_a: f64,
    /// Scattering coefficient σs [cm⁻¹].
    pub sigma_s: f64,
    /// Henyey–Greenstein anisotropy g [-].
    pub g: f64,
    /// Relative refractive index η [-].
    pub eta: f64,
}

impl Medium {
    /// Channel `c` of a material (ambient index 1).
    pub fn channel(m: &mc::Material, c: usize) -> Self {
        Medium {
            sigma_a: m.sigma_a[c],
            sigma_s: m.sigma_s[c],
            g: m.g[c],
            eta: m.eta,
        }
    }

    /// The three channels R, G, B of a material (ambient index 1).
    pub fn channels(m: &mc::Material) -> [Self; 3] {
        [0, 1, 2].map(|c| Medium::channel(m, c))
    }

    /// The medium of an `mc` layer under a medium of index `n_above` (η relative to it).
    pub fn of_layer(layer: &mc::Layer, n_above: f64) -> Self {
        Medium {
            sigma_a: layer.mu_a,
            sigma_s: layer.mu_s,
            g: layer.g,
            eta: layer.n / n_above,
        }
    }

    /// Checks the coefficients; the error names the field.
    pub fn validate(&self) -> Result<()> {
        for (field, v) in [("sigma_a", self.sigma_a), ("sigma_s", self.sigma_s)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(FitError::invalid(
                    field,
                    v,
                    "must be non-negative and finite",
                ));
            }
        }
        if !(self.g.is_finite() && (-1.0..=1.0).contains(&self.g)) {
            return Err(FitError::invalid("g", self.g, "must lie in [-1, 1]"));
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(FitError::invalid(
                "eta",
                self.eta,
                "must be positive and finite",
            ));
        }
        if self.sigma_t_reduced() <= 0.0 {
            return Err(FitError::invalid(
                "sigma_a + sigma_s·(1 − g)",
                self.sigma_t_reduced(),
                "the medium does not interact with light: no profile",
            ));
        }
        Ok(())
    }

    /// σs′ = σs(1 − g) [cm⁻¹].
    pub fn sigma_s_reduced(&self) -> f64 {
        self.sigma_s * (1.0 - self.g)
    }

    /// σt′ = σa + σs′ [cm⁻¹].
    pub fn sigma_t_reduced(&self) -> f64 {
        self.sigma_a + self.sigma_s_reduced()
    }

    /// α′ = σs′/σt′ [-].
    pub fn albedo_reduced(&self) -> f64 {
        self.sigma_s_reduced() / self.sigma_t_reduced()
    }

    /// The transport mean free path ℓ = 1/σt′ [cm].
    pub fn transport_mfp(&self) -> f64 {
        1.0 / self.sigma_t_reduced()
    }

    /// Transmittance of the normally incident beam into the medium, 1 − ((η−1)/(η+1))².
    pub fn entry_transmittance(&self) -> f64 {
        1.0 - ((self.eta - 1.0) / (self.eta + 1.0)).powi(2)
    }
}

/// The analytic models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// Jensen et al. 2001 (draft §3.5.7).
    Dipole,
    /// d'Eon 2012: Grosjean's D and the C_φ/C_E exitance.
    BetterDipole,
    /// Frisvad et al. 2014 at normal incidence (draft §3.5.8).
    DirectionalDipole,
    /// Photon beam diffusion (Habel et al. 2013) with single scattering, as pbrt evaluates it.
    Pbd,
    /// Christensen–Burley normalized diffusion with the searchlight albedo mapping.
    Burley,
}

impl Model {
    /// Every model, in the order of tables and plots.
    pub const ALL: [Model; 5] = [
        Model::Dipole,
        Model::BetterDipole,
        Model::DirectionalDipole,
        Model::Pbd,
        Model::Burley,
    ];

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Model::Dipole => "dipole",
            Model::BetterDipole => "better-dipole",
            Model::DirectionalDipole => "directional-dipole",
            Model::Pbd => "pbd",
            Model::Burley => "burley",
        }
    }

    /// The model named `s` (see [`Model::name`]).
    pub fn parse(s: &str) -> Result<Model> {
        Model::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Model::ALL.iter().map(|m| m.name()).collect();
                FitError::invalid("model", s, format!("expected one of {}", names.join(", ")))
            })
    }

    /// The model's radial profile for one channel.
    pub fn radial(self, m: &Medium) -> Result<Radial> {
        m.validate()?;
        Ok(match self {
            Model::Dipole => Radial::Dipole(Dipole::new(m)),
            Model::BetterDipole => Radial::BetterDipole(BetterDipole::new(m)),
            Model::DirectionalDipole => Radial::DirectionalDipole(DirectionalDipole::new(m)),
            Model::Pbd => Radial::Pbd(BeamDiffusion::new(m, BeamDiffusion::SAMPLES)),
            Model::Burley => Radial::Burley(Burley::from_medium(m)),
        })
    }
}

/// A model set up for one channel: Rd(r) on demand.
#[derive(Clone, Debug)]
pub enum Radial {
    /// Jensen et al.'s dipole ([`Model::Dipole`]).
    Dipole(Dipole),
    /// d'Eon's better dipole ([`Model::BetterDipole`]).
    BetterDipole(BetterDipole),
    /// Frisvad et al.'s directional dipole at normal incidence ([`Model::DirectionalDipole`]).
    DirectionalDipole(DirectionalDipole),
    /// Photon beam diffusion ([`Model::Pbd`]).
    Pbd(BeamDiffusion),
    /// Christensen–Burley from the medium's coefficients ([`Model::Burley`]).
    Burley(Burley),
}

impl Radial {
    /// Rd(r) [cm⁻²] at r [cm] > 0.
    pub fn rd(&self, r: f64) -> f64 {
        match self {
            Radial::Dipole(m) => m.rd(r),
            Radial::BetterDipole(m) => m.rd(r),
            Radial::DirectionalDipole(m) => m.rd(r),
            Radial::Pbd(m) => m.rd(r),
            Radial::Burley(m) => m.density(r),
        }
    }

    /// The average of Rd over the annulus r₀ ≤ |x| < r₁ [cm⁻²], by Gauss–Legendre on r·Rd(r)
    /// (finite even where Rd has Burley's 1/r singularity).
    pub fn annulus_average(&self, r0: f64, r1: f64) -> f64 {
        let rule = gauss_quad::legendre::GaussLegendre::new(8.try_into().expect("8 > 0"));
        2.0 * rule.integrate(r0, r1, |r| r * self.rd(r)) / (r1 * r1 - r0 * r0)
    }

    /// ∫ Rd dA over the disc of radius `r_max` [-]: the total diffuse reflectance it holds,
    /// by Gauss–Legendre on panels that widen geometrically from `r_max`·10⁻⁸.
    pub fn total(&self, r_max: f64) -> f64 {
        let rule = gauss_quad::legendre::GaussLegendre::new(16.try_into().expect("16 > 0"));
        let mut edges = vec![0.0];
        let mut e = r_max * 1e-8;
        while e < r_max {
            edges.push(e);
            e *= 1.25;
        }
        edges.push(r_max);
        edges
            .windows(2)
            .map(|w| rule.integrate(w[0], w[1], |r| 2.0 * std::f64::consts::PI * r * self.rd(r)))
            .sum()
    }
}

/// A model's total diffuse reflectance per unit incident power for a beam at polar angle
/// `theta_deg` [-]. The directional dipole depends on the incidence itself
/// ([`DirectionalDipole::total_rd`]); the radial models only through the entry transmittance,
/// total(0°)·T(θ)/T(0°), T = 1 − Fresnel reflectance.
pub fn total_at(model: Model, m: &Medium, theta_deg: f64) -> Result<f64> {
    let radial = model.radial(m)?;
    if !(theta_deg.is_finite() && (0.0..90.0).contains(&theta_deg)) {
        return Err(FitError::invalid(
            "incidence angle",
            theta_deg,
            "must lie in [0, 90) degrees",
        ));
    }
    Ok(match radial {
        Radial::DirectionalDipole(d) => d.total_rd(theta_deg),
        other => {
            let t = |deg: f64| 1.0 - mc::fresnel(1.0, m.eta, deg.to_radians().cos()).0;
            other.total(1e3 * m.transport_mfp()) * t(theta_deg) / t(0.0)
        }
    })
}

/// MCML's overflow bin for [`profile`]'s grid: Rd [cm⁻²] of everything beyond the `nr` bins of
/// width `dr` [cm] (integrated to 10⁴ times the grid's extent), spread over the annulus of bin
/// `nr`, as MCML's last bin holds the photons beyond its grid.
pub fn overflow(model: Model, material: &mc::Material, dr: f64, nr: usize) -> Result<[f64; 3]> {
    let (edge, far) = (nr as f64 * dr, 1e4 * dr * (nr + 1) as f64);
    let area = std::f64::consts::PI * (2 * nr + 1) as f64 * dr * dr;
    let mut out = [0.0; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let radial = model.radial(&Medium::channel(material, c))?;
        *o = ((radial.total(far) - radial.total(edge)) / area).max(0.0);
    }
    Ok(out)
}

/// The profile of `model` for a material on MCML's radial grid (bin width `dr` [cm], `nr` bins):
/// each value is the annulus average, as MC bins count photons, placed at MCML's optimal
/// coordinate; standard errors are 0.
pub fn profile(model: Model, material: &mc::Material, dr: f64, nr: usize) -> Result<Profile> {
    let radial: Vec<Radial> = (0..3)
        .map(|c| model.radial(&Medium::channel(material, c)))
        .collect::<Result<_>>()
        .map_err(|e| match e {
            FitError::Invalid {
                field,
                value,
                reason,
            } => FitError::Invalid {
                field: format!("material {} {field}", material.name),
                value,
                reason,
            },
            other => other,
        })?;
    let grid = mc::Grid {
        dr,
        dz: dr,
        nr,
        nz: 1,
        na: 1,
    };
    let r: Vec<f64> = (0..nr).map(|i| grid.r_optimal(i)).collect();
    let rd = [0, 1, 2].map(|c| {
        (0..nr)
            .map(|i| radial[c].annulus_average(i as f64 * dr, (i + 1) as f64 * dr))
            .collect()
    });
    Ok(Profile {
        dr,
        r,
        rd,
        se: [vec![0.0; nr], vec![0.0; nr], vec![0.0; nr]],
    })
}
