//! The Python module (`crates/python`): builds its wheel with maturin (the `ci` profile, in the
//! workspace's `target`, so that the crates this test run built are reused: cargo holds its build
//! lock while it compiles, not while the tests run), installs it into
//! a virtual environment that sees the machine's NumPy, Matplotlib and pytest, and runs
//! `crates/python/tests` there (with the example of `examples/python`). Needs maturin and pytest
//! (`.ci/run` installs them); outside CI a machine without them skips, under CI=true it fails.

mod common;

use std::path::Path;
use std::process::Command;

#[test]
fn python_module_passes_its_tests() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    if !common::python_has(
        "maturin, pytest, numpy, matplotlib",
        "maturin, pytest, NumPy or Matplotlib",
        "pip install -r crates/python/requirements-test.txt",
    ) {
        return;
    }
    let target = root.join("target");
    let wheels = tempfile::tempdir().unwrap();
    let run = |cmd: &mut Command, what: &str| {
        let o = cmd.output().unwrap();
        let text = format!(
            "{}\n{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(o.status.success(), "{what} failed:\n{text}");
        text
    };
    run(
        Command::new("python3")
            .args(["-m", "maturin", "build", "--profile", "ci", "--quiet", "-o"])
            .arg(wheels.path())
            .arg("-m")
            .arg(root.join("crates/python/Cargo.toml"))
            .env("CARGO_TARGET_DIR", &target),
        "maturin build",
    );
    let venv = target.join("python-venv");
    run(
        Command::new("python3")
            .args(["-m", "venv", "--system-site-packages", "--clear"])
            .arg(&venv),
        "python3 -m venv",
    );
    let python = venv.join("bin/python");
    let wheel = std::fs::read_dir(wheels.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "whl"))
        .expect("maturin wrote a wheel");
    run(
        Command::new(&python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--no-deps",
                "--force-reinstall",
            ])
            .arg(&wheel),
        "pip install",
    );
    let out = run(
        Command::new(&python)
            .args(["-m", "pytest", "-q", "-s", "-p", "no:cacheprovider"])
            .arg(root.join("crates/python/tests"))
            .env("SSS_BIN", env!("CARGO_BIN_EXE_sss"))
            .current_dir(wheels.path()),
        "pytest",
    );
    eprintln!("{out}");
}
