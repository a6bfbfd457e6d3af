//! Slurm, for real: a single-node cluster started on this machine
//! (`scripts/slurm/local-cluster.sh`: munged, slurmctld and slurmd as root with a generated
//! slurm.conf), a small table build submitted by `scripts/slurm/submit.sh` as 4 array tasks plus
//! the merge job that depends on them (`--dependency=afterok`), and the merged table
//! bit-identical to the one built on one machine. The daemons are stopped by their process ids
//! whatever happens. Skipped, saying so, where Slurm is not installed or the test is not root;
//! under CI=true (`.ci/run` installs `slurm-wlm` and `munge`) that fails instead.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

const TABLE: [&str; 10] = [
    "table",
    "--g",
    "0.5",
    "--eta",
    "1.4",
    "--albedos",
    "8",
    "--max-albedo",
    "0.99",
    "--photons=3e4",
];

/// Stops the cluster when the test ends, passing or not.
struct Cluster {
    script: PathBuf,
    dir: PathBuf,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new("bash")
            .arg(&self.script)
            .arg("stop")
            .arg(&self.dir)
            .status();
    }
}

fn installed() -> bool {
    let tools = ["munged", "slurmctld", "slurmd", "sbatch", "sinfo"];
    let have = tools.iter().all(|t| {
        Command::new("sh")
            .args(["-c", &format!("command -v {t}")])
            .output()
            .is_ok_and(|o| o.status.success())
    });
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    have && root
}

#[test]
fn a_table_built_as_a_slurm_job_array_is_bit_identical_to_the_one_machine_build() {
    if !installed() {
        assert_ne!(
            std::env::var("CI").as_deref(),
            Ok("true"),
            "CI=true and Slurm is not usable here: apt-get install slurm-wlm munge, as root"
        );
        common::report_skip("Slurm (slurm-wlm, munge) is not installed, or not root");
        return;
    }
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let dir = tempfile::tempdir().unwrap();
    let cluster = Cluster {
        script: root.join("scripts/slurm/local-cluster.sh"),
        dir: dir.path().join("cluster"),
    };
    // A port of this process's own, away from a cluster someone may be running.
    let port = 20_000 + std::process::id() % 20_000;
    let up = Command::new("bash")
        .arg(&cluster.script)
        .arg("start")
        .arg(&cluster.dir)
        .env("SSS_SLURM_PORT", port.to_string())
        .output()
        .unwrap();
    assert!(
        up.status.success(),
        "the local cluster did not start: {}",
        String::from_utf8_lossy(&up.stderr)
    );
    let run = dir.path().join("run");
    let submitted = Command::new("timeout")
        .arg("600")
        .arg("bash")
        .arg(root.join("scripts/slurm/submit.sh"))
        .args(["--shards", "4", "--out"])
        .arg(&run)
        .args(["--wait", "--"])
        .args(TABLE)
        .env("SLURM_CONF", cluster.dir.join("slurm.conf"))
        .env("SSS", env!("CARGO_BIN_EXE_sss"))
        .env("CPUS_PER_TASK", "1")
        .env("TIME", "00:10:00")
        .output()
        .unwrap();
    let logs = || {
        std::fs::read_dir(run.join("logs"))
            .map(|d| {
                d.filter_map(|e| e.ok())
                    .map(|e| {
                        let text = std::fs::read_to_string(e.path()).unwrap_or_default();
                        format!("{}:\n{text}", e.path().display())
                    })
                    .collect::<Vec<_>>()
                    .join("\n")
            })
            .unwrap_or_default()
    };
    assert!(
        submitted.status.success(),
        "submit.sh failed: {}{}\n{}",
        String::from_utf8_lossy(&submitted.stdout),
        String::from_utf8_lossy(&submitted.stderr),
        logs()
    );
    let name = "g0.5_eta1.4.table.json";
    for i in 1..=4 {
        assert!(
            run.join(format!("shards/table-shard-{i}-of-4.json"))
                .exists(),
            "array task {i} wrote no shard:\n{}",
            logs()
        );
    }
    let merged = std::fs::read(run.join(name)).unwrap_or_else(|e| panic!("{e}:\n{}", logs()));
    let one = common::sss(&[&TABLE[..], &["--out", "one"]].concat(), dir.path());
    assert!(
        one.status.success(),
        "{}",
        String::from_utf8_lossy(&one.stderr)
    );
    let whole = std::fs::read(dir.path().join("one").join(name)).unwrap();
    assert!(
        merged == whole,
        "the table merged on the cluster differs from the one-machine build"
    );
}
