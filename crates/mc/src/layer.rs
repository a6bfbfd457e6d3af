//! The layered sample: a stack of homogeneous slabs between two ambient media.
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
