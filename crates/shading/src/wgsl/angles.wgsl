// The angle tables' grid, θ = 0°, 10°, …, 80° (incidence, exit and transmitted-exit tables;
// prepended in Rust to the shaders that read them).

// The entry at or below cos θ (x, 0–8) and the weight of the next (y): linear in θ, the 80°
// entry beyond (shading::incidence_ratio and shading::exit_ratio are the CPU twins).
fn angle_index(cos_t: f32) -> vec2<f32> {
    let t = degrees(acos(clamp(cos_t, 0.0, 1.0))) / 10.0;
    let i = min(floor(t), 8.0);
    return vec2<f32>(i, select(t - i, 0.0, i >= 8.0));
}
