//! The lane walk (`lanes.rs`: four photons in flight, traced wherever nothing below the surfaces
//! is tallied) against the scalar walk (MCML's, traced wherever A(r, z) is tallied), and against
//! exact transport where there is an exact answer.

mod common;

use common::{assert_agree, assert_profiles_agree};
use mc::incidence::Incidence;
use mc::{Estimate, Grid, Layer, Output, RunSpec, Sample, TallySet};

fn spec(sample: &Sample, grid: Grid, photons: u64, seed: u64, tallies: TallySet) -> RunSpec {
    RunSpec {
        sample: sample.clone(),
        grid,
        photons,
        seed,
        tallies,
    }
}

fn run(sample: &Sample, grid: Grid, photons: u64, seed: u64, profile_only: bool) -> Output {
    run_at(sample, grid, photons, seed, profile_only, 0.0, 0)
}

fn run_at(
    sample: &Sample,
    grid: Grid,
    photons: u64,
    seed: u64,
    profile_only: bool,
    theta_deg: f64,
    surface_xy: usize,
) -> Output {
    let tallies = TallySet {
        absorption_rz: !profile_only,
        absorption_rz_se: true,
        surface_xy,
    };
    let spec = spec(sample, grid, photons, seed, tallies);
    mc::run_at(&spec, Incidence { theta_deg }, &|_| {}).unwrap()
}

/// A run with A(r, z), its standard errors from per-photon moments (`se`) or not.
fn run_tallies(sample: &Sample, grid: Grid, photons: u64, seed: u64, se: bool) -> Output {
    mc::run(&spec(sample, grid, photons, seed, with_rz(se)), &|_| {}).unwrap()
}

/// The tallies with A(r, z), with per-photon standard errors (`se`) or summed.
fn with_rz(se: bool) -> TallySet {
    TallySet {
        absorption_rz: true,
        absorption_rz_se: se,
        surface_xy: 0,
    }
}

/// |z| of two estimates' difference.
fn z(p: Estimate, q: Estimate) -> f64 {
    let v = p.se * p.se + q.se * q.se;
    if v == 0.0 {
        return if p.value == q.value {
            0.0
        } else {
            f64::INFINITY
        };
    }
    (p.value - q.value).abs() / v.sqrt()
}

/// Finite slabs between mismatched media (both surfaces reflect and transmit) with forward,
/// isotropic and backward scattering: Rd(r), Tt(r), Rd, Tt and A of the lane walk agree with the
/// scalar walk's (independent streams), and energy is conserved.
#[test]
fn lanes_agree_with_the_scalar_walk_in_slabs() {
    for (name, g, mu_a, mu_s, d, n_below) in [
        ("forward g = 0.9", 0.9, 1.0, 30.0, 0.2, 1.33),
        ("isotropic", 0.0, 2.0, 18.0, 0.1, 1.0),
        ("backward g = -0.5", -0.5, 0.5, 9.5, 0.3, 1.5),
    ] {
        let sample = Sample {
            n_above: 1.0,
            n_below,
            layers: vec![Layer {
                n: 1.4,
                mu_a,
                mu_s,
                g,
                thickness: d,
            }],
        };
        let grid = Grid {
            dr: 0.005,
            dz: d,
            nr: 60,
            nz: 1,
            na: 3,
        };
        let lanes = run(&sample, grid, 40_000, 1, true);
        let scalar = run(&sample, grid, 40_000, 2, false);
        assert_agree(name, &lanes, &scalar, 30);
        assert_profiles_agree(&format!("{name} Tt(r)"), &lanes.tt_r, &scalar.tt_r, 30);
        assert!(
            z(lanes.tt, scalar.tt) < 4.0,
            "{name} Tt: {:?} vs {:?}",
            lanes.tt,
            scalar.tt
        );
        // Energy is conserved in expectation (roulette moves it photon by photon): within 4 of
        // the sum's standard error, which is at most the sum of the three.
        let total = lanes.rsp + lanes.rd.value + lanes.tt.value + lanes.a.value;
        let se = lanes.rd.se + lanes.tt.se + lanes.a.se;
        assert!(
            (total - 1.0).abs() < 4.0 * se,
            "{name}: energy {total} ± {se}"
        );
    }
}

/// Oblique incidence (45°) on a half-space: the lane walk's surface grid Rd(x, y), which is
/// not radially symmetric, agrees with the scalar walk's.
#[test]
fn lanes_agree_with_the_scalar_walk_at_oblique_incidence() {
    let sample = Sample {
        n_above: 1.0,
        n_below: 1.0,
        layers: vec![Layer {
            n: 1.3,
            mu_a: 0.5,
            mu_s: 20.0,
            g: 0.5,
            thickness: 1.0e8,
        }],
    };
    let grid = Grid {
        dr: 0.02,
        dz: 0.1,
        nr: 30,
        nz: 1,
        na: 1,
    };
    let lanes = run_at(&sample, grid, 40_000, 3, true, 45.0, 6);
    let scalar = run_at(&sample, grid, 40_000, 4, false, 45.0, 6);
    assert_profiles_agree("Rd(x, y)", &lanes.rd_xy, &scalar.rd_xy, 100);
    assert!(
        z(lanes.rd, scalar.rd) < 4.0,
        "{:?} vs {:?}",
        lanes.rd,
        scalar.rd
    );
}

/// Exact transport where the walk is deterministic but for its interaction sites: an
/// index-matched slab of thickness d with a delta phase function forward (g = 1: scattering
/// changes nothing) or without scattering (albedo 0: the first interaction absorbs everything)
/// transmits exp(−μa·d) and reflects nothing (Beer–Lambert).
#[test]
fn lanes_transmit_beer_lambert_through_non_deflecting_slabs() {
    for (name, mu_a, mu_s, g) in [
        ("delta-forward scattering", 3.0, 7.0, 1.0),
        ("albedo 0", 3.0, 0.0, 0.0),
    ] {
        let d = 0.4;
        let sample = Sample::single(Layer {
            n: 1.0,
            mu_a,
            mu_s,
            g,
            thickness: d,
        });
        let grid = Grid {
            dr: 0.01,
            dz: d,
            nr: 10,
            nz: 1,
            na: 1,
        };
        let out = run(&sample, grid, 20_000, 5, true);
        let exact = (-mu_a * d).exp();
        let t = out.tt;
        assert!(
            (t.value - exact).abs() < 4.0 * t.se.max(1e-12),
            "{name}: Tt {t:?}, exact {exact}"
        );
        assert_eq!(out.rd.value, 0.0, "{name}: Rd");
        // Every transmitted photon leaves on the beam axis.
        let on_axis = out.tt_r[0].value * std::f64::consts::PI * grid.dr * grid.dr;
        assert!(
            (on_axis - t.value).abs() < 1e-9 * t.value.max(1e-300),
            "{name}: {on_axis}"
        );
    }
}

/// The lane walk is deterministic: the same seed gives the same bits whatever the thread count,
/// profile-only and with A(r, z) summed (compared as exact sums: its standard errors are NaN).
#[test]
fn lanes_are_deterministic_across_threads() {
    let sample = Sample::single(Layer {
        n: 1.3,
        mu_a: 0.1,
        mu_s: 10.0,
        g: 0.8,
        thickness: 1.0e8,
    });
    let grid = Grid {
        dr: 0.05,
        dz: 0.1,
        nr: 40,
        nz: 10,
        na: 1,
    };
    let photons = 3 * mc::CHUNK_PHOTONS + 17;
    let pool = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    };
    let profile = |threads| pool(threads).install(|| run(&sample, grid, photons, 9, true));
    assert_eq!(profile(1), profile(2));
    let spec = spec(&sample, grid, photons, 9, with_rz(false));
    let chunks = 0..mc::chunk_count(photons);
    let summed =
        |threads| pool(threads).install(|| mc::accumulate(&spec, chunks.clone(), &|_| {}).unwrap());
    assert_eq!(summed(1), summed(2));
}

/// χ² of a summed tally (no standard errors) against a per-photon one of the same photon count,
/// whose variance both share: Σ (a − b)²/(2 se_b²) over the cells with se_b < 0.2·b, within 5
/// standard deviations of its mean.
fn assert_summed_agrees(name: &str, summed: &[Estimate], exact: &[Estimate], min_cells: usize) {
    let (mut chi, mut dof) = (0.0, 0);
    for (a, b) in summed.iter().zip(exact) {
        assert!(a.se.is_nan(), "{name}: a summed cell has a standard error");
        if b.se > 0.0 && b.se < 0.2 * b.value {
            chi += (a.value - b.value).powi(2) / (2.0 * b.se * b.se);
            dof += 1;
        }
    }
    assert!(dof >= min_cells, "{name}: only {dof} cells to compare");
    assert!(
        chi < dof as f64 + 5.0 * (2.0 * dof as f64).sqrt(),
        "{name}: χ² = {chi:.1} over {dof} cells"
    );
}

/// A(r, z) summed as MCML sums it (`absorption_rz_se` off: lanes in one layer, the scalar walk in
/// two) agrees with A(r, z) gathered per photon (exact standard errors) in A(z) and A(r, z) by
/// χ², every deposit lands in a cell (Σ A(r, z)·volume = A to rounding), its standard errors
/// are marked not estimated (NaN), and the totals keep theirs.
#[test]
fn summed_absorption_agrees_with_per_photon_absorption() {
    let layer = |g, d| Layer {
        n: 1.4,
        mu_a: 1.0,
        mu_s: 19.0,
        g,
        thickness: d,
    };
    for (name, layers) in [
        ("one layer, g = 0.9", vec![layer(0.9, 0.3)]),
        ("half-space, g = 0", vec![layer(0.0, 1.0e8)]),
        ("two layers", vec![layer(0.9, 0.05), layer(0.0, 0.3)]),
    ] {
        let sample = Sample {
            n_above: 1.0,
            n_below: 1.0,
            layers,
        };
        let grid = Grid {
            dr: 0.01,
            dz: 0.01,
            nr: 30,
            nz: 30,
            na: 1,
        };
        let summed = run_tallies(&sample, grid, 40_000, 6, false);
        let exact = run_tallies(&sample, grid, 40_000, 7, true);
        assert_summed_agrees(&format!("{name} A(z)"), &summed.a_z, &exact.a_z, 20);
        assert_summed_agrees(&format!("{name} A(r,z)"), &summed.a_rz, &exact.a_rz, 200);
        // The annulus of bin ir: π((ir + 1)² − ir²)·dr².
        let volume = |ir: usize| 2.0 * std::f64::consts::PI * (ir as f64 + 0.5) * grid.dr * grid.dr;
        let total: f64 = (0..grid.nr * grid.nz)
            .map(|i| summed.a_rz[i].value * volume(i / grid.nz) * grid.dz)
            .sum();
        assert!(
            (total - summed.a.value).abs() < 1e-9 * summed.a.value,
            "{name}: ΣA(r,z) = {total}, A = {:?}",
            summed.a
        );
        for (what, p, q) in [("A", summed.a, exact.a), ("Rd", summed.rd, exact.rd)] {
            assert!(p.se > 0.0 && z(p, q) < 4.0, "{name} {what}: {p:?} vs {q:?}");
        }
    }
}
