//! Hostile values for the numbers and files a user hands `sss`, end to end through the binary:
//! every refusal exits with code 2, names the flag (or the field of the file) on stderr and never
//! panics. No GPU is needed: `render` parses its flags and loads its scene before it asks for an
//! adapter.

mod common;
use common::sss;

use std::path::Path;
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a clean refusal: exit 2, every `needle` on stderr, no panic message.
fn assert_refused(o: &Output, what: &str, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{what}: exit {:?}: {err}",
        o.status
    );
    for n in needles {
        assert!(err.contains(n), "{what}: {err:?} should mention {n:?}");
    }
    for p in ["panicked", "RUST_BACKTRACE"] {
        assert!(!err.contains(p), "{what}: {err}");
    }
}

/// Runs `sss SUBCOMMAND FLAG=VALUE` (the `=` form, so that values such as `-1` stay values).
fn flag(dir: &Path, subcommand: &[&str], flag: &str, value: &str) -> Output {
    let arg = format!("{flag}={value}");
    let mut args = subcommand.to_vec();
    args.extend([arg.as_str(), "--out", "never"]);
    sss(&args, dir)
}

const VEC3: &[&str] = &[
    "", "nan,0,0", "0,inf,0", "0,0,-inf", "1e39,0,0", "1,2", "1,2,3,4", "1;2;3", ",,", "0x1,0,0",
    "🦀,0,0", "1,2,3 4",
];

#[test]
fn render_vectors_refuse_hostile_values() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["--camera", "--target", "--object-albedo", "--floor-albedo"] {
        for v in VEC3 {
            let o = flag(dir.path(), &["render"], f, v);
            assert_refused(&o, &format!("{f}={v}"), &[f]);
        }
    }
    // Valid numbers, but a camera looking at itself.
    let o = sss(
        &[
            "render", "--camera", "0,5,0", "--target", "0,5,0", "--out", "never",
        ],
        dir.path(),
    );
    assert_refused(&o, "coincident camera", &["--camera"]);
}

#[test]
fn render_lights_refuse_hostile_values() {
    let dir = tempfile::tempdir().unwrap();
    for v in [
        "",
        "dir",
        "dir:",
        "dir:0,0,0",
        "dir:1,1,1:-1",
        "dir:1,1,1:nan",
        "dir:1,1,1:inf",
        "dir:1,1,1:1e39",
        "dir:1,1,1:1:1",
        "point:nan,0,0",
        "point:1,2,3:-0.5",
        "point:1,2",
        "spot:1,2,3",
        "🦀:1,2,3",
        "DIR:1,1,1",
        "area:1,2,3",
        "area:1,2,3:0,0,0",
        "area:1,2,3:1,2,3:4",
        "area:1,2,3:0,0,0:0",
        "area:1,2,3:0,0,0:-2",
        "area:1,2,3:0,0,0:1e39",
        "area:1,2,3:0,0,0:2:nan",
        "area:1,2,3:0,0,0:2:-1",
        "area:1,2,3:0,0,0:2:1:1",
        "area:1,2,nan:0,0,0:2",
    ] {
        let o = flag(dir.path(), &["render"], "--light", v);
        assert_refused(&o, &format!("--light={v}"), &["--light"]);
    }
    // Valid lights, more than the renderer holds: two area lights of 8×8 cells (128 point
    // lights), or 65 directional lights.
    let mut args = vec!["render"];
    args.extend(["--light", "area:0,20,0:0,0,0:4"].repeat(2));
    args.extend(["--out", "never"]);
    let o = sss(&args, dir.path());
    assert_refused(&o, "two area lights", &["--light"]);
    let mut args = vec!["render"];
    args.extend(["--light", "dir:0,1,0"].repeat(65));
    args.extend(["--out", "never"]);
    let o = sss(&args, dir.path());
    assert_refused(&o, "65 lights", &["--light"]);
    // The directional dipole draws an area light as points in the slots other lights leave:
    // with four point or directional lights there is none.
    let mut args = vec![
        "render",
        "--method",
        "directional-dipole",
        "--light",
        "area:0,20,0:0,0,0:4",
    ];
    args.extend(["--light", "dir:0,1,0"].repeat(4));
    args.extend(["--out", "never"]);
    let o = sss(&args, dir.path());
    assert_refused(
        &o,
        "dipole with an area light and four others",
        &["--light"],
    );
    // ... and at most four lights.
    let mut args = vec!["render", "--method", "directional-dipole"];
    args.extend(["--light", "dir:0,1,0"].repeat(5));
    args.extend(["--out", "never"]);
    let o = sss(&args, dir.path());
    assert_refused(&o, "dipole with five lights", &["--light"]);
}

#[test]
fn render_boxes_refuse_hostile_values() {
    let dir = tempfile::tempdir().unwrap();
    for v in [
        "",
        "0,0,0",
        "0,0,0:",
        ":1,1,1",
        "1,1,1:0,0,0",
        "0,0,0:0,0,0",
        "0,0,0:1,0,1",
        "nan,0,0:1,1,1",
        "0,0,0:1,1,inf",
        "-inf,0,0:1,1,1",
        "0,0,0:1,1,1:2,2,2",
        "a:b",
    ] {
        let o = flag(dir.path(), &["render"], "--box", v);
        assert_refused(&o, &format!("--box={v}"), &["--box"]);
    }
}

#[test]
fn counts_refuse_hostile_values() {
    let dir = tempfile::tempdir().unwrap();
    for v in [
        "", "0", "-1", "0.5", "nan", "inf", "-inf", "1e400", "1e20", "1e", "1_000", "0x10", "🦀",
        " ",
    ] {
        let o = flag(dir.path(), &["simulate", "skin1"], "--photons", v);
        assert_refused(&o, &format!("--photons={v}"), &["--photons"]);
        let o = flag(dir.path(), &["render"], "--incidence-photons", v);
        assert_refused(
            &o,
            &format!("--incidence-photons={v}"),
            &["--incidence-photons"],
        );
    }
    // A negative count as its own argument reaches the count's parser, which names the flag
    // (clap alone would call "-5" an unexpected argument).
    for sub in [
        &["simulate", "skin1"][..],
        &["render"],
        &["table", "--g", "0", "--eta", "1.3"],
    ] {
        let o = sss(
            &[sub, &["--photons", "-5", "--out", "never"]].concat(),
            dir.path(),
        );
        assert_refused(&o, "--photons -5", &["--photons", "positive"]);
    }
    assert!(!dir.path().join("never").exists(), "a refusal wrote output");
}

/// Hostile files reach the library parsers through the binary: the error names the field.
#[test]
fn hostile_files_are_refused_with_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let material = "name = \"x\"\nunit = \"cm\"\nsigma_a = [1, 1, 1]\nsigma_s = [10, 10, 10]\ng = 0\neta = 1.3\n";
    for (name, text, field) in [
        (
            "nan",
            material.replace("sigma_a = [1,", "sigma_a = [nan,"),
            "sigma_a[R]",
        ),
        (
            "huge",
            material.replace("g = 0", "g = 1e308"),
            "g[R] = 1e308",
        ),
        ("noname", material.replace("\"x\"", "\"\""), "name"),
        ("unicode", material.replace("\"cm\"", "\"🦀\""), "unit"),
    ] {
        let file = format!("{name}.toml");
        std::fs::write(d.join(&file), text).unwrap();
        let o = sss(
            &["simulate", &file, "--photons", "100", "--out", "never"],
            d,
        );
        assert_refused(&o, name, &[field]);
    }

    std::fs::write(
        d.join("bad_config.toml"),
        "photons = 1000\nseed = 1\nthickness_cm = 1e8\nn_above = 0.0\nn_below = 1.0\n[grid]\ndr_per_min_mfp = 6.0\nr_max_mfp = 10.0\nz_max_mfp = 10.0\nnz = 10\nna = 5\n",
    )
    .unwrap();
    let o = sss(
        &[
            "simulate",
            "skin1",
            "--config",
            "bad_config.toml",
            "--out",
            "never",
        ],
        d,
    );
    assert_refused(&o, "config", &["n_above"]);

    std::fs::write(
        d.join("huge.mci"),
        "1.0\n1\nx.mco A\n100\n0.01 0.01\n10 10 10\n1000000000000000\n1.0\n1.3 1 10 0.9 1\n1.0\n",
    )
    .unwrap();
    let o = sss(&["simulate", "--mci", "huge.mci", "--out", "never"], d);
    assert_refused(&o, "mci", &["huge.mci", "layer 2 of 1000000000000000"]);

    std::fs::write(
        d.join("k.toml"),
        "model = \"preint\"\nmaterial = \"x\"\nunit = \"cm\"\ntaps = 0\nrange = 1.0\njitter = 0.0\n\n[[pass]]\nsign = [1.0, 1.0, 1.0]\ntap = []\n",
    )
    .unwrap();
    let o = sss(
        &["export", "k.toml", "--format", "wgsl", "--out", "k.wgsl"],
        d,
    );
    assert_refused(&o, "kernel", &["taps"]);
    assert!(!d.join("k.wgsl").exists());

    std::fs::write(
        d.join("bad.obj"),
        "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 nan\nf 1//1 2//1 3//1\n",
    )
    .unwrap();
    let o = sss(&["render", "--scene", "bad.obj", "--out", "never"], d);
    assert_refused(&o, "obj", &["bad.obj", "normal"]);
    assert!(
        !d.join("never").exists() || std::fs::read_dir(d.join("never")).unwrap().next().is_none()
    );
}

/// A path that never ends (`/dev/zero`) is refused through the input cap, not read forever: as a
/// material, an MCML input, a config, a profile, a kernel and a scene mesh.
#[cfg(unix)]
#[test]
fn endless_inputs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let z = "/dev/zero";
    // A mesh is named by its .obj suffix: a link so named that leads to the endless device.
    std::os::unix::fs::symlink(z, d.join("zero.obj")).unwrap();
    for (what, args, needle) in [
        ("material", vec!["simulate", z, "--out", "never"], "cap"),
        ("mci", vec!["simulate", "--mci", z, "--out", "never"], "cap"),
        (
            "config",
            vec!["simulate", "skin1", "--config", z, "--out", "never"],
            "cap",
        ),
        ("profile", vec!["fit", z, "--out", "never"], "cap"),
        (
            "kernel",
            vec!["export", z, "--format", "wgsl", "--out", "k.wgsl"],
            "cap",
        ),
        (
            "mesh",
            vec![
                "render",
                "--scene",
                "zero.obj",
                "--material",
                "skin1",
                "--out",
                "never",
            ],
            "regular file",
        ),
    ] {
        let o = sss(&args, d);
        let named = if what == "mesh" { "zero.obj" } else { z };
        assert_refused(&o, what, &[named, needle]);
    }
}
