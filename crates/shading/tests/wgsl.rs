//! The WGSL beside the tables stands on its own: the lookups with the package's bindings parse
//! and validate with naga, and each file declares the functions its documentation names (the GPU
//! tests in `gpu` compare what they compute with the CPU twins).

fn validate(name: &str, src: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(src)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(src)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    module
}

#[test]
fn the_lookups_validate_with_the_package_bindings() {
    let src = format!("{}\n{}", shading::LOOKUPS_WGSL, shading::BINDINGS_WGSL);
    let module = validate("lookups + bindings", &src);
    let names: Vec<_> = module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .collect();
    for f in [
        "fresnel",
        "angle_index",
        "sss_incidence",
        "sss_exit",
        "sss_entry_shift",
        "sss_entry_offset",
        "sss_translucency",
        "sss_translucency_exit",
        "sss_back_face_entry",
    ] {
        assert!(
            names.iter().any(|n| n == f),
            "{f} is missing from {names:?}"
        );
    }
}

#[test]
fn the_files_without_accessors_validate_on_their_own() {
    for (name, src) in [
        ("fresnel.wgsl", shading::FRESNEL_WGSL),
        ("angles.wgsl", shading::ANGLES_WGSL),
        ("material.wgsl", shading::MATERIAL_WGSL),
    ] {
        validate(name, src);
    }
}

#[test]
fn a_lookup_without_its_accessor_does_not_validate() {
    // The accessors are the host's: without them the lookups are incomplete, not silently
    // bound to something.
    let src = format!("{}\n{}", shading::ANGLES_WGSL, shading::EXIT_WGSL);
    assert!(naga::front::wgsl::parse_str(&src).is_err());
}

#[test]
fn material_wgsl_has_the_packed_layout() {
    let src = format!(
        "{}\n@group(0) @binding(0) var<storage, read> t: array<SssMaterial>;",
        shading::MATERIAL_WGSL
    );
    let module = validate("material.wgsl", &src);
    let (handle, _) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("SssMaterial"))
        .unwrap();
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    assert_eq!(layouter[handle].size as usize, shading::PACKED_SHADING_SIZE);
}

#[test]
fn the_lookups_translate_to_glsl_and_hlsl() {
    let s = shading::ShaderSources::new().unwrap();
    for f in [
        "sss_incidence",
        "sss_exit",
        "sss_entry_offset",
        "sss_translucency_exit",
    ] {
        assert!(s.glsl.contains(f) && s.hlsl.contains(f), "{f}");
    }
    assert!(s.glsl.starts_with("#version 450"));
    assert!(s.hlsl.contains("[numthreads(64, 1, 1)]"));
}
