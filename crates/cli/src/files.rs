//! Files as the commands name them: inputs read whole through a cap (`mc::input`), outputs
//! written whole or not at all (`mc::outputs::Outputs`), and the `--out` convention: commands
//! that write several files take `--out DIR`, a folder; commands that write a single file take
//! `--out FILE` and also accept an existing folder (or a path ending in `/`), writing their
//! default file name into it ([`out_file`]).

use std::path::{Path, PathBuf};

pub use mc::input::{read_named, read_text};
pub use mc::outputs::Outputs;

/// The file a single-file command writes for `--out`: `out` itself, or `default_name` inside
/// it when `out` is an existing folder or ends in a path separator.
pub fn out_file(out: &Path, default_name: &str) -> PathBuf {
    let text = out.as_os_str().to_string_lossy();
    if out.is_dir() || text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR) {
        out.join(default_name)
    } else {
        out.to_path_buf()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_file_outputs_accept_a_folder() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        assert_eq!(out_file(d, "k.toml"), d.join("k.toml"));
        assert_eq!(out_file(&d.join("x.toml"), "k.toml"), d.join("x.toml"));
        assert_eq!(
            out_file(Path::new("new/"), "k.toml"),
            Path::new("new/k.toml")
        );
    }
}
