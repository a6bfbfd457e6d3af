//! End-to-end tests of `sss simulate`, `sss merge` and `sss materials`.

use std::path::Path;
use std::process::Output;

mod common;
use common::sss;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn files_in(dir: &Path) -> Vec<String> {
    match std::fs::read_dir(dir) {
        Ok(rd) => rd
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    }
}

#[test]
fn simulate_writes_profile_summary_and_mco() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(
        &[
            "simulate",
            "skin1",
            "--full",
            "--photons",
            "2e4",
            "--seed",
            "3",
            "--out",
            "res",
            "--json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["material"], "skin1");
    assert_eq!(summary["photons"], 20_000);
    assert_eq!(summary["seed"], 3);
    for ch in ["R", "G", "B"] {
        for k in ["rsp", "rd", "rd_se", "a", "tt"] {
            assert!(summary["channels"][ch][k].is_number(), "{ch}.{k}");
        }
    }
    // Thesis grid rule: dr = min(MFP)/20 with MFP_B = 1/14.9 cm; nr = ⌈32·MFP_R/dr⌉, MFP_R = 1/7.72 cm.
    let dr = summary["grid"]["dr_cm"].as_f64().unwrap();
    assert!((dr - 1.0 / 14.9 / 20.0).abs() < 1e-15);
    assert_eq!(
        summary["grid"]["nr"].as_u64().unwrap(),
        (32.0 / 7.72 / dr).ceil() as u64
    );

    let res = dir.path().join("res");
    let csv = std::fs::read_to_string(res.join("skin1.profile.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("r_cm,R,G,B,R_se,G_se,B_se"));
    // ∫Rd(r) 2πr dr over the annuli equals total Rd (the last bin collects the rest).
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let integral: f64 = (0..rows.len())
        .map(|i| rows[i][1] * 2.0 * std::f64::consts::PI * (i as f64 + 0.5) * dr * dr)
        .sum();
    let rd = summary["channels"]["R"]["rd"].as_f64().unwrap();
    assert!((integral - rd).abs() < 1e-9 * rd, "{integral} vs {rd}");

    // The .mco reads back with the same totals, and Rsp + Rd + A + Tt = 1 within error.
    let mco = mc::mco::read(
        &std::fs::read_to_string(res.join("skin1.R.mco")).unwrap(),
        "skin1.R.mco",
    )
    .unwrap();
    assert_eq!(mco.photons, 20_000);
    assert!((mco.rd - rd).abs() < 1e-5);
    assert!((mco.rsp + mco.rd + mco.a + mco.tt - 1.0).abs() < 1e-3);
    assert_eq!(mco.rd_r.len(), rows.len());
}

#[test]
fn same_seed_same_files_with_one_or_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    // Profile-only is the default: the explicit flag on 2 threads gives the same bits as none
    // on 1, and neither writes .mco files.
    for (t, flag) in [("1", None), ("2", Some("--profile-only"))] {
        let mut args = vec![
            "simulate",
            "ketchup",
            "--photons",
            "50000",
            "--threads",
            t,
            "--out",
            t,
        ];
        args.extend(flag);
        let o = sss(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            !files_in(&dir.path().join(t))
                .iter()
                .any(|f| f.ends_with(".mco")),
            "profile-only writes no .mco"
        );
    }
    let a = std::fs::read(dir.path().join("1/ketchup.profile.csv")).unwrap();
    let b = std::fs::read(dir.path().join("2/ketchup.profile.csv")).unwrap();
    assert_eq!(a, b);
}

/// Regression: `sss simulate skin1` and `sss simulate --all` gave Skin1 different numbers for the
/// same seed (walk streams were seeded by the walk group's position in the batch, and Skin1 shared
/// a walk with other materials). A material's results depend only on the seed and the material.
/// The batch is the sixteen materials `--all` held then (`mc::builtin::REPRODUCED`): the whole
/// library of today would only add CI time.
#[test]
fn a_material_alone_and_in_all_gives_the_same_profile() {
    let dir = tempfile::tempdir().unwrap();
    let common = ["--photons", "20000", "--seed", "4", "--profile-only"];
    let alone: &[&str] = &["skin1"];
    for (out, what) in [("alone", alone), ("all", &mc::builtin::REPRODUCED[..])] {
        let mut args = vec!["simulate"];
        args.extend_from_slice(what);
        args.extend_from_slice(&["--out", out]);
        args.extend_from_slice(&common);
        let o = sss(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let a = std::fs::read(dir.path().join("alone/skin1.profile.csv")).unwrap();
    let b = std::fs::read(dir.path().join("all/skin1.profile.csv")).unwrap();
    assert!(a == b, "skin1.profile.csv differs alone and in --all");
}

#[test]
fn shards_merge_into_the_unsharded_run() {
    let dir = tempfile::tempdir().unwrap();
    let common = ["--photons", "70000", "--seed", "9", "--profile-only"];
    let run = |extra: &[&str]| {
        let mut args = vec!["simulate", "skin1", "apple"];
        args.extend_from_slice(&common);
        args.extend_from_slice(extra);
        let o = sss(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    };
    run(&["--out", "whole"]);
    run(&["--shard", "1/3", "--out", "shards"]);
    run(&["--shard", "3/3", "--out", "shards"]);
    run(&["--shard", "2/3", "--out", "shards"]);
    // An incomplete set is refused.
    let o = sss(
        &[
            "merge",
            "shards/shard-1-of-3.json",
            "shards/shard-3-of-3.json",
            "--out",
            "merged",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing"), "{}", stderr(&o));
    let o = sss(
        &[
            "merge",
            "shards/shard-3-of-3.json",
            "shards/shard-1-of-3.json",
            "shards/shard-2-of-3.json",
            "--out",
            "merged",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["skin1.profile.csv", "apple.profile.csv"] {
        let a = std::fs::read(dir.path().join("whole").join(f)).unwrap();
        let b = std::fs::read(dir.path().join("merged").join(f)).unwrap();
        assert!(a == b, "{f} differs after merge");
    }
}

/// `merge` checks every shard against the specification it carries and against the other
/// shards: a corrupt or foreign shard is refused with exit code 2, an error naming the file, the
/// field and the value, and nothing written.
#[test]
fn corrupt_or_foreign_shards_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let shard = |i: &str, seed: &str, out: &str| {
        let o = sss(
            &[
                "simulate",
                "skin1",
                "--photons",
                "40000",
                "--seed",
                seed,
                "--profile-only",
                "--shard",
                i,
                "--out",
                out,
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
    };
    shard("1/2", "1", "good");
    shard("2/2", "1", "good");
    shard("2/2", "2", "other");
    let good: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("good/shard-1-of-2.json")).unwrap(),
    )
    .unwrap();
    let nr = good["groups"][0]["layout"]["nr"].as_u64().unwrap();
    let edit = |name: &str, f: &dyn Fn(&mut serde_json::Value)| {
        let mut v = good.clone();
        f(&mut v);
        std::fs::write(dir.path().join(name), v.to_string()).unwrap();
    };
    edit("no-group.json", &|v| {
        v["groups"].as_array_mut().unwrap().pop();
    });
    edit("layout.json", &|v| {
        v["groups"][1]["layout"]["nr"] = (nr + 1).into()
    });
    edit("huge-layout.json", &|v| {
        v["groups"][0]["layout"]["nr"] = 1_000_000_000_000u64.into()
    });
    edit("huge-grid.json", &|v| {
        v["spec"]["channels"][2]["grid"]["nr"] = 1_000_000_000_000u64.into()
    });
    edit("negative.json", &|v| {
        v["groups"][0]["entries"][0][1] = "-5".into()
    });
    edit("escape.json", &|v| {
        for (c, ch) in ["R", "G", "B"].iter().enumerate() {
            v["labels"][c] = format!("../../escaped:{ch}").into();
        }
    });
    let text = good.to_string();
    std::fs::write(dir.path().join("truncated.json"), &text[..text.len() / 2]).unwrap();
    let second = "good/shard-2-of-2.json";
    let cases: [(&str, &str, &[&str]); 8] = [
        (
            "no-group.json",
            second,
            &["no-group.json", "groups: 2", "3 walk groups"],
        ),
        (
            "layout.json",
            second,
            &["layout.json", "group 1 layout nr", &format!("= {}", nr + 1)],
        ),
        (
            "huge-layout.json",
            second,
            &["huge-layout.json", "group 0 layout nr = 1000000000000"],
        ),
        (
            "huge-grid.json",
            second,
            &["huge-grid.json", "channel 2 nr = 1000000000000"],
        ),
        (
            "negative.json",
            second,
            &["negative.json", "group 0 entry", "\"-5\""],
        ),
        ("truncated.json", second, &["truncated.json", "EOF"]),
        (
            "good/shard-1-of-2.json",
            "other/shard-2-of-2.json",
            &["other/shard-2-of-2.json", "seed = 2", "seed = 1"],
        ),
        ("escape.json", second, &["label", "../../escaped:R"]),
    ];
    for (a, b, expect) in cases {
        let o = sss(&["merge", a, b, "--out", "merged"], dir.path());
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{a} + {b}: {err}");
        assert_eq!(
            err.trim().lines().count(),
            1,
            "{a}: one line expected: {err}"
        );
        for e in expect {
            assert!(err.contains(e), "{a} + {b}: {err:?} should mention {e:?}");
        }
        assert!(
            !dir.path().join("merged").exists(),
            "{a}: nothing may be written"
        );
        assert!(
            files_in(dir.path())
                .iter()
                .all(|f| !f.starts_with("escaped")),
            "{a}"
        );
    }
    let o = sss(
        &["merge", "good/shard-1-of-2.json", second, "--out", "merged"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn mci_runs_every_run_and_writes_mcml_output() {
    let dir = tempfile::tempdir().unwrap();
    let mci = "1.0\n2\n# run 1: van de Hulst's slab\nslab.mco A\n20000\n0.01 0.01\n10 20 5\n1\n1.0\n1.0 10 90 0.75 0.02\n1.0\n\n# run 2: two layers\ntwo.mco A\n5000\n0.01 0.01\n10 20 5\n2\n1.0\n1.37 1 100 0.9 0.05\n1.45 2 10 0 0.1\n1.0\n";
    std::fs::write(dir.path().join("in.mci"), mci).unwrap();
    let o = sss(
        &["simulate", "--mci", "in.mci", "--out", "res", "--json"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["runs"].as_array().unwrap().len(), 2);
    let slab = std::fs::read_to_string(dir.path().join("res/slab.mco")).unwrap();
    for section in [
        "InParm",
        "RAT",
        "A_l",
        "A_z",
        "Rd_r",
        "Rd_a",
        "Tt_r",
        "Tt_a",
        "A_rz",
        "Rd_ra",
        "Tt_ra",
        "#Specular reflectance [-]",
        "#Diffuse reflectance [-]",
        "#Absorbed fraction [-]",
        "#Transmittance [-]",
    ] {
        assert!(slab.contains(section), "missing {section}");
    }
    let d = mc::mco::read(&slab, "slab.mco").unwrap();
    // van de Hulst: Rd = 0.09739, Tt = 0.66096 (loose: 20k photons).
    assert!(
        (d.rd - 0.09739).abs() < 0.006 && (d.tt - 0.66096).abs() < 0.01,
        "{} {}",
        d.rd,
        d.tt
    );
    let two = mc::mco::read(
        &std::fs::read_to_string(dir.path().join("res/two.mco")).unwrap(),
        "two.mco",
    )
    .unwrap();
    assert_eq!(two.a_l.len(), 2);
}

/// Bad input: exit code 2, a one-line error naming the field and value, and no output written.
#[test]
fn bad_input_is_refused_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../materials/skin1.toml"),
    )
    .unwrap();
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("negative", good.replace("sigma_a = [0.32", "sigma_a = [-0.32"), vec!["sigma_a[R]", "-0.32"]),
        ("nan", good.replace("sigma_s = [7.4", "sigma_s = [nan"), vec!["sigma_s[R]", "NaN"]),
        ("eta", good.replace("eta = 1.3", "eta = 0.0"), vec!["eta", "0"]),
        ("thick", good + "thickness = 0.0\n", vec!["thickness", "0"]),
        ("malformed", "name = \"x\"\nsigma_a = [1, 2\n".to_string(), vec!["malformed.toml"]),
        ("unit", "name = \"x\"\nunit = \"in\"\nsigma_a = [1.0, 1.0, 1.0]\nsigma_s = [1.0, 1.0, 1.0]\ng = 0.0\neta = 1.3\n".to_string(), vec!["unit", "\"in\""]),
    ];
    for (name, text, expect) in cases {
        let file = format!("{name}.toml");
        std::fs::write(dir.path().join(&file), text).unwrap();
        let o = sss(
            &["simulate", &file, "--photons", "1000", "--out", "never"],
            dir.path(),
        );
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert_eq!(
            err.trim().lines().count(),
            1,
            "{name}: one line expected: {err}"
        );
        for e in expect {
            assert!(err.contains(e), "{name}: {err:?} should mention {e:?}");
        }
    }
    let o = sss(
        &["simulate", "skin1", "--photons", "0", "--out", "never"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("photons"));
    let o = sss(&["simulate", "unobtainium", "--out", "never"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("unknown material \"unobtainium\""),
        "{}",
        stderr(&o)
    );
    std::fs::write(
        dir.path().join("bad.mci"),
        "1.0\n1\nx.mco A\n100\n0.01 0.01\n10 10 10\n1\n1.0\n1.3 1 10 0.9 -1\n1.0\n",
    )
    .unwrap();
    let o = sss(
        &["simulate", "--mci", "bad.mci", "--out", "never"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("run 1 layer 1 thickness = -1"),
        "{}",
        stderr(&o)
    );
    std::fs::write(dir.path().join("trunc.mci"), "1.0\n1\nx.mco A\n100\n").unwrap();
    let o = sss(
        &["simulate", "--mci", "trunc.mci", "--out", "never"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        !dir.path().join("never").exists(),
        "nothing may be written on bad input"
    );
}

#[test]
fn incidence_angles_write_rd_of_theta() {
    let dir = tempfile::tempdir().unwrap();
    common::small_profile(dir.path());
    let o = sss(
        &[
            "simulate",
            "skin1",
            "--config",
            "small.toml",
            "--profile-only",
            "--incidence-angles",
            "0,60,80",
            "--incidence-photons",
            "20000",
            "--out",
            "res",
            "--json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let res = dir.path().join("res");
    let csv = std::fs::read_to_string(res.join("skin1.incidence.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(
            "theta_deg,R,G,B,R_se,G_se,B_se,R_rsp,G_rsp,B_rsp,\
             directional-dipole_R,directional-dipole_G,directional-dipole_B,\
             dipole_R,dipole_G,dipole_B,better-dipole_R,better-dipole_G,better-dipole_B"
        )
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 3);
    assert_eq!([rows[0][0], rows[1][0], rows[2][0]], [0.0, 60.0, 80.0]);

    // Rsp: Fresnel from air (small.toml: n_above = 1) into η = 1.3, unpolarized.
    let eta = 1.3;
    let fresnel = |theta_deg: f64| {
        let cos_i = theta_deg.to_radians().cos();
        let sin_t = theta_deg.to_radians().sin() / eta;
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        let rs = ((cos_i - eta * cos_t) / (cos_i + eta * cos_t)).powi(2);
        let rp = ((cos_t - eta * cos_i) / (cos_t + eta * cos_i)).powi(2);
        0.5 * (rs + rp)
    };
    for c in 0..3 {
        assert!((rows[0][7 + c] - ((eta - 1.0) / (eta + 1.0)).powi(2)).abs() < 1e-12);
        assert!(
            (rows[2][7 + c] - fresnel(80.0)).abs() < 1e-12,
            "{} vs {}",
            rows[2][7 + c],
            fresnel(80.0)
        );
    }
    // At grazing incidence the refracted beam runs shallower and more of the light that enters
    // scatters back: Rd per unit *entering* power, Rd/(1 − Rsp), grows from 0° to 80° (by ~9–18%,
    // many standard errors). Per unit *incident* power (what the CSV holds) it falls instead, as
    // Rsp(80°) ≈ 0.39 reflects much of the beam before it enters.
    for c in 0..3 {
        let entered = |r: &[f64]| r[1 + c] / (1.0 - r[7 + c]);
        let q = entered(&rows[2]) / entered(&rows[0]);
        let q_se = q * (rows[2][4 + c] / rows[2][1 + c]).hypot(rows[0][4 + c] / rows[0][1 + c]);
        assert!(q > 1.0 + 4.0 * q_se, "channel {c}: {q} ± {q_se}");
        assert!(rows[2][1 + c] < rows[0][1 + c], "channel {c}");
    }

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(res.join("skin1.summary.json")).unwrap())
            .unwrap();
    let inc = summary["incidence"].as_array().unwrap();
    assert_eq!(inc.len(), 3);
    assert_eq!(inc[2]["theta_deg"], 80.0);
    for k in ["rd", "rd_se", "rsp"] {
        for ch in ["R", "G", "B"] {
            assert!(inc[1][k][ch].is_number(), "{k}.{ch}");
        }
    }
    // The same number in both files; serde_json's default float parser may read it 1 ulp off.
    let (json_g, csv_g) = (inc[1]["rd"]["G"].as_f64().unwrap(), rows[1][2]);
    assert!(
        (json_g - csv_g).abs() <= 2.0 * f64::EPSILON * csv_g.abs(),
        "{json_g} vs {csv_g}"
    );
    // The analytic models beside it: the radial dipole depends on θ only through the entry
    // transmittance, so its Rd(80°)/Rd(0°) is (1 − Rsp(80°))/(1 − Rsp(0°)) exactly.
    let dipole = |r: &[f64], c: usize| r[13 + c];
    for c in 0..3 {
        let q = dipole(&rows[2], c) / dipole(&rows[0], c);
        let t = (1.0 - rows[2][7 + c]) / (1.0 - rows[0][7 + c]);
        assert!((q - t).abs() < 1e-9, "channel {c}: {q} vs {t}");
        assert_eq!(
            inc[2]["models"]["dipole"][["R", "G", "B"][c]]
                .as_f64()
                .unwrap(),
            rows[2][13 + c]
        );
    }
    let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(printed["incidence"], summary["incidence"]);
    let png = std::fs::read(res.join("skin1.incidence.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
    // The normal run is unchanged by the option.
    let plain = std::fs::read(dir.path().join("profiles/skin1.profile.csv")).unwrap();
    assert_eq!(std::fs::read(res.join("skin1.profile.csv")).unwrap(), plain);
}

#[test]
fn bad_incidence_angles_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (angles, expect) in [
        ("95", "95"),
        ("0,abc", "abc"),
        ("", "not a number"),
        ("-5", "-5"),
    ] {
        let o = sss(
            &[
                "simulate",
                "skin1",
                "--photons",
                "1000",
                "--incidence-angles",
                angles,
                "--out",
                "never",
            ],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(2), "{angles:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(expect), "{angles:?}: {}", stderr(&o));
    }
    let o = sss(
        &[
            "simulate",
            "skin1",
            "--incidence-angles",
            "30",
            "--shard",
            "1/2",
            "--out",
            "never",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        !dir.path().join("never").exists(),
        "nothing may be written on bad input"
    );
}

#[test]
fn materials_lists_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(&["materials", "--json"], dir.path());
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let m = v["materials"].as_array().unwrap();
    assert_eq!(m.len(), mc::builtin::names().len());
    assert!(m.len() >= 50, "{} built-in media", m.len());
    for x in m {
        let source = x["source"].as_str().unwrap();
        assert!(
            source.contains("Jensen et al. 2001") || source.contains("Narasimhan et al. 2006"),
            "{}: {source:?} names no paper",
            x["material"]
        );
    }
    let skin = m.iter().find(|x| x["material"] == "skin1").unwrap();
    // Albedo and MFP from Table 6.2: σa = 0.32, σs = 7.4 cm⁻¹ (R).
    assert!((skin["channels"]["R"]["albedo"].as_f64().unwrap() - 7.4 / 7.72).abs() < 1e-12);
    assert!((skin["channels"]["R"]["mfp_cm"].as_f64().unwrap() - 1.0 / 7.72).abs() < 1e-12);
    // The mm-unit liquids are converted: coffee σa R = 0.1669 mm⁻¹ = 1.669 cm⁻¹.
    let coffee = m.iter().find(|x| x["material"] == "coffee").unwrap();
    assert!((coffee["channels"]["R"]["sigma_a_per_cm"].as_f64().unwrap() - 1.669).abs() < 1e-12);
    // The table names each material's paper, table and units too.
    let o = sss(&["materials"], dir.path());
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    let line = |slug: &str| {
        let l = text
            .lines()
            .rev()
            .find(|l| l.starts_with(&format!("{slug} ")));
        l.unwrap_or_else(|| panic!("no source line for {slug}"))
            .to_string()
    };
    assert!(line("espresso").contains("Narasimhan et al. 2006, Table 1"));
    assert!(line("spectralon").contains("Jensen et al. 2001, Figure 5"));
}

/// `--device gpu` traces the same transport as the CPU with other random numbers: each channel's
/// total diffuse reflectance within 3 combined standard errors of the CPU's, and the same files.
#[test]
fn the_gpu_tracer_gives_the_cpus_totals() {
    let dir = tempfile::tempdir().unwrap();
    let run = |device: &str| {
        let args = ["simulate", "skin1", "--photons", "2e5", "--device", device];
        sss(
            &[&args[..], &["--out", device, "--json"]].concat(),
            dir.path(),
        )
    };
    let gpu = run("gpu");
    if !gpu.status.success() && stderr(&gpu).contains("no GPU adapter") {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI=true and no adapter: {}",
            stderr(&gpu)
        );
        return common::report_skip("no GPU adapter (lavapipe)");
    }
    assert!(gpu.status.success(), "{}", stderr(&gpu));
    let cpu = run("cpu");
    assert!(cpu.status.success(), "{}", stderr(&cpu));
    let json = |o: &Output| -> serde_json::Value { serde_json::from_slice(&o.stdout).unwrap() };
    let (g, c) = (json(&gpu), json(&cpu));
    for ch in ["R", "G", "B"] {
        let at = |v: &serde_json::Value, k: &str| v["channels"][ch][k].as_f64().unwrap();
        let (a, b) = (at(&g, "rd"), at(&c, "rd"));
        let se = at(&g, "rd_se").hypot(at(&c, "rd_se"));
        assert!((a - b).abs() <= 3.0 * se, "{ch}: GPU {a} CPU {b} ± {se}");
    }
    assert_eq!(
        files_in(&dir.path().join("gpu")).len(),
        files_in(&dir.path().join("cpu")).len()
    );
}
