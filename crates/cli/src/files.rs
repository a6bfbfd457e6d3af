//! Writing outputs atomically: each file goes to a temporary name in its folder and is renamed
//! into place, so a reader never sees a half-written file. All files of a command are rendered
//! in memory first and written only when every one of them rendered.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// Writes every (path, contents) pair atomically, creating folders as needed.
pub fn write_all(files: &[(PathBuf, String)]) -> Result<()> {
    for (path, text) in files {
        write_atomic(path, text.as_bytes())?;
    }
    Ok(())
}

pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create folder {}", dir.display()))?;
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    std::fs::write(&tmp, bytes).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path)
        .with_context(|| format!("cannot move {} into place", path.display()))?;
    Ok(())
}
