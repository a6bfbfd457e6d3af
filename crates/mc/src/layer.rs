//! The layered sample: a stack of homogeneous slabs between two ambient media, and the beam's
//! incidence on it.
//!
//! Units: lengths in cm, coefficients in cm⁻¹ (MCML's units). Axis convention: +z points into
//! the sample; layer 0 starts at z = 0 and the light enters from the medium above (z < 0).

use crate::error::{McError, Result};

/// One homogeneous slab (MCML's `LayerStruct`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Layer {
    /// Refractive index η of the slab [-].
    pub n: f64,
    /// Absorption coefficient μa [cm⁻¹].
    pub mu_a: f64,
    /// Scattering coefficient μs [cm⁻¹].
    pub mu_s: f64,
    /// Henyey–Greenstein anisotropy g = ⟨cos θ⟩ [-], in [−1, 1].
    pub g: f64,
    /// Thickness d [cm]; the thesis uses 10⁸ cm for a quasi-infinite half-space.
    pub thickness: f64,
}

impl Layer {
    /// Total interaction coefficient μt = μa + μs [cm⁻¹].
    pub fn mu_t(&self) -> f64 {
        self.mu_a + self.mu_s
    }

    /// Single-scattering albedo a = μs/μt [-]; 0 for a non-interacting (glass) layer.
    pub fn albedo(&self) -> f64 {
        if self.mu_t() > 0.0 {
            self.mu_s / self.mu_t()
        } else {
            0.0
        }
    }

    /// Transport mean free path ℓ′ = 1/(μa + μs(1 − g)) [cm]; infinite for a glass layer.
    pub fn transport_mfp(&self) -> f64 {
        1.0 / (self.mu_a + self.mu_s * (1.0 - self.g))
    }

    /// A layer that neither absorbs nor scatters: MCML's "glass" layer.
    pub fn is_glass(&self) -> bool {
        self.mu_t() == 0.0
    }
}

/// A stack of layers between ambient media (MCML's `InputStruct` geometry part).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sample {
    /// Refractive index of the medium above (where the beam comes from) [-].
    pub n_above: f64,
    /// Refractive index of the medium below [-].
    pub n_below: f64,
    /// Layers from top (z = 0) to bottom.
    pub layers: Vec<Layer>,
}

impl Sample {
    /// One layer in air above and below: the thesis's setup.
    pub fn single(layer: Layer) -> Self {
        Sample {
            n_above: 1.0,
            n_below: 1.0,
            layers: vec![layer],
        }
    }

    /// Checks every field; the error names the first offending one (`layer 2 mu_s`, …).
    pub fn validate(&self) -> Result<()> {
        check_index("n_above", self.n_above)?;
        check_index("n_below", self.n_below)?;
        if self.layers.is_empty() {
            return Err(McError::invalid(
                "layers",
                0,
                "at least one layer is required",
            ));
        }
        for (i, l) in self.layers.iter().enumerate() {
            let name = |f: &str| format!("layer {} {f}", i + 1);
            check_index(&name("n"), l.n)?;
            check_nonneg(&name("mu_a"), l.mu_a)?;
            check_nonneg(&name("mu_s"), l.mu_s)?;
            if !(l.g.is_finite() && (-1.0..=1.0).contains(&l.g)) {
                return Err(McError::invalid(name("g"), l.g, "must lie in [-1, 1]"));
            }
            if !(l.thickness.is_finite() && l.thickness > 0.0) {
                return Err(McError::invalid(
                    name("thickness"),
                    l.thickness,
                    "must be positive and finite",
                ));
            }
        }
        Ok(())
    }
}

fn check_index(field: &str, n: f64) -> Result<()> {
    if n.is_finite() && n > 0.0 {
        Ok(())
    } else {
        Err(McError::invalid(
            field,
            n,
            "refractive index must be positive and finite",
        ))
    }
}

fn check_nonneg(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(McError::invalid(
            field,
            v,
            "must be non-negative and finite",
        ))
    }
}

/// The beam's polar angle θ [degrees] in the medium above, 0 ≤ θ < 90.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Incidence {
    /// Polar angle θ of the beam [degrees].
    pub theta_deg: f64,
}

impl Incidence {
    /// Normal incidence (MCML).
    pub const NORMAL: Incidence = Incidence { theta_deg: 0.0 };

    /// Checks the angle, and that the top layer is not glass when θ > 0 (MCML's closed-form Rsp
    /// with multiple reflections in a glass layer holds at normal incidence only).
    pub fn validate_for(&self, sample: &Sample) -> Result<()> {
        if !(self.theta_deg.is_finite() && (0.0..90.0).contains(&self.theta_deg)) {
            return Err(McError::invalid(
                "incidence angle",
                self.theta_deg,
                "must be in [0, 90) degrees",
            ));
        }
        if self.theta_deg > 0.0 && sample.layers.len() > 1 && sample.layers[0].is_glass() {
            return Err(McError::invalid(
                "incidence angle",
                self.theta_deg,
                "oblique incidence through a glass top layer is not supported",
            ));
        }
        Ok(())
    }
}
