//! The built-in material library and run settings (the repository's `materials/*.toml` and
//! `configs/thesis.toml`, compiled in so `sss` works from any folder), and lookup by name or path.

use std::path::Path;

use anyhow::{Context, Result, bail};
use mc::{Material, SimConfig};

/// (file stem, TOML text) of every built-in material.
pub const MATERIALS: &[(&str, &str)] = &[
    ("apple", include_str!("../../../materials/apple.toml")),
    ("beer", include_str!("../../../materials/beer.toml")),
    ("chicken1", include_str!("../../../materials/chicken1.toml")),
    ("chicken2", include_str!("../../../materials/chicken2.toml")),
    ("coffee", include_str!("../../../materials/coffee.toml")),
    ("cream", include_str!("../../../materials/cream.toml")),
    (
        "grapefruit",
        include_str!("../../../materials/grapefruit.toml"),
    ),
    ("ketchup", include_str!("../../../materials/ketchup.toml")),
    ("marble", include_str!("../../../materials/marble.toml")),
    ("potato", include_str!("../../../materials/potato.toml")),
    ("skimmilk", include_str!("../../../materials/skimmilk.toml")),
    ("skin1", include_str!("../../../materials/skin1.toml")),
    ("skin2", include_str!("../../../materials/skin2.toml")),
    ("soymilk", include_str!("../../../materials/soymilk.toml")),
    (
        "wholemilk",
        include_str!("../../../materials/wholemilk.toml"),
    ),
    ("wine", include_str!("../../../materials/wine.toml")),
];

/// The thesis's simulation settings (Table 6.1).
pub const THESIS_CONFIG: &str = include_str!("../../../configs/thesis.toml");

/// A material with the short name used for file names.
pub struct Named {
    pub slug: String,
    pub material: Material,
}

/// Resolves a material argument: a path to a TOML file (contains a path separator or ends in
/// `.toml`), else a built-in name (case-insensitive).
pub fn material(arg: &str) -> Result<Named> {
    if arg.ends_with(".toml") || arg.contains('/') || arg.contains('\\') {
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
    let key = arg.to_lowercase();
    match MATERIALS.iter().find(|(name, _)| *name == key) {
        Some((name, text)) => Ok(Named {
            slug: name.to_string(),
            material: Material::from_toml(text, &format!("materials/{name}.toml"))?,
        }),
        None => {
            let known: Vec<&str> = MATERIALS.iter().map(|(n, _)| *n).collect();
            bail!(
                "unknown material {arg:?} (built-in: {}; or give a path to a .toml file)",
                known.join(", ")
            )
        }
    }
}

/// Resolves every material argument (see [`material`]).
pub fn materials(args: &[String]) -> Result<Vec<Named>> {
    args.iter().map(|m| material(m)).collect()
}

/// Every built-in material, in alphabetical order.
pub fn all() -> Result<Vec<Named>> {
    MATERIALS.iter().map(|(n, _)| material(n)).collect()
}

/// The run settings: a TOML file, or the built-in thesis settings.
pub fn config(path: Option<&Path>) -> Result<SimConfig> {
    match path {
        Some(p) => {
            let text = crate::files::read_text(p)
                .with_context(|| format!("cannot read config file {}", p.display()))?;
            Ok(SimConfig::from_toml(&text, &p.display().to_string())?)
        }
        None => Ok(SimConfig::from_toml(THESIS_CONFIG, "configs/thesis.toml")?),
    }
}
