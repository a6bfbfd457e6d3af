//! Oblique incidence: a pencil beam at polar angle θ in the medium above, in the x–z plane
//! (azimuth 0, so reflectance shifts towards +x), refracted into the sample by Snell's law with
//! the unpolarized Fresnel reflectance as Rsp. θ = 0 is MCML's normal incidence, bit for bit.
//!
//! [`rd_table`] measures total diffuse reflectance Rd(θ) per channel over a list of angles: one
//! batch run per angle (channels that share g and η share the walk, as everywhere in `mc`), each
//! angle with its own random streams. [`surface_grid_runs`] hands over each angle's whole outputs
//! tallied on a surface grid Rd(x, y), for tables of the reflectance's shape.

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

/// The batch outputs (one per channel) of `spec` at each of `angles` [degrees], tallied on a
/// surface grid Rd(x, y) of half width `half_width` whose channel c has cells of side
/// `cells_cm[c]` (its radial grid too: `half_width` bins of that width). Angle `i` runs with
/// seed `spec.seed + i`; `each` receives its index and outputs as they come, so one angle's grids
/// are held at a time; `progress` gets the photons traced.
pub fn surface_grid_runs(
    spec: &BatchSpec,
    half_width: usize,
    cells_cm: &[f64],
    angles: &[f64],
    progress: &(dyn Fn(u64) + Sync),
    mut each: impl FnMut(usize, &[crate::Output]),
) -> Result<()> {
    if cells_cm.len() != spec.channels.len() {
        return Err(McError::invalid(
            "surface grid: cell sides",
            cells_cm.len(),
            "give one per channel",
        ));
    }
    let mut s = spec.clone();
    s.tallies.surface_xy = half_width;
    for (ch, &cell) in s.channels.iter_mut().zip(cells_cm) {
        ch.grid.dr = cell;
        ch.grid.nr = half_width;
    }
    for (i, &theta_deg) in angles.iter().enumerate() {
        let run = BatchSpec {
            seed: spec.seed.wrapping_add(i as u64),
            ..s.clone()
        };
        let out = crate::simulate::run_batch_at(&run, Incidence { theta_deg }, progress)?;
        each(i, &out);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> BatchSpec {
        let material = crate::Material {
            name: "Skin1".into(),
            source: String::new(),
            sigma_a: [0.32, 1.7, 4.8],
            sigma_s: [7.4, 8.8, 10.1],
            g: [0.0; 3],
            eta: 1.0,
            thickness: None,
        };
        let config = crate::SimConfig::thesis().unwrap();
        config.batch(&[&material], 20_000, 3, true).unwrap()
    }

    /// Each angle's grids come in order, (2n + 1)² cells per channel; the reflectance of the
    /// beam at 60° (propagating towards +x) lies ahead of the entry, at 0° about it.
    #[test]
    fn surface_grid_runs_hand_over_each_angle_and_carry_oblique_light_forward() {
        let (n, cells) = (32, [0.02, 0.02, 0.02]);
        let mut seen = Vec::new();
        surface_grid_runs(&spec(), n, &cells, &[0.0, 60.0], &|_| {}, |k, out| {
            assert_eq!(out.len(), 3);
            let side = 2 * n + 1;
            let o = &out[0];
            assert_eq!(o.rd_xy.len(), side * side);
            let (sw, sxw) = o
                .rd_xy
                .iter()
                .enumerate()
                .fold((0.0, 0.0), |(a, b), (i, v)| {
                    let x = ((i % side) as f64 - n as f64) * cells[0];
                    (a + v.value, b + x * v.value)
                });
            seen.push((k, sxw / sw));
        })
        .unwrap();
        assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), [0, 1]);
        let (at0, at60) = (seen[0].1, seen[1].1);
        assert!(at60 > 0.02 && at0.abs() < 0.25 * at60, "{at0} {at60}");
    }

    #[test]
    fn a_surface_grid_needs_a_cell_side_per_channel() {
        let e = surface_grid_runs(&spec(), 8, &[0.1], &[0.0], &|_| {}, |_, _| {}).unwrap_err();
        assert!(e.to_string().contains("surface grid: cell sides"), "{e}");
    }
}
