//! End-to-end tests of `sss kernel` (material → best shader snippet for a budget) and
//! `sss engine-params` (material → engine fields), including `--from-artist`.

mod common;
use common::{small_profile, sss};

fn json(o: &std::process::Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("stdout is JSON")
}

#[test]
fn kernel_picks_the_lowest_image_error_within_the_budget_and_writes_valid_wgsl() {
    let dir = tempfile::tempdir().unwrap();
    small_profile(dir.path());
    let o = sss(
        &[
            "kernel",
            "skin1",
            "--format",
            "wgsl",
            "--budget",
            "4x17",
            "--profiles",
            "profiles",
            "--out",
            "k.wgsl",
            "--json",
        ],
        dir.path(),
    );
    let j = json(&o);
    let rows = j["candidates"].as_array().unwrap();
    let err = |r: &serde_json::Value| r["mean_image_rms"].as_f64().unwrap();
    assert_eq!(j["chosen"], rows[0]["model"]);
    assert!(rows.iter().all(|r| err(r) >= err(&rows[0])));
    assert!(rows.iter().all(|r| r["passes"].as_u64().unwrap() <= 4));
    // Rank-2 candidates are there (SVD and d'Eon with two terms).
    assert!(rows.iter().any(|r| r["model"] == "svd2-renorm"));
    assert!(rows.iter().any(|r| r["model"] == "deon2"));
    let src = std::fs::read_to_string(dir.path().join("k.wgsl")).unwrap();
    let module = naga::front::wgsl::parse_str(&src).expect("exported WGSL parses");
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .expect("exported WGSL validates");
    // --json needs --out (stdout is taken); a bad budget is refused; nothing written.
    for bad in [
        vec![
            "kernel",
            "skin1",
            "--format",
            "glsl",
            "--profiles",
            "profiles",
            "--json",
        ],
        vec![
            "kernel",
            "skin1",
            "--format",
            "glsl",
            "--profiles",
            "profiles",
            "--budget",
            "3x17",
            "--out",
            "never.glsl",
        ],
    ] {
        let o = sss(&bad, dir.path());
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
    }
    assert!(!dir.path().join("never.glsl").exists());
}

#[test]
fn engine_params_in_each_engine_and_materialx() {
    let dir = tempfile::tempdir().unwrap();
    small_profile(dir.path());
    // The albedo the engines get is the MC profile's total diffuse reflectance.
    let csv = std::fs::read_to_string(dir.path().join("profiles/skin1.profile.csv")).unwrap();
    let p = fit::Profile::from_csv(&csv, "skin1").unwrap();
    for engine in ["unreal", "unity", "blender"] {
        let o = sss(
            &[
                "engine-params",
                "skin1",
                "--engine",
                engine,
                "--json",
                "--profiles",
                "profiles",
            ],
            dir.path(),
        );
        let j = json(&o);
        let fit = &j["burley_fit"];
        for c in 0..3 {
            let a = fit["albedo"][c].as_f64().unwrap();
            assert!((a - p.total(c)).abs() < 1e-12, "{engine}");
            assert!(fit["d_cm"][c].as_f64().unwrap() > 0.0);
            // The Burley profile is not exact: its error is reported, finite and non-zero.
            let e = fit["image_rms"][c].as_f64().unwrap();
            assert!(e.is_finite() && e > 0.0);
        }
        assert!(!j["params"]["fields"].as_array().unwrap().is_empty());
        assert!(j["best_separable"]["image_rms"][0].as_f64().unwrap() > 0.0);
        // Blender also gets the Random Walk fields (Cycles traces the medium itself), saying
        // which Blender versions' remap they invert; the others do not.
        let walk = &j["random_walk"];
        if engine == "blender" {
            assert_eq!(walk["fields"][0]["name"], "Base Color", "{walk}");
            assert!(
                walk["notes"][0]
                    .as_str()
                    .unwrap()
                    .contains("Blender 4.0–5.0")
            );
        } else {
            assert!(walk.is_null(), "{engine}: {walk}");
        }
    }
    let o = sss(
        &[
            "engine-params",
            "skin1",
            "--engine",
            "openpbr",
            "--profiles",
            "profiles",
            "--mtlx",
            "skin1.mtlx",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let x = std::fs::read_to_string(dir.path().join("skin1.mtlx")).unwrap();
    assert!(x.contains("<materialx version=\"1.39\"") && x.contains("open_pbr_surface"));
    // --mtlx belongs to openpbr; unknown engines are refused; nothing written.
    for bad in [
        vec![
            "engine-params",
            "skin1",
            "--engine",
            "unreal",
            "--profiles",
            "profiles",
            "--mtlx",
            "never.mtlx",
        ],
        vec![
            "engine-params",
            "skin1",
            "--engine",
            "godot",
            "--profiles",
            "profiles",
        ],
    ] {
        let o = sss(&bad, dir.path());
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
    }
    assert!(!dir.path().join("never.mtlx").exists());
}

/// An artist's colour and radius go through the Monte Carlo pipeline, and OpenPBR's fields (the
/// same convention) give them back.
#[test]
fn from_artist_round_trips_through_openpbr() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(
        &[
            "engine-params",
            "--from-artist",
            "color=0.6,0.4,0.2",
            "radius=0.5,0.4,0.3:mm",
            "--engine",
            "openpbr",
            "--json",
            "--photons",
            "2e4",
            "--profiles",
            "profiles",
        ],
        dir.path(),
    );
    let j = json(&o);
    let fields = j["params"]["fields"].as_array().unwrap();
    let get = |n: &str| &fields.iter().find(|f| f["name"] == n).unwrap()["value"];
    let radius = get("subsurface_radius").as_f64().unwrap();
    for (c, (color, r_mm)) in [(0.6, 0.5), (0.4, 0.4), (0.2, 0.3)].iter().enumerate() {
        let got = get("subsurface_color")[c].as_f64().unwrap();
        assert!((got - color).abs() < 1e-9, "color[{c}] {got}");
        let r = radius * get("subsurface_radius_scale")[c].as_f64().unwrap();
        assert!((r - 0.1 * r_mm).abs() < 1e-9, "radius[{c}] {r}");
    }
    // A colour outside [0, 1] is refused, naming the field.
    let o = sss(
        &[
            "engine-params",
            "--from-artist",
            "color=1.2,0.4,0.2",
            "radius=1",
            "--engine",
            "unity",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("color[R]"));
}

/// Wine's green and blue channels do not scatter (σs = 0): the built-in material exports like any
/// other. The dark channels' kernel is the identity with weight 0, engines get their lengths from
/// the red channel, and no number is NaN.
#[test]
fn a_material_with_channels_that_do_not_scatter_exports() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let j = json(&sss(
        &[
            "kernel",
            "wine",
            "--format",
            "wgsl",
            "--photons",
            "2e4",
            "--out",
            "k.wgsl",
            "--json",
        ],
        d,
    ));
    assert!(j["chosen"].is_string(), "{j}");
    let j = json(&sss(
        &[
            "engine-params",
            "wine",
            "--engine",
            "unreal",
            "--photons",
            "2e4",
            "--json",
        ],
        d,
    ));
    // (serde_json writes NaN as null.)
    for part in ["burley_fit", "best_separable", "params"] {
        let text = j[part].to_string();
        assert!(!text.contains("null"), "{part}: {text}");
    }
    let notes = j["params"]["notes"].to_string();
    assert!(notes.contains("G: returns no diffuse light"), "{j}");
    let o = sss(&["eval", "wine", "--photons", "2e4", "--json"], d);
    let models = json(&o)["materials"][0]["models"].clone();
    let models = models.as_array().unwrap();
    assert!(models.len() >= 60, "{} rows", models.len());
    for row in models {
        for (key, v) in row.as_object().unwrap() {
            // Only the optional fields (a model's k, rank or variant) may be absent.
            let optional = ["k", "rank", "variant"].contains(&key.as_str());
            assert!(
                optional || !v.is_null(),
                "eval: {key} is null (NaN) in {row}"
            );
        }
    }
}
