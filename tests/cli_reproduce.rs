//! `sss reproduce --quick`: every table has every row and column, values are finite, the plots
//! exist, and the qualitative claims that must hold do hold (Tables 6.3, 6.4 and 6.5, Fig. 5.15
//! and 5.17); the rendered comparison against Mitsuba shows its calibration.

use std::process::Command;

#[test]
fn quick_report_is_complete_and_the_claims_hold() {
    let dir = tempfile::tempdir().unwrap();
    // A comparison against Mitsuba as images.py writes it (two models).
    let images = serde_json::json!({
        "scene": "sphere", "width": 192, "height": 108, "spp": 384, "reference_noise_rel": 0.28,
        "silhouette_fraction": 0.042, "calibration_rmse_rel": 0.0092, "calibration_rmse_se": 0.0094,
        "calibration_energy_ratio": [1.0012, 0.9971, 1.0010], "calibration_pass": true,
        "negative_control": {"energy_ratio": [0.798, 0.800, 0.800], "rejected": true},
        "models": [
            {"model": "preint", "rmse_rel": 0.34, "rmse_noise_corrected": 0.198,
             "rmse_noise_corrected_se": 0.005, "rmse_spatial": 0.132, "ssim": 0.913,
             "energy_ratio": [0.901, 0.851, 0.834]},
            {"model": "preint-incidence", "rmse_rel": 0.30, "rmse_noise_corrected": 0.110,
             "rmse_noise_corrected_se": 0.003, "rmse_spatial": 0.098, "ssim": 0.929,
             "energy_ratio": [0.990, 0.997, 1.018]}
        ],
        "rankings": {"incidence-aware closer than preint": true}
    });
    std::fs::write(dir.path().join("images.json"), images.to_string()).unwrap();
    // run.py's summary: its `images` list, each entry with its scene and material.
    let mut marble = images.clone();
    marble["material"] = serde_json::json!("marble");
    let summary = serde_json::json!({"failed": [], "images": [images, marble]});
    std::fs::write(dir.path().join("summary.json"), summary.to_string()).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_sss"))
        .args([
            "reproduce",
            "--quick",
            "--out",
            "report",
            "--references",
            "images.json",
            "--references",
            "summary.json",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = dir.path().join("report");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap())
            .unwrap();
    let finite = |v: &serde_json::Value| v.as_f64().is_some_and(f64::is_finite);

    // Table 6.2: the 16 materials, three channels of albedo and MFP each.
    let t62 = r["table_6_2"].as_array().unwrap();
    assert_eq!(t62.len(), 16);
    for m in t62 {
        for k in ["albedo", "mfp_cm", "sigma_a", "sigma_s", "g"] {
            assert!(
                m[k].as_array().unwrap().iter().all(finite),
                "{k} of {}",
                m["material"]
            );
        }
    }
    // Table 6.3: five materials × four models × RGB, raw and normalized, beside the published.
    let t63 = r["table_6_3"].as_array().unwrap();
    let names: Vec<&str> = t63
        .iter()
        .map(|m| m["material"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["apple", "marble", "ketchup", "skin1", "wholemilk"]);
    for m in t63 {
        let models = m["models"].as_array().unwrap();
        assert_eq!(
            models
                .iter()
                .map(|x| x["model"].as_str().unwrap())
                .collect::<Vec<_>>(),
            ["svd1", "preint", "guided-k1", "manual"]
        );
        for x in models {
            for k in ["raw", "normalized", "published"] {
                let v = x[k].as_array().unwrap();
                assert_eq!(v.len(), 3);
                assert!(v.iter().all(finite), "{k}");
            }
        }
    }
    // Table 6.5: N = 1…6 × RGB for SVD and d'Eon.
    for k in ["svd", "deon"] {
        let rows = r["table_6_5"][k].as_array().unwrap();
        assert_eq!(rows.len(), 6);
        assert!(
            rows.iter().all(|row| row.as_array().unwrap().len() == 3
                && row.as_array().unwrap().iter().all(finite))
        );
    }
    // Table 5.1: the seven model families with a measured fit time.
    let t51 = r["table_5_1"].as_array().unwrap();
    assert_eq!(t51.len(), 7);
    assert!(t51.iter().all(|m| finite(&m["fit_seconds_per_channel"])));

    // The claims that follow from mathematics must hold: Table 6.3's ordering (Eckart–Young), the
    // thesis's ≈2× ratio, SVD beating d'Eon at equal N in kernel space (Eckart–Young), and
    // convergence with N. The image-space comparison is reported, not asserted: it depends on
    // the test images (the report explains where and why it differs from the thesis's).
    let claims = r["claims"].as_array().unwrap();
    let holds = |prefix: &str| {
        claims
            .iter()
            .find(|c| c["claim"].as_str().unwrap().starts_with(prefix))
            .unwrap()["holds"]
            .as_bool()
            .unwrap()
    };
    assert!(holds("Table 6.3: SVD rank-1"), "{claims:#?}");
    assert!(
        holds("Table 6.3: pre-integration's kernel RMS is roughly twice"),
        "{claims:#?}"
    );
    assert!(holds("Table 6.5: both converge"), "{claims:#?}");
    assert!(holds("Table 6.5 (kernel space)"), "{claims:#?}");
    assert!(claims.iter().any(|c| {
        c["claim"]
            .as_str()
            .unwrap()
            .starts_with("Table 6.5 (image space)")
    }));

    rendered_tables_are_complete_or_skipped_saying_why(&r, &report, dir.path());
    chapter_5_figures_are_complete_and_their_claims_hold(&r, &report);

    // The page and every figure it links.
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    for section in [
        "Table 6.2",
        "Table 6.3",
        "Table 6.5",
        "Table 5.1",
        "Fig. 5.1",
        "Fig. 6.2",
        "Fig. 6.3",
        "Fig. 6.1",
        "Fig. 5.14–5.15",
        "Fig. 5.17",
        "What agrees",
        "Rendered scenes against Mitsuba 3",
        "preint-incidence",
        "11.00 ± 0.30 %",
        "Calibration",
        "0.92 ± 0.94 %",
        "9.80 %",
    ] {
        assert!(html.contains(section), "missing {section}");
    }
    let rendered = r["rendered"].as_array().unwrap();
    assert_eq!(rendered.len(), 3);
    assert_eq!(rendered[2]["material"], "marble");
    assert_eq!(rendered[0]["models"].as_array().unwrap().len(), 2);
    for src in html
        .split("src=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
    {
        let bytes = std::fs::read(report.join(src)).unwrap_or_else(|_| panic!("missing {src}"));
        assert_eq!(&bytes[..4], b"\x89PNG", "{src}");
    }
}

/// A --references file that is not images.py's output is refused before anything is written.
#[test]
fn reproduce_refuses_a_bad_references_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.json"),
        r#"{"models": [{"model": "x"}]}"#,
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_sss"))
        .args([
            "reproduce",
            "--quick",
            "--out",
            "report",
            "--references",
            "bad.json",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--references"), "{e}");
    assert!(!dir.path().join("report").exists());
}

/// Tables 6.4 and 6.5 rendered on our scenes (`gpu::compare_models`): every scene and model with
/// finite per-channel errors normalized as the thesis does (highest per-channel entry = 1),
/// the thesis's values beside them, and their claims; each fitted kernel closer to the 2D ground
/// truth than no scattering, and more terms closer than one (nested fits). Without an adapter
/// (outside CI) they are skipped and the report says why; with the adapter hidden, a run from
/// the same profiles still succeeds and says so.
fn rendered_tables_are_complete_or_skipped_saying_why(
    r: &serde_json::Value,
    report: &std::path::Path,
    dir: &std::path::Path,
) {
    let t = &r["rendered_tables"];
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(html.contains("Table 6.4"), "missing Table 6.4");
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let sum = |v: &serde_json::Value| (0..3).map(|c| f(&v[c])).sum::<f64>();
    if t["status"] == "skipped" {
        assert_ne!(
            std::env::var("CI").as_deref(),
            Ok("true"),
            "CI=true and {t}"
        );
        assert!(
            t["reason"].as_str().unwrap().contains("no GPU adapter"),
            "{t}"
        );
    } else {
        assert_eq!(t["status"], "rendered", "{t}");
        let rows = t["table_6_4"].as_array().unwrap();
        let scenes: Vec<String> = rows
            .iter()
            .map(|r| {
                format!(
                    "{} {}",
                    r["scene"].as_str().unwrap(),
                    r["material"].as_str().unwrap()
                )
            })
            .collect();
        assert_eq!(
            scenes,
            [
                "sphere skin1",
                "sphere apple",
                "sphere ketchup",
                "sphere wholemilk",
                "sphere marble",
                "fin skin1"
            ]
        );
        let mut max = 0.0f64;
        for row in rows {
            for k in ["raw", "normalized", "published"] {
                let models = row[k].as_array().unwrap();
                assert_eq!(models.len(), 4, "{k}");
                for m in models {
                    assert_eq!(m.as_array().unwrap().len(), 3);
                    assert!(
                        m.as_array()
                            .unwrap()
                            .iter()
                            .all(|x| f(x).is_finite() && f(x) >= 0.0)
                    );
                }
            }
            for j in 0..4 {
                max = (0..3)
                    .map(|c| f(&row["normalized"][j][c]))
                    .fold(max, f64::max);
                assert!(
                    sum(&row["normalized"][j]) < sum(&row["lambert"]),
                    "{} model {j}: no closer than no scattering",
                    row["material"]
                );
            }
        }
        assert!((max - 1.0).abs() < 1e-12, "highest per-channel entry {max}");
        // The thesis's Head row (Table 6.4), beside our Skin1 sphere.
        assert_eq!(
            rows[0]["published"][0],
            serde_json::json!([1.0, 0.455, 0.198])
        );
        let models: Vec<&str> = t["models"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["model"].as_str().unwrap())
            .collect();
        assert_eq!(models, ["svd1-renorm", "preint", "guided-k1", "manual"]);
        // Table 6.5 rendered, N = 1…3 in --quick.
        let t65 = &t["table_6_5"];
        for k in ["svd", "deon"] {
            let v = t65[k].as_array().unwrap();
            assert_eq!(v.len(), 3, "{k}");
            assert!(sum(&v[2]) < sum(&v[0]), "{k}: N = 3 not closer than N = 1");
        }
        let claims = r["claims"].as_array().unwrap();
        for prefix in [
            "Table 6.4 (rendered): SVD rank-1",
            "Table 6.4 (rendered): pre-integration, guided",
            "Table 6.5 (rendered): at equal pass count",
            "Table 6.5 (rendered): SVD saves",
        ] {
            let c = claims
                .iter()
                .find(|c| c["claim"].as_str().unwrap().starts_with(prefix))
                .unwrap_or_else(|| panic!("no claim {prefix}"));
            assert!(c["holds"].is_boolean() && c["ours"].is_string() && c["published"].is_string());
        }
        assert!(html.contains("Table 6.5 rendered"));
    }
    // With the Vulkan drivers hidden (the only backend on Linux) the report is still written.
    if cfg!(target_os = "linux") {
        let o = Command::new(env!("CARGO_BIN_EXE_sss"))
            .args(["reproduce", "--quick", "--out", "hidden", "--profiles"])
            .arg(report.join("profiles"))
            .env("VK_ICD_FILENAMES", "/nonexistent.json")
            .env("VK_DRIVER_FILES", "/nonexistent.json")
            .current_dir(dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let h: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("hidden/report.json")).unwrap())
                .unwrap();
        assert_eq!(h["rendered_tables"]["status"], "skipped");
        assert!(
            h["rendered_tables"]["reason"]
                .as_str()
                .unwrap()
                .contains("no GPU adapter")
        );
        let page = std::fs::read_to_string(dir.join("hidden/index.html")).unwrap();
        assert!(page.contains("Skipped: no GPU adapter"));
        assert!(h["table_6_3"].as_array().is_some_and(|t| t.len() == 5));
    }
}

/// Fig. 5.15 and 5.17 on Skin1: both plots, every model and w with finite numbers, and the
/// thesis's claims that follow from its text: k = 1.55, b = 50 is closer to pre-integration in
/// image space than guided k = 1 and SVD rank-1; b = 50 takes away k's control; w moves the manual
/// kernel monotonically from far to near scattering. The kernel-space and Table A.1 rows are
/// reported, not asserted (the report says why they differ).
fn chapter_5_figures_are_complete_and_their_claims_hold(
    r: &serde_json::Value,
    report: &std::path::Path,
) {
    for png in ["fig5_15_guided_vs_preint.png", "fig5_17_manual_w_sweep.png"] {
        let bytes = std::fs::read(report.join(png)).unwrap_or_else(|_| panic!("missing {png}"));
        assert_eq!(&bytes[..4], b"\x89PNG", "{png}");
    }
    let finite3 = |v: &serde_json::Value| {
        v.as_array().is_some_and(|a| {
            a.len() == 3 && a.iter().all(|x| x.as_f64().is_some_and(f64::is_finite))
        })
    };
    let f = &r["fig_5_15"];
    assert_eq!(f["material"], "skin1");
    let models: Vec<&str> = f["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            assert!(
                finite3(&m["image_distance"]) && finite3(&m["kernel_distance"]),
                "{m}"
            );
            m["model"].as_str().unwrap()
        })
        .collect();
    for m in [
        "guided-k1.55-b50",
        "guided-k1",
        "svd1",
        "guided-k0-b50",
        "guided-k2-b50",
    ] {
        assert!(models.contains(&m), "fig_5_15 lacks {m}: {models:?}");
    }
    assert_eq!(f["k_spread"].as_array().unwrap().len(), 2);
    let s = &r["fig_5_17"];
    assert_eq!(s["table_a1_w"], 0.533);
    let w = s["w"].as_array().unwrap();
    assert!(w.len() >= 11 && w[0] == 0.0 && w[w.len() - 1] == 1.0);
    for k in ["image_rms", "edge_width_cm"] {
        let rows = s[k].as_array().unwrap();
        assert_eq!(rows.len(), w.len(), "{k}");
        assert!(rows.iter().all(finite3), "{k}");
    }
    assert!(finite3(&s["truth_edge_width_cm"]) && finite3(&s["best_w"]));

    let claims = r["claims"].as_array().unwrap();
    let row = |prefix: &str| {
        claims
            .iter()
            .find(|c| c["claim"].as_str().unwrap().starts_with(prefix))
            .unwrap_or_else(|| panic!("no claim {prefix}"))
    };
    for prefix in [
        "Fig. 5.15: guided k = 1.55, b = 50",
        "Fig. 5.15c–d",
        "Fig. 5.17: raising w",
    ] {
        assert_eq!(row(prefix)["holds"], true, "{:#}", row(prefix));
    }
    for prefix in ["Fig. 5.15 (kernel space)", "Table A.1 (§5.4"] {
        assert!(row(prefix)["holds"].is_boolean(), "{prefix}");
    }
}
