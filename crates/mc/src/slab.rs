//! Diffuse transmittance of finite slabs: what light entering one face of a thin part delivers
//! out of the other (translucency), by simulating each channel of a batch as a slab of several
//! thicknesses under a normally incident beam. Finite slabs are MCML's home ground.

use crate::batch::BatchSpec;
use crate::error::{McError, Result};
use crate::output::Estimate;

/// Total transmittance and diffuse reflectance of every channel at one slab thickness.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SlabRow {
    /// Slab thickness [cm].
    pub thickness_cm: f64,
    /// Total transmittance Tt per channel, per unit incident power (unscattered light included) [-].
    pub tt: Vec<Estimate>,
    /// Diffuse reflectance Rd per channel, per unit incident power [-].
    pub rd: Vec<Estimate>,
    /// Per channel, the transmitted radiance against exit angle relative to a Lambertian
    /// surface's, h_T(θ) per exit-angle bin of the channel's grid
    /// ([`crate::exitance::transmitted_radiance_ratio`]; empty where nothing came through).
    pub exit: Vec<Vec<crate::exitance::ExitBin>>,
}

/// Runs every channel of `spec` as a slab of each thickness [cm] (each > 0 and finite), normal
/// incidence, with seed `spec.seed + i` for the i-th thickness (independent rows).
pub fn transmittance_table(
    spec: &BatchSpec,
    thicknesses_cm: &[f64],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<SlabRow>> {
    if thicknesses_cm.is_empty() {
        return Err(McError::invalid(
            "slab thicknesses",
            0,
            "give at least one thickness",
        ));
    }
    if let Some(d) = thicknesses_cm
        .iter()
        .find(|d| !(d.is_finite() && **d > 0.0))
    {
        return Err(McError::invalid(
            "slab thickness",
            d,
            "must be positive and finite [cm]",
        ));
    }
    thicknesses_cm
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            let mut s = spec.clone();
            s.seed = spec.seed.wrapping_add(i as u64);
            for c in &mut s.channels {
                c.layer.thickness = d;
            }
            let out = crate::simulate::run_batch(&s, progress)?;
            Ok(SlabRow {
                thickness_cm: d,
                tt: out.iter().map(|o| o.tt).collect(),
                rd: out.iter().map(|o| o.rd).collect(),
                exit: out
                    .iter()
                    .map(crate::exitance::transmitted_radiance_ratio)
                    .collect(),
            })
        })
        .collect()
}
