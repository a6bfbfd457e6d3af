//! Cycles' random walk traced by `mc` (`mc::cycles`): the same walk as `mc`'s own where Cycles'
//! changes do not apply, the similarity-scaled medium where they apply from the start, energy
//! kept but for the walks Cycles drops. (Blender's own renders against it: `scripts/engines/blender.py
//! slab --g`.)

use mc::cycles::{CyclesWalk, run_cycles, similarity_scaled};
use mc::{Grid, Incidence, Layer, Output, RunSpec, Sample, TallySet};

const GRID: Grid = Grid {
    dr: 0.02,
    dz: 0.02,
    nr: 50,
    nz: 10,
    na: 5,
};

fn spec(layer: Layer, photons: u64, tallies: TallySet) -> RunSpec {
    RunSpec {
        sample: Sample::single(layer),
        grid: GRID,
        photons,
        seed: 7,
        tallies,
    }
}

fn layer(alpha: f64, g: f64, thickness: f64) -> Layer {
    Layer {
        n: 1.0,
        mu_a: 10.0 * (1.0 - alpha),
        mu_s: 10.0 * alpha,
        g,
        thickness,
    }
}

fn cycles(s: &RunSpec, walk: CyclesWalk) -> Output {
    run_cycles(s, Incidence::NORMAL, walk, &|_| {}).unwrap()
}

/// Every tally of two runs, bit for bit.
fn assert_same_bits(what: &str, a: &Output, b: &Output) {
    let bits = |o: &Output| -> Vec<u64> {
        [o.rd, o.tt, o.a]
            .iter()
            .chain(&o.rd_r)
            .chain(&o.tt_r)
            .chain(&o.a_rz)
            .chain(&o.rd_a)
            .flat_map(|e| [e.value.to_bits(), e.se.to_bits()])
            .collect()
    };
    assert!(bits(a) == bits(b), "{what}: {:?} against {:?}", a.rd, b.rd);
    assert_eq!(a.interactions, b.interactions, "{what}");
}

/// The given medium throughout, never dropped: `mc`'s own (scalar) walk, bit for bit, on a slab
/// with transmission and on a half-space, anisotropic.
#[test]
fn the_exact_walk_is_mcs_own() {
    for l in [layer(0.9, 0.8, 0.3), layer(0.99, 0.5, 1e6)] {
        let s = spec(l, 20_000, TallySet::default());
        let own = mc::run(&s, &|_| {}).unwrap();
        assert_same_bits("exact", &cycles(&s, CyclesWalk::EXACT), &own);
    }
}

/// At g = 0 the scaled medium is the given one (σs(1 − 0) = σs): Blender's walk is the medium's
/// own, bit for bit, wherever no walk needs 256 flights (single-scattering albedo 0.9: a walk's
/// weight is 0.9²⁵⁶ ≈ 2·10⁻¹² by then, so roulette has ended it).
#[test]
fn at_g_0_blenders_walk_is_the_medium() {
    for thickness in [0.3, 1e6] {
        let s = spec(layer(0.9, 0.0, thickness), 20_000, TallySet::default());
        let own = mc::run(&s, &|_| {}).unwrap();
        assert_same_bits("g = 0", &cycles(&s, CyclesWalk::BLENDER), &own);
    }
}

/// Switching at the first flight traces the similarity-scaled medium σs(1 − g), σa, isotropic,
/// from the start: `mc`'s walk of that medium, bit for bit.
#[test]
fn switching_at_once_traces_the_similarity_scaled_medium() {
    let l = layer(0.95, 0.85, 0.5);
    let s = spec(l, 20_000, TallySet::default());
    let scaled = spec(similarity_scaled(&l), 20_000, TallySet::default());
    let at_once = CyclesWalk {
        exact_flights: 0,
        max_flights: u32::MAX,
    };
    assert_same_bits(
        "switch at 0",
        &cycles(&s, at_once),
        &mc::run(&scaled, &|_| {}).unwrap(),
    );
    assert!((similarity_scaled(&l).mu_s / (l.mu_s * 0.15) - 1.0).abs() < 1e-15);
    assert_eq!(similarity_scaled(&l).mu_a, l.mu_a);
}

/// Energy: without the 256-flight cap, what is reflected, transmitted and absorbed adds up to
/// the light that entered (within noise: roulette is unbiased, not exact), whatever the switch
/// does to the medium. With the cap, in a half-space of single-scattering albedo 0.999 where
/// walks are long, light is lost: Rd + A falls measurably below 1.
#[test]
fn energy_is_kept_but_for_the_walks_cycles_drops() {
    for l in [layer(0.95, 0.9, 0.4), layer(0.999, 0.7, 1e6)] {
        let s = spec(l, 20_000, TallySet::default());
        let uncapped = CyclesWalk {
            max_flights: u32::MAX,
            ..CyclesWalk::BLENDER
        };
        let o = cycles(&s, uncapped);
        let total = o.rd.value + o.tt.value + o.a.value;
        let se = o.rd.se + o.tt.se + o.a.se;
        assert!(
            (total - 1.0).abs() <= 4.0 * se + 1e-12,
            "{l:?}: {total} ± {se}"
        );
    }
    let s = spec(layer(0.999, 0.7, 1e6), 20_000, TallySet::default());
    let o = cycles(&s, CyclesWalk::BLENDER);
    let total = o.rd.value + o.a.value;
    assert!(1.0 - total > 10.0 * (o.rd.se + o.a.se), "{total}");
}
