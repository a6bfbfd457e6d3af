//! The profile cache is honest: a cached `NAME.profile.csv` is reused only when its provenance
//! (`NAME.profile.json`) matches what was asked, reuse is announced, a mismatch is simulated again,
//! and nothing is written outside `--out`/`--profiles`. Also the `--out` convention: a folder for
//! commands that write several files; a file, or a folder to put the default name in, for
//! commands that write one.

mod common;
use common::{small_config, small_profile, sss};

use std::path::Path;
use std::process::Output;

fn stderr(o: &Output) -> String {
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{e}");
    e
}

fn provenance(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    v.sort();
    v
}

#[test]
fn simulate_records_the_provenance_of_each_profile() {
    let dir = tempfile::tempdir().unwrap();
    small_profile(dir.path());
    let p = provenance(&dir.path().join("profiles/skin1.profile.json"));
    assert_eq!(p["format"], "sss-profile-1");
    assert_eq!(p["material"], "skin1");
    assert_eq!(p["photons"], 30000);
    assert_eq!(p["seed"], 2);
    assert!(p["target_error"].is_null());
    let ch = p["channels"].as_array().unwrap();
    assert_eq!(ch.len(), 3);
    // Skin1's R channel (materials/skin1.toml), and the small grid's dr = min MFP / 6.
    assert_eq!(ch[0]["layer"]["mu_a"], 0.32);
    assert_eq!(ch[0]["layer"]["mu_s"], 7.4);
    let dr = ch[0]["grid"]["dr"].as_f64().unwrap();
    assert!((dr - 1.0 / (4.8 + 10.1) / 6.0).abs() < 1e-12, "{dr}");
}

#[test]
fn reuse_is_announced_and_a_mismatch_is_simulated_again() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_profile(d);
    let compare = |extra: &[&str]| {
        let mut args = vec![
            "compare-profiles",
            "skin1",
            "--profiles",
            "profiles",
            "--json",
        ];
        args.extend(extra);
        sss(&args, d)
    };
    // Nothing asked: the cached profile is reused, with what it is.
    let e = stderr(&compare(&[]));
    assert!(
        e.contains("reusing profiles/skin1.profile.csv (3e4 photons, seed 2, dr "),
        "{e}"
    );
    // The same photons, seed and settings asked explicitly: reused.
    let same = ["--photons", "3e4", "--seed", "2", "--config", "small.toml"];
    let e = stderr(&compare(&same));
    assert!(e.contains("reusing profiles/skin1.profile.csv"), "{e}");
    // Other photons: simulated again, said so, and the cache now holds the new run.
    let e = stderr(&compare(&["--photons", "2000", "--config", "small.toml"]));
    assert!(
        e.contains("profiles/skin1.profile.csv does not match what was asked (3e4 photons ≠ 2e3)")
            && e.contains("simulating again"),
        "{e}"
    );
    assert!(e.contains("simulated skin1 (2e3 photons, seed 2"), "{e}");
    let p = provenance(&d.join("profiles/skin1.profile.json"));
    assert_eq!(p["photons"], 2000);
    let e = stderr(&compare(&[
        "--photons",
        "2000",
        "--seed",
        "2",
        "--config",
        "small.toml",
    ]));
    assert!(
        e.contains("reusing profiles/skin1.profile.csv (2e3 photons"),
        "{e}"
    );
    // Another seed: simulated again.
    let e = stderr(&compare(&[
        "--photons",
        "2000",
        "--seed",
        "3",
        "--config",
        "small.toml",
    ]));
    assert!(e.contains("seed 2 ≠ 3"), "{e}");
}

/// A material file with the same short name but other coefficients never reuses the built-in
/// material's profile, even when nothing else was asked.
#[test]
fn another_material_of_the_same_name_is_simulated_again() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_profile(d);
    std::fs::create_dir(d.join("mine")).unwrap();
    std::fs::write(
        d.join("mine/skin1.toml"),
        "name = \"my skin\"\nunit = \"cm\"\nsigma_a = [0.5, 1.7, 3.8]\nsigma_s = [7.4, 8.9, 10.1]\ng = 0.0\neta = 1.3\n",
    )
    .unwrap();
    let e = stderr(&sss(
        &[
            "compare-profiles",
            "mine/skin1.toml",
            "--profiles",
            "profiles",
            "--photons",
            "3e4",
            "--seed",
            "2",
            "--config",
            "small.toml",
            "--json",
        ],
        d,
    ));
    assert!(
        e.contains("does not match") && e.contains("channel R (σa"),
        "{e}"
    );
    let p = provenance(&d.join("profiles/skin1.profile.json"));
    assert_eq!(p["channels"][0]["layer"]["mu_a"], 0.5);
}

#[test]
fn a_profile_without_provenance_is_reused_only_when_nothing_is_asked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_profile(d);
    std::fs::remove_file(d.join("profiles/skin1.profile.json")).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "compare-profiles",
            "skin1",
            "--profiles",
            "profiles",
            "--json",
        ];
        args.extend(extra);
        stderr(&sss(&args, d))
    };
    let e = run(&[]);
    assert!(
        e.contains("reusing profiles/skin1.profile.csv without provenance"),
        "{e}"
    );
    assert!(!d.join("profiles/skin1.profile.json").exists());
    let e = run(&["--photons", "2000", "--config", "small.toml"]);
    assert!(
        e.contains("has no provenance") && e.contains("simulating again"),
        "{e}"
    );
    assert_eq!(
        provenance(&d.join("profiles/skin1.profile.json"))["photons"],
        2000
    );
}

/// `reproduce --profiles DIR` reads files the user named: a mismatch is an error, not a new run.
#[test]
fn reproduce_refuses_named_profiles_that_do_not_match() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("lib")).unwrap();
    std::fs::write(
        d.join("lib/apple.profile.csv"),
        "r_cm,R,G,B,R_se,G_se,B_se\n",
    )
    .unwrap();
    let o = sss(
        &[
            "reproduce",
            "--quick",
            "--profiles",
            "lib",
            "--photons",
            "1e4",
            "--out",
            "r",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("lib/apple.profile.csv has no provenance") && e.contains("--photons 10000"),
        "{e}"
    );
    assert!(!d.join("r").exists());
}

#[test]
fn nothing_is_written_outside_out_and_profiles() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_config(d);
    let e = stderr(&sss(
        &[
            "compare-profiles",
            "skin1",
            "--photons",
            "2000",
            "--config",
            "small.toml",
            "--profiles",
            "p",
            "--plots",
            "x",
            "--json",
        ],
        d,
    ));
    assert!(e.contains("simulated skin1"), "{e}");
    assert_eq!(names(d), ["p", "small.toml", "x"]);
    assert_eq!(
        names(&d.join("p")),
        ["skin1.profile.csv", "skin1.profile.json"]
    );
    assert_eq!(names(&d.join("x")), ["skin1.compare_profiles.png"]);
    // render without --profiles keeps the profile it simulates, and the shading tables built
    // from it, in its --out folder, not in out/.
    let o = sss(
        &[
            "render",
            "--width",
            "32",
            "--height",
            "18",
            "--photons",
            "2000",
            "--config",
            "small.toml",
            "--out",
            "r",
        ],
        d,
    );
    if String::from_utf8_lossy(&o.stderr).contains("no GPU adapter") {
        assert_ne!(std::env::var("CI").as_deref(), Ok("true"));
        return;
    }
    stderr(&o);
    assert_eq!(names(d), ["p", "r", "small.toml", "x"]);
    assert_eq!(
        names(&d.join("r")),
        [
            "render.json",
            "render.pfm",
            "render.png",
            "skin1.profile.csv",
            "skin1.profile.json",
            "skin1.tables.json"
        ]
    );
}

#[test]
fn single_file_commands_take_a_file_or_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("dir")).unwrap();
    // The issue's case: `profile --out DIR` writes the default name into DIR.
    let o = sss(
        &["profile", "marble", "--model", "dipole", "--out", "dir"],
        d,
    );
    stderr(&o);
    assert!(d.join("dir/marble.dipole.profile.csv").exists());
    // A path ending in a separator is a folder, created if missing.
    let o = sss(&["profile", "marble", "--model", "pbd", "--out", "new/"], d);
    stderr(&o);
    assert!(d.join("new/marble.pbd.profile.csv").exists());
    // Otherwise it is the file.
    let o = sss(
        &["profile", "marble", "--model", "pbd", "--out", "m.csv"],
        d,
    );
    stderr(&o);
    assert!(d.join("m.csv").is_file());
    // fit and export follow the same rule.
    let o = sss(
        &[
            "fit",
            "dir/marble.dipole.profile.csv",
            "--model",
            "preint",
            "--out",
            "dir",
        ],
        d,
    );
    stderr(&o);
    let k = d.join("dir/marble.kernel.toml");
    assert!(k.exists());
    let o = sss(
        &[
            "export",
            "dir/marble.kernel.toml",
            "--format",
            "glsl",
            "--out",
            "dir",
        ],
        d,
    );
    stderr(&o);
    assert!(d.join("dir/marble.kernel.glsl").exists());
}
