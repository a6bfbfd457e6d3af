//! Every command that writes files writes them whole or not at all: a failure late in the run
//! (after work has started, or when the outputs are finally written) leaves the output folder
//! and the profile folder exactly as they were — no folder created, no file written.

mod common;
use common::{no_adapter, small_config, small_profile, sss};

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

/// Every file and folder under `dir` (relative path → contents; folders hold no bytes), or an
/// empty map when `dir` does not exist.
fn snapshot(dir: &Path) -> BTreeMap<String, Option<Vec<u8>>> {
    let mut all = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            let key = p.strip_prefix(dir).unwrap().display().to_string();
            if p.is_dir() {
                all.insert(key, None);
                todo.push(p);
            } else {
                all.insert(key, Some(std::fs::read(&p).unwrap()));
            }
        }
    }
    all
}

/// The command failed with exit code 2, saying `why` on stderr.
fn failed(o: &Output, why: &str) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains(why), "expected {why:?} in: {e}");
}

/// A folder in `out` named like the file `name`: writing it fails only when the outputs are
/// committed, after all the work.
fn block(out: &Path, name: &str) {
    std::fs::create_dir_all(out.join(name).join("keep")).unwrap();
}

#[test]
fn simulate_writes_nothing_when_a_later_output_cannot_be_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o_dir = d.join("o");
    block(&o_dir, "marble.summary.json");
    let before = snapshot(&o_dir);
    let o = sss(
        &[
            "simulate",
            "skin1",
            "marble",
            "--photons",
            "1000",
            "--profile-only",
            "--out",
            "o",
        ],
        d,
    );
    failed(&o, "marble.summary.json");
    assert_eq!(snapshot(&o_dir), before, "no skin1 file, no temporaries");
    // An invalid second material: nothing simulated, no folder.
    std::fs::write(d.join("bad.toml"), "name = \"bad\"\n").unwrap();
    let o = sss(&["simulate", "skin1", "bad.toml", "--out", "never"], d);
    failed(&o, "bad.toml");
    assert!(!d.join("never").exists());
}

#[test]
fn merge_writes_nothing_on_a_corrupt_shard_or_a_blocked_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for i in ["1/2", "2/2"] {
        let o = sss(
            &[
                "simulate",
                "skin1",
                "--photons",
                "2000",
                "--profile-only",
                "--shard",
                i,
                "--out",
                "s",
            ],
            d,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let shards = ["s/shard-1-of-2.json", "s/shard-2-of-2.json"];
    block(&d.join("m"), "skin1.summary.json");
    let before = snapshot(&d.join("m"));
    let o = sss(&["merge", shards[0], shards[1], "--out", "m"], d);
    failed(&o, "skin1.summary.json");
    assert_eq!(snapshot(&d.join("m")), before);
    std::fs::write(d.join("cut.json"), "{\"format\": \"sss-shard-2\"").unwrap();
    let o = sss(&["merge", shards[0], "cut.json", "--out", "never"], d);
    failed(&o, "cut.json");
    assert!(!d.join("never").exists());
}

#[test]
fn fit_writes_nothing_when_the_model_is_refused_after_the_profile_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_profile(d);
    let o = sss(
        &[
            "fit",
            "profiles/skin1.profile.csv",
            "--model",
            "manual",
            "--rank",
            "2",
            "--out",
            "new/k.toml",
        ],
        d,
    );
    failed(&o, "--rank");
    assert!(!d.join("new").exists());
}

/// The first material is simulated on demand and evaluated; the second's profile provenance is
/// corrupt. Neither the plots nor the first material's new profile are written.
#[test]
fn eval_writes_no_plots_and_no_profiles_when_a_later_material_fails() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_config(d);
    let p = d.join("p");
    std::fs::create_dir(&p).unwrap();
    std::fs::write(p.join("marble.profile.csv"), "r_cm,R,G,B,R_se,G_se,B_se\n").unwrap();
    std::fs::write(p.join("marble.profile.json"), "{ not json").unwrap();
    let before = snapshot(&p);
    let o = sss(
        &[
            "eval",
            "skin1",
            "marble",
            "--photons",
            "5000",
            "--config",
            "small.toml",
            "--profiles",
            "p",
            "--plots",
            "plots",
        ],
        d,
    );
    failed(&o, "marble.profile.json");
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("fitting and evaluating every model for skin1"),
        "the failure came after skin1's evaluation"
    );
    assert!(!d.join("plots").exists());
    assert_eq!(
        snapshot(&p),
        before,
        "skin1's simulated profile is not written"
    );
}

#[test]
fn profile_writes_nothing_for_a_material_outside_the_models_domain() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("clear.toml"), "name = \"clear\"\nunit = \"cm\"\nsigma_a = [0, 0, 1]\nsigma_s = [0, 0, 1]\ng = 0.0\neta = 1.3\n").unwrap();
    let o = sss(
        &[
            "profile",
            "clear.toml",
            "--model",
            "pbd",
            "--out",
            "new/c.csv",
        ],
        d,
    );
    failed(&o, "sigma_a");
    assert!(!d.join("new").exists());
}

#[test]
fn compare_profiles_writes_nothing_when_a_later_material_fails() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_config(d);
    let p = d.join("p");
    std::fs::create_dir(&p).unwrap();
    std::fs::write(p.join("marble.profile.csv"), "r_cm,R,G,B,R_se,G_se,B_se\n").unwrap();
    std::fs::write(p.join("marble.profile.json"), "[]").unwrap();
    let before = snapshot(&p);
    let o = sss(
        &[
            "compare-profiles",
            "skin1",
            "marble",
            "--photons",
            "2000",
            "--config",
            "small.toml",
            "--profiles",
            "p",
            "--plots",
            "plots",
        ],
        d,
    );
    failed(&o, "marble.profile.json");
    assert!(!d.join("plots").exists());
    assert_eq!(snapshot(&p), before);
}

#[test]
fn area_table_writes_nothing_when_its_plot_cannot_be_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    block(&d.join("t"), "skin1.area_effect.png");
    let before = snapshot(&d.join("t"));
    let o = sss(&["area-table", "skin1", "--size", "16", "--out", "t"], d);
    failed(&o, "skin1.area_effect.png");
    assert_eq!(snapshot(&d.join("t")), before, "no table, no header");
    std::fs::write(d.join("bad.csv"), "r_cm,R,G,B\n").unwrap();
    let o = sss(
        &[
            "area-table",
            "skin1",
            "--profile",
            "bad.csv",
            "--size",
            "16",
            "--out",
            "never",
        ],
        d,
    );
    failed(&o, "bad.csv");
    assert!(!d.join("never").exists());
}

#[test]
fn render_writes_nothing_on_a_bad_kernel_or_a_late_failure() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("bad.toml"), "model = \"preint\"\n").unwrap();
    let o = sss(
        &[
            "render", "--kernel", "bad.toml", "--width", "32", "--height", "18", "--out", "never",
        ],
        d,
    );
    failed(&o, "bad.toml");
    assert!(!d.join("never").exists());
    // --compare-models's sheet cannot be written: not even render.png, nor the profile simulated
    // for the kernel.
    small_config(d);
    let r = d.join("r");
    block(&r, "compare_sheet.png");
    let before = snapshot(&r);
    let o = sss(
        &[
            "render",
            "--width",
            "48",
            "--height",
            "27",
            "--photons",
            "2000",
            "--config",
            "small.toml",
            "--compare-models",
            "--out",
            "r",
        ],
        d,
    );
    if no_adapter(&o) {
        return;
    }
    failed(&o, "compare_sheet.png");
    assert_eq!(snapshot(&r), before);
    assert!(!d.join("out").exists());
}

/// Fifteen usable library profiles and a corrupt one (wine, the last): the report's profiles and
/// plots of the first fifteen are not written.
#[test]
fn reproduce_writes_nothing_when_a_later_profile_is_corrupt() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lib = d.join("lib");
    std::fs::create_dir(&lib).unwrap();
    let mut csv = String::from("r_cm,R,G,B,R_se,G_se,B_se\n");
    for i in 0..12 {
        let r = 0.01 * (i as f64 + 2.0 / 3.0);
        let v = (-10.0 * r).exp();
        csv += &format!("{r},{v},{},{},0,0,0\n", 0.8 * v, 0.6 * v);
    }
    // Every reproduced material but the last, wine (alphabetical).
    let names = mc::builtin::REPRODUCED;
    assert_eq!(names.last(), Some(&"wine"));
    for m in &names[..names.len() - 1] {
        std::fs::write(lib.join(format!("{m}.profile.csv")), &csv).unwrap();
    }
    std::fs::write(
        lib.join("wine.profile.csv"),
        "r_cm,R,G,B,R_se,G_se,B_se\n0.1,nan,0,0,0,0,0\n",
    )
    .unwrap();
    let o = sss(
        &[
            "reproduce",
            "--quick",
            "--profiles",
            "lib",
            "--out",
            "report",
        ],
        d,
    );
    failed(&o, "wine.profile.csv");
    assert!(!d.join("report").exists());
}

#[test]
fn export_writes_nothing_for_a_bad_kernel() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("k.toml"), "taps = 3\n").unwrap();
    let o = sss(
        &[
            "export",
            "k.toml",
            "--format",
            "wgsl",
            "--out",
            "new/k.wgsl",
        ],
        d,
    );
    failed(&o, "k.toml");
    assert!(!d.join("new").exists());
}

/// The snippet's file cannot be written after the profile was simulated and every candidate
/// ranked: the profile is not written either.
#[test]
fn kernel_writes_nothing_when_its_snippet_cannot_be_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_config(d);
    block(&d.join("k"), "skin1.wgsl");
    let before = snapshot(&d.join("k"));
    let o = sss(
        &[
            "kernel",
            "skin1",
            "--format",
            "wgsl",
            "--photons",
            "5000",
            "--config",
            "small.toml",
            "--profiles",
            "p",
            "--out",
            "k",
        ],
        d,
    );
    failed(&o, "skin1.wgsl");
    assert!(String::from_utf8_lossy(&o.stderr).contains("chose"));
    assert_eq!(snapshot(&d.join("k")), before);
    assert!(!d.join("p").exists());
}

#[test]
fn engine_params_writes_nothing_when_its_mtlx_cannot_be_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_config(d);
    block(&d.join("m"), "skin1.mtlx");
    let before = snapshot(&d.join("m"));
    let o = sss(
        &[
            "engine-params",
            "skin1",
            "--engine",
            "openpbr",
            "--photons",
            "5000",
            "--config",
            "small.toml",
            "--profiles",
            "p",
            "--mtlx",
            "m",
        ],
        d,
    );
    failed(&o, "skin1.mtlx");
    assert_eq!(snapshot(&d.join("m")), before);
    assert!(!d.join("p").exists());
}

/// An output folder that cannot be written (here: below a file) is refused before any work,
/// by the early check's own words ("cannot write into", naming the folder that blocks): without
/// it each command would simulate first and fail only when committing, with "cannot create
/// folder".
#[test]
fn an_output_folder_that_cannot_be_written_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("blocker"), "a file, not a folder").unwrap();
    let few = ["--photons", "1000"];
    let runs: [Vec<&str>; 4] = [
        vec!["simulate", "skin1", "--out", "blocker/o"],
        vec![
            "export",
            "skin1",
            "--format",
            "package",
            "--out",
            "blocker/o",
        ],
        vec!["eval", "skin1", "--plots", "blocker/o"],
        vec![
            "render",
            "--out",
            "blocker/o",
            "--incidence-photons",
            "1000",
        ],
    ];
    for args in runs {
        let o = sss(&[&args[..], &few[..]].concat(), d);
        failed(&o, "cannot write into blocker/o (blocker)");
        assert_eq!(
            snapshot(d).len(),
            1,
            "{args:?} wrote something: {:?}",
            snapshot(d).keys()
        );
    }
}
