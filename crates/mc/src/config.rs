//! Simulation settings for materials (the thesis's Table 6.1 by default), read from TOML.
//!
//! ```toml
//! photons = 10_000_000
//! seed = 1
//! thickness_cm = 1e8      # quasi-infinite half-space
//! n_above = 1.0           # ambient media
//! n_below = 1.0
//! [grid]
//! dr_per_min_mfp = 20.0   # dr = min(MFP_rgb) / 20
//! r_max_mfp = 32.0        # nr = ⌈32 · max(MFP_rgb) / dr⌉
//! z_max_mfp = 32.0        # depth range of A(r,z), in max(MFP_rgb)
//! nz = 100
//! na = 30
//! ```

use serde::Deserialize;

use crate::error::{McError, Result};
use crate::grid::Grid;
use crate::material::Material;

/// Per-material run settings.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimConfig {
    /// Photon packets per channel.
    pub photons: u64,
    /// Seed of every random stream.
    pub seed: u64,
    /// Layer thickness when the material sets none [cm].
    pub thickness_cm: f64,
    /// Refractive index above the sample [-].
    pub n_above: f64,
    /// Refractive index below the sample [-].
    pub n_below: f64,
    /// The grid rule.
    pub grid: GridRule,
}

/// How the grid follows from a material's mean free paths (thesis Table 6.1).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridRule {
    /// dr = min(MFP_rgb) / dr_per_min_mfp.
    pub dr_per_min_mfp: f64,
    /// nr = ⌈r_max_mfp · max(MFP_rgb) / dr⌉.
    pub r_max_mfp: f64,
    /// dz = z_max_mfp · max(MFP_rgb) / nz.
    pub z_max_mfp: f64,
    /// Depth bins of A(r, z).
    pub nz: usize,
    /// Exit-angle bins over [0, π/2].
    pub na: usize,
}

impl SimConfig {
    /// Parses and validates a config TOML; `source_name` is used in error messages.
    pub fn from_toml(text: &str, source_name: &str) -> Result<Self> {
        let c: SimConfig = toml::from_str(text).map_err(|e| McError::toml(text, source_name, e))?;
        for (field, v) in [
            ("grid.dr_per_min_mfp", c.grid.dr_per_min_mfp),
            ("grid.r_max_mfp", c.grid.r_max_mfp),
            ("grid.z_max_mfp", c.grid.z_max_mfp),
            ("thickness_cm", c.thickness_cm),
            ("n_above", c.n_above),
            ("n_below", c.n_below),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(McError::invalid(
                    field,
                    McError::number(v),
                    "must be positive and finite",
                ));
            }
        }
        if c.photons == 0 {
            return Err(McError::invalid("photons", 0, "must be at least 1"));
        }
        // The bin counts are checked against the grid's own limits now, not when the first
        // material's grid is derived; spacings and nr are placeholders here.
        let probe = Grid {
            dr: 1.0,
            dz: 1.0,
            nr: 1,
            nz: c.grid.nz,
            na: c.grid.na,
        };
        probe.validate().map_err(|e| match e {
            McError::InvalidValue {
                field,
                value,
                reason,
            } => McError::InvalidValue {
                field: format!("grid.{field}"),
                value,
                reason,
            },
            other => other,
        })?;
        Ok(c)
    }

    /// The thesis grid for a material: dr from the smallest MFP, nr to cover 32 of the largest.
    /// Channels that do not interact at all (infinite MFP) are left out of the rule.
    pub fn grid_for(&self, m: &Material) -> Result<Grid> {
        let mfps: Vec<f64> = (0..3).map(|c| m.mfp(c)).filter(|l| l.is_finite()).collect();
        if mfps.is_empty() {
            return Err(McError::invalid(
                format!("material {} sigma_a + sigma_s", m.name),
                0,
                "no channel interacts with light: no grid to derive",
            ));
        }
        let min = mfps.iter().cloned().fold(f64::INFINITY, f64::min);
        let max = mfps.iter().cloned().fold(0.0, f64::max);
        let r = &self.grid;
        let dr = min / r.dr_per_min_mfp;
        let nr = (r.r_max_mfp * max / dr).ceil() as usize;
        let grid = Grid {
            dr,
            dz: r.z_max_mfp * max / r.nz as f64,
            nr,
            nz: r.nz,
            na: r.na,
        };
        grid.validate()?;
        Ok(grid)
    }
}
