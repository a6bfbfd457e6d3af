//! The angle tables of incidence- and exit-aware shading (`gpu::AngleTables::from_mc`) against
//! Chandrasekhar's exact results for an index-matched, isotropically scattering half-space.

use gpu::{AngleTables, INCIDENCE_STEPS};

#[path = "../../../tests/support/chandrasekhar.rs"]
mod chandrasekhar;
use chandrasekhar::h_function as h;

/// Three channels of albedo 0.99, 0.9 and 0.5, η = 1, g = 0, a half-space. The total diffuse
/// reflectance at incidence cos θ = μ₀ is 1 − √(1−w)·H(μ₀), so the incidence table must be
/// (1 − √(1−w)H(cos θ))/(1 − √(1−w)H(1)); the light reflected at normal incidence has radiance
/// ∝ H(μ)/(1 + μ) at exit cosine μ, so h(θ) is that over 2∫H(μ)/(1 + μ)·μ dμ, compared at the
/// exit bins the table averages (5° for 0°, 10k ± 5° for 10k°).
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
        let radiance = |mu: f64| h(w, mu) / (1.0 + mu);
        let norm: f64 = 2.0
            * (0..n)
                .map(|k| {
                    let mu = (k as f64 + 0.5) / n as f64;
                    radiance(mu) * mu / n as f64
                })
                .sum::<f64>();
        let h_at = |deg: f64| radiance(deg.to_radians().cos()) / norm;
        for k in 0..INCIDENCE_STEPS {
            let want = if k == 0 {
                h_at(5.0)
            } else {
                0.5 * (h_at(10.0 * k as f64 - 5.0) + h_at(10.0 * k as f64 + 5.0))
            };
            let (got, se) = (t.exit[k][c] as f64, t.exit_se[k][c] as f64);
            assert!(
                (got - want).abs() <= 4.0 * se + 0.01 * want,
                "w {w}, {}°: h(θ) {got} ± {se}, Chandrasekhar {want}",
                10 * k
            );
        }
    }
    // Off means all ones, and no run; a material that reflects nothing is refused by name.
    assert_eq!(
        AngleTables::from_mc(&spec, false, false, &|_| panic!("no run")).unwrap(),
        AngleTables::ONES
    );
    let black = mc::Material {
        sigma_s: [0.0; 3],
        ..material
    };
    let spec = config.batch(&[&black], 1000, 11, true).unwrap();
    let e = AngleTables::from_mc(&spec, true, false, &|_| {}).unwrap_err();
    assert!(e.to_string().contains("normal incidence"), "{e}");
}
