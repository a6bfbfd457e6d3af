//! The radial profile Rd(r) [cm⁻²] of a material's half-space, from `mc`: what its kernels are
//! fitted to and what the surface gather reads.

use crate::error::Result;

/// A material's Monte Carlo profile and the CSV `sss simulate` writes for it (one row per bin,
/// then MCML's overflow bin).
#[derive(Clone, Debug)]
pub struct SimulatedProfile {
    /// The profile, overflow bin left out.
    pub profile: fit::Profile,
    /// The profile as CSV, overflow bin included ([`fit::Profile::csv_from_mc`]).
    pub csv: String,
}

/// Runs the profile-only batch `spec` of one material (three channels R, G, B, one grid) and
/// reads its profile back from the CSV it writes, so that a profile simulated here and one read
/// from a cache are the same numbers. `progress` receives photon counts; `name` labels errors.
pub fn simulate(
    spec: &mc::BatchSpec,
    name: &str,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<SimulatedProfile> {
    if spec.channels.len() != 3 {
        return Err(crate::ShadingError::invalid(
            "profile: channels",
            spec.channels.len(),
            "one material (three channels) per profile",
        ));
    }
    let out = mc::run_batch(spec, progress)?;
    let csv = fit::Profile::csv_from_mc([&out[0], &out[1], &out[2]]);
    let profile = fit::Profile::from_csv(&csv, name)?;
    Ok(SimulatedProfile { profile, csv })
}
