//! The angular distribution of the diffusely reflected light: the radiance leaving the surface
//! at polar angle θ relative to that of a Lambertian surface with the same total reflectance.
//!
//! For a beam of unit power on a laterally uniform half-space the radiant intensity reflected into
//! direction θ is Rd_a(θ) [sr⁻¹] (MCML's `Rd_a`, integrated over the surface), so the
//! spatially integrated exitant radiance per unit incident irradiance is Rd_a(θ)/cos θ. A
//! Lambertian reflector of the same total Rd has Rd_a = Rd·cos θ/π, hence the ratio
//!
//!   h(θ) = π·Rd_a(θ) / (Rd·cos θ),
//!
//! whose cosine-weighted hemispherical mean (1/π)∫h cos θ dω is 1: h redistributes the reflected
//! light over exit angles without changing its total. For isotropic scattering behind a matched
//! boundary, Chandrasekhar's (1960) reflection function gives
//! Rd_a(μ) = a·μ·H(μ)·H(μ₀)/(4π(μ + μ₀)) at incidence cosine μ₀ (tested in
//! `tests/validation.rs`), so h rises from grazing towards the normal for high albedos.

use crate::output::{Estimate, Output};

/// h(θ) in one exit-angle bin.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ExitBin {
    /// The bin's centre, (k + ½)·da [degrees].
    pub theta_deg: f64,
    /// h(θ) [-] with its standard error (that of Rd_a; the total Rd is a sum over every bin, far
    /// less noisy).
    pub h: Estimate,
}

/// h(θ) at the centre of each exit-angle bin of a run; empty when it reflected nothing.
pub fn radiance_ratio(o: &Output) -> Vec<ExitBin> {
    ratio(o.rd.value, &o.rd_a, o.grid.da())
}

/// The same for the transmitted light leaving the far face of a slab (MCML's `Tt_a` over `Tt`,
/// unscattered light included: at normal incidence it lies in the first bin): the radiance
/// through a thin part relative to a Lambertian surface's; empty when nothing came through.
pub fn transmitted_radiance_ratio(o: &Output) -> Vec<ExitBin> {
    ratio(o.tt.value, &o.tt_a, o.grid.da())
}

/// π·X_a(θ)/(X·cos θ) per bin of width `da` [rad] for a total X and its angular tally X_a.
fn ratio(total: f64, per_angle: &[Estimate], da: f64) -> Vec<ExitBin> {
    if total.is_nan() || total <= 0.0 {
        return Vec::new();
    }
    per_angle
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let theta = (k as f64 + 0.5) * da;
            let s = std::f64::consts::PI / (total * theta.cos());
            ExitBin {
                theta_deg: theta.to_degrees(),
                h: Estimate {
                    value: e.value * s,
                    se: e.se * s,
                },
            }
        })
        .collect()
}

/// The solid angle MCML divides exit-angle bin `k` of width `da` by [sr]: 2π·sin((k+½)da)·da
/// (its `ScaleRdTt`; the exact 2π(cos kda − cos (k+1)da) differs by O(da²)). Rd = Σ Rd_a·ΔΩ_k
/// holds exactly with this ΔΩ.
pub fn bin_solid_angle(k: usize, da: f64) -> f64 {
    2.0 * std::f64::consts::PI * ((k as f64 + 0.5) * da).sin() * da
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Grid, Layer, RunSpec, Sample, TallySet};

    /// Every reflected weight lands in some exit bin, so Σ h_k cos θ_k ΔΩ_k / π = Σ Rd_a ΔΩ / Rd
    /// = 1 to rounding: h changes where light goes, not how much.
    #[test]
    fn cosine_weighted_mean_is_one() {
        let spec = RunSpec {
            sample: Sample::single(Layer {
                n: 1.4,
                mu_a: 1.0,
                mu_s: 50.0,
                g: 0.8,
                thickness: 1e8,
            }),
            grid: Grid {
                dr: 0.01,
                dz: 0.01,
                nr: 50,
                nz: 2,
                na: 9,
            },
            photons: 20_000,
            seed: 5,
            tallies: TallySet::default(),
        };
        let o = crate::run(&spec, &|_| {}).unwrap();
        let da = o.grid.da();
        let mean: f64 = radiance_ratio(&o)
            .iter()
            .enumerate()
            .map(|(k, b)| b.h.value * b.theta_deg.to_radians().cos() * bin_solid_angle(k, da))
            .sum::<f64>()
            / std::f64::consts::PI;
        assert!((mean - 1.0).abs() < 1e-12, "{mean}");
        // The midpoint rule for ∫ 2π sin θ dθ = 2π: within O(da²) of the hemisphere.
        let total: f64 = (0..9).map(|k| bin_solid_angle(k, da)).sum();
        assert!((total / (2.0 * std::f64::consts::PI) - 1.0).abs() < da * da / 20.0);
    }
}
