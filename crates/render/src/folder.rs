//! A render's folder: `render.json` beside `render.png` and `render.pfm` says which scene and
//! materials they show, so that a render of another scene or material is refused there instead
//! of silently replacing them.

use std::path::Path;

use crate::error::{RenderError, Result};

/// The file beside a render's images that says what they show (the command's JSON summary, with
/// at least `scene` and `materials`).
pub const RECORD: &str = "render.json";

/// The images a render writes into its folder.
pub const IMAGES: [&str; 2] = ["render.png", "render.pfm"];

/// Refuses to render into `dir` where it already holds a render of another scene or of other
/// materials (what its [`RECORD`] names; images without a readable record count as another
/// render), unless `overwrite`. The same scene and materials again replace the earlier render:
/// a change of light, size or method is that render redone.
pub fn claim(dir: &Path, scene: &str, materials: &[String], overwrite: bool) -> Result<()> {
    if overwrite || !IMAGES.iter().any(|f| dir.join(f).exists()) {
        return Ok(());
    }
    let record = std::fs::read(dir.join(RECORD))
        .ok()
        .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok());
    let held = record.as_ref().and_then(|r| {
        let names = r["materials"].as_array()?.iter().map(|m| m.as_str());
        Some((r["scene"].as_str()?, names.collect::<Option<Vec<&str>>>()?))
    });
    let what = match held {
        Some((s, m)) if s == scene && m == materials => return Ok(()),
        Some((s, m)) => format!("a render of scene {s} with {}", m.join(", ")),
        None => format!("images of a render without its {RECORD}"),
    };
    Err(RenderError::invalid(
        "out",
        dir.display(),
        format!("the folder holds {what}; pass --overwrite to replace it, or name another folder"),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(dir: &Path, scene: &str, materials: &[&str]) {
        let json = serde_json::json!({ "scene": scene, "materials": materials });
        std::fs::write(dir.join(RECORD), json.to_string()).unwrap();
        std::fs::write(dir.join(IMAGES[0]), b"png").unwrap();
    }

    /// An empty or missing folder and the same render again pass; another scene, other
    /// materials or images without a record are refused by name, unless overwriting.
    #[test]
    fn a_folder_holding_another_render_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let skin = ["skin1".to_string()];
        claim(&d.path().join("new"), "sphere", &skin, false).unwrap();
        claim(d.path(), "sphere", &skin, false).unwrap();
        record(d.path(), "sphere", &["skin1"]);
        claim(d.path(), "sphere", &skin, false).unwrap();
        let e = claim(d.path(), "fin", &skin, false)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("out") && e.contains("scene sphere") && e.contains("--overwrite"),
            "{e}"
        );
        let marble = ["marble".to_string()];
        assert!(claim(d.path(), "sphere", &marble, false).is_err());
        claim(d.path(), "fin", &skin, true).unwrap();
        std::fs::remove_file(d.path().join(RECORD)).unwrap();
        let e = claim(d.path(), "sphere", &skin, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("without its render.json"), "{e}");
    }
}
