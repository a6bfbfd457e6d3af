//! The shape table (`shading::shape`) against physics: bodies of a thousand diffusion lengths are
//! the half-space, thin slabs lose light through their back, convex bodies return more than the
//! half-space and concave ones less; its lookups against their definition (exact at the nodes,
//! linear between, clamped beyond, per channel from physical units); and the table as data:
//! deterministic, ones for a channel that does not scatter, refused with a name when broken,
//! unchanged through JSON. Expected values come from physics and from the lookups' definition,
//! never from this code's own output.

use mc::body::{Body, Coefficients, run_body};
use shading::shape::{ShapeRow, curved_body, half_space, shape_run};
use shading::{
    CURVATURE_STEPS, Estimate, HALF_SPACE_NODE, SHAPE_CURVATURES, SHAPE_THICKNESSES, ShapeEntry,
    ShapeTable, THICKNESS_STEPS,
};

/// A skin-like medium behind a skin-like boundary: 1/σ_tr = 0.22 cm, η = 1.4.
const SKIN: Coefficients = Coefficients {
    n: 1.4,
    mu_a: 1.0,
    mu_s: 30.0,
    g: 0.8,
};

/// The windowed run of `body` in `SKIN` at θ.
fn window(body: Body, theta_deg: f64, photons: u64) -> mc::body::Window {
    let spec = shape_run(body, SKIN, theta_deg, photons, 3);
    run_body(&spec, &|_| {}).unwrap().reflected.window
}

/// |a − b| in combined standard errors.
fn z(a: Estimate, b: Estimate) -> f64 {
    (a.value - b.value) / a.se.hypot(b.se)
}

/// κ → 0 from both sides: a sphere and a cavity of radius 1000/σ_tr differ from the half-space
/// by O(κ) = 10⁻³ (step 1's sphere of 10/σ_tr differs by 15 %), far below the runs' noise. Their
/// energy ratio is 1 within 3 standard errors, and their shift and width are the half-space's
/// within 3 combined standard errors, at normal incidence and at 45°.
#[test]
fn bodies_of_a_thousand_diffusion_lengths_are_the_half_space() {
    let s = SKIN.sigma_tr();
    for theta in [0.0, 45.0] {
        let half = window(half_space(s), theta, 40_000);
        for kappa in [1e-3, -1e-3] {
            let body = curved_body(kappa, s);
            let e = ShapeEntry::relative(&window(body, theta, 40_000), &half);
            let what = format!("{body:?} at {theta}°");
            assert!(
                (e.energy.value - 1.0).abs() < 3.0 * e.energy.se,
                "{what}: E = {:?}",
                e.energy
            );
            assert!(
                z(e.shift_cm, half.shift).abs() < 3.0,
                "{what}: shift {:?} vs {:?}",
                e.shift_cm,
                half.shift
            );
            assert!(
                z(e.width_cm, half.mean_radius).abs() < 3.0,
                "{what}: width {:?} vs {:?}",
                e.width_cm,
                half.mean_radius
            );
        }
    }
}

/// Thin slabs lose reflected light through their back: a slab of 0.25/σ_tr (optical thickness
/// σt·t = 1.7 here) returns less than the half-space by many standard errors, while one of
/// 8/σ_tr, where diffuse light has decayed by e⁻⁸ ≈ 3·10⁻⁴ before it reaches the back, returns
/// the half-space's within 3 SE and 10⁻³. Diffusion in a curved body: the medium of a sphere of
/// radius 1/σ_tr lies within two diffusion lengths of its surface, so light the half-space would
/// absorb deep or far away comes back out (E > 1); around a cavity of that radius the surface
/// curves away from the diffusing light and more medium surrounds the entry (E < 1).
#[test]
fn thin_slabs_lose_light_convex_bodies_gain_it_concave_ones_lose_it() {
    let s = SKIN.sigma_tr();
    let photons = 40_000;
    for theta in [0.0, 45.0] {
        let half = window(half_space(s), theta, photons);
        let entry = |body: Body| ShapeEntry::relative(&window(body, theta, photons), &half).energy;
        let thin = entry(Body::Slab {
            thickness_cm: 0.25 / s,
        });
        assert!(
            thin.value < 1.0 - 5.0 * thin.se,
            "{theta}°: slab of 0.25/σ_tr: E = {thin:?}"
        );
        let thick = entry(Body::Slab {
            thickness_cm: 8.0 / s,
        });
        assert!(
            (thick.value - 1.0).abs() < 3.0 * thick.se + 1e-3,
            "{theta}°: slab of 8/σ_tr: E = {thick:?}"
        );
        let convex = entry(curved_body(1.0, s));
        let concave = entry(curved_body(-1.0, s));
        assert!(
            convex.value > 1.0 + 5.0 * convex.se && concave.value < 1.0 - 5.0 * concave.se,
            "{theta}°: E(κ = 1) = {convex:?}, E(κ = −1) = {concave:?}"
        );
    }
}

/// A table of known values: channels of σ_tr 2, 4 and 8 cm⁻¹ (powers of two, so that κ·σ_tr/σ_tr
/// is exact in f32), entries linear in κ or τ's index, θ and the channel, with E = 1 at κ = 0 as
/// a built table has.
fn synthetic() -> ShapeTable {
    let mut t = ShapeTable::ones([2.0, 4.0, 8.0]);
    let at = |v: f64| Estimate { value: v, se: 0.01 };
    let fill = |rows: &mut [ShapeRow], node: &dyn Fn(usize) -> f64, energy_one_at_zero: bool| {
        for (i, row) in rows.iter_mut().enumerate() {
            for (k, entries) in row.iter_mut().enumerate() {
                for (c, e) in entries.iter_mut().enumerate() {
                    let x = node(i);
                    let (kf, cf) = (k as f64, c as f64);
                    *e = ShapeEntry {
                        energy: if energy_one_at_zero && x == 0.0 {
                            ShapeEntry::ONES.energy
                        } else {
                            at(1.0 + 0.1 * x * (1.0 + 0.5 * cf) * (1.0 + 0.1 * kf))
                        },
                        shift_cm: at(0.1 * x + 0.01 * kf + 0.001 * cf),
                        width_cm: at(1.0 + x * x + 0.1 * kf + cf),
                    };
                }
            }
        }
    };
    fill(&mut t.curvature, &|i| SHAPE_CURVATURES[i] as f64, true);
    fill(
        &mut t.thickness,
        &|i| -1.0 / (1.0 + SHAPE_THICKNESSES[i] as f64),
        false,
    );
    t.validate().unwrap();
    t
}

/// The three quantities of entry (θ index `k`) of a row, per channel, as f32.
fn row_at(row: &ShapeRow, k: usize) -> [[f32; 3]; 3] {
    let q = |f: fn(&ShapeEntry) -> f64| [0, 1, 2].map(|c| f(&row[k][c]) as f32);
    [
        q(|e| e.energy.value),
        q(|e| e.shift_cm.value),
        q(|e| e.width_cm.value),
    ]
}

fn factors(f: shading::ShapeFactors) -> [[f32; 3]; 3] {
    [f.energy, f.shift_cm, f.width_cm]
}

fn close(a: [[f32; 3]; 3], b: [[f32; 3]; 3], tolerance: f32, what: &str) {
    for q in 0..3 {
        for c in 0..3 {
            assert!(
                (a[q][c] - b[q][c]).abs() <= tolerance * (1.0 + b[q][c].abs()),
                "{what}: quantity {q}, channel {c}: {} vs {}",
                a[q][c],
                b[q][c]
            );
        }
    }
}

/// The curvature lookup is its definition: every node exactly at normal incidence and to f32
/// rounding of cos/acos at the other angles; linear in κ halfway between nodes and in θ at 5°;
/// the end nodes beyond ±2 (and the half-space for NaN); E = 1 at κ = 0 at every angle; and a
/// physical curvature 1/R [cm⁻¹] is κ = 1/(σ_tr·R) in each channel.
#[test]
fn the_curvature_lookup_is_linear_between_exact_nodes_and_clamped() {
    let t = synthetic();
    assert_eq!(SHAPE_CURVATURES[HALF_SPACE_NODE], 0.0);
    let sigma = [2.0f32, 4.0, 8.0];
    for (i, &kappa) in SHAPE_CURVATURES.iter().enumerate() {
        let per_channel = |k: usize| {
            let f = [0, 1, 2].map(|c| {
                let cos = (10.0 * k as f32).to_radians().cos();
                factors(t.at(kappa * sigma[c], cos)).map(|q| q[c])
            });
            // [channel][quantity] → [quantity][channel]
            [0, 1, 2].map(|q| [0, 1, 2].map(|c| f[c][q]))
        };
        assert_eq!(per_channel(0), row_at(&t.curvature[i], 0), "κ = {kappa}");
        for k in 1..shading::INCIDENCE_STEPS {
            close(
                per_channel(k),
                row_at(&t.curvature[i], k),
                1e-5,
                &format!("κ = {kappa}, θ = {}°", 10 * k),
            );
        }
    }
    // Curvatures in cm⁻¹ that give κ = 0.5·(κ_i + κ_{i+1}) in the channel of σ_tr = 4.
    for i in 0..CURVATURE_STEPS - 1 {
        let mid = 0.5 * (SHAPE_CURVATURES[i] + SHAPE_CURVATURES[i + 1]);
        let got = factors(t.at(4.0 * mid, 1.0)).map(|q| q[1]);
        let (a, b) = (row_at(&t.curvature[i], 0), row_at(&t.curvature[i + 1], 0));
        for q in 0..3 {
            let want = 0.5 * (a[q][1] + b[q][1]);
            assert!((got[q] - want).abs() < 1e-6, "κ = {mid}, quantity {q}");
        }
    }
    let at_5 = factors(t.at(0.0, 5f32.to_radians().cos()));
    let (a, b) = (
        row_at(&t.curvature[HALF_SPACE_NODE], 0),
        row_at(&t.curvature[HALF_SPACE_NODE], 1),
    );
    let mean = [0, 1, 2].map(|q| [0, 1, 2].map(|c| 0.5 * (a[q][c] + b[q][c])));
    close(at_5, mean, 1e-4, "κ = 0, θ = 5°");
    // Beyond the ends, in every channel.
    let last = CURVATURE_STEPS - 1;
    assert_eq!(factors(t.at(1e3, 1.0)), row_at(&t.curvature[last], 0));
    assert_eq!(factors(t.at(-1e3, 1.0)), row_at(&t.curvature[0], 0));
    assert_eq!(
        factors(t.at(f32::NAN, 1.0)),
        row_at(&t.curvature[HALF_SPACE_NODE], 0)
    );
    for k in 0..shading::INCIDENCE_STEPS {
        let cos = (10.0 * k as f32).to_radians().cos();
        assert_eq!(t.at(0.0, cos).energy, [1.0; 3], "θ = {}°", 10 * k);
    }
    // R = 0.5 cm: κ = 1/(σ_tr·R) = 1, 0.5 and 0.25 in the three channels.
    assert_eq!(t.kappa(2.0), [1.0, 0.5, 0.25]);
    let e = t.at(1.0 / 0.5, 1.0).energy;
    let node = |kappa: f32, c: usize| {
        let i = SHAPE_CURVATURES.iter().position(|&k| k == kappa).unwrap();
        t.curvature[i][0][c].energy.value as f32
    };
    assert_eq!(e, [node(1.0, 0), node(0.5, 1), node(0.25, 2)]);
}

/// The thickness lookup: every node exactly; linear in ln τ (halfway at the geometric mean of
/// two nodes); the first node below it; the half-space (E = 1, the κ = 0 node's shift and
/// width) beyond the last; τ = σ_tr·t per channel.
#[test]
fn the_thickness_lookup_is_linear_in_ln_tau_and_the_half_space_beyond() {
    let t = synthetic();
    let sigma = [2.0f32, 4.0, 8.0];
    for (i, &tau) in SHAPE_THICKNESSES.iter().enumerate() {
        for c in 0..3 {
            let got = factors(t.slab_at(tau / sigma[c], 1.0)).map(|q| q[c]);
            let want = row_at(&t.thickness[i], 0).map(|q| q[c]);
            assert_eq!(got, want, "τ = {tau}, channel {c}");
        }
    }
    for i in 0..THICKNESS_STEPS - 1 {
        let mid = (SHAPE_THICKNESSES[i] * SHAPE_THICKNESSES[i + 1]).sqrt();
        let got = factors(t.slab_at(mid / 4.0, 1.0));
        let (a, b) = (row_at(&t.thickness[i], 0), row_at(&t.thickness[i + 1], 0));
        for q in 0..3 {
            let want = 0.5 * (a[q][1] + b[q][1]);
            assert!((got[q][1] - want).abs() < 1e-5, "τ = {mid}, quantity {q}");
        }
    }
    assert_eq!(factors(t.slab_at(1e-6, 1.0)), row_at(&t.thickness[0], 0));
    assert_eq!(factors(t.slab_at(0.0, 1.0)), row_at(&t.thickness[0], 0));
    let beyond = SHAPE_THICKNESSES[THICKNESS_STEPS - 1] * 1.01 / 2.0;
    for k in [0, 4, 8] {
        let cos = (10.0 * k as f32).to_radians().cos();
        let got = factors(t.slab_at(beyond, cos));
        close(
            got,
            row_at(&t.curvature[HALF_SPACE_NODE], k),
            1e-5,
            &format!("{}°", 10 * k),
        );
        assert_eq!(got[0], [1.0; 3]);
    }
}

/// What a thin body keeps, `ShapeTable::thin_factor`: a slab t thick entered at θ has the chord
/// t/cos θ along the light and keeps E_slab(t, θ); a sphere of radius R has the chord 2R·cos θ
/// and keeps all of E(κ) (factor 1) at every angle; an unknown chord (0, negative, NaN) changes
/// nothing; the factor is never above 1; and a body thinner than its sphere keeps less.
#[test]
fn a_thin_body_keeps_the_slabs_share_and_a_sphere_all_of_its_own() {
    let t = synthetic();
    for k in [0usize, 3, 6] {
        let cos = (10.0 * k as f32).to_radians().cos();
        for t_cm in [0.05f32, 0.2, 0.6, 5.0] {
            let got = t.thin_factor(0.0, t_cm / cos, cos);
            let want = t.slab_at(t_cm, cos).energy.map(|e| e.min(1.0));
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() < 1e-5,
                    "slab {t_cm} cm at {}°",
                    10 * k
                );
            }
        }
        for r in [0.05f32, 0.3, 2.0] {
            let sphere = t.thin_factor(1.0 / r, 2.0 * r * cos, cos);
            for f in sphere {
                assert!((f - 1.0).abs() < 1e-5, "sphere of {r} cm at {}°", 10 * k);
            }
            let thinner = t.thin_factor(1.0 / r, r * cos, cos);
            assert!(thinner.iter().all(|&f| f <= 1.0), "{thinner:?}");
        }
    }
    // The synthetic slabs keep 1 − 0.1·(1 + c/2)/(1 + τ) (channel c): a flat plate keeps less.
    assert!(t.thin_factor(0.0, 0.1, 1.0).iter().all(|&f| f < 0.95));
    for unknown in [0.0f32, -1.0, f32::NAN] {
        assert_eq!(t.thin_factor(0.5, unknown, 0.7), [1.0; 3]);
    }
    assert_eq!(
        ShapeTable::ones([2.0, 4.0, 8.0]).thin_factor(0.0, 0.01, 1.0),
        [1.0; 3]
    );
}

/// Skin1's table with few photons: the same bits with one thread and two, E = 1 ± 0 at κ = 0,
/// and unchanged through JSON.
#[test]
fn a_table_is_deterministic_and_survives_json() {
    let material = mc::Material::builtin("skin1").unwrap();
    let config = mc::SimConfig::thesis().unwrap();
    let spec = config.batch(&[&material], 300, 9, true).unwrap();
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| ShapeTable::from_mc(&spec, &|_| {}).unwrap())
    };
    let (one, two) = (on(1), on(2));
    let json = serde_json::to_string(&one).unwrap();
    assert_eq!(json, serde_json::to_string(&two).unwrap());
    for k in 0..shading::INCIDENCE_STEPS {
        for c in 0..3 {
            assert_eq!(
                one.curvature[HALF_SPACE_NODE][k][c].energy,
                ShapeEntry::ONES.energy
            );
        }
    }
    let back: ShapeTable = serde_json::from_str(&json).unwrap();
    assert_eq!(back, one);
}

/// Wine's G and B channels do not scatter (σs = 0): no diffuse light, so no change by shape, exact
/// ones (shift and width 0) and no error; its R channel (albedo 0.007) is finite.
#[test]
fn a_channel_that_does_not_scatter_gets_ones() {
    let material = mc::Material::builtin("wine").unwrap();
    let config = mc::SimConfig::thesis().unwrap();
    let spec = config.batch(&[&material], 200, 4, true).unwrap();
    let t = ShapeTable::from_mc(&spec, &|_| {}).unwrap();
    for row in t.curvature.iter().chain(&t.thickness) {
        for entries in row {
            for c in [1, 2] {
                assert_eq!(entries[c], ShapeEntry::ONES);
            }
            let r = &entries[0];
            for v in [r.energy, r.shift_cm, r.width_cm] {
                assert!(v.value.is_finite() && v.se.is_finite(), "{r:?}");
            }
        }
    }
    let f = t.at(10.0, 0.5);
    assert_eq!([f.energy[1], f.energy[2]], [1.0, 1.0]);
}

/// A broken table is refused naming the entry; so are a spec of two channels and a scattering
/// channel that does not absorb (its lengths in 1/σ_tr would be infinite).
#[test]
fn broken_tables_and_inputs_are_refused_by_name() {
    let mut t = synthetic();
    t.curvature[4][3][1].shift_cm.value = f64::NAN;
    let e = t.validate().unwrap_err().to_string();
    for part in ["shift", "κ = -0.5", "θ = 30°", "channel 1", "NaN"] {
        assert!(e.contains(part), "{part}: {e}");
    }
    let mut t = synthetic();
    t.thickness[4][0][2].energy.se = -1.0;
    let e = t.validate().unwrap_err().to_string();
    assert!(e.contains("energy SE at τ = 4") && e.contains("-1"), "{e}");
    let mut t = synthetic();
    t.curvature[HALF_SPACE_NODE][0][0].energy.value = 1.01;
    let e = t.validate().unwrap_err().to_string();
    assert!(e.contains("energy at κ = 0"), "{e}");

    let config = mc::SimConfig::thesis().unwrap();
    let skin1 = mc::Material::builtin("skin1").unwrap();
    let mut spec = config.batch(&[&skin1], 100, 1, true).unwrap();
    spec.channels.pop();
    let e = ShapeTable::from_mc(&spec, &|_| {}).unwrap_err().to_string();
    assert!(e.contains("channels") && e.contains('2'), "{e}");
    let clear = mc::Material {
        sigma_a: [0.3, 0.0, 0.3],
        ..skin1
    };
    let spec = config.batch(&[&clear], 100, 1, true).unwrap();
    let e = ShapeTable::from_mc(&spec, &|_| {}).unwrap_err().to_string();
    assert!(e.contains("σ_tr of channel 1") && e.contains('0'), "{e}");
}
