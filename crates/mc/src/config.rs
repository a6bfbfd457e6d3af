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

use crate::batch::{BatchSpec, ChannelSpec};
use crate::error::{McError, Result};
use crate::grid::Grid;
use crate::material::Material;
use crate::tally::TallySet;

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

/// The thesis's run settings (Table 6.1), `configs/thesis.toml`, compiled in.
pub const THESIS_TOML: &str = include_str!("../../../configs/thesis.toml");

impl SimConfig {
    /// The thesis's run settings ([`THESIS_TOML`]).
    pub fn thesis() -> Result<Self> {
        Self::from_toml(THESIS_TOML, "configs/thesis.toml")
    }

    /// The run settings of a TOML file, or the thesis's ([`SimConfig::thesis`]) without one.
    pub fn read(path: Option<&std::path::Path>) -> Result<Self> {
        let Some(p) = path else {
            return Self::thesis();
        };
        let name = p.display().to_string();
        let text = crate::input::read_text(p)
            .map_err(|e| McError::file(format!("cannot read config file {name}"), e))?;
        Self::from_toml(&text, &name)
    }

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
        crate::job::check_photons(c.photons)?;
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

    /// The batch run of `materials` under these settings: three channels (R, G, B) per material
    /// in order, each on its material's grid ([`SimConfig::grid_for`]) and thickness (the
    /// material's, else `thickness_cm`), `photons` per channel from `seed`; A(r, z) is tallied
    /// unless `profile_only`, summed as MCML sums it (no per-photon standard errors). Validated.
    pub fn batch(
        &self,
        materials: &[&Material],
        photons: u64,
        seed: u64,
        profile_only: bool,
    ) -> Result<BatchSpec> {
        let mut channels = Vec::new();
        for m in materials {
            let grid = self.grid_for(m)?;
            let thickness = m.thickness.unwrap_or(self.thickness_cm);
            channels.extend((0..3).map(|c| ChannelSpec {
                layer: m.layer(c, thickness),
                grid,
            }));
        }
        let spec = BatchSpec {
            n_above: self.n_above,
            n_below: self.n_below,
            channels,
            photons,
            seed,
            tallies: TallySet {
                absorption_rz: !profile_only,
                // What `simulate --full` writes of A(r, z) (the .mco files) has no standard errors.
                absorption_rz_se: false,
                surface_xy: 0,
            },
        };
        spec.validate()?;
        Ok(spec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(name: &str, thickness: Option<f64>) -> Material {
        Material {
            name: name.into(),
            source: String::new(),
            sigma_a: [0.1, 0.5, 2.0],
            sigma_s: [10.0, 20.0, 40.0],
            g: [0.0, 0.5, 0.9],
            eta: 1.4,
            thickness,
        }
    }

    /// Three channels per material in order, each with its material's layer, grid and thickness;
    /// the tallies follow `profile_only`; a zero photon count is refused.
    #[test]
    fn batch_lays_out_three_channels_per_material() {
        let config = SimConfig::thesis().unwrap();
        let (a, b) = (material("a", None), material("b", Some(0.2)));
        let spec = config.batch(&[&a, &b], 1000, 7, true).unwrap();
        assert_eq!(spec.channels.len(), 6);
        assert_eq!((spec.photons, spec.seed), (1000, 7));
        assert!(!spec.tallies.absorption_rz);
        for (k, ch) in spec.channels.iter().enumerate() {
            let (m, c) = (if k < 3 { &a } else { &b }, k % 3);
            assert_eq!(
                ch.layer,
                m.layer(c, m.thickness.unwrap_or(config.thickness_cm))
            );
            assert_eq!(ch.grid, config.grid_for(m).unwrap());
        }
        assert!(
            config
                .batch(&[&a], 1000, 7, false)
                .unwrap()
                .tallies
                .absorption_rz
        );
        assert!(config.batch(&[&a], 0, 7, true).is_err());
        // A count beyond MAX_PHOTONS is a typo, not a run: refused, naming the field.
        let e = config
            .batch(&[&a], crate::MAX_PHOTONS + 1, 7, true)
            .unwrap_err();
        assert!(e.to_string().contains("photons"), "{e}");
        assert!(config.batch(&[&a], crate::MAX_PHOTONS, 7, true).is_ok());
    }
}
