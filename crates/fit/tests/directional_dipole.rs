//! The full directional dipole (Frisvad et al. 2014): geometry identities, energy bounds at
//! extreme inputs, the oblique far-field shift, light through a slab against Monte Carlo, the
//! δ-Eddington reduced intensity's limits, and the draft's misprinted Apple coefficient.

use fit::analytic::{Dipole, DirectionalDipole, Medium, SurfacePoint};
use mc::{BatchSpec, ChannelSpec, Grid, Layer, Material, TallySet};
use nalgebra::{Rotation3, Vector3};
use std::f64::consts::PI;

fn material(name: &str) -> Material {
    Material::builtin(name).unwrap()
}

fn medium(sigma_a: f64, sigma_s: f64, g: f64, eta: f64) -> Medium {
    Medium {
        sigma_a,
        sigma_s,
        g,
        eta,
    }
}

fn point(x: [f64; 3], n: [f64; 3]) -> SurfacePoint {
    SurfacePoint {
        x: Vector3::from(x),
        n: Vector3::from(n).normalize(),
    }
}

/// The model is built from distances and dot products only: moving and rotating the whole
/// configuration rigidly leaves S_d unchanged, on curved (non-coplanar) geometry, front- and
/// back-lit.
#[test]
fn bssrdf_is_invariant_under_rigid_motions() {
    let dd = DirectionalDipole::new(&medium(0.3, 12.0, 0.2, 1.4));
    let cases = [
        // Curved: normals tilted against each other, light oblique.
        (
            point([0.0, 0.0, 0.0], [0.1, 0.0, 1.0]),
            [0.4, 0.2, 1.0],
            point([0.3, 0.1, -0.05], [0.3, -0.2, 1.0]),
        ),
        // Back-lit: x_o on the far side of a 2 mm part.
        (
            point([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            [0.0, 0.3, 1.0],
            point([0.05, 0.0, -0.2], [0.0, 0.0, -1.0]),
        ),
    ];
    let rot = Rotation3::from_euler_angles(0.7, -0.4, 1.9);
    let shift = Vector3::new(3.0, -1.0, 7.5);
    for (i, w, o) in cases {
        let w = Vector3::from(w).normalize();
        let s = dd.s_d(&i, &w, &o);
        assert!(s > 0.0 && s.is_finite(), "{s}");
        let mv = |p: &SurfacePoint| SurfacePoint {
            x: rot * p.x + shift,
            n: rot * p.n,
        };
        let s2 = dd.s_d(&mv(&i), &(rot * w), &mv(&o));
        assert!((s2 / s - 1.0).abs() < 1e-10, "{s} vs {s2}");
    }
}

/// Energy over the inputs the issue names: albedo → 0 and → 1, g → ±1, η = 1 and η > 2. The
/// model is finite and non-negative everywhere, reflects nothing without scattering, and keeps
/// total Rd ≤ 1 inside its domain (0.5 ≤ α′ ≤ 0.999, θ ≤ 80°). Outside it, measured and
/// documented, it is not a conserving model:
/// - α′ → 1: total Rd 1.216 at α′ = 1 − 10⁻⁷, η = 1.3, θ = 0, integrated out to 10³ transport
///   mean free paths (the overshoot behind its +22 … +30 % against Monte Carlo at normal
///   incidence);
/// - α′ → 0: 0.137 at α′ = 10⁻³, where the truth is ≈ α′/2: the ray source carries the whole
///   refracted power, not the scattered share α′ of it;
/// - g = 0.99, η = 1, θ = 89°: 1.22.
#[test]
fn total_reflectance_stays_physical_at_extreme_inputs() {
    for (sa, ss, g, eta) in [
        (1.0, 1e-3, 0.0, 1.3),   // albedo → 0
        (1e-6, 10.0, 0.0, 1.3),  // albedo → 1
        (0.01, 10.0, 0.99, 1.0), // g → 1, index matched: α′ = 0.91
        (0.01, 10.0, -0.99, 2.4),
        (0.1, 10.0, 0.0, 2.5),
        (0.32, 7.4, 0.0, 1.3), // Skin1 R
        (4.8, 10.1, 0.0, 1.3), // Skin1 B: α′ = 0.68
    ] {
        let m = medium(sa, ss, g, eta);
        let dd = DirectionalDipole::new(&m);
        for theta in [0.0, 45.0, 80.0, 89.0] {
            let t = dd.total_rd(theta);
            eprintln!("σa {sa} σs {ss} g {g} η {eta} θ {theta}: total Rd {t:.4}");
            assert!(t.is_finite() && t >= 0.0, "{t}");
            if (0.5..=0.999).contains(&m.albedo_reduced()) && theta <= 80.0 {
                assert!(t <= 1.0, "σa {sa} σs {ss} g {g} η {eta} θ {theta}: {t}");
            }
        }
    }
    let clear = DirectionalDipole::new(&medium(1.0, 0.0, 0.0, 1.3));
    assert_eq!(clear.rd(0.1), 0.0);
}

/// The draft's §3.5.6 fluence has e^{+σtr r}; the model decays: far from the source Rd(r)
/// falls as e^{−σtr r}, the ratio over one step Δr tending to e^{−σtr Δr}.
#[test]
fn diffuse_profile_decays_with_the_transport_coefficient() {
    let m = medium(0.5, 10.0, 0.0, 1.3);
    let dd = DirectionalDipole::new(&m);
    let sigma_tr = (3.0 * m.sigma_a * m.sigma_t_reduced()).sqrt();
    let (r, step) = (30.0 / sigma_tr, 0.1);
    let ratio = dd.rd(r + step) / dd.rd(r);
    // The algebraic prefactor ~ 1/r² contributes (r/(r + Δr))² at this distance.
    let expected = (-sigma_tr * step).exp() * (r / (r + step)).powi(2);
    assert!(
        (ratio / expected - 1.0).abs() < 0.02,
        "{ratio} vs {expected}"
    );
}

/// Wang & Jacques (Appl. Opt. 34:2362, 1995): the far-field centre of Rd(x, y) at oblique
/// incidence moves by Δx = sin θt/(σs′ + 0.35σa). The directional dipole is a diffusion model,
/// so it must reproduce this diffusion result (measured as in `mc`'s test: the centroid over a
/// ring 3–8 transport mean free paths around the centre, iterated to a fixed point); the
/// classical dipole, radially symmetric, has Δx = 0. Measured: 0.0391 cm against the
/// prediction's 0.0523 cm (Monte Carlo: 0.0513 cm, `mc`'s test): it captures three quarters of
/// the shift. Asserted: within 30 % of the prediction.
#[test]
fn oblique_far_field_shifts_as_wang_and_jacques() {
    let m = medium(0.5, 100.0, 0.9, 1.33);
    let dd = DirectionalDipole::new(&m);
    let sin_t = 45f64.to_radians().sin() / m.eta;
    let expected = sin_t / (m.sigma_s_reduced() + 0.35 * m.sigma_a);
    let ell = m.transport_mfp();
    let (n, dr) = (200i32, 0.005);
    let mut c = 0.0;
    for _ in 0..20 {
        let (mut sw, mut sx) = (0.0, 0.0);
        for iy in -n..=n {
            for ix in -n..=n {
                let (x, y) = (ix as f64 * dr, iy as f64 * dr);
                let r = (x - c).hypot(y);
                if (3.0 * ell..=8.0 * ell).contains(&r) {
                    let v = dd.rd_xy(x, y, 45.0);
                    sw += v;
                    sx += x * v;
                }
            }
        }
        c = sx / sw;
    }
    eprintln!("directional dipole far-field shift {c:.5} cm, Wang–Jacques {expected:.5} cm");
    assert!((c / expected - 1.0).abs() < 0.3, "{c} vs {expected}");
}

/// Light through a slab (the back-lit branch of d_r): a normally incident beam on top of a slab
/// of thickness d; the transmitted exitance integrated over the bottom face, T(0)·4πC_φ(1/η)·
/// ∫ S_d dA, against Monte Carlo's total transmittance of the same slab (σa 0.1, σs 20 cm⁻¹,
/// η = 1.3). This is where the model loses: it knows no second boundary, and on the far side the
/// modified tangent plane turns the virtual source sideways, where it nearly cancels the real
/// one. Measured at 2 / 5 / 10 transport mean free paths: 0.457 / 0.159 / 0.043 against Monte
/// Carlo's 0.498 / 0.277 / 0.135; its transmittance decays about twice as fast as σtr, Monte
/// Carlo's near σtr (diffusion theory's slab asymptote, reached only for thicker slabs: measured
/// 18–21 % above it between 5 and 10 mean free paths). Asserted: positive, below Monte Carlo and
/// within a factor 4 of it; Monte Carlo's decay rate within 30 % of σtr.
#[test]
fn backlit_branch_against_monte_carlo_slab_transmittance() {
    let m = medium(0.1, 20.0, 0.0, 1.3);
    let dd = DirectionalDipole::new(&m);
    let ell = m.transport_mfp();
    let mut rows = Vec::new();
    for thickness_mfp in [2.0, 5.0, 10.0] {
        let d = thickness_mfp * ell;
        let i = point([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        let w = Vector3::z();
        let r_max = d + 30.0 * ell;
        let (nr, mut sum) = (4000, 0.0);
        for k in 0..nr {
            let r = (k as f64 + 0.5) / nr as f64 * r_max;
            let o = point([r, 0.0, -d], [0.0, 0.0, -1.0]);
            sum += dd.s_d(&i, &w, &o) * 2.0 * PI * r * r_max / nr as f64;
        }
        let t_in = 1.0 - mc::fresnel(1.0, m.eta, 1.0).0;
        let model = t_in * 4.0 * PI * fit::analytic::fresnel_moments::c_phi(1.0 / m.eta) * sum;
        let spec = BatchSpec {
            n_above: 1.0,
            n_below: 1.0,
            channels: vec![ChannelSpec {
                layer: Layer {
                    n: m.eta,
                    mu_a: m.sigma_a,
                    mu_s: m.sigma_s,
                    g: m.g,
                    thickness: d,
                },
                grid: Grid {
                    dr: 0.01,
                    dz: 0.01,
                    nr: 10,
                    nz: 1,
                    na: 1,
                },
            }],
            photons: 50_000,
            seed: 3,
            tallies: TallySet {
                absorption_rz: false,
                absorption_rz_se: true,
                surface_xy: 0,
            },
        };
        let out = mc::run_batch(&spec, &|_| {}).unwrap();
        let mc_tt = out[0].tt;
        eprintln!(
            "slab {thickness_mfp} mfp: MC Tt {:.4} ± {:.4}, directional dipole {model:.4}",
            mc_tt.value, mc_tt.se
        );
        assert!(model > 0.0 && model < mc_tt.value && model > 0.25 * mc_tt.value);
        rows.push((d, mc_tt.value));
    }
    let sigma_tr = (3.0 * m.sigma_a * m.sigma_t_reduced()).sqrt();
    let rate = (rows[1].1 / rows[2].1).ln() / (rows[2].0 - rows[1].0);
    assert!((rate / sigma_tr - 1.0).abs() < 0.3, "{rate} vs {sigma_tr}");
}

/// δ-Eddington limits of the reduced intensity: for isotropic scattering (g = 0) no forward
/// peak exists and it is the exact unscattered (Beer–Lambert) beam e^{−σt s}; for g → 1 all
/// scattering is forward and only absorption remains, e^{−σa s}.
#[test]
fn reduced_intensity_has_the_delta_eddington_limits() {
    let s = 0.37;
    let iso = DirectionalDipole::new(&medium(0.4, 9.0, 0.0, 1.3));
    assert!((iso.reduced_intensity(s) - (-(0.4 + 9.0) * s).exp()).abs() < 1e-15);
    let fwd = DirectionalDipole::new(&medium(0.4, 9.0, 1.0, 1.3));
    assert!((fwd.reduced_intensity(s) - (-0.4 * s).exp()).abs() < 1e-15);
    let mid = DirectionalDipole::new(&medium(0.4, 9.0, 0.5, 1.3));
    assert!((mid.reduced_intensity(s) - (-(0.4 + 9.0 * 0.75) * s).exp()).abs() < 1e-15);
}

/// The draft's Table 4.1 prints Apple's blue σa as 0.0046 mm⁻¹. Jensen et al. 2001 measured
/// 0.046 mm⁻¹ and a total diffuse reflectance of 0.85 / 0.84 / 0.53 (R/G/B); their dipole's
/// closed-form total (per unit power entering) reproduces those numbers with our library's
/// Apple (σa B = 0.46 cm⁻¹), and gives a far brighter blue with the draft's value.
#[test]
fn apple_blue_absorption_of_the_draft_is_a_misprint() {
    let apple = material("apple");
    let jensen = [0.85, 0.84, 0.53];
    for (c, &measured) in jensen.iter().enumerate() {
        let m = Medium::channel(&apple, c);
        let rd = Dipole::new(&m).total() / m.entry_transmittance();
        assert!(
            (rd - measured).abs() < 0.03,
            "channel {c}: {rd} vs {measured}"
        );
    }
    let mut draft = Medium::channel(&apple, 2);
    draft.sigma_a = 0.0046 * 10.0; // mm⁻¹ → cm⁻¹
    let rd = Dipole::new(&draft).total() / draft.entry_transmittance();
    assert!(rd > 0.75, "{rd}");
}

/// The library's total (polar midpoint rule) against the Gauss–Legendre total of the radial
/// profile at normal incidence, and `total_at` for the radial models follows T(θ)/T(0).
#[test]
fn total_reflectance_quadratures_agree() {
    use fit::analytic::{Model, total_at};
    for m in [medium(0.32, 7.4, 0.0, 1.3), medium(0.0021, 21.9, 0.0, 1.5)] {
        let dd = DirectionalDipole::new(&m);
        let gl = Model::DirectionalDipole
            .radial(&m)
            .unwrap()
            .total(1e3 * m.transport_mfp());
        assert!(
            (dd.total_rd(0.0) / gl - 1.0).abs() < 1e-3,
            "{} vs {gl}",
            dd.total_rd(0.0)
        );
        let t = |deg: f64| 1.0 - mc::fresnel(1.0, m.eta, deg.to_radians().cos()).0;
        let d0 = total_at(Model::Dipole, &m, 0.0).unwrap();
        let d60 = total_at(Model::Dipole, &m, 60.0).unwrap();
        assert!((d60 / d0 - t(60.0) / t(0.0)).abs() < 1e-12);
        assert!((d0 - Dipole::new(&m).total()).abs() < 1e-3 * d0);
    }
    assert!(total_at(Model::Dipole, &medium(0.3, 7.0, 0.0, 1.3), 90.0).is_err());
}

/// Rd(x, y) at 45° against `mc`'s surface tally on Skin1's red channel (η = 1.3), cell by cell:
/// the share of the diffuse reflectance that leaves ahead of the entry point (x > 0, the beam's
/// direction), and the far-field centre (ring centroid, as in the Wang–Jacques test). The
/// classical and better dipoles are radially symmetric: share ½, shift 0. Measured: share ahead
/// 0.666 (Monte Carlo) against 0.595 (directional dipole): it wins over the radial models, with
/// 58 % of the asymmetry; far-field centre 0.119 cm against 0.053 cm (Wang–Jacques's diffusion
/// estimate: 0.072 cm): it loses most of the shift at this albedo (α′ = 0.96). Asserted: the
/// share is closer to Monte Carlo's than ½, the shift lies between 0 and Monte Carlo's.
#[test]
fn oblique_profile_against_the_monte_carlo_surface_tally() {
    let m = medium(0.32, 7.4, 0.0, 1.3);
    let (n, dr) = (100usize, 0.02);
    let side = 2 * n + 1;
    let spec = mc::RunSpec {
        sample: mc::Sample::single(Layer {
            n: m.eta,
            mu_a: m.sigma_a,
            mu_s: m.sigma_s,
            g: m.g,
            thickness: 1e8,
        }),
        grid: Grid {
            dr: 0.01,
            dz: 0.01,
            nr: 10,
            nz: 1,
            na: 1,
        },
        photons: 200_000,
        seed: 11,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: true,
            surface_xy: n,
        },
    };
    let o = mc::run_at(&spec, mc::incidence::Incidence { theta_deg: 45.0 }, &|_| {}).unwrap();
    let dd = DirectionalDipole::new(&m);
    // (x [cm], y [cm], Monte Carlo Rd, model Rd) per surface cell.
    type Cell = (f64, f64, f64, f64);
    let cells: Vec<Cell> = o
        .rd_xy
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let x = ((i % side) as f64 - n as f64) * dr;
            let y = ((i / side) as f64 - n as f64) * dr;
            // The model's cell average by 4×4 midpoint sub-samples.
            let mut v = 0.0;
            for a in 0..4 {
                for b in 0..4 {
                    let (sx, sy) = ((a as f64 - 1.5) / 4.0 * dr, (b as f64 - 1.5) / 4.0 * dr);
                    v += dd.rd_xy(x + sx, y + sy, 45.0) / 16.0;
                }
            }
            (x, y, e.value, v)
        })
        .collect();
    let ahead = |pick: &dyn Fn(&Cell) -> f64| {
        let fwd: f64 = cells.iter().filter(|c| c.0 > 0.0).map(pick).sum();
        let back: f64 = cells.iter().filter(|c| c.0 < 0.0).map(pick).sum();
        fwd / (fwd + back)
    };
    let (share_mc, share_dd) = (ahead(&|c| c.2), ahead(&|c| c.3));
    let ell = m.transport_mfp();
    let centre = |pick: &dyn Fn(&Cell) -> f64| {
        let mut c = 0.0;
        for _ in 0..20 {
            let (mut sw, mut sx) = (0.0, 0.0);
            for cell in &cells {
                let r = (cell.0 - c).hypot(cell.1);
                if (3.0 * ell..=8.0 * ell).contains(&r) {
                    sw += pick(cell);
                    sx += cell.0 * pick(cell);
                }
            }
            c = sx / sw;
        }
        c
    };
    let (c_mc, c_dd) = (centre(&|c| c.2), centre(&|c| c.3));
    eprintln!(
        "45°: share ahead MC {share_mc:.4}, directional dipole {share_dd:.4}; far-field centre MC {c_mc:.4} cm, directional dipole {c_dd:.4} cm"
    );
    assert!(share_mc > 0.5 && share_dd > 0.5);
    assert!((share_dd - share_mc).abs() < (0.5 - share_mc).abs());
    assert!(c_dd > 0.0 && c_dd < c_mc, "{c_dd} vs {c_mc}");
}
