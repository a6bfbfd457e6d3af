//! Materials and run settings as the CLI names them: a built-in name (`mc::builtin`) or a path
//! to a TOML file, and the thesis's settings (`mc::SimConfig::thesis`) or a file.

use std::path::Path;

use anyhow::{Context, Result, bail};
use mc::{Material, SimConfig};

/// A material with the short name used for file names.
pub use render::NamedMaterial as Named;

/// Resolves a material argument: a path to a TOML file (contains a path separator or ends in
/// `.toml`), else a built-in name (case-insensitive).
pub fn material(arg: &str) -> Result<Named> {
    if mc::builtin::is_path(arg) {
        let text = crate::files::read_text(arg)
            .with_context(|| format!("cannot read material file {arg}"))?;
        let material = Material::from_toml(&text, arg)?;
        let slug = Path::new(arg)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("material")
            .to_lowercase();
        return Ok(Named { slug, material });
    }
    if !mc::builtin::names().contains(&arg.to_lowercase().as_str()) {
        bail!(
            "unknown material {arg:?} (built-in: {}; or give a path to a .toml file)",
            mc::builtin::names().join(", ")
        );
    }
    Ok(Named {
        slug: arg.to_lowercase(),
        material: Material::builtin(arg)?,
    })
}

/// Resolves every material argument (see [`material`]).
pub fn materials(args: &[String]) -> Result<Vec<Named>> {
    args.iter().map(|m| material(m)).collect()
}

/// Every built-in material, in alphabetical order.
pub fn all() -> Result<Vec<Named>> {
    mc::builtin::names().into_iter().map(material).collect()
}

/// The run settings: a TOML file, or the built-in thesis settings.
pub fn config(path: Option<&Path>) -> Result<SimConfig> {
    Ok(SimConfig::read(path)?)
}
