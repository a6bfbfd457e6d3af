//! The built-in material library: the repository's `materials/*.toml` (the thesis's eleven
//! materials of Table 6.2 and five of Narasimhan et al.'s liquids), compiled in so that every
//! tool finds them from any folder.

use crate::error::{McError, Result};
use crate::material::Material;

/// Each stem with its file `materials/STEM.toml`, compiled in.
macro_rules! builtin {
    ($($stem:literal),*) => {
        &[$(($stem, include_str!(concat!("../../../materials/", $stem, ".toml")))),*]
    };
}

/// (file stem, TOML text) of every built-in material.
pub const MATERIALS: &[(&str, &str)] = builtin!(
    "apple",
    "beer",
    "chicken1",
    "chicken2",
    "coffee",
    "cream",
    "grapefruit",
    "ketchup",
    "marble",
    "potato",
    "skimmilk",
    "skin1",
    "skin2",
    "soymilk",
    "wholemilk",
    "wine"
);

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

/// Whether a material argument names a file (it ends in `.toml` or holds a path separator)
/// rather than a built-in material: the rule every tool applies.
pub fn is_path(arg: &str) -> bool {
    arg.ends_with(".toml") || arg.contains('/') || arg.contains('\\')
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
