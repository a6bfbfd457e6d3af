//! Blender's random-walk fields against the walk Cycles really runs (`mc::cycles`): read back
//! through Cycles' own remap and traced as Cycles traces them, they reflect the material's own
//! Rd at normal incidence, within the noise of the runs that found them and of this check.

use fit::engine::{Value, random_walk, random_walk_exact};
use mc::cycles::{CyclesWalk, run_cycles};
use mc::{Grid, Incidence, Layer, RunSpec, Sample, TallySet};

fn rd(layer: Layer, walk: CyclesWalk, photons: u64, seed: u64) -> mc::Estimate {
    let spec = RunSpec {
        sample: Sample::single(layer),
        grid: Grid {
            dr: 0.1,
            dz: 0.1,
            nr: 1,
            nz: 1,
            na: 1,
        },
        photons,
        seed,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    };
    run_cycles(&spec, Incidence::NORMAL, walk, &|_| {})
        .unwrap()
        .rd
}

fn fields(p: &fit::engine::EngineParams) -> ([f64; 3], [f64; 3], f64, f64) {
    let v = |n: &str| p.fields.iter().find(|f| f.name == n).unwrap().value.clone();
    let (Value::Color(c), Value::Color(r), Value::Number(s), Value::Number(g)) = (
        v("Base Color"),
        v("Subsurface Radius"),
        v("Subsurface Scale"),
        v("Subsurface Anisotropy"),
    ) else {
        panic!()
    };
    (c, r, s, g)
}

/// Skin1's σa and σs at g = 0.5 and 0.9, and Coffee (g 0.88–0.91 per channel): Cycles' walk of
/// the fields' medium (its remap read back: σt = 4π/(Radius·Scale·(1 − g)), σs/σt = α(Base
/// Color)) reflects the material's Rd(0°) within 3 standard errors of the difference (this
/// check's runs at another seed, and the root find's own runs, 2·10⁵ photons each).
#[test]
fn cycles_walk_of_the_fields_reflects_the_materials_rd() {
    let skin1 = mc::Material::builtin("skin1").unwrap();
    let mut materials: Vec<mc::Material> = [0.5, 0.9]
        .map(|g| mc::Material {
            g: [g; 3],
            eta: 1.0,
            ..skin1.clone()
        })
        .into();
    materials.push(mc::Material {
        eta: 1.0,
        ..mc::Material::builtin("coffee").unwrap()
    });
    for m in &materials {
        let p = random_walk(m);
        let (color, radius, scale, g) = fields(&p);
        for c in 0..3 {
            let sigma_t = fit::cycles::sigma_t(radius[c] * scale * 100.0, g);
            let alpha = fit::cycles::alpha(color[c], g);
            let st = m.sigma_a[c] + m.sigma_s[c];
            assert!((sigma_t / st - 1.0).abs() < 1e-9, "the radius keeps σt");
            let cycles = Layer {
                n: 1.0,
                mu_a: sigma_t * (1.0 - alpha),
                mu_s: sigma_t * alpha,
                g,
                thickness: 1e6,
            };
            let own = Layer {
                n: 1.0,
                mu_a: m.sigma_a[c],
                mu_s: m.sigma_s[c],
                g: m.g[c],
                thickness: 1e6,
            };
            let (walk, truth) = (
                rd(cycles, CyclesWalk::BLENDER, 400_000, 1),
                rd(own, CyclesWalk::EXACT, 400_000, 2),
            );
            // The root find's runs: 2·10⁵ photons, half this check's each, so twice its variance.
            let se = (3.0 * (walk.se.powi(2) + truth.se.powi(2))).sqrt();
            assert!(
                (walk.value - truth.value).abs() <= 3.0 * se,
                "{} channel {c}: Cycles' walk {walk:?}, the medium {truth:?}; {:?}",
                m.name,
                p.notes
            );
        }
    }
}

/// Where g = 0 Cycles' walk is the medium's (but for its 256-bounce cap): the fields are the
/// exact inversion, unchanged (Skin1, Marble).
#[test]
fn isotropic_materials_keep_the_exact_inversion() {
    for name in ["skin1", "marble"] {
        let m = mc::Material::builtin(name).unwrap();
        assert_eq!(
            fields(&random_walk(&m)),
            fields(&random_walk_exact(&m)),
            "{name}"
        );
    }
}
