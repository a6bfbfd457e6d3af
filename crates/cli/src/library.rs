//! Materials and run settings as the CLI names them: a built-in name (`mc::builtin`) or a path
//! to a TOML file, and the thesis's settings (`mc::SimConfig::thesis`) or a file.

use std::path::Path;

use anyhow::{Result, bail};
use mc::SimConfig;

/// A material with the short name used for file names.
pub use render::NamedMaterial as Named;

/// Resolves a material argument: a path to a TOML file (contains a path separator or ends in
/// `.toml`), else a built-in name (case-insensitive).
pub fn material(arg: &str) -> Result<Named> {
    if !mc::builtin::is_path(arg) && !mc::builtin::names().contains(&arg.to_lowercase().as_str()) {
        bail!(
            "unknown material {arg:?} (built-in: {}; or give a path to a .toml file)",
            mc::builtin::names().join(", ")
        );
    }
    let (slug, material) = mc::builtin::resolve(arg)?;
    material.notes().iter().for_each(|n| eprintln!("note: {n}"));
    Ok(Named { slug, material })
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
