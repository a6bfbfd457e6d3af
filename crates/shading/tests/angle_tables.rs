//! The angle tables of incidence- and exit-aware shading (`shading::AngleTables::from_mc`) against
//! Chandrasekhar's exact results for an index-matched, isotropically scattering half-space.

use shading::{AngleTables, INCIDENCE_STEPS};

use testkit::chandrasekhar::{h_function as h, h_solver};

/// Three channels of albedo 0.99, 0.9 and 0.5, η = 1, g = 0, a half-space. The total diffuse
/// reflectance at incidence cos θ = μ₀ is 1 − √(1−w)·H(μ₀), so the incidence table must be
/// (1 − √(1−w)H(cos θ))/(1 − √(1−w)H(1)); the light reflected at incidence cosine μ₀ has
/// radiance ∝ H(μ)/(μ + μ₀) at exit cosine μ, so h(θ_o; θ_i) is that over 2∫H(μ)/(μ + μ₀)·μ dμ,
/// compared on the exit bins the table averages (the 0–10° bin for 0°, the two around 10k°).
#[test]
fn tables_match_chandrasekhar_for_an_isotropic_half_space() {
    let albedo = [0.99, 0.9, 0.5];
    let material = mc::Material {
        name: "isotropic".into(),
        source: String::new(),
        sigma_a: albedo.map(|w| 10.0 * (1.0 - w)),
        sigma_s: albedo.map(|w| 10.0 * w),
        g: [0.0; 3],
        eta: 1.0,
        thickness: None,
    };
    let config = mc::SimConfig::thesis().unwrap();
    let spec = config.batch(&[&material], 100_000, 11, true).unwrap();
    let t = AngleTables::from_mc(&spec, true, true, &|_| {}).unwrap();
    let n = 2000;
    for (c, &w) in albedo.iter().enumerate() {
        // H(·) solved once per albedo (h_function solves it at every call).
        let h_w = h_solver(w);
        let h = |_: f64, mu: f64| h_w(mu);
        let rd = |mu: f64| 1.0 - (1.0 - w).sqrt() * h(w, mu);
        for k in 0..INCIDENCE_STEPS {
            let mu0 = (10.0 * k as f64).to_radians().cos();
            let want = rd(mu0) / rd(1.0);
            let (got, se) = (t.incidence[k][c] as f64, t.incidence_se[k][c] as f64);
            assert!(
                (got - want).abs() <= 4.0 * se + 2e-3,
                "w {w}, {}°: ρ(θ)/ρ(0) {got} ± {se}, Chandrasekhar {want}",
                10 * k
            );
        }
        for (i, row) in t.exit.iter().enumerate() {
            let mu0 = (10.0 * i as f64).to_radians().cos();
            let radiance = |mu: f64| h(w, mu) / (mu + mu0);
            let norm: f64 = 2.0
                * (0..n)
                    .map(|k| {
                        let mu = (k as f64 + 0.5) / n as f64;
                        radiance(mu) * mu / n as f64
                    })
                    .sum::<f64>();
            // An exit bin's h as mc tallies it: the intensity (radiance · cos θ) averaged over
            // the bin's solid angle, over cos θ at its centre (`mc::exitance`).
            let bin = |b: usize| {
                let (lo, hi) = (
                    (10.0 * b as f64).to_radians(),
                    (10.0 * (b + 1) as f64).to_radians(),
                );
                let m = 200;
                let (mut num, mut den) = (0.0, 0.0);
                for j in 0..m {
                    let th = lo + (j as f64 + 0.5) / m as f64 * (hi - lo);
                    num += radiance(th.cos()) * th.cos() * th.sin();
                    den += th.sin();
                }
                num / den / (0.5 * (lo + hi)).cos() / norm
            };
            for (k, entry) in row.iter().enumerate() {
                let want = if k == 0 {
                    bin(0)
                } else {
                    0.5 * (bin(k - 1) + bin(k))
                };
                let (got, se) = (entry[c] as f64, t.exit_se[i][k][c] as f64);
                assert!(
                    (got - want).abs() <= 4.0 * se + 0.01 * want,
                    "w {w}, entering at {}°, leaving at {}°: h {got} ± {se}, Chandrasekhar {want}",
                    10 * i,
                    10 * k
                );
            }
        }
    }
    // Off means all ones, and no run.
    assert_eq!(
        AngleTables::from_mc(&spec, false, false, &|_| panic!("no run")).unwrap(),
        AngleTables::ONES
    );
}

/// A channel that does not scatter (σs = 0) returns no diffuse light at any angle: nothing to
/// shape, so its entries stay ones, while the channel that scatters beside it (albedo 0.9) gets
/// its own table: Chandrasekhar's ρ(θ)/ρ(0) at 80°, as above.
#[test]
fn a_channel_that_does_not_scatter_keeps_neutral_tables() {
    let material = mc::Material {
        name: "dark".into(),
        source: String::new(),
        sigma_a: [1.0, 16.4, 19.2],
        sigma_s: [9.0, 0.0, 0.0],
        g: [0.0; 3],
        eta: 1.0,
        thickness: None,
    };
    let config = mc::SimConfig::thesis().unwrap();
    let spec = config.batch(&[&material], 2000, 11, true).unwrap();
    let t = AngleTables::from_mc(&spec, true, true, &|_| {}).unwrap();
    for c in [1, 2] {
        for k in 0..INCIDENCE_STEPS {
            assert_eq!(t.incidence[k][c], 1.0);
            assert_eq!(t.incidence_se[k][c], 0.0);
            assert!(t.exit[k].iter().all(|e| e[c] == 1.0));
        }
    }
    let rd = |mu: f64| 1.0 - (1.0f64 - 0.9).sqrt() * h(0.9, mu);
    let want = rd(80f64.to_radians().cos()) / rd(1.0);
    let (got, se) = (t.incidence[8][0] as f64, t.incidence_se[8][0] as f64);
    assert!(
        (got - want).abs() <= 4.0 * se + 2e-3,
        "{got} ± {se}, Chandrasekhar {want}"
    );
}
