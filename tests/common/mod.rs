//! Helpers shared by the end-to-end CLI tests.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `sss` with `args` in `cwd`.
pub fn sss(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sss"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("sss runs")
}
