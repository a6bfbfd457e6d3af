// The lookups evaluated at sampled inputs, for comparing a GPU's results with the CPU twins
// (shading::check): per sample four vec4 in, ten out. With bindings.wgsl, a self-test an
// engine can dispatch as it is.

// First x: the number of samples (not arrayLength: HLSL compilers disagree on whether a byte
// buffer's GetDimensions counts bytes or words); then per sample: [x: material, y: cos θ_o,
// z: cos θ_i, w: thickness d [cm]], [xyz: unit normal n, w: η], [xyz: unit direction towards the
// light l, w: δ [cm]], [x: signed curvature [cm⁻¹], yzw: 0].
@group(0) @binding(1) var<storage, read> sss_check_in: array<vec4<f32>>;
// Per sample: [sss_incidence(m, cos_i), fresnel(η, cos_o)], [sss_exit(m, cos_o, cos_i),
// sss_back_face_entry(η, cos_i)], [sss_entry_shift(m, cos_i), 0], [sss_entry_offset(n, l, δ), 0],
// [sss_translucency(m, d), 0], [sss_translucency_exit(m, d, cos_o), 0],
// [sss_shape_energy(m, curvature, cos_i), 0], [sss_shape_shift(m, curvature, cos_i), 0],
// [sss_shape_width(m, curvature, cos_i), 0], [sss_shape_thin(m, curvature, d, cos_i), 0].
@group(0) @binding(2) var<storage, read_write> sss_check_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn sss_check(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= u32(sss_check_in[0].x) {
        return;
    }
    let a = sss_check_in[4u * i + 1u];
    let nb = sss_check_in[4u * i + 2u];
    let lb = sss_check_in[4u * i + 3u];
    let curvature = sss_check_in[4u * i + 4u].x;
    let m = u32(a.x);
    let o = 10u * i;
    sss_check_out[o] = vec4<f32>(sss_incidence(m, a.z), fresnel(nb.w, a.y));
    sss_check_out[o + 1u] = vec4<f32>(sss_exit(m, a.y, a.z), sss_back_face_entry(nb.w, a.z));
    sss_check_out[o + 2u] = vec4<f32>(sss_entry_shift(m, a.z), 0.0);
    sss_check_out[o + 3u] = vec4<f32>(sss_entry_offset(nb.xyz, lb.xyz, lb.w), 0.0);
    sss_check_out[o + 4u] = vec4<f32>(sss_translucency(m, a.w), 0.0);
    sss_check_out[o + 5u] = vec4<f32>(sss_translucency_exit(m, a.w, a.y), 0.0);
    sss_check_out[o + 6u] = vec4<f32>(sss_shape_energy(m, curvature, a.z), 0.0);
    sss_check_out[o + 7u] = vec4<f32>(sss_shape_shift(m, curvature, a.z), 0.0);
    sss_check_out[o + 8u] = vec4<f32>(sss_shape_width(m, curvature, a.z), 0.0);
    sss_check_out[o + 9u] = vec4<f32>(sss_shape_thin(m, curvature, a.w, a.z), 0.0);
}
