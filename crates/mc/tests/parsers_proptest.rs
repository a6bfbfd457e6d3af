//! Hostile input for every text `mc` reads from users: material TOML ([`Material::from_toml`]),
//! run settings TOML ([`SimConfig::from_toml`]) and MCML's `.mci` ([`mc::mci::parse`]).
//!
//! Requirement: no panic, no abort (a count in the file never sizes an allocation before it is
//! checked), no silently accepted garbage (whatever parses validates), and every refusal is a
//! typed [`McError`] that names the field and the value.

use testkit::hostile;

use mc::{Material, McError, SimConfig};
use proptest::prelude::*;

const MATERIAL: &str = "name = \"Skin1\"\nsource = \"Jensen et al. 2001\"\nunit = \"cm\"\nsigma_a = [0.32, 1.7, 4.8]\nsigma_s = [7.4, 8.8, 10.1]\ng = 0.0\neta = 1.3\nthickness = 2.5\n";

const ARTIST: &str = "name = \"Wax\"\nunit = \"mm\"\ncolor = [0.8, 0.6, 0.4]\nradius = [1.0, 0.5, 0.25]\ng = [0.0, 0.5, 0.9]\neta = 1.4\n";

const CONFIG: &str = "photons = 10_000_000\nseed = 1\nthickness_cm = 1e8\nn_above = 1.0\nn_below = 1.0\n\n[grid]\ndr_per_min_mfp = 20.0\nr_max_mfp = 32.0\nz_max_mfp = 32.0\nnz = 100\nna = 30\n";

const MCI: &str = "1.0 # version\n\n2 # runs\n\n# run 1\na.mco A\n1000\n0.01 0.02\n10 20 5\n2\n1.0\n1.37 1 100 0.9 0.1 # layer 1\n1.4 2 10 0 0.2\n1.0\n\nb.mco\tA\n50 1\n0.1 0.1\n1 2 3\n1\n1\n1.5 10 90 0.75 0.02\n1\n";

/// A refusal must say where: a field and value, or a line of the input.
fn check_error(e: &McError, text: &str) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    match e {
        McError::InvalidValue { field, value, .. } => {
            prop_assert!(!field.is_empty() && !value.is_empty(), "{msg}");
        }
        McError::Parse { line, message, .. } => {
            prop_assert!(!message.is_empty(), "{msg}");
            prop_assert!(*line <= text.lines().count().max(1), "{msg}");
        }
        McError::ShardMismatch(_)
        | McError::Slice(_)
        | McError::ShardLabel { .. }
        | McError::ShardLabelCount(_)
        | McError::Artist(_) => {
            prop_assert!(false, "a parser reported a shard error: {msg}")
        }
        McError::File { .. } => prop_assert!(false, "a parser reported a file error: {msg}"),
    }
    Ok(())
}

fn check_material(text: &str) -> Result<(), TestCaseError> {
    match Material::from_toml(text, "m.toml") {
        Ok(m) => {
            prop_assert!(m.validate().is_ok(), "accepted an invalid material: {m:?}");
            prop_assert!(!m.name.trim().is_empty(), "accepted an empty name: {m:?}");
        }
        Err(e) => check_error(&e, text)?,
    }
    Ok(())
}

fn check_config(text: &str) -> Result<(), TestCaseError> {
    match SimConfig::from_toml(text, "c.toml") {
        Ok(c) => {
            for v in [c.thickness_cm, c.n_above, c.n_below, c.grid.dr_per_min_mfp] {
                prop_assert!(v.is_finite() && v > 0.0, "accepted {c:?}");
            }
            prop_assert!(
                c.grid.r_max_mfp.is_finite() && c.grid.r_max_mfp > 0.0,
                "{c:?}"
            );
            prop_assert!(
                c.grid.z_max_mfp.is_finite() && c.grid.z_max_mfp > 0.0,
                "{c:?}"
            );
            prop_assert!((1..=1_000_000).contains(&c.grid.nz), "accepted {c:?}");
            prop_assert!((1..=1_000_000).contains(&c.grid.na), "accepted {c:?}");
            prop_assert!(c.photons >= 1, "accepted {c:?}");
            // Deriving a grid for a real material must then fail cleanly or validate.
            let m = Material::from_toml(MATERIAL, "m.toml").unwrap();
            if let Ok(g) = c.grid_for(&m) {
                prop_assert!(g.validate().is_ok());
            }
        }
        Err(e) => check_error(&e, text)?,
    }
    Ok(())
}

fn check_mci(text: &str) -> Result<(), TestCaseError> {
    match mc::mci::parse(text, "t.mci", 1) {
        Ok(runs) => {
            prop_assert!(!runs.is_empty());
            for r in &runs {
                prop_assert!(r.spec.validate().is_ok(), "accepted an invalid run: {r:?}");
                prop_assert!(r.spec.photons < u64::MAX, "photon count saturated: {r:?}");
                prop_assert!(!r.out_name.is_empty());
            }
        }
        Err(e) => check_error(&e, text)?,
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn material_toml_survives_hostile_input(text in hostile::hostile(MATERIAL)) {
        check_material(&text)?;
    }

    #[test]
    fn artist_material_toml_survives_hostile_input(text in hostile::hostile(ARTIST)) {
        check_material(&text)?;
    }

    #[test]
    fn config_toml_survives_hostile_input(text in hostile::hostile(CONFIG)) {
        check_config(&text)?;
    }

    #[test]
    fn mci_survives_hostile_input(text in hostile::hostile(MCI)) {
        check_mci(&text)?;
    }
}

/// Replaces the `k`-th numeric token of `text` by `v`.
fn replace_number(text: &str, k: usize, v: &str) -> String {
    let (a, b) = hostile::numbers(text)[k];
    format!("{}{v}{}", &text[..a], &text[b..])
}

/// Every number of every file, replaced in turn by every hostile value: no panic, and no
/// accepted garbage (a deterministic sweep complementing the random mutations above).
#[test]
fn every_number_replaced_by_every_hostile_value() {
    for (valid, check) in [
        (
            MATERIAL,
            check_material as fn(&str) -> Result<(), TestCaseError>,
        ),
        (ARTIST, check_material),
        (CONFIG, check_config),
        (MCI, check_mci),
    ] {
        for k in 0..hostile::numbers(valid).len() {
            for v in hostile::HOSTILE_NUMBERS {
                let text = replace_number(valid, k, v);
                if let Err(e) = check(&text) {
                    panic!("{e}\n--- input:\n{text}");
                }
            }
        }
    }
}

/// Refusals name the field and the value as written.
#[test]
fn material_errors_name_field_and_value() {
    for (from, to, field, value) in [
        ("sigma_a = [0.32", "sigma_a = [nan", "sigma_a[R]", "NaN"),
        ("1.7, 4.8]", "1.7, inf]", "sigma_a[B]", "inf"),
        ("sigma_s = [7.4", "sigma_s = [-1", "sigma_s[R]", "-1"),
        ("g = 0.0", "g = 1e308", "g[R]", "1e308"),
        ("eta = 1.3", "eta = 0", "eta", "0"),
        ("thickness = 2.5", "thickness = -inf", "thickness", "-inf"),
        ("unit = \"cm\"", "unit = \"\"", "unit", "\"\""),
        ("name = \"Skin1\"", "name = \"  \"", "name", "\"  \""),
    ] {
        let text = MATERIAL.replace(from, to);
        let e = Material::from_toml(&text, "m.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(field) && e.contains(value),
            "{to}: {e} should name {field} and {value}"
        );
    }
    for (from, to, field, value) in [
        ("0.8, 0.6", "0.8, -0.6", "color[G]", "-0.6"),
        ("0.25]", "nan]", "radius[B]", "NaN"),
    ] {
        let text = ARTIST.replace(from, to);
        let e = Material::from_toml(&text, "m.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains(field) && e.contains(value), "{to}: {e}");
    }
    let e = Material::from_toml("name = \"x\"\nunit = \"cm\"\ng = \"🦀\"\n", "m.toml")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("m.toml:"), "{e}");
}

/// The limits decided from physics (docs/commands.md, "Materials"): g = 1 scatters without
/// deflecting, so the medium never returns light and is refused naming g and the way to a
/// non-scattering channel; g = −1 (straight back) is a real limit and runs. One η for the three
/// channels: three equal values are that value, three different ones are refused naming eta.
/// η < 1 runs with a note giving the critical angle seen from the air, asin(η/1).
#[test]
fn material_limits_are_decided_from_physics() {
    let with = |from: &str, to: &str| Material::from_toml(&MATERIAL.replace(from, to), "m.toml");
    let e = with("g = 0.0", "g = 1.0").unwrap_err().to_string();
    assert!(e.contains("g[R]") && e.contains("sigma_s = 0"), "{e}");
    let e = with("g = 0.0", "g = [0.5, 0.5, 1]")
        .unwrap_err()
        .to_string();
    assert!(e.contains("g[B]"), "{e}");
    assert_eq!(with("g = 0.0", "g = -1.0").unwrap().g, [-1.0; 3]);
    assert_eq!(with("g = 0.0", "g = 0.9999").unwrap().g, [0.9999; 3]);
    let m = with("eta = 1.3", "eta = [1.66, 1.66, 1.66]").unwrap();
    assert_eq!(m.eta, 1.66);
    let e = with("eta = 1.3", "eta = [1.3, 1.4, 1.5]")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("eta") && e.contains("one refractive index"),
        "{e}"
    );
    assert!(with("eta = 1.3", "eta = 1.3").unwrap().notes().is_empty());
    let notes = with("eta = 1.3", "eta = 0.5").unwrap().notes();
    assert!(notes.len() == 1 && notes[0].contains("30.0°"), "{notes:?}");
}

/// A TOML mistake is reported on its own line (a misspelled field on line 4 at line 4, not 3),
/// a missing field by name without a line, and a half-given pair of coefficients names the
/// missing one alone.
#[test]
fn material_errors_point_at_the_line_or_the_missing_field() {
    let text = MATERIAL.replace("g = 0.0", "gg = 0.0");
    let line = 1 + text.lines().position(|l| l.starts_with("gg")).unwrap();
    let e = Material::from_toml(&text, "m.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!("m.toml:{line}: unknown field `gg`")),
        "{e}"
    );
    let e = Material::from_toml(&MATERIAL.replace("unit = \"cm\"\n", ""), "m.toml")
        .unwrap_err()
        .to_string();
    assert_eq!(e, "m.toml: missing field `unit`");
    for (drop, named) in [
        ("sigma_s = [7.4, 8.8, 10.1]\n", "sigma_s"),
        ("sigma_a = [0.32, 1.7, 4.8]\n", "sigma_a"),
    ] {
        let e = Material::from_toml(&MATERIAL.replace(drop, ""), "m.toml")
            .unwrap_err()
            .to_string();
        let other = if named == "sigma_s" {
            "sigma_a"
        } else {
            "sigma_s"
        };
        assert!(
            e.contains(&format!("invalid {named}")) && e.contains(&format!("{other} is given")),
            "{e}"
        );
        assert!(!e.contains("color"), "{e}");
    }
}

#[test]
fn config_errors_name_field_and_value() {
    for (from, to, field, value) in [
        ("photons = 10_000_000", "photons = 0", "photons", "0"),
        (
            "thickness_cm = 1e8",
            "thickness_cm = nan",
            "thickness_cm",
            "NaN",
        ),
        ("n_above = 1.0", "n_above = 0.0", "n_above", "0"),
        ("n_below = 1.0", "n_below = -inf", "n_below", "-inf"),
        (
            "dr_per_min_mfp = 20.0",
            "dr_per_min_mfp = -1",
            "grid.dr_per_min_mfp",
            "-1",
        ),
        ("nz = 100", "nz = 0", "grid.nz", "0"),
        (
            "na = 30",
            "na = 1000000000000000",
            "grid.na",
            "1000000000000000",
        ),
    ] {
        let text = CONFIG.replace(from, to);
        let e = SimConfig::from_toml(&text, "c.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(field) && e.contains(value),
            "{to}: {e} should name {field} and {value}"
        );
    }
    // A count too large for its type is a parse error pointing at its line.
    let e = SimConfig::from_toml(&CONFIG.replace("10_000_000", "1e15"), "c.toml")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("c.toml:1:"), "{e}");
}

/// Counts of 10¹⁵ (runs, layers, bins, photons) must be refused or run out of lines, never size
/// an allocation.
#[test]
fn mci_huge_counts_are_refused_before_allocating() {
    for (from, to, field, value) in [
        (
            "2 # runs",
            "1000000000000000 # runs",
            "run 3",
            "1000000000000000",
        ),
        ("10 20 5", "10 1e15 5", "run 1 nr", "1000000000000000"),
        ("10 20 5", "10 20 1e308", "run 1 na", "1e308"),
        ("1000\n", "1e308\n", "run 1 number of photons", "1e308"),
        (
            "1000\n",
            "18446744073709551616\n",
            "run 1 number of photons",
            "1.8446744073709552e19",
        ),
        ("1000\n", "NaN\n", "run 1 number of photons", "NaN"),
        ("1000\n", "0.5\n", "run 1 number of photons", "0.5"),
        (
            "\n2\n1.0\n1.37",
            "\n1e15\n1.0\n1.37",
            "run 1 layer 3",
            "1000000000000000",
        ),
        (
            "\n2\n1.0\n1.37",
            "\n1e308\n1.0\n1.37",
            "run 1 number of layers",
            "1e308",
        ),
        (
            "\n2\n1.0\n1.37",
            "\n-1\n1.0\n1.37",
            "run 1 number of layers",
            "-1",
        ),
        ("0.01 0.02", "0.01 inf", "run 1 dr", "inf"),
        (
            "1.37 1 100 0.9 0.1",
            "1.37 1 100 0.9 1e309",
            "run 1 layer 1 thickness",
            "inf",
        ),
    ] {
        let text = MCI.replacen(from, to, 1);
        assert_ne!(text, MCI, "{from:?} not found");
        let e = mc::mci::parse(&text, "t.mci", 1).unwrap_err().to_string();
        assert!(
            e.contains(field) && e.contains(value),
            "{to:?}: {e} should name {field} and {value}"
        );
    }
    // 10¹⁴ photons (mc::MAX_PHOTONS) is a legal, if long, run; 10¹⁵ a typed exponent, refused
    // naming the count.
    let runs = mc::mci::parse(&MCI.replacen("1000\n", "1e14\n", 1), "t.mci", 1).unwrap();
    assert_eq!(runs[0].spec.photons, mc::MAX_PHOTONS);
    let e = mc::mci::parse(&MCI.replacen("1000\n", "1e15\n", 1), "t.mci", 1).unwrap_err();
    assert!(e.to_string().contains("run 1 photons"), "{e}");
}
