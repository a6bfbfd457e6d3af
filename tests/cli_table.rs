//! `sss table`: tables written whole, sharded builds merged bit-identical to the one-machine
//! build for N = 1, 3, 4 (white, the default, and one walk per albedo, `--white off`) (and
//! `--shard auto` from a job array's environment), the same tables on the GPU (`--device gpu`),
//! profiles and kernels from tables, and bad input refused with exit code 2, naming the field,
//! writing nothing.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::sss;

/// A small table: 8 albedos up to 0.99, 7·10⁴ photons each (5 chunks of 16 384).
const SMALL: [&str; 10] = [
    "table",
    "--g",
    "0",
    "--eta",
    "1.3",
    "--albedos",
    "8",
    "--max-albedo",
    "0.99",
    "--photons=7e4",
];

fn table(extra: &[&str], dir: &Path) -> Output {
    let args: Vec<&str> = SMALL.iter().chain(extra).copied().collect();
    sss(&args, dir)
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn refused(o: &Output, says: &str) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains(says), "expected {says:?} in: {e}");
}

const FILE: &str = "g0_eta1.3.table.json";

/// `sss merge --out OUT SHARD…` in `dir`.
fn merge(out: &str, shards: &[&str], dir: &Path) -> Output {
    let mut args = vec!["merge", "--out", out];
    args.extend(shards);
    sss(&args, dir)
}

/// `sss profile MATERIAL --model table --table TABLE --out OUT` in `dir`.
fn from_table(material: &str, table: &str, out: &str, dir: &Path) -> Output {
    sss(
        &[
            "profile", material, "--model", "table", "--table", table, "--out", out,
        ],
        dir,
    )
}

#[test]
fn sharded_builds_merge_bit_identical_to_the_one_machine_build() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&table(&["--out", "whole", "--threads", "2"], d));
    let whole = std::fs::read(d.join("whole").join(FILE)).unwrap();
    for n in [1, 3, 4] {
        let out = format!("s{n}");
        let mut files = Vec::new();
        for i in (1..=n).rev() {
            ok(&table(
                &[
                    "--out",
                    &out,
                    "--shard",
                    &format!("{i}/{n}"),
                    "--threads",
                    "1",
                ],
                d,
            ));
            files.push(format!("{out}/table-shard-{i}-of-{n}.json"));
        }
        let merged = format!("m{n}");
        let files: Vec<&str> = files.iter().map(String::as_str).collect();
        ok(&merge(&merged, &files, d));
        let got = std::fs::read(d.join(&merged).join(FILE)).unwrap();
        assert!(
            got == whole,
            "N = {n}: the merged table differs from the unsharded one"
        );
    }
    // The per-albedo build (one walk per albedo, `--white off`) shards and merges the same way,
    // and its shards do not mix with the white build's.
    ok(&table(&["--out", "each", "--white", "off"], d));
    let each = std::fs::read(d.join("each").join(FILE)).unwrap();
    assert!(each != whole, "--white off built the white table");
    for i in 1..=3 {
        let shard = format!("{i}/3");
        ok(&table(
            &["--out", "e3", "--shard", &shard, "--white", "off"],
            d,
        ));
    }
    let e3 = [1, 2, 3].map(|i| format!("e3/table-shard-{i}-of-3.json"));
    ok(&merge("me3", &e3.each_ref().map(String::as_str), d));
    assert!(std::fs::read(d.join("me3").join(FILE)).unwrap() == each);
    refused(
        &merge("bad", &[&e3[0], &e3[1], "s3/table-shard-3-of-3.json"], d),
        "different tables",
    );

    // A job array's environment: Slurm task ids 10..13 are slices 1..4.
    for id in 10..14 {
        let o = Command::new(env!("CARGO_BIN_EXE_sss"))
            .args(SMALL)
            .args(["--out", "auto", "--shard", "auto"])
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .env("SLURM_ARRAY_TASK_MIN", "10")
            .env("SLURM_ARRAY_TASK_COUNT", "4")
            .current_dir(d)
            .output()
            .unwrap();
        ok(&o);
    }
    let shards: Vec<String> = (1..=4)
        .map(|i| format!("auto/table-shard-{i}-of-4.json"))
        .collect();
    let shards: Vec<&str> = shards.iter().map(String::as_str).collect();
    ok(&merge("mauto", &shards, d));
    assert!(std::fs::read(d.join("mauto").join(FILE)).unwrap() == whole);

    // Mismatched or missing shards: refused, nothing written.
    ok(&table(
        &["--out", "other", "--shard", "1/3", "--seed", "9"],
        d,
    ));
    refused(
        &merge(
            "bad",
            &[
                "s3/table-shard-2-of-3.json",
                "s3/table-shard-3-of-3.json",
                "other/table-shard-1-of-3.json",
            ],
            d,
        ),
        "different tables",
    );
    refused(
        &merge(
            "bad",
            &["s3/table-shard-1-of-3.json", "s3/table-shard-3-of-3.json"],
            d,
        ),
        "shard 2/3 is missing",
    );
    refused(
        &merge(
            "bad",
            &["s3/table-shard-1-of-3.json", "s4/table-shard-2-of-4.json"],
            d,
        ),
        "shards of different builds",
    );
    assert!(!d.join("bad").exists());

    // Without a job array, `auto` says what it looked for.
    let o = Command::new(env!("CARGO_BIN_EXE_sss"))
        .args(SMALL)
        .args(["--out", "none", "--shard", "auto"])
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("AWS_BATCH_JOB_ARRAY_INDEX")
        .env_remove("JOB_COMPLETION_INDEX")
        .current_dir(d)
        .output()
        .unwrap();
    refused(&o, "no job array in the environment");
    assert!(!d.join("none").exists());
}

#[test]
fn profiles_and_kernels_come_from_tables_and_bad_tables_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&table(&["--out", "t"], d));
    // Skin1 (g = 0, η = 1.3, albedos 0.68–0.96) lies within the table.
    ok(&from_table("skin1", "t", "p.csv", d));
    let csv = std::fs::read_to_string(d.join("p.csv")).unwrap();
    let p = fit::Profile::from_csv(&csv, "p.csv").unwrap();
    // The thesis grid of Skin1: dr = min transport MFP / 20.
    assert!((p.dr - (1.0 / 14.9) / 20.0).abs() < 1e-12, "dr = {}", p.dr);
    ok(&sss(
        &[
            "kernel",
            "skin1",
            "--table",
            "t/g0_eta1.3.table.json",
            "--format",
            "hlsl",
            "--out",
            "k.hlsl",
        ],
        d,
    ));
    assert!(
        std::fs::read_to_string(d.join("k.hlsl"))
            .unwrap()
            .contains("float4")
    );
    ok(&sss(
        &[
            "kernel",
            "--from-artist",
            "color=0.6,0.5,0.3",
            "radius=0.1,0.05,0.02",
            "--table",
            "t",
            "--format",
            "glsl",
            "--out",
            "a.glsl",
        ],
        d,
    ));

    // A material outside the grid: Marble has η = 1.5.
    refused(&from_table("marble", "t", "q.csv", d), "η = 1.5");
    // An albedo above the table's largest (Cream's R: 0.99997 > 0.99).
    refused(&from_table("cream", "t", "q.csv", d), "albedo");
    // A truncated table, and a foreign JSON file.
    let text = std::fs::read_to_string(d.join("t").join(FILE)).unwrap();
    std::fs::write(d.join("cut.table.json"), &text[..text.len() / 2]).unwrap();
    refused(
        &from_table("skin1", "cut.table.json", "q.csv", d),
        "not an sss table",
    );
    let edited = text.replacen("\"g\":0.0", "\"g\":0.5", 1);
    assert_ne!(edited, text);
    std::fs::write(d.join("edited.table.json"), &edited).unwrap();
    // A table relabelled g = 0.5 no longer stands for Skin1's g = 0.
    refused(
        &from_table("skin1", "edited.table.json", "q.csv", d),
        "g = 0, η = 1.3",
    );
    std::fs::write(d.join("foreign.table.json"), "{\"format\":\"sss-shard-2\"}").unwrap();
    refused(
        &from_table("skin1", "foreign.table.json", "q.csv", d),
        "not an sss table",
    );
    assert!(!d.join("q.csv").exists());
}

#[test]
fn simulate_takes_its_slice_from_a_job_array() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    common::small_config(d);
    let run = |env: &[(&str, &str)], out: &str| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_sss"));
        c.args([
            "simulate",
            "skin1",
            "--config",
            "small.toml",
            "--photons=5e4",
        ])
        .args(["--shard", "auto", "--out", out])
        .current_dir(d);
        for (k, v) in env {
            c.env(k, v);
        }
        c.output().unwrap()
    };
    // AWS Batch numbers array children from 0.
    for i in ["0", "1"] {
        ok(&run(
            &[
                ("AWS_BATCH_JOB_ARRAY_INDEX", i),
                ("AWS_BATCH_JOB_ARRAY_SIZE", "2"),
            ],
            "aws",
        ));
    }
    ok(&sss(
        &[
            "merge",
            "--out",
            "merged",
            "aws/shard-1-of-2.json",
            "aws/shard-2-of-2.json",
        ],
        d,
    ));
    ok(&sss(
        &[
            "simulate",
            "skin1",
            "--config",
            "small.toml",
            "--photons=5e4",
            "--out",
            "whole",
        ],
        d,
    ));
    let csv = |p: &str| std::fs::read(d.join(p).join("skin1.profile.csv")).unwrap();
    assert!(csv("merged") == csv("whole"));
    // A Kubernetes Indexed Job needs N.
    refused(&run(&[("JOB_COMPLETION_INDEX", "1")], "k8s"), "auto/N");
}

/// `--device gpu` builds the same table file on the GPU (lavapipe in CI), named for its adapter,
/// equal to the CPU's within noise (Skin1's profile from each: χ²/dof ≤ 1.5 per channel over the
/// bins both resolve; the statistics per albedo are `crates/mc_gpu/tests/table.rs`'s), and a
/// sharded GPU build is refused.
#[test]
fn the_gpu_builds_the_same_table() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let gpu = table(&["--device", "gpu", "--out", "gpu"], d);
    if common::no_adapter(&gpu) {
        return;
    }
    ok(&gpu);
    let text = std::fs::read_to_string(d.join("gpu").join(FILE)).unwrap();
    let t = mc::table::Table::from_json(&text, FILE).unwrap();
    assert!(t.tracer.as_deref().is_some_and(|s| s.starts_with("gpu: ")));
    ok(&table(&["--out", "cpu"], d));
    let profile = |dir: &str| {
        ok(&from_table("skin1", dir, &format!("{dir}.csv"), d));
        let csv = std::fs::read_to_string(d.join(format!("{dir}.csv"))).unwrap();
        fit::Profile::from_csv(&csv, "p.csv").unwrap()
    };
    let (a, b) = (profile("gpu"), profile("cpu"));
    for c in 0..3 {
        let (mut chi2, mut dof) = (0.0, 0);
        for k in 0..a.r.len() {
            let var = a.se[c][k].powi(2) + b.se[c][k].powi(2);
            if var > 0.0 && var.sqrt() < 0.1 * (a.rd[c][k] + b.rd[c][k]) / 2.0 {
                chi2 += (a.rd[c][k] - b.rd[c][k]).powi(2) / var;
                dof += 1;
            }
        }
        assert!(
            dof >= 10 && chi2 / dof as f64 <= 1.5,
            "channel {c}: χ² {chi2} over {dof}"
        );
    }
    refused(&table(&["--device", "gpu", "--shard", "1/2"], d), "--shard");
}
