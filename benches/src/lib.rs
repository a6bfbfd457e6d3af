//! Shared setup of the `sss-benches` criterion benchmarks (`benches/mc.rs`, `fit.rs`,
//! `eval.rs`): the built-in materials and the thesis run settings (Table 6.1) from `mc`, a single-channel run on the
//! thesis grid, and the analytic Skin1 profile the `fit` and `eval` benches work on.
//!
//! Lengths in cm, coefficients in cm⁻¹, as in `mc` and `fit`. Setup panics with the file and the
//! reason when an input is missing or invalid: a benchmark has nothing to report an error to.

use fit::Profile;
use fit::analytic::Model;
use mc::{Material, RunSpec, Sample, SimConfig, TallySet};

/// The built-in material `slug` (`mc::builtin`).
pub fn material(slug: &str) -> Material {
    Material::builtin(slug).unwrap_or_else(|e| panic!("{e}"))
}

/// The thesis's run settings (Table 6.1).
pub fn thesis_config() -> SimConfig {
    SimConfig::thesis().unwrap_or_else(|e| panic!("{e}"))
}

/// One channel `c` of a material as `sss bench mc` traces it: a half-space on the material's
/// thesis grid, `photons` packets, seed 1.
pub fn single_channel(m: &Material, c: usize, photons: u64, tallies: TallySet) -> RunSpec {
    let config = thesis_config();
    RunSpec {
        sample: Sample {
            n_above: config.n_above,
            n_below: config.n_below,
            layers: vec![m.layer(c, m.thickness.unwrap_or(config.thickness_cm))],
        },
        grid: config.grid_for(m).unwrap_or_else(|e| panic!("{e}")),
        photons,
        seed: 1,
        tallies,
    }
}

/// Skin1's Rd(r) [cm⁻²] from photon beam diffusion, every bin an annulus average (as `sss
/// profile skin1 --model pbd` computes it), on the thesis grid: dr = min MFP / 20, bins out to
/// 32 of the largest MFP, or to `reach_mfp` of it when given. The size and shape of the Monte
/// Carlo profile without simulating it.
pub fn skin1_profile(reach_mfp: Option<f64>) -> Profile {
    let m = material("skin1");
    let mut config = thesis_config();
    if let Some(reach) = reach_mfp {
        config.grid.r_max_mfp = reach;
    }
    let grid = config.grid_for(&m).unwrap_or_else(|e| panic!("{e}"));
    fit::analytic::profile(Model::Pbd, &m, grid.dr, grid.nr).unwrap_or_else(|e| panic!("{e}"))
}
