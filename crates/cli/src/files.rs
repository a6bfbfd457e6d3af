//! A command's outputs, written whole or not at all: every file is rendered in memory and added
//! to an [`Outputs`]; when the command has finished, [`Outputs::commit`] creates the folders,
//! writes each file to a temporary name in its folder and only then renames them all into place.
//! A command that fails before the commit writes nothing, and a commit that fails before the
//! renames removes what it created, so a failing command leaves the file system as it was.
//!
//! The `--out` convention: commands that write several files take `--out DIR`, a folder;
//! commands that write a single file take `--out FILE` and also accept an existing folder (or a
//! path ending in `/`), writing their default file name into it ([`out_file`]).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

pub use mc::input::read_text;

/// Files held in memory until the command has finished.
#[derive(Default)]
pub struct Outputs {
    files: Vec<(PathBuf, Vec<u8>)>,
}

impl Outputs {
    /// Adds a file; a later file with the same path replaces the earlier one.
    pub fn add(&mut self, path: impl Into<PathBuf>, bytes: impl Into<Vec<u8>>) {
        let (path, bytes) = (path.into(), bytes.into());
        match self.files.iter_mut().find(|(p, _)| *p == path) {
            Some(f) => f.1 = bytes,
            None => self.files.push((path, bytes)),
        }
    }

    /// Adds each (file name, contents) of `named` in folder `dir`.
    pub fn add_in(&mut self, dir: &Path, named: Vec<(String, Vec<u8>)>) {
        for (name, bytes) in named {
            self.add(dir.join(name), bytes);
        }
    }

    /// The contents of a file added earlier in this command.
    pub fn get(&self, path: &Path) -> Option<&[u8]> {
        self.files
            .iter()
            .find(|(p, _)| p == path)
            .map(|(_, b)| b.as_slice())
    }

    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// Writes every file. Targets that are folders are refused before anything is touched;
    /// missing folders are created, then every file is written to a temporary name beside its
    /// target, then all are renamed into place. A failure before the renames removes the
    /// temporary files and the folders created here. (A rename itself failing, after others
    /// succeeded, is the one case that leaves some files replaced.)
    pub fn commit(self) -> Result<()> {
        for (path, _) in &self.files {
            if path.is_dir() {
                bail!("cannot write {}: it is a folder", path.display());
            }
        }
        let mut created: Vec<PathBuf> = Vec::new();
        let mut temps: Vec<PathBuf> = Vec::new();
        let undo = |created: &[PathBuf], temps: &[PathBuf]| {
            for t in temps {
                let _ = std::fs::remove_file(t);
            }
            for d in created.iter().rev() {
                let _ = std::fs::remove_dir(d);
            }
        };
        for (path, bytes) in &self.files {
            let staged = create_folders(folder(path), &mut created).and_then(|()| {
                let tmp = temp_name(path);
                temps.push(tmp.clone());
                std::fs::write(&tmp, bytes)
                    .with_context(|| format!("cannot write {}", tmp.display()))
            });
            if let Err(e) = staged {
                undo(&created, &temps);
                return Err(e);
            }
        }
        for (k, (path, _)) in self.files.iter().enumerate() {
            if let Err(e) = std::fs::rename(&temps[k], path) {
                undo(&[], &temps[k..]);
                return Err(e)
                    .with_context(|| format!("cannot move {} into place", path.display()));
            }
        }
        Ok(())
    }
}

/// The folder a file goes into (`.` for a bare file name).
fn folder(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Creates `dir` and its missing ancestors, recording each one created (outermost first).
fn create_folders(dir: &Path, created: &mut Vec<PathBuf>) -> Result<()> {
    let missing: Vec<&Path> = dir
        .ancestors()
        .take_while(|d| !d.as_os_str().is_empty() && !d.exists())
        .collect();
    for d in missing.into_iter().rev() {
        std::fs::create_dir(d).with_context(|| format!("cannot create folder {}", d.display()))?;
        created.push(d.to_path_buf());
    }
    Ok(())
}

/// A hidden name beside `path`, unique to this process.
fn temp_name(path: &Path) -> PathBuf {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    folder(path).join(format!(".{name}.{}.tmp", std::process::id()))
}

/// Each file's text with its name, for messages; `what` names the kind of file in errors.
pub fn read_named(paths: &[PathBuf], what: &str) -> Result<Vec<(String, String)>> {
    paths
        .iter()
        .map(|p| {
            let name = p.display().to_string();
            let text = read_text(p).with_context(|| format!("cannot read {what} {name}"))?;
            Ok((name, text))
        })
        .collect()
}

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
    fn a_blocked_target_leaves_nothing_behind() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir_all(d.join("a/blocked")).unwrap();
        let mut out = Outputs::default();
        out.add(d.join("new/deep/x.txt"), "x");
        out.add(d.join("a/y.txt"), "y");
        out.add(d.join("a/blocked"), "z");
        assert!(out.commit().is_err());
        assert!(!d.join("new").exists());
        assert!(!d.join("a/y.txt").exists());
        // A parent that is a file: the folder cannot be created; what was staged is removed.
        std::fs::write(d.join("file"), "f").unwrap();
        let mut out = Outputs::default();
        out.add(d.join("new/x.txt"), "x");
        out.add(d.join("file/y.txt"), "y");
        assert!(out.commit().is_err());
        let mut left: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        left.sort();
        assert_eq!(left, ["a", "file"]);
        assert_eq!(std::fs::read_dir(d.join("a")).unwrap().count(), 1);
    }

    #[test]
    fn commit_writes_every_file_and_the_last_of_a_path_wins() {
        let dir = tempfile::tempdir().unwrap();
        let mut out = Outputs::default();
        out.add(dir.path().join("f/x.txt"), "old");
        out.add(dir.path().join("f/x.txt"), "new");
        out.add(dir.path().join("y.bin"), vec![1u8, 2]);
        assert_eq!(out.get(&dir.path().join("f/x.txt")), Some(&b"new"[..]));
        assert_eq!(out.len(), 2);
        out.commit().unwrap();
        assert_eq!(
            std::fs::read_to_string(dir.path().join("f/x.txt")).unwrap(),
            "new"
        );
        assert_eq!(std::fs::read(dir.path().join("y.bin")).unwrap(), [1, 2]);
        assert_eq!(
            std::fs::read_dir(dir.path().join("f")).unwrap().count(),
            1,
            "no temporaries left"
        );
    }

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
