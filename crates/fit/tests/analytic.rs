//! Analytic profiles: closed forms and identities, asymptotics, quadrature convergence, and the
//! Monte Carlo ground truth for high-albedo materials.

use fit::Profile;
use fit::analytic::{BeamDiffusion, BetterDipole, Dipole, Medium, Model};
use fit::profile_compare::compare;
use mc::{BatchSpec, ChannelSpec, Grid, Material, TallySet};

fn material(name: &str) -> Material {
    Material::builtin(name).unwrap()
}

fn media() -> Vec<Medium> {
    let mut v = Vec::new();
    for (sa, ss, g, eta) in [
        (0.32, 7.4, 0.0, 1.3),    // Skin1 R
        (4.8, 10.1, 0.0, 1.3),    // Skin1 B: low albedo
        (0.0021, 2.19, 0.0, 1.5), // Marble R: α′ ≈ 0.999
        (0.1, 10.0, 0.9, 1.33),   // forward scattering
        (1.0, 10.0, 0.0, 1.0),    // index matched
        (0.5, 20.0, -0.3, 2.2),   // η > 2, backward scattering
    ] {
        v.push(Medium {
            sigma_a: sa,
            sigma_s: ss,
            g,
            eta,
        });
    }
    v
}

/// Jensen's closed form of the dipole's total diffuse reflectance against the integral of its
/// profile over the plane.
#[test]
fn dipole_profile_integrates_to_its_closed_form_total() {
    for m in media() {
        let d = Dipole::new(&m);
        let integral = Model::Dipole
            .radial(&m)
            .unwrap()
            .total(1e3 * m.transport_mfp());
        assert!(
            (integral - d.total()).abs() < 1e-8 * d.total(),
            "{m:?}: ∫Rd = {integral} vs closed form {}",
            d.total()
        );
    }
    // Without absorption every photon leaves: α′ = 1 gives Rd = 1 (times entry transmittance).
    let m = Medium {
        sigma_a: 0.0,
        sigma_s: 10.0,
        g: 0.0,
        eta: 1.0,
    };
    assert!((Dipole::new(&m).total() - 1.0).abs() < 1e-12);
}

#[test]
fn better_dipole_profile_integrates_to_its_closed_form_total() {
    for m in media() {
        let b = BetterDipole::new(&m);
        let integral = Model::BetterDipole
            .radial(&m)
            .unwrap()
            .total(1e3 * m.transport_mfp());
        assert!(
            (integral - b.total()).abs() < 1e-8 * b.total(),
            "{m:?}: ∫Rd = {integral} vs closed form {}",
            b.total()
        );
    }
}

/// Burley's profile holds exactly its albedo A (its radial CDF reaches 1), and Christensen–Burley's
/// fit maps α′ = 0 and 1 to A = 0 and 1.
#[test]
fn burley_integrates_to_its_albedo() {
    for m in media() {
        let b = fit::Burley::from_medium(&m);
        let integral = Model::Burley
            .radial(&m)
            .unwrap()
            .total(1e3 * m.transport_mfp());
        assert!(
            (integral - b.a).abs() < 1e-8,
            "{m:?}: {integral} vs {}",
            b.a
        );
        assert!(b.a > 0.0 && b.a < m.entry_transmittance());
    }
    let white = Medium {
        sigma_a: 0.0,
        sigma_s: 1.0,
        g: 0.0,
        eta: 1.0,
    };
    assert!((fit::Burley::from_medium(&white).a - 1.0).abs() < 1e-12);
}

/// Far from the source every diffusion model decays as e^{−σtr r} (σtr = √(3σaσt′) for the
/// classical and directional dipoles, √(σa/D) with Grosjean's D for the better dipole and PBD).
#[test]
fn diffusion_profiles_decay_at_the_transport_rate() {
    let m = Medium {
        sigma_a: 0.5,
        sigma_s: 10.0,
        g: 0.0,
        eta: 1.3,
    };
    let st = m.sigma_t_reduced();
    let classical = (3.0 * m.sigma_a * st).sqrt();
    let grosjean = (m.sigma_a * 3.0 * st * st / (2.0 * m.sigma_a + m.sigma_s)).sqrt();
    for (model, rate) in [
        (Model::Dipole, classical),
        (Model::DirectionalDipole, classical),
        (Model::BetterDipole, grosjean),
        (Model::Pbd, grosjean),
    ] {
        let p = model.radial(&m).unwrap();
        // Slope of ln(r²·Rd) between 40 and 41 MFP: the r⁻² of the point source's flux cancels.
        let (r1, r2) = (40.0 / st, 41.0 / st);
        let f = |r: f64| (r * r * p.rd(r)).ln();
        let slope = -(f(r2) - f(r1)) / (r2 - r1);
        assert!(
            (slope - rate).abs() < 0.03 * rate,
            "{}: slope {slope} vs σtr {rate}",
            model.name()
        );
    }
}

/// PBD's depth quadrature converges: errors against a 20 000-point rule fall as N grows.
#[test]
fn beam_diffusion_converges_as_its_quadrature_grows() {
    let m = Medium {
        sigma_a: 0.32,
        sigma_s: 7.4,
        g: 0.0,
        eta: 1.3,
    };
    let reference = BeamDiffusion::new(&m, 20_000);
    let err = |n: usize| {
        let b = BeamDiffusion::new(&m, n);
        [0.02, 0.1, 0.5, 2.0]
            .iter()
            .map(|&r| ((b.rd(r) - reference.rd(r)) / reference.rd(r)).abs())
            .fold(0.0, f64::max)
    };
    let errs: Vec<f64> = [10, 40, 160, 640].iter().map(|&n| err(n)).collect();
    for w in errs.windows(2) {
        assert!(w[1] < 0.6 * w[0], "{errs:?}");
    }
    assert!(errs[3] < 1e-3, "{errs:?}");
}

/// Analytic profiles for a medium that does not scatter are zero, not NaN; one that does not
/// interact is refused with its field named.
#[test]
fn extreme_media_give_finite_profiles_or_clear_errors() {
    let black = Medium {
        sigma_a: 5.0,
        sigma_s: 0.0,
        g: 0.0,
        eta: 1.4,
    };
    for model in Model::ALL {
        let p = model.radial(&black).unwrap();
        for r in [1e-6, 0.01, 1.0, 100.0] {
            assert_eq!(p.rd(r), 0.0, "{} at {r}", model.name());
        }
    }
    let clear = Medium {
        sigma_a: 0.0,
        sigma_s: 0.0,
        g: 0.0,
        eta: 1.4,
    };
    let e = Model::Dipole.radial(&clear).unwrap_err().to_string();
    assert!(e.contains("sigma_a + sigma_s"), "{e}");
    let bad = Medium {
        sigma_a: 1.0,
        sigma_s: 1.0,
        g: 1.5,
        eta: 1.4,
    };
    assert!(
        Model::Pbd
            .radial(&bad)
            .unwrap_err()
            .to_string()
            .contains("g")
    );
    for model in Model::ALL {
        for m in media() {
            let p = model.radial(&m).unwrap();
            for r in [1e-7, 1e-3, 0.1, 10.0, 1e3] {
                let v = p.rd(r);
                assert!(
                    v.is_finite() && v >= 0.0,
                    "{} {m:?} at {r}: {v}",
                    model.name()
                );
            }
        }
    }
}

/// An MC profile of a half-space of `m` (240 bins of ℓ_min/8), as `sss simulate` writes it, and
/// the total diffuse reflectance per channel with its exact standard error.
fn mc_profile(m: &Material, photons: u64) -> (Profile, [(f64, f64); 3]) {
    let l_min = (0..3)
        .map(|c| Medium::channel(m, c).transport_mfp())
        .fold(f64::INFINITY, f64::min);
    let grid = Grid {
        dr: l_min / 8.0,
        dz: l_min,
        nr: 241,
        nz: 1,
        na: 1,
    };
    let channels = (0..3)
        .map(|c| ChannelSpec {
            layer: m.layer(c, 1e8),
            grid,
        })
        .collect();
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels,
        photons,
        seed: 11,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: true,
            surface_xy: 0,
        },
    };
    let out = mc::run_batch(&spec, &|_| {}).unwrap();
    let n = grid.nr - 1;
    let p = Profile {
        dr: grid.dr,
        r: (0..n).map(|j| grid.r_optimal(j)).collect(),
        rd: [0, 1, 2].map(|c| out[c].rd_r[..n].iter().map(|e| e.value).collect()),
        se: [0, 1, 2].map(|c| out[c].rd_r[..n].iter().map(|e| e.se).collect()),
    };
    (p, [0, 1, 2].map(|c| (out[c].rd.value, out[c].rd.se)))
}

/// Against MC for the high-albedo materials the issue names. What holds, asserted:
/// - d'Eon's better dipole is closer than the classical dipole to the total diffuse reflectance;
/// - PBD (with single scattering) is far closer in the shape of r·Rd(r) within 3 MFP.
///
/// What does not hold, measured and reported (`sss compare-profiles`): in total Rd the classical
/// dipole (−0.3 … −1.6%) beats PBD (+2.5 … +4.4%, pbrt's ρ′² weighting double-counts part of the
/// single scattering) and the directional dipole at normal incidence (+22 … +30%).
#[test]
fn analytic_models_against_monte_carlo_on_high_albedo_materials() {
    // Cream's models differ by 0.0015 in R: it needs 10⁶ photons to tell them apart.
    for (name, photons) in [
        ("marble", 100_000),
        ("wholemilk", 100_000),
        ("cream", 1_000_000),
    ] {
        let mat = material(name);
        let (mc, totals) = mc_profile(&mat, photons);
        let models = compare(&mc, &mat).unwrap();
        let get = |model: Model, c: usize| {
            models.iter().find(|m| m.model == model).unwrap().channels[c].clone()
        };
        for (c, &(t, se)) in totals.iter().enumerate() {
            let (dipole, better, pbd) = (
                get(Model::Dipole, c),
                get(Model::BetterDipole, c),
                get(Model::Pbd, c),
            );
            eprintln!(
                "{name} {c}: Rd MC {:.4} ± {:.4}; dipole {:.4}, better {:.4}, directional {:.4}, pbd {:.4}; \
                 rms r·Rd: dipole {:.3}, pbd {:.3}",
                dipole.total_mc,
                dipole.total_mc_se,
                dipole.total_model,
                better.total_model,
                get(Model::DirectionalDipole, c).total_model,
                pbd.total_model,
                dipole.rms_r_rd_3mfp,
                pbd.rms_r_rd_3mfp
            );
            // Totals over the whole plane against MC's total Rd (exact per-photon standard error):
            // MC lies on the better dipole's side of the two models' midpoint by more than 3 SE.
            let m = Medium::channel(&mat, c);
            let total = |model: Model| model.radial(&m).unwrap().total(1e3 * m.transport_mfp());
            let (b, d) = (total(Model::BetterDipole), total(Model::Dipole));
            eprintln!("  whole plane: MC {t:.4} ± {se:.4}, dipole {d:.4}, better dipole {b:.4}");
            assert!(
                (b - d).signum() * (t - 0.5 * (b + d)) > 3.0 * se,
                "{name} {c}: better dipole {b:.4}, dipole {d:.4}, MC {t:.4} ± {se:.4}"
            );
            assert!(
                pbd.rms_r_rd_3mfp < 0.5 * dipole.rms_r_rd_3mfp,
                "{name} {c}: pbd {:.3} vs dipole {:.3}",
                pbd.rms_r_rd_3mfp,
                dipole.rms_r_rd_3mfp
            );
        }
    }
}

/// Total Rd of the directional dipole at incidence θ: ∫∫ Rd(x, y; θ) dx dy on a polar grid.
fn directional_total(d: &fit::analytic::DirectionalDipole, theta: f64, r_max: f64) -> f64 {
    let (nr, nphi) = (3000, 180);
    let dr = r_max / nr as f64;
    let mut sum = 0.0;
    for i in 0..nr {
        let r = (i as f64 + 0.5) * dr;
        for j in 0..nphi {
            let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * std::f64::consts::PI;
            sum += d.rd_xy(r * phi.cos(), r * phi.sin(), theta) * r;
        }
    }
    sum * dr * 2.0 * std::f64::consts::PI / nphi as f64
}

/// The directional dipole at oblique incidence against Monte Carlo: total Rd(θ)/Rd(0) on
/// Skin1 and Marble (η = 1.3, 1.5). The classical dipole depends on θ only through the entry
/// Fresnel transmittance T(θ)/T(0); in Monte Carlo shallower paths add back-scattered light
/// (Skin1's ratio rises above 1, Marble's entry loss at η = 1.5 still wins), and the directional
/// dipole follows: its ratio is closer to Monte Carlo's than the classical dipole's in every
/// channel. The normal-incidence
/// profile is unchanged: `rd(r)` equals `rd_xy(r, 0, 0)`.
#[test]
fn directional_dipole_follows_monte_carlo_at_oblique_incidence() {
    for name in ["skin1", "marble"] {
        let mat = material(name);
        let chans: Vec<ChannelSpec> = (0..3)
            .map(|c| {
                let layer = mat.layer(c, 1e8);
                ChannelSpec {
                    layer,
                    grid: Grid {
                        dr: 0.01,
                        dz: 0.01,
                        nr: 10,
                        nz: 1,
                        na: 1,
                    },
                }
            })
            .collect();
        let spec = BatchSpec {
            n_above: 1.0,
            n_below: 1.0,
            channels: chans,
            photons: 100_000,
            seed: 5,
            tallies: TallySet {
                absorption_rz: false,
                absorption_rz_se: true,
                surface_xy: 0,
            },
        };
        let rows = mc::incidence::rd_table(&spec, &[0.0, 60.0], &|_| {}).unwrap();
        for c in 0..3 {
            let m = Medium::channel(&mat, c);
            let dd = fit::analytic::DirectionalDipole::new(&m);
            assert_eq!(dd.rd(0.05), dd.rd_xy(0.05, 0.0, 0.0));
            let r_max = 40.0 * m.transport_mfp();
            let ratio_dd = directional_total(&dd, 60.0, r_max) / directional_total(&dd, 0.0, r_max);
            let (e0, e60) = (rows[0].rd[c], rows[1].rd[c]);
            let ratio_mc = e60.value / e0.value;
            let se = ratio_mc * ((e0.se / e0.value).powi(2) + (e60.se / e60.value).powi(2)).sqrt();
            let t = |deg: f64| 1.0 - mc::fresnel(1.0, m.eta, deg.to_radians().cos()).0;
            let ratio_dipole = t(60.0) / t(0.0);
            eprintln!(
                "{name} {c}: Rd(60°)/Rd(0°) MC {ratio_mc:.4} ± {se:.4}, directional dipole {ratio_dd:.4}, classical dipole {ratio_dipole:.4}"
            );
            assert!(
                (ratio_dd - ratio_mc).abs() < (ratio_dipole - ratio_mc).abs(),
                "{name} channel {c}"
            );
        }
    }
}
