//! The built-in material library: the repository's `materials/*.toml`, compiled in so that every
//! tool finds them from any folder. Every medium of Jensen et al. 2001 (the thesis's eleven of
//! Table 6.2, in cm⁻¹, and Spectralon) and the 35 media of Narasimhan et al. 2006 that pbrt and
//! Mitsuba transcribe (undiluted, mm⁻¹, g per channel), plus the five liquids of the
//! directional-dipole draft's Table 4.1 as it quotes them; each file names its source, table
//! and units (docs/media.md).
//!
//! [`REPRODUCED`] names the set that simulations iterate over: code that runs the
//! tracer on "the library" takes [`REPRODUCED`], so that adding media to the library grows
//! neither `sss reproduce` nor CI time.

use crate::error::{McError, Result};
use crate::material::Material;

/// Each stem with its file `materials/STEM.toml`, compiled in.
macro_rules! builtin {
    ($($stem:literal),*) => {
        &[$(($stem, include_str!(concat!("../../../materials/", $stem, ".toml")))),*]
    };
}

/// (file stem, TOML text) of every built-in material, in alphabetical (byte) order of the stems.
pub const MATERIALS: &[(&str, &str)] = builtin!(
    "apple",
    "apple_juice",
    "beer",
    "budweiser_beer",
    "cappuccino_powder",
    "chardonnay",
    "chicken1",
    "chicken2",
    "clorox",
    "coffee",
    "coke",
    "coors_light_beer",
    "cranberry_juice",
    "cream",
    "espresso",
    "gatorade",
    "grape_juice",
    "grapefruit",
    "head_and_shoulders_shampoo",
    "ketchup",
    "lemon_tea_powder",
    "lowfat_chocolate_milk",
    "lowfat_milk",
    "lowfat_soy_milk",
    "marble",
    "merlot",
    "mint_mocha_coffee",
    "orange_powder",
    "pacific_ocean_surface_water",
    "pepsi",
    "pink_lemonade_powder",
    "potato",
    "reduced_milk",
    "regular_chocolate_milk",
    "regular_milk",
    "regular_soy_milk",
    "ruby_grapefruit_juice",
    "salt_powder",
    "shampoo",
    "skimmilk",
    "skin1",
    "skin2",
    "soymilk",
    "spectralon",
    "sprite",
    "strawberry_shampoo",
    "sugar_powder",
    "suisse_mocha_powder",
    "white_grapefruit_juice",
    "white_zinfandel",
    "wholemilk",
    "wine"
);

/// The materials `sss reproduce` simulates and lists in its Table 6.2, the tracer benchmark's
/// library and the GPU tracer's whole-library check: the thesis's eleven (Freude 2014, Table 6.2:
/// Jensen et al. 2001's measurements) and the directional-dipole draft's five liquids (beer,
/// coffee, grapefruit, soymilk, wine: Table 4.1), the library before the media of docs/media.md
/// were added, in alphabetical order.
pub const REPRODUCED: [&str; 16] = [
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
    "wine",
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
/// transport mean free path [cm] (thesis Table 6.1's columns); then, after an empty line, each
/// material's name and source (paper, table and the units it gives) on one line.
pub fn table_lines(materials: &[(&str, &Material)]) -> Vec<String> {
    let w = (materials.iter().map(|(s, _)| s.chars().count()))
        .max()
        .unwrap_or(0)
        .max(11);
    let mut out = vec![format!(
        "{:<w$} {:>2} {:>10} {:>10} {:>6} {:>5} {:>9} {:>10}",
        "material", "ch", "σa [1/cm]", "σs [1/cm]", "g", "η", "albedo", "MFP [cm]"
    )];
    for (slug, m) in materials {
        for (c, ch) in crate::CHANNELS.iter().enumerate() {
            out.push(format!(
                "{:<w$} {:>2} {:>10.4} {:>10.4} {:>6.3} {:>5.2} {:>9.6} {:>10.5}",
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
    out.push(String::new());
    out.push(format!("{:<w$} source", "material"));
    for (slug, m) in materials {
        out.push(format!("{slug:<w$} {}: {}", m.name, m.source));
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

    /// At least 50 media, every one validated on load, naming its paper, table and units.
    #[test]
    fn every_built_in_material_names_its_paper_table_and_units() {
        assert!(
            MATERIALS.len() >= 50,
            "{} built-in materials",
            MATERIALS.len()
        );
        for name in names() {
            let m = Material::builtin(name).unwrap();
            let s = &m.source;
            assert!(
                s.contains("Jensen et al. 2001") || s.contains("Narasimhan et al. 2006"),
                "{name}: {s:?} names no paper"
            );
            assert!(s.contains("Table") || s.contains("Figure"), "{name}: {s:?}");
            assert!(s.contains("mm⁻¹"), "{name}: {s:?} gives no units");
            assert!(!m.name.trim().is_empty(), "{name}");
        }
    }

    /// The list holds every `materials/*.toml` once, in byte order of the stems, and the sets
    /// the simulations take are drawn from it.
    #[test]
    fn the_list_is_the_folder_and_the_simulated_sets_are_in_it() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../materials");
        let mut files: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter_map(|f| f.strip_suffix(".toml").map(str::to_string))
            .collect();
        files.sort();
        assert_eq!(names(), files);
        for stem in names() {
            assert!(
                stem.bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_'),
                "{stem}: a name every tool takes (and no path)"
            );
            assert!(!is_path(stem));
        }
        assert!(REPRODUCED.is_sorted());
        assert!(REPRODUCED.iter().all(|s| names().contains(s)));
    }
}
