//! End-to-end tests of `sss render` on whatever adapter wgpu finds (lavapipe in CI). Outside CI a
//! machine without any adapter skips them; under CI=true it fails.

mod common;
use common::sss;

fn no_adapter(o: &std::process::Output) -> bool {
    let e = String::from_utf8_lossy(&o.stderr);
    if e.contains("no GPU adapter") {
        assert_ne!(
            std::env::var("CI").as_deref(),
            Ok("true"),
            "CI=true and {e}"
        );
        eprintln!("skipping: {e}");
        return true;
    }
    false
}

#[test]
fn render_writes_png_and_pfm_and_compares_every_model() {
    let dir = tempfile::tempdir().unwrap();
    let o = sss(
        &[
            "render",
            "--width",
            "240",
            "--height",
            "135",
            "--photons",
            "30000",
            "--profiles",
            "p",
            "--out",
            "r",
            "--compare-models",
            "--json",
        ],
        dir.path(),
    );
    if no_adapter(&o) {
        return;
    }
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let png = std::fs::read(dir.path().join("r/render.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let pfm = std::fs::read(dir.path().join("r/render.pfm")).unwrap();
    assert!(pfm.starts_with(b"PF\n240 135\n-1.0\n"));
    assert_eq!(pfm.len(), "PF\n240 135\n-1.0\n".len() + 240 * 135 * 12);
    assert!(dir.path().join("r/compare_sheet.png").exists());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rms = |m: &str| {
        v["compare"]["models"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["model"] == m)
            .unwrap()["image_rms_rel"]
            .as_f64()
            .unwrap()
    };
    // Scattering with a fitted kernel is closer to the 2D ground truth than no scattering at
    // all, and rank 3 is closer than rank 1 (Eckart–Young, seen through the image).
    for m in ["preint", "svd3", "deon3", "guided"] {
        assert!(
            rms(m) < rms("lambert"),
            "{m}: {} vs lambert {}",
            rms(m),
            rms("lambert")
        );
    }
    assert!(
        rms("svd3") < rms("svd1"),
        "{} vs {}",
        rms("svd3"),
        rms("svd1")
    );
}

#[test]
fn render_refuses_bad_input_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    for (args, field) in [
        (vec!["render", "--width", "0"], "--width"),
        (vec!["render", "--light", "sun:1,2,3"], "dir"),
        (vec!["render", "--scene", "teapot"], "scene"),
        (vec!["render", "--jitter", "2"], "--jitter"),
        (
            vec!["render", "--method", "directional-dipole", "--samples", "0"],
            "samples",
        ),
        (
            vec![
                "render",
                "--method",
                "directional-dipole",
                "--incidence-aware",
                "on",
            ],
            "--incidence-aware",
        ),
    ] {
        let o = sss(&args, dir.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(field), "{args:?}: {e}");
    }
    assert!(!dir.path().join("out").exists(), "nothing written");
}

/// The linear RGB pixels of a PFM `sss render` wrote.
fn pfm_pixels(path: &std::path::Path) -> Vec<[f32; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes[..32.min(bytes.len())]).to_string();
    let header: usize = text.splitn(4, '\n').take(3).map(|l| l.len() + 1).sum();
    bytes[header..]
        .chunks(12)
        .map(|p| [0, 1, 2].map(|c| f32::from_le_bytes(p[4 * c..4 * c + 4].try_into().unwrap())))
        .collect()
}

/// The directional-dipole method through the CLI, lit exactly from −x: the faces of the fins the
/// camera sees (+x) get no direct light, so where the plain Lambertian image is black and the
/// dipole's is not, the light came through the fins. On a black floor without ambient or
/// specular light, that region must exist (the 3 mm and 1 mm fins glow). The summary names the
/// method, and rescaled to Monte Carlo every channel's factor lies in (0, 1): the published
/// model overestimates Skin1's total reflectance in every channel.
#[test]
fn render_with_the_directional_dipole_lights_thin_parts_from_behind() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "--scene",
        "fin",
        "--light",
        "dir:-1,0,0",
        "--floor-albedo",
        "0,0,0",
        "--ambient",
        "0",
        "--specular",
        "0",
        "--width",
        "160",
        "--height",
        "90",
    ];
    let mut args = vec!["render", "--method", "directional-dipole"];
    args.extend(common);
    args.extend([
        "--samples",
        "8",
        "--frames",
        "2",
        "--photons",
        "30000",
        "--profiles",
        "p",
        "--out",
        "dd",
        "--json",
    ]);
    let o = sss(&args, dir.path());
    if no_adapter(&o) {
        return;
    }
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["method"], "directional-dipole");
    for c in 0..3 {
        let k = v["dipole"]["scale"][c].as_f64().unwrap();
        assert!(k > 0.0 && k < 1.0, "channel {c}: {k}");
    }
    let mut args = vec!["render", "--no-sss"];
    args.extend(common);
    args.extend(["--out", "lambert"]);
    let o = sss(&args, dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let dd = pfm_pixels(&dir.path().join("dd/render.pfm"));
    let lambert = pfm_pixels(&dir.path().join("lambert/render.pfm"));
    assert_eq!(dd.len(), 160 * 90);
    assert!(dd.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
    let through = dd
        .iter()
        .zip(&lambert)
        .filter(|(d, l)| l.iter().all(|&x| x == 0.0) && d[0] > 1e-3)
        .count();
    assert!(through >= 50, "{through} pixels lit through the fins");
}
