//! End-to-end tests of `sss export` on a kernel fitted to a small simulated profile.

mod common;
use common::{small_profile, sss};

#[test]
fn export_writes_valid_wgsl_and_json_and_refuses_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    small_profile(path);
    let o = sss(
        &[
            "fit",
            "profiles/skin1.profile.csv",
            "--model",
            "svd",
            "--rank",
            "2",
            "--out",
            "k.toml",
        ],
        path,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    // WGSL on standard output: parses and validates with naga.
    let o = sss(&["export", "k.toml", "--format", "wgsl"], path);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let wgsl = String::from_utf8(o.stdout).unwrap();
    let module = naga::front::wgsl::parse_str(&wgsl)
        .unwrap_or_else(|e| panic!("{}\n{wgsl}", e.emit_to_string(&wgsl)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{e:?}\n{wgsl}"));
    assert!(wgsl.contains("KERNEL_SIGN_1") && !wgsl.contains("KERNEL_SIGN_2"));

    // JSON to a file: two passes in mm, the centre tap first.
    let o = sss(
        &[
            "export", "k.toml", "--format", "json", "--unit", "mm", "--out", "k.json",
        ],
        path,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stdout.is_empty());
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path.join("k.json")).unwrap()).unwrap();
    assert_eq!(v["unit"], "mm");
    let passes = v["passes"].as_array().unwrap();
    assert_eq!(passes.len(), 2);
    for p in passes {
        let kernel = p["kernel"].as_array().unwrap();
        assert_eq!(kernel.len(), v["taps"].as_u64().unwrap() as usize);
        assert_eq!(kernel[0][3].as_f64(), Some(0.0), "centre tap first");
    }

    // A bad format is a usage error (exit 2) naming the value.
    let o = sss(
        &[
            "export",
            "k.toml",
            "--format",
            "spirv",
            "--out",
            "never.txt",
        ],
        path,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("spirv"));
    assert!(!path.join("never.txt").exists());

    // A kernel whose header disagrees with its taps is refused naming the field; nothing written.
    let text = std::fs::read_to_string(path.join("k.toml")).unwrap();
    let bad = text.replacen("taps = ", "taps = 1", 1);
    assert_ne!(bad, text);
    std::fs::write(path.join("bad.toml"), bad).unwrap();
    let o = sss(
        &[
            "export",
            "bad.toml",
            "--format",
            "hlsl",
            "--out",
            "never.hlsl",
        ],
        path,
    );
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("pass[0] taps"), "{e}");
    assert!(!path.join("never.hlsl").exists());
}
