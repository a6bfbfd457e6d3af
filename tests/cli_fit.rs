//! End-to-end tests of `sss fit` and `sss eval` (with its Pareto report) on a small simulated
//! profile.

mod common;
use common::{small_profile, sss};
use serde_json::Value;

#[test]
fn fit_writes_shader_kernels_for_every_model() {
    let dir = tempfile::tempdir().unwrap();
    small_profile(dir.path());
    for (model, extra, passes) in [
        ("preint", vec![], 1),
        ("svd", vec!["--rank", "3"], 3),
        ("guided", vec!["--k", "1", "--b", "50"], 1),
        ("manual", vec![], 1),
        ("deon", vec!["--rank", "2"], 2),
        ("skin", vec![], 1),
        ("burley", vec![], 1),
    ] {
        let out = format!("{model}.toml");
        let mut args = vec![
            "fit",
            "profiles/skin1.profile.csv",
            "--model",
            model,
            "--taps",
            "17",
            "--out",
            &out,
        ];
        args.extend(extra);
        let o = sss(&args, dir.path());
        assert!(
            o.status.success(),
            "{model}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let text = std::fs::read_to_string(dir.path().join(&out)).unwrap();
        let k = fit::taps::ShaderKernel::from_toml(&text, &out).unwrap();
        assert_eq!(k.pass.len(), passes, "{model}");
        for p in &k.pass {
            assert_eq!(p.tap.len(), 17);
            assert!(
                p.tap
                    .iter()
                    .all(|t| t.offset.is_finite() && t.weight.iter().all(|w| w.is_finite()))
            );
            // Offsets are symmetric about 0 and increasing.
            assert!(
                p.tap.windows(2).all(|w| w[0].offset < w[1].offset),
                "{model}"
            );
            assert!(
                (p.tap[0].offset + p.tap[16].offset).abs() < 1e-12,
                "{model}"
            );
        }
        // Energy: the passes' weights reproduce the kernel's L1 norm of 1 (normalized ground truth)
        // for the energy-conserving models; weights are integrated over cells, so nothing is lost.
        if ["preint", "guided", "manual", "deon", "skin"].contains(&model) {
            for c in 0..3 {
                let l1: f64 = k
                    .pass
                    .iter()
                    .map(|p| p.sign[c] * p.tap.iter().map(|t| t.weight[c]).sum::<f64>().powi(2))
                    .sum();
                assert!((l1 - 1.0).abs() < 1e-6, "{model} channel {c}: Σ = {l1}");
            }
        }
    }
    // Bad options are refused with exit code 2 and nothing written.
    let o = sss(
        &[
            "fit",
            "profiles/skin1.profile.csv",
            "--model",
            "svd",
            "--rank",
            "0",
            "--out",
            "never.toml",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    std::fs::write(
        dir.path().join("bad.csv"),
        "r_cm,R,G,B,R_se,G_se,B_se\n0.1,1,1,1,0,0,0\n",
    )
    .unwrap();
    let o = sss(
        &["fit", "bad.csv", "--model", "preint", "--out", "never.toml"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("bins"));
    assert!(!dir.path().join("never.toml").exists());
}

#[test]
fn eval_reports_every_model_and_writes_plots() {
    let dir = tempfile::tempdir().unwrap();
    small_profile(dir.path());
    let o = sss(
        &[
            "eval",
            "skin1",
            "--profiles",
            "profiles",
            "--plots",
            "plots",
            "--json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    check_pareto(&v, dir.path());
    let m = &v["materials"][0];
    assert_eq!(m["name"], "skin1");
    let rows = m["models"].as_array().unwrap();
    // "model" is the model's name as `--model` takes it, "family" its stem.
    let count = |family: &str| rows.iter().filter(|r| r["family"] == family).count();
    assert_eq!(count("svd"), 18, "ranks 1–6 × 3 channels");
    assert_eq!(count("deon"), 18);
    assert_eq!(count("guided"), 9, "k = 0, 1, 2 × 3 channels");
    for model in ["preint", "manual"] {
        assert_eq!(count(model), 3, "{model}");
    }
    assert_eq!(count("skin"), 6, "SSSS defaults and fitted by eq. 4.13");
    assert_eq!(count("burley"), 6, "radial and projected");
    for name in [
        "svd3",
        "guided-k1",
        "manual",
        "deon6",
        "skin-fit",
        "burley-radial",
    ] {
        assert_eq!(
            rows.iter().filter(|r| r["model"] == name).count(),
            3,
            "{name}"
        );
    }
    for r in rows {
        for key in [
            "kernel_rms",
            "kernel_rms_normalized",
            "l1_error",
            "fit_seconds",
        ] {
            assert!(r[key].as_f64().is_some_and(f64::is_finite), "{key} in {r}");
        }
        for s in ["edge", "circle_squares", "dot", "shaded", "uniform"] {
            assert!(
                r["image_rms"][s].as_f64().is_some_and(f64::is_finite),
                "{s} in {r}"
            );
        }
    }
    // Pre-integration is exact on the edge, through the whole evaluation path.
    for r in rows.iter().filter(|r| r["model"] == "preint") {
        assert!(r["image_rms"]["edge"].as_f64().unwrap() < 1e-12, "{r}");
    }
    for f in [
        "skin1.profile.png",
        "skin1.slices_rank1.png",
        "skin1.singular_values.png",
        "skin1.conv_edge.png",
        "skin1.conv_circle_squares.png",
    ] {
        let bytes = std::fs::read(dir.path().join("plots").join(f)).unwrap();
        assert_eq!(&bytes[..4], b"\x89PNG", "{f}");
    }
}

/// (taps per pixel, mean image RMS) of a serialized point.
fn cost_error(p: &Value) -> (u64, f64) {
    (
        p["cost"]["taps"].as_u64().unwrap(),
        p["mean_image_rms"].as_f64().unwrap(),
    )
}

/// `sss eval`'s Pareto report (issue 17 item 7): every model's cost, a front of exactly the
/// non-dominated models, and per pass budget the best separable model within it.
fn check_pareto(v: &Value, dir: &std::path::Path) {
    let pareto = &v["materials"][0]["pareto"];
    assert_eq!(pareto["taps_per_pass"], 17);
    let points = pareto["points"].as_array().unwrap();
    assert_eq!(points.len(), 21, "every model of the evaluation");

    // Costs: 2 passes of 17 taps per rank-1 term; the radial Burley kernel is one 17×17 pass.
    let find = |name: &str| points.iter().find(|p| p["model"] == name).unwrap();
    assert_eq!(find("preint")["cost"]["passes"], 2);
    assert_eq!(find("preint")["cost"]["taps"], 34);
    assert_eq!(find("deon3")["cost"]["taps"], 102);
    assert_eq!(find("burley-radial")["cost"]["passes"], 1);
    assert_eq!(find("burley-radial")["cost"]["taps"], 289);
    assert_eq!(find("burley-radial")["cost"]["dense"], true);

    // Every front member is non-dominated among all points, and every point missing from the
    // front is dominated by one.
    let front = pareto["front"].as_array().unwrap();
    assert!(!front.is_empty());
    let dominates =
        |a: (u64, f64), b: (u64, f64)| a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1);
    for p in points {
        let on_front = front.iter().any(|f| f["model"] == p["model"]);
        let dominated = points
            .iter()
            .any(|q| dominates(cost_error(q), cost_error(p)));
        assert_eq!(on_front, !dominated, "{}", p["model"]);
    }

    // Each budget's pick fits in it, is separable, and nothing separable within it does better.
    let recommended = pareto["recommended"].as_array().unwrap();
    let budgets: Vec<u64> = recommended
        .iter()
        .map(|r| r["budget"].as_u64().unwrap())
        .collect();
    assert_eq!(budgets, [2, 4, 6, 8, 12]);
    for r in recommended {
        let budget = r["budget"].as_u64().unwrap();
        let best = &r["best"];
        assert!(best["cost"]["passes"].as_u64().unwrap() <= budget, "{r}");
        assert_eq!(best["cost"]["dense"], false, "{r}");
        let error = best["mean_image_rms"].as_f64().unwrap();
        for p in points.iter().filter(|p| {
            p["cost"]["dense"] == false && p["cost"]["passes"].as_u64().unwrap() <= budget
        }) {
            assert!(
                p["mean_image_rms"].as_f64().unwrap() >= error,
                "{p} beats {r}"
            );
        }
    }
    assert_eq!(pareto["dense"][0]["model"], "burley-radial");

    let bytes = std::fs::read(dir.join("plots/skin1.pareto.png")).unwrap();
    assert_eq!(&bytes[..4], b"\x89PNG");
}
