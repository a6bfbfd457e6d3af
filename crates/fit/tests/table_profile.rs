//! Profiles interpolated from a Monte Carlo table (`mc::table`, `fit::table_profile`) against
//! direct simulations of the same materials: by the exact similarity Rd(r; σa, σs) =
//! σt²·R̂(σt·r; α), both estimate the same transport, so they must agree within their noise.
//!
//! 20 random materials (every channel's albedo off the table's grid, 1 − α log-uniform in
//! [3·10⁻⁵, 0.1] or uniform in [0.1, 0.9], σt from 0.5 to 50 cm⁻¹), g and η on the table's grid:
//! χ²/dof ≤ 1.5 of the interpolated profile against a 10⁶-photon simulation within 10 transport
//! mean free paths, on the thesis grid's annuli merged until each holds ~100 simulated photons
//! and spans a table bin (both standard errors) per material, over its three channels, with no
//! channel's χ² beyond chance (probability ≥ 10⁻⁴), and the total Rd within 0.003 (0.3 % of
//! the incident power) and within 4 standard errors. `SSS_TABLE_PHOTONS` sets the table's photons
//! per albedo (default 10⁶, as the acceptance asks).

use fit::table_profile::Tables;
use mc::table::{TableSpec, default_albedos};
use mc::{Material, SimConfig};

const G: f64 = 0.3;
const ETA: f64 = 1.4;

/// SplitMix64: the materials' own random numbers, fixed by the test.
struct Mix(u64);
impl Mix {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn photons_from_env(var: &str, default: u64) -> u64 {
    std::env::var(var)
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .map_or(default, |v| v as u64)
}

#[test]
fn interpolated_profiles_agree_with_direct_simulations_within_their_noise() {
    let spec = TableSpec {
        g: G,
        eta: ETA,
        albedos: default_albedos(100, 0.99999),
        photons: photons_from_env("SSS_TABLE_PHOTONS", 1_000_000),
        seed: 7,
        white: true,
    };
    let table = mc::table::build(std::slice::from_ref(&spec), &|_| {}).unwrap();
    let tables = Tables::new(vec![("test".into(), table[0].clone())]).unwrap();
    let config = SimConfig::thesis().unwrap();
    let edges = mc::table::radius_edges();
    let mut rng = Mix(2026);
    let mut materials = Vec::new();
    while materials.len() < 20 {
        let mut sigma_a = [0.0; 3];
        let mut sigma_s = [0.0; 3];
        for c in 0..3 {
            // 1 − α: log-uniform in [3·10⁻⁵, 0.1] for 70 % of channels, else uniform in [0.1, 0.9].
            let absorb = if rng.next() < 0.3 {
                0.1 + 0.8 * rng.next()
            } else {
                10f64.powf(-4.5 + 3.5 * rng.next())
            };
            let sigma_t = 0.5 * 100f64.powf(rng.next());
            sigma_a[c] = sigma_t * absorb;
            sigma_s[c] = sigma_t - sigma_a[c];
        }
        let m = Material {
            name: format!("random{}", materials.len()),
            source: "test".into(),
            sigma_a,
            sigma_s,
            g: [G; 3],
            eta: ETA,
            thickness: None,
        };
        // Off the grid: no channel within 10⁻⁹ of a table albedo.
        let on_grid = (0..3).any(|c| spec.albedos.iter().any(|a| (a - m.albedo(c)).abs() < 1e-9));
        if !on_grid {
            materials.push(m);
        }
    }
    let mut worst_chi2 = (0.0, String::new());
    let mut worst_rd = (0.0, String::new());
    let mut worst_material = 0.0f64;
    for m in &materials {
        let grid = config.grid_for(m).unwrap();
        let from_table = tables
            .profile(m, &grid, config.n_above, config.thickness_cm)
            .unwrap();
        let batch = config.batch(&[m], 1_000_000, 11, true).unwrap();
        let direct = mc::run_batch(&batch, &|_| {}).unwrap();
        let sim = fit::Profile::from_mc([&direct[0], &direct[1], &direct[2]]);
        let (mut material_chi2, mut material_dof) = (0.0, 0usize);
        for (c, direct) in direct.iter().enumerate() {
            let label = format!(
                "{} {} (albedo {:.6}, σt {:.3} cm⁻¹)",
                m.name,
                mc::CHANNELS[c],
                m.albedo(c),
                m.sigma_a[c] + m.sigma_s[c]
            );
            let r_max = 10.0 * m.mfp(c);
            // A χ² needs Gaussian, independent terms. The thesis grid's annuli are merged, from
            // the centre out, until the simulation holds ~100 photons' worth (relative standard
            // error ≤ 0.1: sparser annuli are skewed, zero, one, a few photons, and their noise
            // estimate is no measure of their error) and the group is at least as wide as the
            // table's radial bin there (narrower groups share one table bin's noise: correlated
            // terms). The table's error of a group is its own (`Interpolated::annulus`).
            let sigma_t = m.sigma_a[c] + m.sigma_s[c];
            let at = table[0].at(m.albedo(c)).unwrap();
            let (mut chi2, mut dof) = (0.0, 0usize);

            let (mut start, mut t, mut v, mut v_var) = (0usize, 0.0, 0.0, 0.0);
            for i in 0..sim.r.len() {
                if (i + 1) as f64 * sim.dr > r_max {
                    break;
                }
                let area = 2.0 * std::f64::consts::PI * (i as f64 + 0.5) * sim.dr * sim.dr;
                t += from_table.profile.rd[c][i] * area;
                v += sim.rd[c][i] * area;
                v_var += (sim.se[c][i] * area).powi(2);
                let (a, b) = (
                    sigma_t * start as f64 * sim.dr,
                    sigma_t * (i + 1) as f64 * sim.dr,
                );
                let k = edges.partition_point(|&e| e <= a).min(edges.len() - 1);
                let width = edges[k] - if k > 0 { edges[k - 1] } else { 0.0 };
                if v > 0.0 && v_var.sqrt() <= 0.1 * v && b - a >= width {
                    let t_se = at.annulus(a, b).se * std::f64::consts::PI * (b * b - a * a);
                    chi2 += (t - v).powi(2) / (t_se * t_se + v_var);

                    dof += 1;
                    (start, t, v, v_var) = (i + 1, 0.0, 0.0, 0.0);
                }
            }
            assert!(
                dof >= 5,
                "{label}: only {dof} groups of annuli within 10 MFP"
            );
            // Per channel, no excess beyond chance: P(χ²_dof ≥ χ²) ≥ 10⁻⁴ (Wilson–Hilferty's
            // normal approximation, z ≤ 3.72). The acceptance's χ²/dof ≤ 1.5 is checked per
            // material, over its three channels' groups, where it has the power to decide (a
            // channel of 30 groups exceeds 1.5 by chance 4 % of the time).
            let k = dof as f64;
            let z = ((chi2 / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
            assert!(
                z <= 3.72,
                "{label}: χ²/dof = {:.3} over {dof} groups (z = {z:.2})",
                chi2 / k
            );
            material_chi2 += chi2;
            material_dof += dof;
            let chi2 = chi2 / k;
            let (t, s) = (from_table.rd[c], direct.rd);
            let d = (t.value - s.value).abs();
            let sigma = (t.se.powi(2) + s.se.powi(2)).sqrt();
            assert!(
                d <= 0.003 && d <= 4.0 * sigma,
                "{label}: Rd {:.5} ± {:.5} from the table, {:.5} ± {:.5} simulated",
                t.value,
                t.se,
                s.value,
                s.se
            );
            if chi2 > worst_chi2.0 {
                worst_chi2 = (chi2, label.clone());
            }
            if d / s.value > worst_rd.0 {
                worst_rd = (
                    d / s.value,
                    format!("{label}: Δ = {d:.2e} ({:.1}σ)", d / sigma),
                );
            }
        }
        let per_dof = material_chi2 / material_dof as f64;
        assert!(
            per_dof <= 1.5,
            "{}: χ²/dof = {per_dof:.3} over {material_dof} groups of its three channels",
            m.name
        );
        worst_material = worst_material.max(per_dof);
    }
    eprintln!(
        "worst material χ²/dof {worst_material:.3}; worst channel χ²/dof {:.3}: {}; worst relative ΔRd {:.3}%: {}",
        worst_chi2.0,
        worst_chi2.1,
        100.0 * worst_rd.0,
        worst_rd.1
    );
}

/// Between tables of neighbouring g, each is read at the coefficients similar to the material's
/// (the same σa and σs(1 − g)) and blended linearly: Skin1's coefficients at g = 0.25 from tables
/// at g = 0 and 0.5 against a direct simulation. Measured at 10⁶/3·10⁵-photon tables: total Rd
/// within 0.2–2.0 % and r·Rd 2.3–3.1 % RMS; asserted within 3 % and 6 % RMS (the tables here are
/// smaller). Outside the grid: refused.
#[test]
fn between_tables_of_neighbouring_g_the_similar_coefficients_are_blended() {
    let spec = |g: f64| TableSpec {
        g,
        eta: 1.3,
        albedos: default_albedos(16, 0.99),
        photons: 200_000,
        seed: 3,
        white: true,
    };
    let built = mc::table::build(&[spec(0.0), spec(0.5)], &|_| {}).unwrap();
    let tables = Tables::new(
        built
            .into_iter()
            .enumerate()
            .map(|(i, t)| (format!("table {i}"), t))
            .collect(),
    )
    .unwrap();
    let config = SimConfig::thesis().unwrap();
    let mut m = Material::builtin("skin1").unwrap();
    m.g = [0.25; 3];
    let grid = config.grid_for(&m).unwrap();
    let blended = tables
        .profile(&m, &grid, config.n_above, config.thickness_cm)
        .unwrap();
    let batch = config.batch(&[&m], 2_000_000, 5, true).unwrap();
    let direct = mc::run_batch(&batch, &|_| {}).unwrap();
    let sim = fit::Profile::from_mc([&direct[0], &direct[1], &direct[2]]);
    for (c, d) in direct.iter().enumerate() {
        // The shape: r·Rd(r) within 3 transport mean free paths, in groups of annuli holding
        // ~2500 simulated photons (2 % noise). Linear weights on the material's own
        // coefficients miss it by 7–9 % RMS (7.2 % in R with these tables); the similar
        // coefficients by 2.8–5.2 % with these tables, 2.3–3.1 % with larger ones.
        let (mut t, mut v, mut var, mut sq, mut groups) = (0.0, 0.0, 0.0, 0.0, 0usize);
        for i in 0..sim.r.len() {
            if (i + 1) as f64 * sim.dr > 3.0 * m.mfp(c) {
                break;
            }
            let area = 2.0 * std::f64::consts::PI * (i as f64 + 0.5) * sim.dr * sim.dr;
            t += blended.profile.rd[c][i] * area;
            v += sim.rd[c][i] * area;
            var += (sim.se[c][i] * area).powi(2);
            if v > 0.0 && var.sqrt() <= 0.02 * v {
                sq += ((t - v) / v).powi(2);
                groups += 1;
                (t, v, var) = (0.0, 0.0, 0.0);
            }
        }
        let rms = (sq / groups as f64).sqrt();
        assert!(
            groups >= 10 && rms < 0.06,
            "{}: r·Rd {:.1} % RMS from simulation over {groups} groups",
            mc::CHANNELS[c],
            100.0 * rms
        );
        let rel = (blended.rd[c].value - d.rd.value) / d.rd.value;
        assert!(
            rel.abs() < 0.03,
            "{}: Rd {:.5} blended, {:.5} ± {:.5} simulated ({:+.2} %)",
            mc::CHANNELS[c],
            blended.rd[c].value,
            d.rd.value,
            d.rd.se,
            100.0 * rel
        );
    }
    m.g = [0.6; 3];
    let e = tables
        .profile(&m, &grid, config.n_above, config.thickness_cm)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("g = 0.6, η = 1.3") && e.contains("outside"),
        "{e}"
    );
}
