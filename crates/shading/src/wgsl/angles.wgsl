// The angle tables' grid, θ = 0°, 10°, …, 80° (incidence, exit and transmitted-exit tables;
// prepended in Rust to the shaders that read them).

// The entry at or below cos θ (x, 0–8) and the weight of the next (y): linear in θ, the 80°
// entry beyond (shading::incidence_ratio and shading::exit_ratio are the CPU twins).
fn angle_index(cos_t: f32) -> vec2<f32> {
    let t = degrees(acos(clamp(cos_t, 0.0, 1.0))) / 10.0;
    let i = min(floor(t), 8.0);
    return vec2<f32>(i, select(t - i, 0.0, i >= 8.0));
}

// An angle table (θ = 0°, 10°, …, 80°: the incidence table ρ(θ)/ρ(0), the entry shift δ(θ)) at
// cos θ: linear in θ between entries, the 80° value beyond (shading::incidence_ratio and
// shading::EntryShift::at are its CPU twins).
fn angle_table(table: array<vec4<f32>, 9>, cos_a: f32) -> vec3<f32> {
    var t = table;
    let a = angle_index(cos_a);
    let i = u32(a.x);
    return mix(t[i].rgb, t[min(i + 1u, 8u)].rgb, a.y);
}
