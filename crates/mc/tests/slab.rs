//! Slab transmittance tables: exact for a non-scattering slab (Beer–Lambert between two Fresnel
//! interfaces, multiple internal reflections summed), and monotone in thickness for a scattering
//! one.

use mc::slab::transmittance_table;
use mc::{BatchSpec, ChannelSpec, Grid, Layer, TallySet};

fn spec(mu_a: f64, mu_s: f64, n: f64) -> BatchSpec {
    BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: vec![ChannelSpec {
            layer: Layer {
                n,
                mu_a,
                mu_s,
                g: 0.0,
                thickness: 1.0,
            },
            grid: Grid {
                dr: 0.01,
                dz: 0.01,
                nr: 10,
                nz: 1,
                na: 1,
            },
        }],
        photons: 20_000,
        seed: 9,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: true,
            surface_xy: 0,
        },
    }
}

/// Without scattering, a normally incident beam crosses the slab, and each internal reflection
/// (R = ((n − 1)/(n + 1))²) sends part of it back and forth: Tt = (1 − R)²e^{−μa d}/(1 −
/// R²e^{−2μa d}). Implicit capture makes every photon score the same weight: exact to rounding.
#[test]
fn non_scattering_slab_is_beer_lambert_between_two_interfaces() {
    let (mu_a, n): (f64, f64) = (2.0, 1.4);
    let r = ((n - 1.0) / (n + 1.0)).powi(2);
    let rows = transmittance_table(&spec(mu_a, 0.0, n), &[0.05, 0.3, 1.0], &|_| {}).unwrap();
    for row in rows {
        let a = (-mu_a * row.thickness_cm).exp();
        let want = (1.0 - r).powi(2) * a / (1.0 - r * r * a * a);
        let got = row.tt[0];
        assert!(
            (got.value - want).abs() < 1e-3 * want + 4.0 * got.se,
            "d = {}: {} ± {} vs {want}",
            row.thickness_cm,
            got.value,
            got.se
        );
    }
}

/// A scattering slab transmits less the thicker it is (each step many standard errors apart),
/// and bad thicknesses are refused with the field named.
#[test]
fn scattering_slab_transmits_less_when_thicker() {
    let s = spec(0.5, 20.0, 1.3);
    let rows = transmittance_table(&s, &[0.02, 0.1, 0.3], &|_| {}).unwrap();
    for w in rows.windows(2) {
        let (a, b) = (w[0].tt[0], w[1].tt[0]);
        assert!(
            a.value - b.value > 5.0 * a.se.hypot(b.se),
            "{a:?} then {b:?}"
        );
    }
    for bad in [0.0, -1.0, f64::NAN] {
        let e = transmittance_table(&s, &[bad], &|_| {}).unwrap_err();
        assert!(e.to_string().contains("thickness"), "{e}");
    }
}
