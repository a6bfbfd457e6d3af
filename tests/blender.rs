//! Blender in the loop (scripts/engines/blender.py slab): the Principled BSDF fields `sss
//! engine-params --engine blender` writes, rendered by Blender's own Cycles (`bpy`, on the CPU),
//! on a thick flat slab under a distant light at normal incidence. Needs `bpy`
//! (scripts/engines/requirements.txt; `.ci/run` installs it); outside CI a machine without it
//! skips, under CI=true it fails.

mod common;

#[test]
fn cycles_random_walk_reflects_what_mc_does() {
    if !common::python_has(
        "bpy, numpy",
        "Blender's Python module",
        "pip install -r scripts/engines/requirements.txt",
    ) {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let json = out.path().join("slab.json");
    common::python_script(
        "scripts/engines/blender.py",
        &["slab".as_ref(), "--json".as_ref(), json.as_os_str()],
        out.path(),
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    // The light first: an opaque white Lambertian slab under a sun of strength 1 has radiance
    // 1/π (Blender's sun strength is irradiance).
    for view in v["calibration"].as_object().unwrap().values() {
        for x in view.as_array().unwrap() {
            assert!((x.as_f64().unwrap() - 1.0).abs() <= 0.005, "{v}");
        }
    }
    let numbers = |c: &serde_json::Value, k: &str| -> Vec<f64> {
        c[k].as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    // The parameters: Cycles' walk starts from the camera, refracting the view ray (by its
    // smallest IOR, 1.01), and reaches the light through a diffuse BSDF where it leaves. Under
    // normal light, π × radiance / irradiance seen from θ is then the escape probability of a walk
    // entering at the refracted angle θt: `mc`'s total diffuse reflectance Rd(θt) of the same σa,
    // σs, g, within 3 % per channel at every one of the five view angles (0° and four
    // Gauss–Legendre nodes up to 75°), with the comparison's own noise well below that.
    // The same on a 0.2 cm slab (1.5–3 mean free paths), whose reflectance depends on lengths
    // where a half-space's does not: the test of the radius.
    let checks = v["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 6, "{v}");
    for c in checks {
        for (r, se) in numbers(c, "ratio").iter().zip(numbers(c, "ratio_se")) {
            assert!((r - 1.0).abs() <= 0.03 && se < 0.01, "{c}");
        }
    }
    let reported = |what: &str| {
        v["reported"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["what"].as_str().unwrap().contains(what))
            .unwrap_or_else(|| panic!("{what}: {v}"))
    };
    // The thin slab can tell: in some channel its reflectance is well over 3 % below the
    // half-space's (a radius off by a factor would show).
    let lengths = reported("what lengths change");
    assert!(
        numbers(lengths, "ratio")
            .iter()
            .zip(numbers(lengths, "ratio_se"))
            .any(|(r, se)| r - 1.0 > 0.03 + 5.0 * se),
        "{lengths}"
    );
    // What Cycles leaves out, resolved in the direction physics says. Its light side is diffuse:
    // tilting the light to 60° leaves π × radiance / (irradiance) unchanged (the medium's own
    // reflectance rises with incidence), ...
    let blind = reported("incidence-blind");
    for (r, se) in numbers(blind, "ratio")
        .iter()
        .zip(numbers(blind, "ratio_se"))
    {
        assert!((r - 1.0).abs() <= 3.0 * se + 1e-3, "{blind}");
    }
    // ... so under normal light it reflects the white-sky albedo, more than Rd(0°), since Rd(θ)
    // rises with θ; ...
    let energy = reported("reflected energy under normal light");
    for (r, se) in numbers(energy, "ratio")
        .iter()
        .zip(numbers(energy, "ratio_se"))
    {
        assert!(r - 1.0 > 5.0 * se, "{energy}");
    }
    // ... and behind Skin1's own boundary (η = 1.3), where the medium reflects light back in at
    // the surface and loses more of it to absorption, Cycles' walk leaves without internal
    // reflection: brighter than `mc`.
    let boundary = reported("no internal reflection");
    assert_eq!(boundary["eta"], 1.3);
    for (r, se) in numbers(boundary, "ratio")
        .iter()
        .zip(numbers(boundary, "ratio_se"))
    {
        assert!(r - 1.0 > 5.0 * se, "{boundary}");
    }
    // Christensen–Burley: reported, finite.
    let burley = reported("Christensen-Burley");
    assert!(
        numbers(burley, "ratio")
            .iter()
            .all(|r| r.is_finite() && *r > 0.0)
    );
    assert_eq!(v["pass"], true);
}
