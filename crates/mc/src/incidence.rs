//! Oblique incidence: a pencil beam at polar angle θ in the medium above, in the x–z plane
//! (azimuth 0, so reflectance shifts towards +x), refracted into the sample by Snell's law with
//! the unpolarized Fresnel reflectance as Rsp. θ = 0 is MCML's normal incidence, bit for bit.
//!
//! [`rd_table`] measures total diffuse reflectance Rd(θ) per channel over a list of angles: one
//! batch run per angle (channels that share g and η share the walk, as everywhere in `mc`), each
//! angle with its own random streams.

use crate::batch::BatchSpec;
use crate::error::{McError, Result};
use crate::layer::Sample;
use crate::output::Estimate;

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

/// Rd(θ) of every channel of a batch at one angle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct IncidenceRow {
    /// Polar angle of the beam [degrees].
    pub theta_deg: f64,
    /// Specular reflectance at entry per channel [-] (exact).
    pub rsp: Vec<f64>,
    /// Total diffuse reflectance per channel, per unit incident power [-].
    pub rd: Vec<Estimate>,
    /// Per channel, the reflected radiance against exit angle relative to a Lambertian
    /// surface's, h(θ) per exit-angle bin ([`crate::exitance`]).
    pub exit: Vec<Vec<crate::exitance::ExitBin>>,
}

/// Total diffuse reflectance of every channel of `spec` at each of `angles` [degrees]. Angle `i`
/// runs with seed `spec.seed + i`, so rows are independent; `progress` gets the photons traced.
pub fn rd_table(
    spec: &BatchSpec,
    angles: &[f64],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<IncidenceRow>> {
    if angles.is_empty() {
        return Err(McError::invalid(
            "incidence angles",
            0,
            "give at least one angle",
        ));
    }
    angles
        .iter()
        .enumerate()
        .map(|(i, &theta_deg)| {
            let s = BatchSpec {
                seed: spec.seed.wrapping_add(i as u64),
                ..spec.clone()
            };
            let out = crate::simulate::run_batch_at(&s, Incidence { theta_deg }, progress)?;
            Ok(IncidenceRow {
                theta_deg,
                rsp: out.iter().map(|o| o.rsp).collect(),
                rd: out.iter().map(|o| o.rd).collect(),
                exit: out.iter().map(crate::exitance::radiance_ratio).collect(),
            })
        })
        .collect()
}
