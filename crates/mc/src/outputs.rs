//! A command's outputs, written whole or not at all: every file is rendered in memory and added
//! to an [`Outputs`]; when the command has finished, [`Outputs::commit`] creates the folders,
//! writes each file to a temporary name in its folder and only then renames them all into place.
//! A command that fails before the commit writes nothing, and a commit that fails before the
//! renames removes what it created, so a failing command leaves the file system as it was.
//!
//! It lives in `mc`, the lowest crate, because every layer above writes what it is asked to
//! through it: the profile cache of `render`, the reports of `report`, the CLI's commands.
//!
//! ```
//! let dir = std::env::temp_dir().join(format!("mc-outputs-doc-{}", std::process::id()));
//! let mut out = mc::outputs::Outputs::default();
//! out.add(dir.join("a/x.txt"), "x");
//! out.add(dir.join("y.bin"), vec![1u8, 2]);
//! out.commit().unwrap();
//! assert_eq!(std::fs::read_to_string(dir.join("a/x.txt")).unwrap(), "x");
//! # std::fs::remove_dir_all(&dir).unwrap();
//! ```

use std::path::{Path, PathBuf};

use crate::error::{McError, Result};

/// Files held in memory until the command has finished.
#[derive(Default)]
pub struct Outputs {
    files: Vec<(PathBuf, Vec<u8>)>,
}

impl Outputs {
    /// An empty set of outputs for folder `dir`, once [`check_writable`] has passed: what a
    /// command that writes into one folder makes first, before its work.
    pub fn checked(dir: &Path) -> Result<Outputs> {
        check_writable(dir)?;
        Ok(Outputs::default())
    }

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

    /// How many files are held.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// Whether no file is held.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// Writes every file. Targets that are folders are refused before anything is touched;
    /// missing folders are created, then every file is written to a temporary name beside its
    /// target, then all are renamed into place. A failure before the renames removes the
    /// temporary files and the folders created here. (A rename itself failing, after others
    /// succeeded, is the one case that leaves some files replaced.)
    pub fn commit(self) -> Result<()> {
        for (path, _) in &self.files {
            if path.is_dir() {
                return Err(McError::file(
                    format!("cannot write {}", path.display()),
                    std::io::Error::other("it is a folder"),
                ));
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
                    .map_err(|e| McError::file(format!("cannot write {}", tmp.display()), e))
            });
            if let Err(e) = staged {
                undo(&created, &temps);
                return Err(e);
            }
        }
        for (k, (path, _)) in self.files.iter().enumerate() {
            if let Err(e) = std::fs::rename(&temps[k], path) {
                undo(&[], &temps[k..]);
                return Err(McError::file(
                    format!("cannot move {} into place", path.display()),
                    e,
                ));
            }
        }
        Ok(())
    }
}

/// Checks, before any work, that files can be written into folder `dir` (created at commit where
/// missing): its nearest existing ancestor is a folder in which a file can be created (a probe,
/// removed at once). A command calls it first, so that a folder it cannot write is refused
/// before a long simulation rather than after.
pub fn check_writable(dir: &Path) -> Result<()> {
    let cannot = |what: &Path, e: std::io::Error| {
        McError::file(
            format!("cannot write into {} ({})", dir.display(), what.display()),
            e,
        )
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let Some(existing) = dir
        .ancestors()
        .find(|d| d.as_os_str().is_empty() || d.exists())
    else {
        return Ok(());
    };
    let existing = if existing.as_os_str().is_empty() {
        Path::new(".")
    } else {
        existing
    };
    if !existing.is_dir() {
        return Err(cannot(
            existing,
            std::io::Error::other("it is not a folder"),
        ));
    }
    let probe = existing.join(format!(".sss-probe.{}.tmp", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| cannot(existing, e))?;
    std::fs::remove_file(&probe).map_err(|e| cannot(&probe, e))
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
        std::fs::create_dir(d)
            .map_err(|e| McError::file(format!("cannot create folder {}", d.display()), e))?;
        created.push(d.to_path_buf());
    }
    Ok(())
}

/// A hidden name beside `path`, unique to this process.
fn temp_name(path: &Path) -> PathBuf {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    folder(path).join(format!(".{name}.{}.tmp", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder that exists and takes files passes, and so does a new folder below it (not
    /// created by the check); a path below a file, or in a folder that refuses files, is
    /// refused naming the folder.
    #[test]
    fn a_folder_is_checked_writable_before_any_work() {
        let s = Scratch::new("writable");
        check_writable(&s.0).unwrap();
        check_writable(&s.0.join("new/deeper")).unwrap();
        assert!(!s.0.join("new").exists(), "the check created a folder");
        std::fs::write(s.0.join("file"), "x").unwrap();
        let e = check_writable(&s.0.join("file/below"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("file") && e.contains("not a folder"), "{e}");
        // /proc takes no new files, for root too (Linux).
        if Path::new("/proc/self").exists() {
            let e = check_writable(Path::new("/proc/forbidden"))
                .unwrap_err()
                .to_string();
            assert!(e.contains("/proc"), "{e}");
        }
    }

    /// A fresh folder of this process's, removed when dropped.
    struct Scratch(PathBuf);

    impl Scratch {
        fn new(name: &str) -> Self {
            let d = std::env::temp_dir().join(format!("mc-outputs-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&d);
            std::fs::create_dir_all(&d).unwrap();
            Scratch(d)
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    #[test]
    fn a_blocked_target_leaves_nothing_behind() {
        let dir = Scratch::new("blocked");
        let d = dir.0.as_path();
        std::fs::create_dir_all(d.join("a/blocked")).unwrap();
        let mut out = Outputs::default();
        out.add(d.join("new/deep/x.txt"), "x");
        out.add(d.join("a/y.txt"), "y");
        out.add(d.join("a/blocked"), "z");
        let e = out.commit().unwrap_err().to_string();
        assert!(e.ends_with("blocked: it is a folder"), "{e}");
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
        let dir = Scratch::new("commit");
        let d = dir.0.as_path();
        let mut out = Outputs::default();
        out.add(d.join("f/x.txt"), "old");
        out.add(d.join("f/x.txt"), "new");
        out.add(d.join("y.bin"), vec![1u8, 2]);
        assert_eq!(out.get(&d.join("f/x.txt")), Some(&b"new"[..]));
        assert_eq!(out.len(), 2);
        out.commit().unwrap();
        assert_eq!(std::fs::read_to_string(d.join("f/x.txt")).unwrap(), "new");
        assert_eq!(std::fs::read(d.join("y.bin")).unwrap(), [1, 2]);
        assert_eq!(
            std::fs::read_dir(d.join("f")).unwrap().count(),
            1,
            "no temporaries left"
        );
    }
}
