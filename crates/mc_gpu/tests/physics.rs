//! Answers physics gives exactly: Fresnel's reflectance at the entry surface, a slab that does not
//! scatter (Beer–Lambert between two Fresnel interfaces, every multiple reflection summed), and
//! index matching (η = 1: no reflection anywhere).

mod common;

use mc::{Grid, Layer, RunSpec, Sample, TallySet, specular};

fn slab(n: f64, mu_a: f64, mu_s: f64, thickness: f64) -> RunSpec {
    RunSpec {
        sample: Sample::single(Layer {
            n,
            mu_a,
            mu_s,
            g: 0.0,
            thickness,
        }),
        grid: Grid {
            dr: 0.01,
            dz: 0.01,
            nr: 50,
            nz: 1,
            na: 10,
        },
        photons: 1_000_000,
        seed: 11,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    }
}

/// A glass slab of η = 1 in air reflects nothing, specularly or inside, and transmits every
/// photon straight through: Tt = 1 with no noise at all, Rsp = Rd = A = 0.
#[test]
fn an_index_matched_glass_slab_transmits_everything_exactly() {
    let Some(gpu) = common::gpu() else { return };
    let out = mc_gpu::run(&gpu, &slab(1.0, 0.0, 0.0, 0.3), &|_| {}).unwrap();
    assert_eq!(out.rsp, 0.0);
    assert_eq!((out.tt.value, out.tt.se), (1.0, 0.0));
    assert_eq!((out.rd.value, out.a.value), (0.0, 0.0));
    // Straight down the axis: the first radial and exit-angle bins.
    assert!(out.tt_ra[0].value > 0.0);
    assert_eq!(out.tt_ra.iter().filter(|e| e.value > 0.0).count(), 1);
}

/// A scattering half-space of η = 1 has no specular reflection: Rsp = 0 exactly and the launched
/// weight is 1; its profile still agrees with the CPU's.
#[test]
fn eta_one_gives_no_specular_reflection() {
    let Some(gpu) = common::gpu() else { return };
    let mut spec = slab(1.0, 1.0, 50.0, 1e8);
    spec.photons = 200_000;
    let g = mc_gpu::run(&gpu, &spec, &|_| {}).unwrap();
    let c = mc::run(&spec, &|_| {}).unwrap();
    assert_eq!((g.rsp, c.rsp), (0.0, 0.0));
    // Every launched photon's weight 1 ends up reflected or absorbed (roulette is unbiased).
    assert!(common::within(
        mc::Estimate {
            value: g.rd.value + g.a.value,
            se: g.rd.se + g.a.se
        },
        mc::Estimate {
            value: 1.0,
            se: 0.0
        },
        3.0,
        1e-6
    ));
    common::agree("eta = 1", &g, &c).unwrap_or_else(|l| panic!("{l}"));
}

/// A slab that absorbs but does not scatter, η = 1.5 in air: Rsp = ((n − 1)/(n + 1))² exactly,
/// and with R that reflectance, T = e^{−μa d} the transmission of one crossing,
/// Tt = (1 − R)² T / (1 − R²T²) and Rd = (1 − R)² R T² / (1 − R²T²) (the geometric series of
/// the reflections inside); every photon's weight is deposited, transmitted or reflected whole,
/// so A = 1 − Rsp − Rd − Tt up to f32 rounding.
#[test]
fn a_slab_that_does_not_scatter_follows_beer_lambert_and_fresnel() {
    let Some(gpu) = common::gpu() else { return };
    let (n, mu_a, d) = (1.5, 2.0, 0.5);
    let out = mc_gpu::run(&gpu, &slab(n, mu_a, 0.0, d), &|_| {}).unwrap();
    let r: f64 = ((n - 1.0) / (n + 1.0)).powi(2);
    assert_eq!(out.rsp, specular(1.0, n, None));
    assert_eq!(out.rsp, r);
    let t = (-mu_a * d).exp();
    let tt = (1.0 - r).powi(2) * t / (1.0 - r * r * t * t);
    let rd = (1.0 - r).powi(2) * r * t * t / (1.0 - r * r * t * t);
    let exact = |value| mc::Estimate { value, se: 0.0 };
    assert!(
        common::within(out.tt, exact(tt), 3.0, 0.0),
        "Tt {:?} vs {tt}",
        out.tt
    );
    assert!(
        common::within(out.rd, exact(rd), 3.0, 0.0),
        "Rd {:?} vs {rd}",
        out.rd
    );
    let sum = out.rsp + out.rd.value + out.tt.value + out.a.value;
    assert!((sum - 1.0).abs() < 1e-6, "energy: {sum}");
    // Nothing leaves off the axis.
    assert_eq!(out.rd_r.iter().skip(1).map(|e| e.value).sum::<f64>(), 0.0);
}

/// A half-space that does not scatter reflects only specularly: Rd = 0 and Tt = 0 exactly, and
/// every launched photon is absorbed, A = 1 − Rsp.
#[test]
fn a_half_space_that_does_not_scatter_reflects_only_specularly() {
    let Some(gpu) = common::gpu() else { return };
    let out = mc_gpu::run(&gpu, &slab(1.4, 3.0, 0.0, 1e8), &|_| {}).unwrap();
    assert_eq!(out.rsp, specular(1.0, 1.4, None));
    assert_eq!((out.rd.value, out.tt.value), (0.0, 0.0));
    assert!((out.a.value - (1.0 - out.rsp)).abs() < 1e-7, "{:?}", out.a);
}
