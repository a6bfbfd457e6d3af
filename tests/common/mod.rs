//! Helpers shared by the end-to-end CLI tests.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `sss` with `args` in `cwd`.
#[allow(dead_code)] // not every test binary that includes `common` runs `sss`
pub fn sss(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sss"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("sss runs")
}

/// A coarse grid (dr = min MFP / 6, 10 max MFP) keeps the kernels small.
const SMALL: &str = "photons = 30000\nseed = 2\nthickness_cm = 1e8\nn_above = 1.0\nn_below = 1.0\n[grid]\ndr_per_min_mfp = 6.0\nr_max_mfp = 10.0\nz_max_mfp = 10.0\nnz = 10\nna = 5\n";

/// Writes the small run settings to `dir/small.toml`.
#[allow(dead_code)] // not every test binary that includes `common` uses it
pub fn small_config(dir: &Path) {
    std::fs::write(dir.join("small.toml"), SMALL).unwrap();
}

/// Simulates a small Skin1 profile into `dir/profiles/skin1.profile.csv`.
#[allow(dead_code)] // not every test binary that includes `common` uses it
pub fn small_profile(dir: &Path) {
    small_config(dir);
    let o = sss(
        &[
            "simulate",
            "skin1",
            "--config",
            "small.toml",
            "--profile-only",
            "--out",
            "profiles",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Says that the running test was skipped, on the process's own stderr: libtest captures only
/// `print!` and `eprint!`, so the line shows in `cargo test`'s output (a skip is never a silent
/// pass).
#[allow(dead_code)] // not every test binary that includes `common` skips
pub fn report_skip(reason: &str) {
    use std::io::Write;
    let name = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let _ = writeln!(std::io::stderr().lock(), "SKIPPED {name}: {reason}");
}

/// Whether `python3` imports every module of `modules` (comma-separated, e.g. "mitsuba, numpy").
/// Without them the test is skipped (said on stderr, naming `what`), except under CI=true, where
/// that fails and says how to install them (`install`).
#[allow(dead_code)] // not every test binary that includes `common` runs Python
pub fn python_has(modules: &str, what: &str, install: &str) -> bool {
    let probe = Command::new("python3")
        .args(["-c", &format!("import {modules}")])
        .output();
    if probe.is_ok_and(|o| o.status.success()) {
        return true;
    }
    assert_ne!(
        std::env::var("CI").as_deref(),
        Ok("true"),
        "CI=true and {what} is not importable: {install}"
    );
    report_skip(&format!("{what} is not installed"));
    false
}

/// Runs one of the repository's Python scripts (`path` relative to the repository root) with
/// `--sss` set to the built binary before `args`, in `cwd`; prints its stdout (libtest shows it
/// when the test fails) and asserts that it succeeded, with its stderr.
#[allow(dead_code)] // not every test binary that includes `common` runs Python
pub fn python_script(path: &str, args: &[&std::ffi::OsStr], cwd: &Path) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let o = Command::new("python3")
        .arg(format!("{root}/{path}"))
        .args(["--sss", env!("CARGO_BIN_EXE_sss")])
        .args(args)
        .current_dir(cwd)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    eprintln!("{stdout}");
    assert!(
        o.status.success(),
        "{path}: {stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Whether `sss` stopped for want of a GPU adapter; then the test is skipped (said on stderr),
/// except under CI=true, where that fails.
#[allow(dead_code)] // not every test binary that includes `common` renders
pub fn no_adapter(o: &Output) -> bool {
    let e = String::from_utf8_lossy(&o.stderr);
    let none = e.contains("no GPU adapter");
    if none {
        assert_ne!(
            std::env::var("CI").as_deref(),
            Ok("true"),
            "CI=true and {e}"
        );
        report_skip(e.trim());
    }
    none
}
