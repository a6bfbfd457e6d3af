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

/// A material argument as every tool takes it, with its slug (the short name files are named
/// after): a path ([`is_path`]) read and parsed, slug its file stem in lower case; else a
/// built-in name (case-insensitive), slug the name in lower case.
pub fn resolve(arg: &str) -> Result<(String, Material)> {
    if is_path(arg) {
        let text = crate::input::read_text(arg).map_err(|io| McError::File {
            what: format!("cannot read material file {arg}"),
            io,
        })?;
        let slug = std::path::Path::new(arg)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("material")
            .to_lowercase();
        return Ok((slug, Material::from_toml(&text, arg)?));
    }
    Ok((arg.to_lowercase(), Material::builtin(arg)?))
}

/// The library as a table, one line per material and channel: σa, σs [cm⁻¹], g, η, albedo and
/// transport mean free path [cm] (thesis Table 6.1's columns).
pub fn table_lines(materials: &[(&str, &Material)]) -> Vec<String> {
    let mut out = vec![format!(
        "{:<11} {:>2} {:>10} {:>10} {:>6} {:>5} {:>9} {:>10}",
        "material", "ch", "σa [1/cm]", "σs [1/cm]", "g", "η", "albedo", "MFP [cm]"
    )];
    for (slug, m) in materials {
        for (c, ch) in crate::CHANNELS.iter().enumerate() {
            out.push(format!(
                "{:<11} {:>2} {:>10.4} {:>10.4} {:>6.3} {:>5.2} {:>9.6} {:>10.5}",
                if c == 0 { slug } else { "" },
                ch,
                m.sigma_a[c],
                m.sigma_s[c],
                m.g[c],
                m.eta,
                m.albedo(c),
                m.mfp(c)
            ));
        }
    }
    out
}

/// One material as `sss materials --json` lists it: names, source, η and per channel σa, σs
/// [cm⁻¹], g, albedo and transport mean free path [cm].
pub fn json(slug: &str, m: &Material) -> serde_json::Value {
    use serde_json::json;
    let channels: serde_json::Map<String, serde_json::Value> = (crate::CHANNELS.iter().enumerate())
        .map(|(c, ch)| {
            let v = json!({
                "sigma_a_per_cm": m.sigma_a[c], "sigma_s_per_cm": m.sigma_s[c], "g": m.g[c],
                "albedo": m.albedo(c), "mfp_cm": m.mfp(c),
            });
            (ch.to_string(), v)
        })
        .collect();
    json!({
        "material": slug, "name": m.name, "source": m.source, "eta": m.eta, "channels": channels,
    })
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
