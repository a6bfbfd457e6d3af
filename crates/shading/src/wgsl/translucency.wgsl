// Light through thin parts (shading::Translucency): a slab of material m and thickness d
// transmits Tt(d) of the light entering its far face at normal incidence; the table holds
// Tt(d)/ρ at d_k = first·ratio^k (k = 0…15), ρ the material's total diffuse reflectance, and the
// transmitted light's exit law h_T(θ_o; d_k). The scene pass adds, for each light behind a
// surface, irradiance × T(θ)/T(0) × Tt(d)/ρ × h_T, d the thickness along the light (its shadow
// map's first surface), before the blur.
// Reads sss_translucency_grid(m) (x: first [cm], y: ln ratio), sss_translucency_entry(m, k) and
// sss_translucency_exit_entry(m, 9·k + o) (θ_o = 10°·o), which the host defines.

// The table position of thickness d [cm]: x the entry at or below it, y the weight of the next
// (held outside the table).
fn sss_thickness_index(m: u32, d: f32) -> vec2<f32> {
    let grid = sss_translucency_grid(m);
    let t = log(max(d, 1e-30) / grid.x) / grid.y;
    if !(t > 0.0) {
        return vec2<f32>(0.0);
    }
    let i = floor(t);
    if i >= 15.0 {
        return vec2<f32>(15.0, 0.0);
    }
    return vec2<f32>(i, t - i);
}

// Tt(d)/ρ (rgb) at thickness d [cm]: linear in ln d between entries, held outside them
// (shading::Translucency::at is the CPU twin).
fn sss_translucency(m: u32, d: f32) -> vec3<f32> {
    let p = sss_thickness_index(m, d);
    let i = u32(p.x);
    return mix(sss_translucency_entry(m, i), sss_translucency_entry(m, min(i + 1u, 15u)), p.y);
}

// h_T(θ_o; d) (rgb) at thickness d [cm] and exit cosine cos_o: linear in ln d and in θ_o, held
// outside the tables (shading::Translucency::exit_at is the CPU twin).
fn sss_translucency_exit(m: u32, d: f32, cos_o: f32) -> vec3<f32> {
    let p = sss_thickness_index(m, d);
    let i = u32(p.x);
    let j = min(i + 1u, 15u);
    let o = angle_index(cos_o);
    let a = u32(o.x);
    let b = min(a + 1u, 8u);
    let lo = mix(sss_translucency_exit_entry(m, i * 9u + a), sss_translucency_exit_entry(m, i * 9u + b), o.y);
    let hi = mix(sss_translucency_exit_entry(m, j * 9u + a), sss_translucency_exit_entry(m, j * 9u + b), o.y);
    return mix(lo, hi, p.y);
}

// The light entering a thin part's far face at incidence cos θ = c relative to normal
// incidence: the smooth boundary's Fresnel transmittance T(θ)/T(0) for index eta
// (shading::back_face_entry is the CPU twin).
fn sss_back_face_entry(eta: f32, c: f32) -> f32 {
    return (1.0 - fresnel(eta, c)) / (1.0 - fresnel(eta, 1.0));
}
