//! Area pre-integration (Maisch & Ropinski 2020 §3.2, §7.2) against brute-force integration of
//! the profile over discs.

use fit::analytic::{Medium, Model};
use fit::area_table::{AreaTable, RadialTable, cutoff_radius};

/// (1/A)∫_disc Rd by the midpoint rule in polar coordinates about the profile's origin, with
/// the disc as an indicator function sampled on each ring (so Rd is evaluated once per ring and
/// its peak at the origin is integrated as accurately as anywhere else).
fn brute_force(rd: &dyn Fn(f64) -> f64, r: f64, r_a: f64) -> f64 {
    let (n_rho, n_phi) = (4096, 4096);
    let (lo, hi) = ((r - r_a).max(0.0), r + r_a);
    let d_rho = (hi - lo) / n_rho as f64;
    // The angular window that bounds the disc, so that small discs get every sample.
    let window = if r > r_a {
        (r_a / r).asin()
    } else {
        std::f64::consts::PI
    };
    let mut sum = 0.0;
    for a in 0..n_rho {
        let rho = lo + (a as f64 + 0.5) * d_rho;
        let inside = (0..n_phi)
            .filter(|&b| {
                let phi = -window + (b as f64 + 0.5) / n_phi as f64 * 2.0 * window;
                let (x, y) = (rho * phi.cos() - r, rho * phi.sin());
                x * x + y * y < r_a * r_a
            })
            .count();
        sum += rd(rho) * rho * d_rho * 2.0 * window * inside as f64 / n_phi as f64;
    }
    sum / (std::f64::consts::PI * r_a * r_a)
}

/// A small deterministic generator for the random (r, A) draws.
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn disc_averages_match_brute_force_integration() {
    let skin_r = Medium {
        sigma_a: 0.32,
        sigma_s: 7.4,
        g: 0.0,
        eta: 1.3,
    };
    let r_max = cutoff_radius(&skin_r, 1e-7);
    // Q(r_max) = 10⁻⁷ by construction.
    let q = skin_r.albedo_reduced()
        * skin_r.sigma_t_reduced()
        * (-skin_r.sigma_t_reduced() * r_max).exp();
    assert!((q / 1e-7 - 1.0).abs() < 1e-9);
    let mut state = 42;
    for model in [Model::Dipole, Model::BetterDipole, Model::Pbd] {
        let p = model.radial(&skin_r).unwrap();
        let rd = |x: f64| p.rd(x.max(1e-12));
        let table = RadialTable::new(&rd, 2.0 * r_max);
        for _ in 0..12 {
            // Distances and radii spread over decades: tiny footprints near the peak to discs
            // larger than the profile.
            let r = r_max * 10f64.powf(-3.0 * lcg(&mut state));
            let r_a = r_max * 10f64.powf(-3.0 * lcg(&mut state));
            let fast = table.disc_average(r, r_a);
            let slow = brute_force(&rd, r, r_a);
            assert!(
                (fast / slow - 1.0).abs() < 1e-3,
                "{} r = {r} r_A = {r_a}: table {fast} vs brute force {slow}",
                model.name()
            );
        }
    }
}

#[test]
fn table_texels_match_brute_force_and_small_discs_tend_to_the_point_value() {
    let m = Medium {
        sigma_a: 0.0021 * 10.0,
        sigma_s: 21.9,
        g: 0.0,
        eta: 1.5,
    };
    let p = Model::BetterDipole.radial(&m).unwrap();
    let rd = |x: f64| p.rd(x.max(1e-12));
    let r_max = cutoff_radius(&m, 1e-7);
    let t = AreaTable::build([&rd, &rd, &rd], r_max, 64, 64);
    let mut state = 7;
    for _ in 0..8 {
        let (i, j) = (
            (lcg(&mut state) * 64.0) as usize,
            (lcg(&mut state) * 64.0) as usize,
        );
        let (r, a) = (t.r_at(i), t.area_at(j));
        let slow = brute_force(&rd, r, (a / std::f64::consts::PI).sqrt());
        let v = t.values[1][j * 64 + i];
        assert!(
            (v / slow - 1.0).abs() < 1e-3,
            "texel ({i}, {j}): {v} vs {slow}"
        );
        let looked_up = t.lookup(1, r, a);
        assert!(
            (looked_up / v - 1.0).abs() < 1e-12,
            "a texel centre looks up its own value"
        );
    }
    // A vanishing disc averages to the point value.
    let table = RadialTable::new(&rd, 2.0 * r_max);
    for r in [0.01, 0.1, 1.0] {
        let v = table.disc_average(r, 1e-5);
        assert!((v / p.rd(r) - 1.0).abs() < 1e-4, "{r}: {v} vs {}", p.rd(r));
    }
}

/// A disc centred on the origin that holds the whole profile averages to total/area: the
/// table conserves energy.
#[test]
fn a_disc_holding_the_profile_averages_to_its_total() {
    let m = Medium {
        sigma_a: 1.7,
        sigma_s: 8.8,
        g: 0.0,
        eta: 1.3,
    };
    for model in Model::ALL {
        let p = model.radial(&m).unwrap();
        let rd = |x: f64| p.rd(x.max(1e-12));
        let r_max = cutoff_radius(&m, 1e-7);
        let table = RadialTable::new(&rd, 2.0 * r_max);
        let r_a = r_max;
        let total = p.total(r_a);
        let avg = table.disc_average(1e-9, r_a);
        let want = total / (std::f64::consts::PI * r_a * r_a);
        assert!(
            (avg / want - 1.0).abs() < 1e-3,
            "{}: {avg} vs {want}",
            model.name()
        );
    }
}

/// `AreaTable::energy`, what a GPU gather divides by to make the kernel's weights sum to one, is
/// the profile's total diffuse reflectance within r_max (the analytic integral `Radial::total`).
#[test]
fn the_table_knows_its_energy_within_r_max() {
    let m = Medium {
        sigma_a: 0.5,
        sigma_s: 20.0,
        g: 0.0,
        eta: 1.3,
    };
    let r_max = cutoff_radius(&m, 1e-7);
    for model in Model::ALL {
        let p = model.radial(&m).unwrap();
        let rd = |x: f64| p.rd(x.max(1e-12));
        let table = AreaTable::build([&rd, &rd, &rd], r_max, 128, 128);
        let want = p.total(r_max);
        let got = table.energy[1];
        assert!(
            (got / want - 1.0).abs() < 1e-3,
            "{}: {got} vs {want}",
            model.name()
        );
    }
}

/// The paper's Fig. 2 effect, measured: gathering a peaked profile with point samples at pixel
/// centres, with pixels of a few mean free paths, misweighs the energy (by a different factor per
/// channel), while area pre-integration keeps it.
#[test]
fn area_pre_integration_removes_the_zoom_dependent_energy_loss() {
    let m = [
        Medium {
            sigma_a: 0.32,
            sigma_s: 7.4,
            g: 0.0,
            eta: 1.3,
        },
        Medium {
            sigma_a: 4.8,
            sigma_s: 10.1,
            g: 0.0,
            eta: 1.3,
        },
    ];
    let p: Vec<_> = m
        .iter()
        .map(|m| Model::BetterDipole.radial(m).unwrap())
        .collect();
    let rd0 = |x: f64| p[0].rd(x.max(1e-12));
    let rd1 = |x: f64| p[1].rd(x.max(1e-12));
    let r_max = cutoff_radius(&m[0], 1e-7);
    let t = AreaTable::build([&rd0, &rd1, &rd1], r_max, 256, 256);
    let pitch = 2.0 * m[1].transport_mfp();
    let (radial0, radial1) = (RadialTable::new(&rd0, r_max), RadialTable::new(&rd1, r_max));
    let (point0, area0) = fit::area_table::gathered_energy(&t, &radial0, 0, pitch);
    let (point1, area1) = fit::area_table::gathered_energy(&t, &radial1, 1, pitch);
    eprintln!("pitch {pitch} cm: point {point0} {point1}, area {area0} {area1}");
    // Discs stand in for square pixels: within a per cent or two even where the centre pixel
    // holds most of a channel.
    assert!(
        (area0 - 1.0).abs() < 0.01 && (area1 - 1.0).abs() < 0.02,
        "{area0} {area1}"
    );
    // Point sampling errs several times more, and far more in the narrow channel than in the
    // wide one: the image's brightness and colour change as the camera zooms.
    assert!(
        (point1 - 1.0).abs() > 5.0 * (area1 - 1.0).abs(),
        "{point1} vs {area1}"
    );
    assert!((point1 - point0).abs() > 0.1, "{point0} {point1}");
}
