//! The importance roulette of profile-only runs (`mc::IMPORTANCE_THRESHOLD`): unbiased against
//! runs without it, and it removes most of the interactions of photons deep in weakly absorbing
//! half-spaces. (Against exact transport: `validation.rs`, `profile_only_runs_match_chandrasekhar`.)

mod common;

use common::assert_agree;
use mc::{Grid, Layer, Output, RunSpec, Sample, TallySet};

const PROFILE_ONLY: TallySet = TallySet {
    absorption_rz: false,
    absorption_rz_se: true,
    surface_xy: 0,
};

fn run(layer: Layer, grid: Grid, photons: u64, seed: u64, tallies: TallySet) -> Output {
    let spec = RunSpec {
        sample: Sample::single(layer),
        grid,
        photons,
        seed,
        tallies,
    };
    mc::run(&spec, &|_| {}).unwrap()
}

/// Wholemilk R and Soy milk R (thesis Table 6.2, directional-dipole draft Table 4.1; σa, σs in
/// cm⁻¹, η = 1.3):
/// the profile, Rd and A of a profile-only run agree with an independent run with MCML's tallies
/// (no importance roulette), the reflectance's standard error is within 10 % of it, and the
/// profile-only run takes less than half the interactions per photon.
#[test]
fn importance_roulette_keeps_profiles_and_halves_the_work() {
    for (name, mu_a, mu_s, g, photons) in [
        ("wholemilk R", 0.011, 25.5, 0.0, 100_000),
        ("soymilk R", 0.001, 2.433, 0.873, 20_000),
    ] {
        let layer = Layer {
            n: 1.3,
            mu_a,
            mu_s,
            g,
            thickness: 1.0e8,
        };
        let mfp = 1.0 / (layer.mu_a + layer.mu_s * (1.0 - g));
        let grid = Grid {
            dr: mfp / 20.0,
            dz: mfp,
            nr: 20 * 32,
            nz: 4,
            na: 4,
        };
        let full = run(layer, grid, photons, 1, TallySet::default());
        let fast = run(layer, grid, photons, 2, PROFILE_ONLY);
        assert_agree(name, &fast, &full, 50);
        assert!(
            fast.rd.se < 1.1 * full.rd.se,
            "{name}: Rd ± {} vs {}",
            fast.rd.se,
            full.rd.se
        );
        let per = |o: &Output| o.interactions as f64 / o.photons as f64;
        assert!(
            per(&fast) < 0.5 * per(&full),
            "{name}: {:.0} vs {:.0} interactions per photon",
            per(&fast),
            per(&full)
        );
    }
}

/// Several layers, a glass top and a finite bottom: τ(z) accumulates layer by layer (glass adds
/// nothing) and the importance looks towards the nearer surface, so the light transmitted through
/// the bottom is still sampled. Profile-only and MCML-tallied runs agree on the profile, Rd, A and
/// Tt, and the importance roulette saves work.
#[test]
fn importance_roulette_is_unbiased_in_a_layered_slab() {
    let layer = |n: f64, mu_a: f64, mu_s: f64, g: f64, thickness: f64| Layer {
        n,
        mu_a,
        mu_s,
        g,
        thickness,
    };
    let sample = Sample {
        n_above: 1.0,
        n_below: 1.0,
        layers: vec![
            layer(1.52, 0.0, 0.0, 0.0, 0.1),
            layer(1.37, 0.05, 20.0, 0.8, 2.0),
            layer(1.4, 0.02, 30.0, 0.5, 2.0),
        ],
    };
    let grid = Grid {
        dr: 0.02,
        dz: 0.1,
        nr: 200,
        nz: 4,
        na: 4,
    };
    let spec = |seed: u64, tallies: TallySet| RunSpec {
        sample: sample.clone(),
        grid,
        photons: 40_000,
        seed,
        tallies,
    };
    let full = mc::run(&spec(5, TallySet::default()), &|_| {}).unwrap();
    let fast = mc::run(&spec(6, PROFILE_ONLY), &|_| {}).unwrap();
    assert_agree("layered slab", &fast, &full, 50);
    assert!(
        full.tt.value > 10.0 * full.tt.se,
        "Tt {:?} must be resolved",
        full.tt
    );
    let z = (fast.tt.value - full.tt.value) / fast.tt.se.hypot(full.tt.se);
    assert!(
        z.abs() < 4.0,
        "Tt: {:?} vs {:?} (z = {z:.2})",
        fast.tt,
        full.tt
    );
    assert!(
        fast.interactions < full.interactions * 9 / 10,
        "{} vs {} interactions",
        fast.interactions,
        full.interactions
    );
}
