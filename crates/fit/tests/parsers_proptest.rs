//! Hostile input for every text `fit` reads from users: profile CSV ([`Profile::parse_csv`],
//! [`Profile::from_csv`]) and kernel TOML ([`ShaderKernel::from_toml`]).
//!
//! Requirement: no panic, no silently accepted garbage (whatever parses is usable: finite,
//! increasing radii, taps a shader can hold), and every refusal is a typed [`FitError`] naming
//! the field and value or the line.

use testkit::hostile;

use fit::taps::ShaderKernel;
use fit::{FitError, Profile};
use proptest::prelude::*;

const PROFILE: &str = "r_cm,R,G,B,R_se,G_se,B_se\n0.006666666666666667,12.5,9.75,3.5,0.25,0.125,0.0625\n0.015185185185185185,8.5,5.25,1.5,0.25,0.125,0.0625\n0.025111111111111112,4.5,2.25,0.5,0.125,0.0625,0.03125\n0.03507936507936508,2.5,1.25,0.25,0.0625,0.03125,0\n0.04506172839506173,1.5,0.5,0,0.03125,0,0\n0.05505050505050505,0.75,0.25,0,0,0,0\n";

const KERNEL: &str = "model = \"svd2-renorm\"\nmaterial = \"skin1\"\nunit = \"mm\"\ntaps = 3\nrange = 2.0\njitter = 0.25\n\n[[pass]]\nsign = [1.0, 1.0, 1.0]\n\n[[pass.tap]]\noffset = -2.0\nweight = [0.125, 0.25, 0.0625]\n\n[[pass.tap]]\noffset = 0.0\nweight = [0.5, 0.375, 0.75]\n\n[[pass.tap]]\noffset = 2.0\nweight = [0.125, 0.25, 0.0625]\n\n[[pass]]\nsign = [-1.0, 1.0, -1.0]\n\n[[pass.tap]]\noffset = -2.0\nweight = [0.01, 0.02, 0.03]\n\n[[pass.tap]]\noffset = 0.0\nweight = [0.04, 0.05, 0.06]\n\n[[pass.tap]]\noffset = 2.0\nweight = [0.01, 0.02, 0.03]\n";

/// A refusal must say where: a field and value, or a line of the input.
fn check_error(e: &FitError, text: &str) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    match e {
        FitError::Invalid { field, value, .. } => {
            prop_assert!(!field.is_empty() && !value.is_empty(), "{msg}");
        }
        FitError::Parse { line, message, .. } => {
            prop_assert!(!message.is_empty(), "{msg}");
            prop_assert!(*line <= text.lines().count().max(1), "{msg}");
        }
        FitError::Plot { .. } => prop_assert!(false, "a parser reported a plot error: {msg}"),
    }
    Ok(())
}

/// What every parsed profile guarantees: at least two bins, positive finite dr, finite strictly
/// increasing radii, finite values, finite non-negative standard errors.
fn check_profile_shape(p: &Profile) -> Result<(), TestCaseError> {
    prop_assert!(p.len() >= 2, "{p:?}");
    prop_assert!(p.dr.is_finite() && p.dr > 0.0, "{p:?}");
    prop_assert!(p.r.iter().all(|r| r.is_finite() && *r > 0.0), "{p:?}");
    prop_assert!(p.r.windows(2).all(|w| w[0] < w[1]), "{p:?}");
    for c in 0..3 {
        prop_assert_eq!(p.rd[c].len(), p.len());
        prop_assert_eq!(p.se[c].len(), p.len());
        prop_assert!(p.rd[c].iter().all(|v| v.is_finite()), "{p:?}");
        prop_assert!(p.se[c].iter().all(|v| v.is_finite() && *v >= 0.0), "{p:?}");
    }
    Ok(())
}

fn check_profile(text: &str) -> Result<(), TestCaseError> {
    match Profile::parse_csv(text, "p.csv") {
        Ok(p) => check_profile_shape(&p)?,
        Err(e) => check_error(&e, text)?,
    }
    match Profile::from_csv(text, "p.csv") {
        Ok(p) => {
            check_profile_shape(&p)?;
            prop_assert!(p.validate().is_ok());
            // Lookups anywhere stay finite on a fittable profile.
            for c in 0..3 {
                for r in [
                    0.0,
                    p.r[0],
                    0.5 * (p.r[0] + p.r[1]),
                    p.r[p.len() - 1],
                    1e300,
                ] {
                    prop_assert!(p.at(c, r).is_finite(), "{p:?} at {r}");
                }
            }
        }
        Err(e) => check_error(&e, text)?,
    }
    Ok(())
}

/// A shader can use what parses: 1..=1025 taps in every pass, numbers within f32, unit signs,
/// jitter in [0, 1], offsets in cm; and the file round-trips.
fn check_kernel(text: &str) -> Result<(), TestCaseError> {
    let k = match ShaderKernel::from_toml(text, "k.toml") {
        Ok(k) => k,
        Err(e) => return check_error(&e, text),
    };
    let f32_ok = |v: f64| v.is_finite() && v.abs() <= f32::MAX as f64;
    prop_assert!((1..=1025).contains(&k.taps), "{k:?}");
    prop_assert!((0.0..=1.0).contains(&k.jitter), "{k:?}");
    prop_assert!(f32_ok(k.range) && k.range >= 0.0, "{k:?}");
    prop_assert_eq!(&k.unit, "cm");
    prop_assert!(!k.pass.is_empty());
    for p in &k.pass {
        prop_assert_eq!(p.tap.len(), k.taps);
        prop_assert!(p.sign.iter().all(|s| s.abs() == 1.0), "{p:?}");
        for t in &p.tap {
            prop_assert!(
                f32_ok(t.offset) && t.weight.iter().all(|w| f32_ok(*w)),
                "{t:?}"
            );
        }
    }
    let again = ShaderKernel::from_toml(&k.to_toml(), "again.toml");
    prop_assert!(again.as_ref().is_ok_and(|a| *a == k), "{again:?}");
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn profile_csv_survives_hostile_input(text in hostile::hostile(PROFILE)) {
        check_profile(&text)?;
    }

    #[test]
    fn kernel_toml_survives_hostile_input(text in hostile::hostile(KERNEL)) {
        check_kernel(&text)?;
    }

    /// Whole rows of random numbers, hostile values included.
    #[test]
    fn profile_csv_of_random_rows(rows in prop::collection::vec(
        prop::collection::vec(prop_oneof![
            any::<f64>().prop_map(|v| v.to_string()),
            prop::sample::select(hostile::HOSTILE_NUMBERS).prop_map(str::to_string),
        ], 0..9),
        0..12,
    )) {
        let text = std::iter::once("r_cm,R,G,B,R_se,G_se,B_se".to_string())
            .chain(rows.iter().map(|r| r.join(",")))
            .collect::<Vec<_>>()
            .join("\n");
        check_profile(&text)?;
    }
}

/// Every number of both files, replaced in turn by every hostile value.
#[test]
fn every_number_replaced_by_every_hostile_value() {
    for (valid, check) in [
        (
            PROFILE,
            check_profile as fn(&str) -> Result<(), TestCaseError>,
        ),
        (KERNEL, check_kernel),
    ] {
        for (a, b) in hostile::numbers(valid) {
            for v in hostile::HOSTILE_NUMBERS {
                let text = format!("{}{v}{}", &valid[..a], &valid[b..]);
                if let Err(e) = check(&text) {
                    panic!("{e}\n--- input:\n{text}");
                }
            }
        }
    }
}

#[test]
fn profile_errors_name_column_and_value() {
    for (from, to, needle) in [
        ("0.015185185185185185,8.5", "NaN,8.5", "r_cm = NaN"),
        ("0.015185185185185185,8.5", "0.001,8.5", "r_cm = 0.001"),
        ("12.5,9.75", "12.5,inf", "G = inf"),
        (
            "0.25,0.125,0.0625\n0.015",
            "0.25,-1,0.0625\n0.015",
            "G_se = -1",
        ),
        (
            "0.006666666666666667,",
            "-0.006666666666666667,",
            "r_cm = -0.006666666666666667",
        ),
        ("0.006666666666666667,", "0,", "r_cm = 0"),
    ] {
        let text = PROFILE.replacen(from, to, 1);
        assert_ne!(text, PROFILE, "{from:?} not found");
        let e = Profile::parse_csv(&text, "p.csv").unwrap_err().to_string();
        assert!(
            e.starts_with("p.csv:") && e.contains(needle),
            "{to}: {e} should name {needle}"
        );
    }
}

#[test]
fn kernel_errors_name_field_and_value() {
    for (from, to, field, value) in [
        ("taps = 3", "taps = 0", "taps", "0"),
        (
            "taps = 3",
            "taps = 1000000000000000",
            "taps",
            "1000000000000000",
        ),
        ("jitter = 0.25", "jitter = nan", "jitter", "NaN"),
        ("jitter = 0.25", "jitter = 2", "jitter", "2"),
        ("range = 2.0", "range = 1e308", "range", "1e308"),
        ("offset = 0.0", "offset = 1e300", "pass[0].tap[1]", "1e300"),
        ("[0.5, 0.375", "[-1e39, 0.375", "pass[0].tap[1]", "-1e39"),
        ("sign = [-1.0", "sign = [nan", "pass[1].sign", "NaN"),
        ("unit = \"mm\"", "unit = \"\u{1F980}\"", "unit", "\u{1F980}"),
    ] {
        let text = KERNEL.replacen(from, to, 1);
        assert_ne!(text, KERNEL, "{from:?} not found");
        let e = ShaderKernel::from_toml(&text, "k.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(field) && e.contains(value),
            "{to}: {e} should name {field} and {value}"
        );
    }
    let e = ShaderKernel::from_toml(
        &KERNEL.replace("svd2-renorm", "svd1000000000000000"),
        "k.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("k.toml:1:") && e.contains("1000000000000000"),
        "{e}"
    );
}
