//! End-to-end tests of `sss profile`, `sss compare-profiles` and `sss area-table`.

mod common;
use common::sss;

#[test]
fn profile_writes_the_simulate_csv_on_the_thesis_grid() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(
        &["profile", "skin1", "--model", "dipole", "--out", "d.csv"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.path().join("d.csv")).unwrap();
    let p = fit::Profile::from_csv(&text, "d.csv").unwrap();
    // The thesis grid of Skin1: dr = min MFP / 20 (Table 6.1), 32 max MFP; MFP = 1/(σa + σs).
    let (min_mfp, max_mfp) = (1.0 / (4.8 + 10.1), 1.0 / (0.32 + 7.4));
    assert!((p.dr - min_mfp / 20.0).abs() < 1e-12 * p.dr, "{}", p.dr);
    assert_eq!(p.len() + 1, (32.0 * max_mfp / p.dr).ceil() as usize);
    assert!(p.se.iter().flatten().all(|&s| s == 0.0));
    // Bins hold annulus averages: the grid's energy plus the overflow row is Jensen's closed-form
    // total (the grid reaches 32 MFP of R, where the profile is ~e⁻¹⁹ of its peak).
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let area = |i: usize| std::f64::consts::PI * (2 * i + 1) as f64 * p.dr * p.dr;
    let total_r: f64 = rows
        .iter()
        .enumerate()
        .map(|(i, row)| row[1] * area(i))
        .sum();
    let m = fit::analytic::Medium {
        sigma_a: 0.32,
        sigma_s: 7.4,
        g: 0.0,
        eta: 1.3,
    };
    let closed = fit::analytic::Dipole::new(&m).total();
    assert!(
        (total_r / closed - 1.0).abs() < 1e-6,
        "{total_r} vs {closed}"
    );
}

#[test]
fn profile_refuses_unknown_models_and_materials_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(&["profile", "skin1", "--model", "tripole"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("tripole") && e.contains("better-dipole"), "{e}");
    std::fs::write(dir.path().join("clear.toml"), "name = \"clear\"\nunit = \"cm\"\nsigma_a = [0, 0, 1]\nsigma_s = [0, 0, 1]\ng = 0.0\neta = 1.3\n").unwrap();
    let o = sss(
        &["profile", "clear.toml", "--model", "pbd", "--out", "c.csv"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("sigma_a"), "{e}");
    assert!(!dir.path().join("c.csv").exists(), "nothing half-written");
}

#[test]
fn compare_profiles_reports_every_model_and_draws_a_plot() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(
        &[
            "compare-profiles",
            "skin1",
            "--photons",
            "20000",
            "--profiles",
            "p",
            "--plots",
            "plots",
            "--json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let models = v["materials"][0]["models"].as_array().unwrap();
    let names: Vec<&str> = models
        .iter()
        .map(|m| m["model"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "dipole",
            "better-dipole",
            "directional-dipole",
            "pbd",
            "burley"
        ]
    );
    for m in models {
        for ch in ["R", "G", "B"] {
            let c = &m["channels"][ch];
            for key in ["total_mc", "total_model", "total_rel_err", "rms_r_rd_3mfp"] {
                assert!(c[key].as_f64().unwrap().is_finite(), "{m} {ch} {key}");
            }
        }
    }
    let png = std::fs::read(dir.path().join("plots/skin1.compare_profiles.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

#[test]
fn area_table_writes_the_table_its_header_and_the_zoom_plot() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(
        &["area-table", "skin1", "--size", "64", "--out", "t"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(dir.path().join("t/skin1.area.f32")).unwrap();
    assert_eq!(bytes.len(), 64 * 64 * 3 * 4);
    let v: Vec<f32> = bytes
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert!(v.iter().all(|x| x.is_finite() && *x >= 0.0));
    let h: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("t/skin1.area.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(h["columns"], 64);
    // r_max: Q(r) = α′σt′e^{−σt′r} = 10⁻⁷ in the channel with the longest reach (R).
    let st: f64 = 0.32 + 7.4;
    let want = (7.4 / st * st / 1e-7).ln() / st;
    assert!((h["r_max_cm"].as_f64().unwrap() - want).abs() < 1e-9 * want);
    assert!(dir.path().join("t/skin1.area_effect.png").exists());
    let o = sss(&["area-table", "skin1", "--size", "1"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--size"));
}
