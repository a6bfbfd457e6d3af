//! Transport in a sphere, a spherical cavity and a slab (`mc::body`), checked against physics:
//! the half-space they become as they grow, adding-doubling for slabs, exact non-scattering
//! answers, energy conservation, reciprocity, the order that nested bodies must keep, and
//! determinism. Expected values come from theory, the literature or iadpython, never from this
//! code's own output.

use mc::body::{Body, BodyOutput, BodySpec, Coefficients, SurfaceGrid, run_bodies, run_body};
use mc::{Estimate, Grid, Incidence, Layer, Output, RunSpec, Sample, TallySet};

#[allow(dead_code)] // this suite uses chi2 alone
mod common;

/// A skin-like medium: 1/σ_tr = 0.22 cm, 1/σt = 0.032 cm, η = 1.4.
const SKIN: Coefficients = Coefficients {
    n: 1.4,
    mu_a: 1.0,
    mu_s: 30.0,
    g: 0.8,
};

/// The same medium index-matched to the air around it (no reflection at any surface).
const MATCHED: Coefficients = Coefficients { n: 1.0, ..SKIN };

const GRID: SurfaceGrid = SurfaceGrid {
    dr: 0.02,
    nr: 61,
    n_azimuth: 4,
    n_exit: 9,
};

fn spec(body: Body, coefficients: Coefficients, theta_deg: f64, photons: u64) -> BodySpec {
    BodySpec {
        body,
        coefficients,
        incidence: Incidence { theta_deg },
        grid: GRID,
        photons,
        seed: 7,
    }
}

fn run(body: Body, coefficients: Coefficients, theta_deg: f64, photons: u64) -> BodyOutput {
    run_body(&spec(body, coefficients, theta_deg, photons), &|_| {}).unwrap()
}

/// `mc`'s own half-space (MCML's run, 10⁸ cm thick) of the same medium, on the same radial bins.
fn half_space(c: Coefficients, theta_deg: f64, photons: u64) -> Output {
    let spec = RunSpec {
        sample: Sample::single(Layer {
            n: c.n,
            mu_a: c.mu_a,
            mu_s: c.mu_s,
            g: c.g,
            thickness: 1e8,
        }),
        grid: Grid {
            dr: GRID.dr,
            dz: 1.0,
            nr: GRID.nr,
            nz: 1,
            na: GRID.n_exit,
        },
        photons,
        seed: 11,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    };
    mc::run_at(&spec, Incidence { theta_deg }, &|_| {}).unwrap()
}

/// |a − b| in combined standard errors.
fn z(a: Estimate, b: Estimate) -> f64 {
    (a.value - b.value) / a.se.hypot(b.se)
}

/// Asserts |got − want| ≤ k·se + slack.
fn within(what: &str, got: Estimate, want: f64, k: f64, slack: f64) {
    assert!(
        (got.value - want).abs() <= k * got.se + slack,
        "{what}: {} ± {}, expected {want} (off by {:.2} se)",
        got.value,
        got.se,
        (got.value - want) / got.se
    );
}

/// R → ∞: a sphere and a cavity of radius 1000/σ_tr reflect what the half-space reflects, in
/// total and as a profile (on the bins well inside the last, which collects everything beyond),
/// at normal incidence and at 45°, and their shift along the plane of incidence is the thick
/// slab's (a half-space with the body's own tally).
#[test]
fn sphere_and_cavity_of_a_thousand_diffusion_lengths_are_the_half_space() {
    let radius_cm = 1000.0 / SKIN.sigma_tr();
    let photons = 200_000;
    for theta in [0.0, 45.0] {
        let reference = half_space(SKIN, theta, photons);
        let slab = run(
            Body::Slab {
                thickness_cm: radius_cm,
            },
            SKIN,
            theta,
            photons,
        );
        for body in [Body::Sphere { radius_cm }, Body::Cavity { radius_cm }] {
            let o = run(body, SKIN, theta, photons);
            let what = format!("{body:?} at {theta}°");
            assert!(
                z(o.r, reference.rd).abs() < 3.0,
                "{what}: R {:?} vs {:?}",
                o.r,
                reference.rd
            );
            assert_eq!(o.rs, reference.rsp, "{what}: Rs");
            let inner = GRID.nr - 1;
            let (a, b) = (&o.reflected.radial[..inner], &reference.rd_r[..inner]);
            common::assert_profiles_agree(&what, a, b, 40);
            let (s, t) = (o.reflected.shift, slab.reflected.shift);
            assert!(
                z(s, t).abs() < 3.0,
                "{what}: shift {s:?} vs the slab's {t:?}"
            );
            let (m, t) = (o.reflected.mean_radius, slab.reflected.mean_radius);
            assert!(
                z(m, t).abs() < 3.0,
                "{what}: mean radius {m:?} vs the slab's {t:?}"
            );
        }
    }
}

/// Slabs in air against adding-doubling: Rs + R (iadpython's UR1, specular included) and T
/// (UT1, unscattered light included) under a normally incident beam, from a thin slab (optical
/// thickness 0.155) to a thick one (14 diffusion lengths: the half-space limit), and van de
/// Hulst's index-matched slab (MCML's validation case, published Rd = 0.09739, Tt = 0.66096).
///
/// Reference: `tests/data/slab_adding_doubling.py` with iadpython 0.5.3 (40 quadrature points,
/// 24 for the matched slab); its own uncertainty (the change from 8 points fewer) is below 10⁻⁵.
#[test]
fn slab_totals_equal_adding_doubling() {
    let vdh = Coefficients {
        n: 1.0,
        mu_a: 10.0,
        mu_s: 90.0,
        g: 0.75,
    };
    // (medium, thickness [cm], UR1, UT1)
    let cases = [
        (vdh, 0.02, 0.097395, 0.660958),
        (SKIN, 0.005, 0.065389, 0.924166),
        (SKIN, 0.05, 0.146529, 0.732840),
        (SKIN, 0.2, 0.212297, 0.342635),
        (SKIN, 1.0, 0.210474, 0.009693),
        (SKIN, 3.0, 0.210470, 0.000001),
    ];
    for (c, thickness_cm, ur1, ut1) in cases {
        let o = run(Body::Slab { thickness_cm }, c, 0.0, 200_000);
        let what = |x: &str| format!("t = {thickness_cm} cm, n = {}: {x}", c.n);
        let reflected = Estimate {
            value: o.rs + o.r.value,
            se: o.r.se,
        };
        within(&what("Rs + R"), reflected, ur1, 3.0, 1e-5);
        within(&what("T"), o.t, ut1, 3.0, 1e-5);
    }
}

/// Every photon's weight ends specular, leaving through a surface or absorbed: Rs + R + T + A = 1.
/// Roulette keeps the balance in expectation only (a killed packet's weight, below 10⁻⁴, goes to
/// the survivors), so the sum is held to its standard error, and to 10⁻³ whatever that is.
#[test]
fn energy_is_conserved_in_every_body() {
    let bodies = [
        Body::Sphere { radius_cm: 0.3 },
        Body::Cavity { radius_cm: 0.3 },
        Body::Slab { thickness_cm: 0.3 },
    ];
    for body in bodies {
        for theta in [0.0, 60.0] {
            let o = run(body, SKIN, theta, 30_000);
            let sum = o.rs + o.r.value + o.t.value + o.a.value;
            let se = (o.r.se.powi(2) + o.t.se.powi(2) + o.a.se.powi(2)).sqrt();
            assert!(
                (sum - 1.0).abs() < (3.0 * se).min(1e-3),
                "{body:?} at {theta}°: Rs + R + T + A = {sum} (se {se})"
            );
            assert!(o.transmitted.is_some() == body.has_far_face(), "{body:?}");
            // The profiles are per unit area of the body's surface: over the bands (a sphere's,
            // clamped at its antipode πR = 0.94 cm, inside the grid; a plane's annuli) they sum
            // to the totals.
            let band = |i: usize| {
                let (s0, s1) = (i as f64 * GRID.dr, (i + 1) as f64 * GRID.dr);
                match body {
                    Body::Slab { .. } => std::f64::consts::PI * (s1 * s1 - s0 * s0),
                    _ => {
                        let r = body.size_cm();
                        let cap = |s: f64| (s / r).min(std::f64::consts::PI).cos();
                        2.0 * std::f64::consts::PI * r * r * (cap(s0) - cap(s1))
                    }
                }
            };
            let integral = |e: &[Estimate]| -> f64 {
                e.iter().enumerate().map(|(i, x)| x.value * band(i)).sum()
            };
            let sides = [(o.r, Some(&o.reflected)), (o.t, o.transmitted.as_ref())];
            for (total, exits) in sides.into_iter().filter_map(|(t, e)| Some((t, e?))) {
                let i = integral(&exits.radial);
                assert!(
                    (i - total.value).abs() < 1e-9,
                    "{body:?}: ∫ Rd dA = {i} vs {total:?}"
                );
            }
            if !body.has_far_face() {
                assert_eq!(
                    o.t,
                    Estimate {
                        value: 0.0,
                        se: 0.0
                    },
                    "{body:?}"
                );
            }
        }
    }
}

/// Unpolarized Fresnel reflectance from a medium of index `n` into air at incidence cosine `cos_i`
/// inside (Born & Wolf), and the cosine of the refracted ray in air.
fn fresnel_out(n: f64, cos_i: f64) -> f64 {
    let sin_t = n * (1.0 - cos_i * cos_i).sqrt();
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let rs = ((n * cos_i - cos_t) / (n * cos_i + cos_t)).powi(2);
    let rp = ((n * cos_t - cos_i) / (n * cos_t + cos_i)).powi(2);
    0.5 * (rs + rp)
}

/// A clear slab (no absorption, no scattering) at normal incidence: the beam bounces between two
/// faces of reflectance r = ((n − 1)/(n + 1))², so Rs + R = 2r/(1 + r) and T = (1 − r)/(1 + r)
/// (the geometric series), and every packet leaves with its whole weight: R + T = 1 − Rs to
/// rounding. With absorption, Beer–Lambert between the two faces along the refracted ray:
/// T = (1 − r)² e^{−σa d/cos θt} / (1 − r² e^{−2σa d/cos θt}) at any angle (r the Fresnel
/// reflectance at θt inside, the same as at θ outside by reciprocity). Index-matched, the beam
/// leaves the far face at exactly d·tan θt from the point below the entry.
#[test]
fn non_scattering_slabs_are_fresnel_and_beer_lambert() {
    let n = 1.5;
    let clear = Coefficients {
        n,
        mu_a: 0.0,
        mu_s: 0.0,
        g: 0.0,
    };
    let o = run(Body::Slab { thickness_cm: 0.1 }, clear, 0.0, 50_000);
    let r = ((n - 1.0) / (n + 1.0)).powi(2);
    assert!((o.rs - r).abs() < 1e-15);
    assert!((o.r.value + o.t.value - (1.0 - r)).abs() < 1e-12, "{o:?}");
    assert_eq!(o.a.value, 0.0);
    within(
        "clear slab: Rs + R",
        Estimate {
            value: o.rs + o.r.value,
            ..o.r
        },
        2.0 * r / (1.0 + r),
        4.0,
        0.0,
    );
    within("clear slab: T", o.t, (1.0 - r) / (1.0 + r), 4.0, 0.0);

    let d = 0.2;
    for (n, theta) in [(1.4, 0.0), (1.4, 50.0), (1.0, 50.0)] {
        let absorbing = Coefficients {
            n,
            mu_a: 3.0,
            ..clear
        };
        let o = run(Body::Slab { thickness_cm: d }, absorbing, theta, 50_000);
        let sin_t = theta.to_radians().sin() / n;
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        let r = fresnel_out(n, cos_t);
        let e = (-absorbing.mu_a * d / cos_t).exp();
        let want = (1.0 - r).powi(2) * e / (1.0 - r * r * e * e);
        within(&format!("n = {n}, θ = {theta}°: T"), o.t, want, 4.0, 0.0);
        if n == 1.0 {
            let x = d * sin_t / cos_t;
            let far = o.transmitted.unwrap();
            assert!(
                (far.mean_radius.value - x).abs() < 1e-12,
                "{:?}",
                far.mean_radius
            );
            assert!((far.shift.value - x).abs() < 1e-12, "{:?}", far.shift);
            assert!(far.shift.se < 1e-9, "{:?}", far.shift);
        }
    }
}

/// A sphere that only absorbs: the refracted beam crosses the chord 2R cos θt, leaves or reflects
/// with the same Fresnel reflectance r at every hit (a sphere's chords from one chord all meet
/// the surface at θt), so R = (1 − Rs)(1 − r)e^{−σa L}/(1 − r e^{−σa L}), L = 2R cos θt, and
/// nothing is transmitted. Index-matched, every exit lies at the chord's far end, the geodesic
/// R(π − 2θt) ahead of the entry.
#[test]
fn a_non_scattering_sphere_is_beer_lambert_along_its_chord() {
    let radius = 0.4;
    let theta: f64 = 30.0;
    for n in [1.0, 1.4] {
        let c = Coefficients {
            n,
            mu_a: 2.0,
            mu_s: 0.0,
            g: 0.0,
        };
        let o = run(Body::Sphere { radius_cm: radius }, c, theta, 50_000);
        let sin_t = theta.to_radians().sin() / n;
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        let r = fresnel_out(n, cos_t);
        assert!((o.rs - fresnel_out(1.0 / n, theta.to_radians().cos())).abs() < 1e-12);
        let e = (-c.mu_a * 2.0 * radius * cos_t).exp();
        let want = (1.0 - o.rs) * (1.0 - r) * e / (1.0 - r * e);
        within(&format!("n = {n}: R"), o.r, want, 4.0, 0.0);
        assert_eq!(o.t.value, 0.0);
        if n == 1.0 {
            let s = radius * (std::f64::consts::PI - 2.0 * sin_t.asin());
            let m = o.reflected.mean_radius;
            assert!((m.value - s).abs() < 1e-12 && m.se < 1e-9, "{m:?} vs {s}");
            assert!((o.reflected.shift.value - s).abs() < 1e-12);
            // All of it in the forward azimuth bin of the geodesic's radial bin.
            let bin = (s / GRID.dr) as usize * GRID.n_azimuth;
            let area = o.reflected.profile.iter().filter(|e| e.value > 0.0).count();
            assert!(area == 1 && o.reflected.profile[bin].value > 0.0);
        }
    }
}

/// A sphere that scatters and does not absorb (σa = 0) keeps every photon's weight until it
/// leaves, and a closed body has nowhere to send it but back out: every packet leaves with the
/// 1 − Rs(θ) it entered with (Fresnel at entry), so R = 1 − Rs to rounding and A = 0 exactly,
/// however the walks went (the path roulette of 10⁵ interactions is never reached here).
#[test]
fn a_sphere_that_does_not_absorb_returns_all_it_admits() {
    let clear = Coefficients { mu_a: 0.0, ..SKIN };
    for theta in [0.0, 60.0] {
        let o = run(Body::Sphere { radius_cm: 0.3 }, clear, theta, 20_000);
        let rs = fresnel_out(1.0 / clear.n, theta.to_radians().cos());
        assert!((o.rs - rs).abs() < 1e-12, "{theta}°: Rs {} vs {rs}", o.rs);
        assert!(
            (o.r.value - (1.0 - rs)).abs() < 1e-12,
            "{theta}°: R {:?} vs 1 − Rs = {}",
            o.r,
            1.0 - rs
        );
        assert_eq!(o.a.value, 0.0, "{theta}°");
    }
}

/// The window holds exactly the exits nearer than the grid's reach nr·dr: with the same seed (the
/// grid does not change the walks), a run whose reach is 10 bins of 0.02 cm has in its window
/// what a finer-reaching grid's first 10 radial bins hold, and the window's standard error is
/// the per-photon one that disjoint bins give, var = Σ se_i² + (Σ m_i² − (Σ m_i)²)/(N − 1)
/// with m_i the bins' means (a photon leaves through one bin, so the cross terms of the bins'
/// sum are −m_i·m_j). A reach beyond a sphere's antipode holds everything: the totals.
#[test]
fn the_window_holds_the_exits_within_the_grids_reach() {
    let near = SurfaceGrid { nr: 10, ..GRID };
    let photons = 20_000;
    for body in [
        Body::Sphere { radius_cm: 0.3 },
        Body::Slab { thickness_cm: 1.0 },
    ] {
        let cut = run_body(
            &BodySpec {
                grid: near,
                ..spec(body, SKIN, 45.0, photons)
            },
            &|_| {},
        )
        .unwrap();
        let full = run(body, SKIN, 45.0, photons);
        let w = cut.reflected.window;
        assert_eq!(w.reach_cm, 10.0 * GRID.dr);
        let band = |i: usize| {
            let (s0, s1) = (i as f64 * GRID.dr, (i + 1) as f64 * GRID.dr);
            match body {
                Body::Sphere { radius_cm: r } => {
                    2.0 * std::f64::consts::PI * r * r * ((s0 / r).cos() - (s1 / r).cos())
                }
                _ => std::f64::consts::PI * (s1 * s1 - s0 * s0),
            }
        };
        let bins: Vec<Estimate> = (0..10)
            .map(|i| {
                let e = full.reflected.radial[i];
                Estimate {
                    value: e.value * band(i),
                    se: e.se * band(i),
                }
            })
            .collect();
        let sum: f64 = bins.iter().map(|e| e.value).sum();
        let squares: f64 = bins.iter().map(|e| e.value * e.value).sum();
        let var = bins.iter().map(|e| e.se * e.se).sum::<f64>()
            + (squares - sum * sum) / (photons - 1) as f64;
        assert!(
            (w.r.value - sum).abs() < 1e-12,
            "{body:?}: {:?} vs {sum}",
            w.r
        );
        assert!(
            (w.r.se * w.r.se - var).abs() < 1e-9 * var,
            "{body:?}: se {} vs {}",
            w.r.se,
            var.sqrt()
        );
        assert!(w.r.value < cut.r.value && w.mean_radius.value < 10.0 * GRID.dr);
        // The sphere's antipode, π·0.3 cm, lies within 61 bins of 0.02 cm.
        if let Body::Sphere { .. } = body {
            let all = full.reflected.window;
            let exits = &full.reflected;
            for (a, b) in [
                (all.r, full.r),
                (all.shift, exits.shift),
                (all.mean_radius, exits.mean_radius),
            ] {
                assert!((a.value - b.value).abs() < 1e-12 && (a.se - b.se).abs() < 1e-12);
            }
        }
    }
}

/// A table's runs at once are each the run alone, bit for bit, with one thread or two.
#[test]
fn run_bodies_is_run_body_one_at_a_time() {
    let specs: Vec<BodySpec> = [
        Body::Sphere { radius_cm: 0.3 },
        Body::Cavity { radius_cm: 0.3 },
        Body::Slab { thickness_cm: 0.3 },
    ]
    .into_iter()
    .map(|b| spec(b, SKIN, 30.0, mc::CHUNK_PHOTONS + 5))
    .collect();
    let alone: Vec<BodyOutput> = specs
        .iter()
        .map(|s| run_body(s, &|_| {}).unwrap())
        .collect();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let together = pool.install(|| run_bodies(&specs, &|_| {}).unwrap());
        assert_eq!(
            serde_json::to_string(&together).unwrap(),
            serde_json::to_string(&alone).unwrap(),
            "{threads} threads"
        );
    }
    let bad = BodySpec {
        photons: 0,
        ..specs[0]
    };
    let e = run_bodies(&[specs[1], bad], &|_| {}).unwrap_err();
    assert!(e.to_string().contains("photons"), "{e}");
}

/// Helmholtz reciprocity of a slab in air: the azimuth-averaged BRDF and BTDF,
/// f(θi → θo) = (dR/dω_o or dT/dω_o)/cos θo per unit incident power, are symmetric in θi and θo
/// (transmission's reverse path enters the far face, the same as the entry face by the slab's
/// symmetry). Each beam enters at the centre of an exit-angle bin, so f(θ₁ → bin of θ₂) is
/// compared with f(θ₂ → bin of θ₁); bin averaging differs between the two by O(Δθ²) of f's
/// curvature, below a percent for 10° bins.
#[test]
fn a_slab_is_reciprocal() {
    let slab = Body::Slab { thickness_cm: 0.1 };
    let d_exit = GRID.d_exit();
    let centre = |k: usize| (k as f64 + 0.5) * d_exit;
    let (k1, k2) = (1, 5);
    let photons = 400_000;
    let at = |k: usize| run(slab, SKIN, centre(k).to_degrees(), photons);
    let (o1, o2) = (at(k1), at(k2));
    let f = |e: Estimate, k: usize| {
        let c = centre(k).cos();
        Estimate {
            value: e.value / c,
            se: e.se / c,
        }
    };
    let surfaces = [
        ("reflection", &o1.reflected, &o2.reflected),
        (
            "transmission",
            o1.transmitted.as_ref().unwrap(),
            o2.transmitted.as_ref().unwrap(),
        ),
    ];
    for (what, a, b) in surfaces {
        let forward = f(a.exit_angle[k2], k2);
        let back = f(b.exit_angle[k1], k1);
        let tolerance = 3.0 * forward.se.hypot(back.se) + 0.01 * forward.value;
        assert!(
            (forward.value - back.value).abs() < tolerance,
            "{what}: f(θ₁ → θ₂) = {forward:?}, f(θ₂ → θ₁) = {back:?}"
        );
    }
}

/// Index-matched, nothing reflects at a surface and the walks of nested bodies that share the
/// entry point couple: the walk in the smaller medium ends no later than in the larger one, with
/// at least its weight. Each sphere tangent at the entry lies inside a larger one and inside the
/// half-space; the half-space lies inside the medium around a cavity, and that around a larger
/// cavity inside that around a smaller one; a slab lies inside a thicker one, and light a slab
/// sends out of its far face a thicker one may still absorb. So diffuse reflectance orders as
/// sphere(0.1) > sphere(0.5) > half-space > cavity(0.5) > cavity(0.1) and
/// slab(0.05) < slab(0.2) < half-space: convex bodies return light a half-space sends deep, thin
/// ones lose it through their far side. Each step holds by many standard errors.
#[test]
fn nested_bodies_reflect_in_the_order_of_their_media() {
    for theta in [0.0, 45.0] {
        let photons = 40_000;
        let half = half_space(MATCHED, theta, photons).rd;
        let r = |body| run(body, MATCHED, theta, photons).r;
        let convex_to_concave = [
            ("sphere 0.1", r(Body::Sphere { radius_cm: 0.1 })),
            ("sphere 0.5", r(Body::Sphere { radius_cm: 0.5 })),
            ("half-space", half),
            ("cavity 0.5", r(Body::Cavity { radius_cm: 0.5 })),
            ("cavity 0.1", r(Body::Cavity { radius_cm: 0.1 })),
        ];
        let thin_to_thick = [
            ("slab 0.05", r(Body::Slab { thickness_cm: 0.05 })),
            ("slab 0.2", r(Body::Slab { thickness_cm: 0.2 })),
            ("half-space", half),
        ];
        for (larger, smaller) in convex_to_concave
            .windows(2)
            .map(|w| (w[0], w[1]))
            .chain(thin_to_thick.windows(2).map(|w| (w[1], w[0])))
        {
            assert!(
                z(larger.1, smaller.1) > 5.0,
                "{theta}°: R of {} = {:?} is not above {} = {:?}",
                larger.0,
                larger.1,
                smaller.0,
                smaller.1
            );
        }
    }
}

/// At normal incidence the exits are symmetric about the entry: no shift, and every azimuth bin
/// of the profile the same within noise. At 45° they move ahead of the entry, where the refracted
/// beam goes (Wang & Jacques 1995's shifted centre), on every body.
#[test]
fn exits_are_symmetric_at_normal_incidence_and_shift_forward_at_45() {
    for body in [
        Body::Sphere { radius_cm: 0.3 },
        Body::Cavity { radius_cm: 0.3 },
        Body::Slab { thickness_cm: 0.3 },
    ] {
        let o = run(body, SKIN, 0.0, 40_000);
        let s = o.reflected.shift;
        assert!(s.value.abs() < 4.0 * s.se, "{body:?}: shift {s:?}");
        let p = &o.reflected.profile;
        let azimuth = |k: usize| -> Vec<Estimate> {
            (0..GRID.nr - 1)
                .map(|ir| p[ir * GRID.n_azimuth + k])
                .collect()
        };
        for k in 1..GRID.n_azimuth {
            let (a, b) = (azimuth(0), azimuth(k));
            common::assert_profiles_agree(&format!("{body:?}: azimuth bin {k}"), &a, &b, 1);
        }
        let s = run(body, SKIN, 45.0, 40_000).reflected.shift;
        assert!(s.value > 5.0 * s.se, "{body:?}: shift at 45° {s:?}");
    }
}

/// The same seed gives the same bits whatever the thread count (several chunks per run).
#[test]
fn same_seed_same_bits_whatever_the_thread_count() {
    for body in [
        Body::Sphere { radius_cm: 0.3 },
        Body::Cavity { radius_cm: 0.3 },
        Body::Slab { thickness_cm: 0.3 },
    ] {
        let s = spec(body, SKIN, 30.0, 3 * mc::CHUNK_PHOTONS + 17);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let o = pool.install(|| run_body(&s, &|_| {}).unwrap());
            serde_json::to_string(&o).unwrap()
        };
        assert_eq!(on(1), on(2), "{body:?}");
    }
}

/// Bad input is refused with an error naming the field and the value.
#[test]
fn bad_input_is_refused_naming_the_field() {
    let good = spec(Body::Sphere { radius_cm: 1.0 }, SKIN, 0.0, 100);
    let refused = |s: BodySpec, field: &str, value: &str| {
        let e = run_body(&s, &|_| {}).unwrap_err().to_string();
        assert!(e.contains(field) && e.contains(value), "{e}");
    };
    for (body, field) in [
        (Body::Sphere { radius_cm: 0.0 }, "radius_cm"),
        (Body::Cavity { radius_cm: -1.0 }, "radius_cm"),
        (
            Body::Slab {
                thickness_cm: f64::NAN,
            },
            "thickness_cm",
        ),
        (
            Body::Sphere {
                radius_cm: f64::INFINITY,
            },
            "radius_cm",
        ),
    ] {
        refused(
            BodySpec { body, ..good },
            field,
            &format!("{}", body.size_cm()),
        );
    }
    for theta_deg in [90.0, -1.0, f64::NAN] {
        let s = BodySpec {
            incidence: Incidence { theta_deg },
            ..good
        };
        refused(s, "theta_deg", &theta_deg.to_string());
    }
    let with = |c: Coefficients| BodySpec {
        coefficients: c,
        ..good
    };
    refused(with(Coefficients { mu_s: -1.0, ..SKIN }), "mu_s", "-1");
    refused(
        with(Coefficients {
            mu_a: f64::NAN,
            ..SKIN
        }),
        "mu_a",
        "NaN",
    );
    refused(with(Coefficients { g: 1.5, ..SKIN }), "g", "1.5");
    refused(with(Coefficients { n: 0.0, ..SKIN }), "n", "0");
    let cavity = BodySpec {
        body: Body::Cavity { radius_cm: 1.0 },
        coefficients: Coefficients { mu_a: 0.0, ..SKIN },
        ..good
    };
    refused(cavity, "mu_a", "0");
    refused(BodySpec { photons: 0, ..good }, "photons", "0");
    let grid = |g: SurfaceGrid| BodySpec { grid: g, ..good };
    refused(grid(SurfaceGrid { dr: 0.0, ..GRID }), "dr", "0");
    refused(
        grid(SurfaceGrid {
            n_azimuth: 0,
            ..GRID
        }),
        "n_azimuth",
        "0",
    );
    refused(grid(SurfaceGrid { n_exit: 0, ..GRID }), "n_exit", "0");
}

/// The standard errors are the scatter between independent runs: over 16 seeds, the variance of
/// each number (R, A, the shift and the mean radius, the last two ratio estimators with the delta
/// method's error) against its mean squared standard error. For 15 degrees of freedom the ratio
/// is χ²₁₅/15, inside [0.3, 2.5] with probability above 0.998.
#[test]
fn standard_errors_are_the_scatter_between_seeds() {
    let runs: Vec<BodyOutput> = (0..16)
        .map(|seed| {
            let s = BodySpec {
                seed,
                ..spec(Body::Sphere { radius_cm: 0.3 }, SKIN, 45.0, 8_000)
            };
            run_body(&s, &|_| {}).unwrap()
        })
        .collect();
    let numbers = [
        ("R", runs.iter().map(|o| o.r).collect::<Vec<_>>()),
        ("A", runs.iter().map(|o| o.a).collect()),
        ("shift", runs.iter().map(|o| o.reflected.shift).collect()),
        (
            "mean radius",
            runs.iter().map(|o| o.reflected.mean_radius).collect(),
        ),
    ];
    for (what, e) in numbers {
        let k = e.len() as f64;
        let mean = e.iter().map(|x| x.value).sum::<f64>() / k;
        let scatter = e.iter().map(|x| (x.value - mean).powi(2)).sum::<f64>() / (k - 1.0);
        let claimed = e.iter().map(|x| x.se * x.se).sum::<f64>() / k;
        let ratio = scatter / claimed;
        assert!(
            (0.3..2.5).contains(&ratio),
            "{what}: variance / se² = {ratio:.2}"
        );
    }
}
