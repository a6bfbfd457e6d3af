//! The built-in material library: the repository's `materials/*.toml` (the thesis's eleven
//! materials of Table 6.2 and five of Narasimhan et al.'s liquids), compiled in so that every
//! tool finds them from any folder.

use crate::error::{McError, Result};
use crate::material::Material;

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

impl Material {
    /// The built-in material `name` (a file stem of [`MATERIALS`], case-insensitive).
    pub fn builtin(name: &str) -> Result<Material> {
        let key = name.to_lowercase();
        match MATERIALS.iter().find(|(stem, _)| *stem == key) {
            Some((stem, text)) => Material::from_toml(text, &format!("materials/{stem}.toml")),
            None => Err(McError::invalid(
                "material",
                format!("{name:?} (built-in: {})", names().join(", ")),
                "is not a built-in material",
            )),
        }
    }
}

/// The built-in materials' names, in alphabetical order.
pub fn names() -> Vec<&'static str> {
    MATERIALS.iter().map(|(n, _)| *n).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_material_parses_and_unknown_names_are_refused() {
        for name in names() {
            assert!(Material::builtin(name).is_ok(), "{name}");
        }
        assert_eq!(Material::builtin("SKIN1").unwrap().name, "Skin1");
        let e = Material::builtin("unobtainium").unwrap_err().to_string();
        assert!(e.contains("unobtainium") && e.contains("skin1"), "{e}");
    }
}
