//! The forward shift of obliquely entering light: where a half-space returns light that entered
//! at θ, on average. `mc`'s Rd(x, y; θ) for a beam whose propagation runs along +x has its
//! centroid δ(θ) ahead of the entry point (Wang & Jacques' shifted source; the directional
//! dipole's and `surface_gather`'s anisotropy): the first moment of the exit offset along the
//! propagation, δ = ∫∫ x·Rd dx dy / ∫∫ Rd dx dy. On the bust of `scripts/references`, a radial
//! profile centred δ ahead of the entry carries all that Rd(x, y; θ) adds over the radial profile
//! (surface gather, CI size: 16.4 against 16.1 %, the radial profile 25.0 %), while the profile's
//! change of shape with θ carries none (24.6 %); the scene pass moves each light's entry by it
//! (`Shading::entry_shift`, lighting.wgsl). By reciprocity the same table serves the exit: light
//! leaving towards a camera at θ_o last scattered, on average, δ(θ_o) further along the view
//! ray's propagation over the surface (what the camera sees of a shadow edge moves with it), so
//! the scene pass reads the light the camera sees at `entry_offset(n, l, δ(θ_i)) −
//! entry_offset(n, v, δ(θ_o))` (Skin1's bust against Mitsuba: 17.4 % with the light's term
//! alone, 13.1 % with both; docs/measurements.md, "The exit shift").

use crate::angles::{INCIDENCE_STEPS, incidence_ratio};
use crate::error::{Result, ShadingError};

/// The half width n of the surface grid (2n + 1 cells a side) the centroid is tallied on.
pub const SHIFT_GRID_HALF_WIDTH: usize = 192;

/// The grid's reach in transport mean free paths ℓ′ = 1/(σa + σs(1 − g)): the anisotropic part
/// of Rd(x, y; θ) lives within a few ℓ′ of the entry, the symmetric tail beyond adds nothing to
/// the first moment. Cells are ℓ′/9.6.
pub const SHIFT_GRID_REACH_MFP: f64 = 20.0;

/// The centroid δ(θ) [cm] of the light a half-space of the material returns, per channel, at
/// θ = 0°, 10°, …, 80° (the incidence table's angles; beyond 80° the last value), with its
/// standard error.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EntryShift {
    /// δ(θ) [cm], [θ index][channel]; ≥ 0 in expectation (the light is carried forward).
    pub shift_cm: [[f32; 3]; INCIDENCE_STEPS],
    /// Its standard error [cm] from the cells' per-photon second moments.
    pub shift_se_cm: [[f32; 3]; INCIDENCE_STEPS],
}

impl EntryShift {
    /// No shift: light leaves around where it entered (radial profiles).
    pub const NONE: EntryShift = EntryShift {
        shift_cm: [[0.0; 3]; INCIDENCE_STEPS],
        shift_se_cm: [[0.0; 3]; INCIDENCE_STEPS],
    };

    /// The table of the three channels of `spec` (a profile-only batch of one material), each
    /// angle a run of `spec.photons` per channel with seed `spec.seed` + angle index, tallied on
    /// a surface grid of [`SHIFT_GRID_HALF_WIDTH`] reaching [`SHIFT_GRID_REACH_MFP`] transport
    /// mean free paths (light beyond it is left out of the moment; a channel returning nothing
    /// at an angle has δ = 0). `progress` receives photon counts.
    pub fn from_mc(spec: &mc::BatchSpec, progress: &(dyn Fn(u64) + Sync)) -> Result<EntryShift> {
        if spec.channels.len() != 3 {
            return Err(ShadingError::invalid(
                "entry shift: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        let n = SHIFT_GRID_HALF_WIDTH;
        let mut cells = [0.0f64; 3];
        for (c, ch) in spec.channels.iter().enumerate() {
            let m = fit::analytic::Medium::of_layer(&ch.layer, spec.n_above);
            let mfp = 1.0 / m.sigma_t_reduced();
            if !(mfp.is_finite() && mfp > 0.0) {
                return Err(ShadingError::invalid(
                    format!("entry shift: transport mean free path of channel {c} [cm]"),
                    mfp,
                    "must be finite and positive (σa + σs(1 − g) > 0)",
                ));
            }
            cells[c] = SHIFT_GRID_REACH_MFP * mfp / n as f64;
        }
        let side = 2 * n + 1;
        let angles: Vec<f64> = (0..INCIDENCE_STEPS).map(|k| 10.0 * k as f64).collect();
        let mut table = EntryShift::NONE;
        mc::incidence::surface_grid_runs(spec, n, &cells, &angles, progress, |k, out| {
            for (c, o) in out.iter().enumerate() {
                // Cell (ix, iy) is centred at x = (ix − n)·s: the first moment δ = Σx·w/Σw and
                // its standard error (cells independent: each photon exits once).
                let x = |i: usize| ((i % side) as f64 - n as f64) * cells[c];
                let sum_w: f64 = o.rd_xy.iter().map(|v| v.value).sum();
                if sum_w > 0.0 {
                    let sum_xw: f64 = o
                        .rd_xy
                        .iter()
                        .enumerate()
                        .map(|(i, v)| x(i) * v.value)
                        .sum();
                    let delta = sum_xw / sum_w;
                    let var: f64 = (o.rd_xy.iter().enumerate())
                        .map(|(i, v)| ((x(i) - delta) / sum_w * v.se).powi(2))
                        .sum();
                    table.shift_cm[k][c] = delta as f32;
                    table.shift_se_cm[k][c] = var.sqrt() as f32;
                }
            }
        })?;
        table.validate()?;
        Ok(table)
    }

    /// Checks the table: finite entries, standard errors ≥ 0; the error names the field.
    pub fn validate(&self) -> Result<()> {
        for (what, t) in [("shift", &self.shift_cm), ("shift SE", &self.shift_se_cm)] {
            if let Some(v) = t.iter().flatten().find(|v| !v.is_finite()) {
                return Err(ShadingError::invalid(
                    format!("entry shift: {what} [cm]"),
                    v,
                    "must be finite",
                ));
            }
        }
        if let Some(v) = self.shift_se_cm.iter().flatten().find(|v| **v < 0.0) {
            return Err(ShadingError::invalid(
                "entry shift: shift SE [cm]",
                v,
                "must be ≥ 0",
            ));
        }
        Ok(())
    }

    /// δ at cos θ = `cos_i` per channel [cm], linear in θ between entries, the 80° value beyond
    /// (also for light from behind, cos θ ≤ 0): the CPU twin of `sss_entry_shift`
    /// ([`ENTRY_SHIFT_WGSL`]).
    pub fn at(&self, cos_i: f32) -> [f32; 3] {
        incidence_ratio(&self.shift_cm, cos_i)
    }
}

/// The WGSL of the entry shift's lookup, `sss_entry_shift(m, cos_i) -> vec3<f32>` [cm], and of
/// `sss_entry_offset(n, l, delta) -> vec3<f32>`, where the light leaving a point entered
/// (`wgsl/entry_shift.wgsl`; reads the host's `sss_shift_entry(m, k)`).
pub const ENTRY_SHIFT_WGSL: &str = include_str!("wgsl/entry_shift.wgsl");

/// Where the light leaving a point entered, relative to it [cm]: `delta` [cm] behind along the
/// light's propagation over the surface, t = −l less its part along the unit normal `n` (`l`:
/// the unit direction towards the light); zero where the light arrives along `n` (|t| ≤ 1e-4).
/// The CPU twin of `sss_entry_offset`.
pub fn entry_offset(n: [f32; 3], l: [f32; 3], delta: f32) -> [f32; 3] {
    let n_dot_l = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    let t = [0, 1, 2].map(|c| -l[c] + n_dot_l * n[c]);
    let along = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
    if along > 1e-4 {
        t.map(|v| -delta * v / along)
    } else {
        [0.0; 3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The single-scattering limit of δ(θ) [in 1/σt]: a photon entering an index-matched
    /// half-space at θ scatters first at path length τ/σt (τ ~ e^{−τ}), at depth τ·cos θ/σt and
    /// τ·sin θ/σt ahead of the entry; isotropically scattered, it escapes without another
    /// interaction with P(u) = ½∫₀¹ e^{−u/μ} dμ at optical depth u, and its exit offset averages
    /// to the scattering point's over the azimuth. So
    /// δ·σt = sin θ·∫τ e^{−τ} P(τ cos θ) dτ / ∫e^{−τ} P(τ cos θ) dτ (midpoint quadrature).
    fn single_scattering(theta_deg: f64) -> f64 {
        let (sin, cos) = theta_deg.to_radians().sin_cos();
        let escape = |u: f64| {
            let m = 400;
            (0..m)
                .map(|j| {
                    let mu = (j as f64 + 0.5) / m as f64;
                    (-u / mu).exp()
                })
                .sum::<f64>()
                * 0.5
                / m as f64
        };
        let (n, tau_max) = (4000, 40.0);
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..n {
            let tau = (i as f64 + 0.5) * tau_max / n as f64;
            let w = (-tau).exp() * escape(tau * cos);
            num += tau * w;
            den += w;
        }
        sin * num / den
    }

    /// Three index-matched media of single-scattering albedo 1 %, 2 % and 0.5 % (σt = 10, 5 and
    /// 20 cm⁻¹, isotropic): what returns has scattered once, up to a share of about the albedo.
    /// Every angle's δ lies within 3 standard errors plus that share (3 %) of the quadrature,
    /// δ(0°) is 0 within 3 SE (the mirror symmetry of normal incidence), and δ scales as 1/σt.
    #[test]
    fn the_shift_of_a_nearly_absorbing_medium_is_single_scatterings() {
        let material = mc::Material {
            name: "single".into(),
            source: String::new(),
            sigma_a: [9.9, 4.9, 19.9],
            sigma_s: [0.1, 0.1, 0.1],
            g: [0.0; 3],
            eta: 1.0,
            thickness: None,
        };
        let config = mc::SimConfig::thesis().unwrap();
        let spec = config.batch(&[&material], 200_000, 11, true).unwrap();
        let t = EntryShift::from_mc(&spec, &|_| {}).unwrap();
        let sigma_t = [10.0, 5.0, 20.0];
        for k in 0..INCIDENCE_STEPS {
            let want = single_scattering(10.0 * k as f64);
            for (c, s) in sigma_t.iter().enumerate() {
                let (got, se) = (t.shift_cm[k][c] as f64 * s, t.shift_se_cm[k][c] as f64 * s);
                eprintln!(
                    "θ = {}°, channel {c}: δ·σt = {got:.4} ± {se:.4}, single scattering {want:.4}",
                    10 * k
                );
                assert!(se > 0.0, "{k}, {c}: no standard error");
                assert!(
                    (got - want).abs() < 3.0 * se + 0.03 * want,
                    "θ = {}°, channel {c}: δ·σt = {got:.4} ± {se:.4}, single scattering {want:.4}",
                    10 * k
                );
            }
        }
    }

    #[test]
    fn a_medium_with_nothing_to_scatter_is_refused_by_name() {
        let material = mc::Material {
            name: "void".into(),
            source: String::new(),
            sigma_a: [0.0; 3],
            sigma_s: [0.0; 3],
            g: [0.0; 3],
            eta: 1.0,
            thickness: None,
        };
        let config = mc::SimConfig::thesis().unwrap();
        match config.batch(&[&material], 1000, 1, true) {
            // The batch itself may refuse it first; either way it never reaches a shader.
            Err(_) => {}
            Ok(spec) => {
                let e = EntryShift::from_mc(&spec, &|_| {}).unwrap_err().to_string();
                assert!(e.contains("transport mean free path"), "{e}");
            }
        }
    }
}
