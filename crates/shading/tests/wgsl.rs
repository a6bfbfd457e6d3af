//! The WGSL beside the tables stands on its own: each file parses and validates with naga with
//! nothing prepended, so a renderer or an exporter can take it as it is (the GPU tests compare
//! what it computes with the CPU twins).

#[test]
fn every_wgsl_file_validates_on_its_own() {
    for (name, src) in [
        ("fresnel.wgsl", shading::FRESNEL_WGSL),
        ("angles.wgsl", shading::ANGLES_WGSL),
    ] {
        let module = naga::front::wgsl::parse_str(src)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        assert!(!module.functions.is_empty(), "{name} defines no function");
    }
}
