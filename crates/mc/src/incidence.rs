//! Oblique incidence: a pencil beam at polar angle θ in the medium above, in the x–z plane
//! (azimuth 0, so reflectance shifts towards +x), refracted into the sample by Snell's law with
//! the unpolarized Fresnel reflectance as Rsp. θ = 0 is MCML's normal incidence, bit for bit.
//!
//! [`rd_table`] measures total diffuse reflectance Rd(θ) per channel over a list of angles: one
//! batch run per angle (channels that share g and η share the walk, as everywhere in `mc`), each
//! angle with its own random streams.

use crate::batch::BatchSpec;
use crate::error::{McError, Result};
pub use crate::layer::Incidence;
use crate::output::Estimate;

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
