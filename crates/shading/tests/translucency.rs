//! Translucency's table from `mc` (`Translucency::from_mc`) against the Beer–Lambert bounds.

use shading::{TRANSLUCENCY_STEPS, Translucency};

/// The table of a material by `mc` (`Translucency::from_mc`), with ρ = 1 so that it holds the
/// slab's total transmittance: index-matched (no boundary), every packet crossing a slab of
/// thickness d travels at least d, so Tt(d) ≤ e^{−σa·d}, and the unscattered part alone is
/// e^{−σt·d} ≤ Tt(d) (each within 4 standard errors of a binomial-sized count). The thicknesses
/// start at a quarter of the shortest transport mean free path.
#[test]
fn table_from_mc_lies_between_the_beer_lambert_bounds() {
    let material = shading::Material {
        name: "bounds".into(),
        source: String::new(),
        sigma_a: [1.0, 0.3, 3.0],
        sigma_s: [0.5, 4.0, 2.0],
        g: [0.0, 0.8, -0.3],
        eta: 1.0,
        thickness: None,
    };
    let config = shading::SimConfig::thesis().unwrap();
    let photons = 20_000;
    let spec = config.batch(&[&material], photons, 5, true).unwrap();
    let t = Translucency::from_mc(&spec, [1.0; 3], &|_| {}).unwrap();
    let media = [0, 1, 2].map(|c| fit::analytic::Medium::channel(&material, c));
    let shortest = media
        .iter()
        .map(|m| m.transport_mfp())
        .fold(f64::MAX, f64::min);
    assert!((t.first_cm as f64 / (0.25 * shortest) - 1.0).abs() < 1e-6);
    for k in 0..TRANSLUCENCY_STEPS {
        let d = t.first_cm as f64 * (t.ratio as f64).powi(k as i32);
        for c in 0..3 {
            let tt = t.table[k][c] as f64;
            let (lo, hi) = (
                (-(material.sigma_a[c] + material.sigma_s[c]) * d).exp(),
                (-material.sigma_a[c] * d).exp(),
            );
            // A packet's weight lies in [0, 1] with mean m ≤ hi: its variance is at most
            // m(1 − m) ≤ hi(1 − hi) below ½, else ¼.
            let var = if hi < 0.5 { hi * (1.0 - hi) } else { 0.25 };
            let slack = 4.0 * (var / photons as f64).sqrt() + 1e-6;
            assert!(
                tt >= lo - slack && tt <= hi + slack,
                "channel {c}, d {d} cm: Tt {tt} outside [{lo}, {hi}]"
            );
        }
    }
    let e = Translucency::from_mc(&spec, [1.0, 0.0, 1.0], &|_| {}).unwrap_err();
    assert!(e.to_string().contains("ρ"), "{e}");
}
