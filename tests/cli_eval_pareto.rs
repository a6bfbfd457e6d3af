//! End-to-end test of `sss eval`'s Pareto report (issue 17 item 7): kernel cost against image
//! error, the front and the recommendation per pass budget, on a small simulated profile.

mod common;
use common::{small_profile, sss};
use serde_json::Value;

/// (taps per pixel, mean image RMS) of a serialized point.
fn cost_error(p: &Value) -> (u64, f64) {
    (
        p["cost"]["taps"].as_u64().unwrap(),
        p["mean_image_rms"].as_f64().unwrap(),
    )
}

#[test]
fn eval_recommends_within_the_budget_from_a_non_dominated_front() {
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

    let bytes = std::fs::read(dir.path().join("plots/skin1.pareto.png")).unwrap();
    assert_eq!(&bytes[..4], b"\x89PNG");
}
