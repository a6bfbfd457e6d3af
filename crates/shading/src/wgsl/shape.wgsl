// The body's shape (shading::ShapeTable): light entering a sphere of radius R (convex) or the
// medium around a spherical cavity of radius R (concave) at θ returns E(κ, θ) times what a
// half-space returns within 8 diffusion lengths of its entry, centred ⟨x⟩(κ, θ) [cm] ahead of it,
// κ = 1/(σ_tr·R) per channel, signed (> 0 convex). The scene pass multiplies the light entering
// an SSS surface by E at the surface's mean curvature there.
// Reads, which the host defines: sss_shape_params(m) (rgb: σ_tr per channel [cm⁻¹]; w: 1 on, 0
// off), sss_shape_grid(m, j) (the curvature nodes κ 4j … 4j + 3, SSS_SHAPE_STEPS of them),
// sss_shape_energy_entry(m, i, k) and sss_shape_shift_entry(m, i, k) (node i, θ = 10°·k).

// Nodes of the curvature axis (shading::CURVATURE_STEPS).
const SSS_SHAPE_STEPS: u32 = 15u;

fn sss_shape_node(m: u32, i: u32) -> f32 {
    return sss_shape_grid(m, i / 4u)[i % 4u];
}

// The node at or below κ (x) and the weight of the next (y): κ clamped to the first and last
// node, NaN read as 0 (shading::curvature_position is the CPU twin).
fn sss_curvature_position(m: u32, kappa: f32) -> vec2<f32> {
    let first = sss_shape_node(m, 0u);
    let last = sss_shape_node(m, SSS_SHAPE_STEPS - 1u);
    let k = select(clamp(kappa, first, last), 0.0, kappa != kappa);
    var i = 0u;
    for (var j = 1u; j < SSS_SHAPE_STEPS - 1u; j++) {
        if sss_shape_node(m, j) <= k {
            i = j;
        }
    }
    let lo = sss_shape_node(m, i);
    return vec2<f32>(f32(i), (k - lo) / (sss_shape_node(m, i + 1u) - lo));
}

// E (rgb) where the surface's signed curvature is `curvature` [cm⁻¹] (±1/R, > 0 convex) and the
// light enters at cos θ = cos_i: linear in κ = curvature/σ_tr between the nodes, linear in θ as
// the angle tables (shading::ShapeTable::at's energy is the CPU twin). 1 where the table is off.
fn sss_shape_energy(m: u32, curvature: f32, cos_i: f32) -> vec3<f32> {
    let p = sss_shape_params(m);
    if p.w < 0.5 {
        return vec3<f32>(1.0);
    }
    let a = angle_index(cos_i);
    let k0 = u32(a.x);
    let k1 = min(k0 + 1u, 8u);
    var e = vec3<f32>(1.0);
    for (var c = 0u; c < 3u; c++) {
        let s = sss_curvature_position(m, curvature / p[c]);
        let i = u32(s.x);
        let lo = mix(sss_shape_energy_entry(m, i, k0)[c], sss_shape_energy_entry(m, i, k1)[c], a.y);
        let hi = mix(sss_shape_energy_entry(m, i + 1u, k0)[c],
            sss_shape_energy_entry(m, i + 1u, k1)[c], a.y);
        e[c] = mix(lo, hi, s.y);
    }
    return e;
}

// ⟨x⟩ [cm] (rgb), the returned light's centroid ahead of its entry along the light's direction
// over the surface, where the surface's signed curvature along that direction is `curvature`
// [cm⁻¹], at cos θ = cos_i; as sss_shape_energy (shading::ShapeTable::at's shift is the CPU
// twin). 0 where the table is off.
fn sss_shape_shift(m: u32, curvature: f32, cos_i: f32) -> vec3<f32> {
    let p = sss_shape_params(m);
    if p.w < 0.5 {
        return vec3<f32>(0.0);
    }
    let a = angle_index(cos_i);
    let k0 = u32(a.x);
    let k1 = min(k0 + 1u, 8u);
    var x = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        let s = sss_curvature_position(m, curvature / p[c]);
        let i = u32(s.x);
        let lo = mix(sss_shape_shift_entry(m, i, k0)[c], sss_shape_shift_entry(m, i, k1)[c], a.y);
        let hi = mix(sss_shape_shift_entry(m, i + 1u, k0)[c],
            sss_shape_shift_entry(m, i + 1u, k1)[c], a.y);
        x[c] = mix(lo, hi, s.y);
    }
    return x;
}
