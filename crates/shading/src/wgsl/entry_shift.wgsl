// δ(θ), the entry shift: light entering material m at θ leaves a half-space, on average, δ(θ)
// [cm] ahead of where it entered along its propagation over the surface
// (shading::EntryShift). The scene pass lights a pixel with the light that entered δ behind it:
// the light's shadow map is read at the shifted point, not at the pixel.
// Reads sss_shift_entry(m, k) [cm], θ = 10°·k (k = 0…8), which the host defines.

// δ(θ) [cm] (rgb) at cos θ = cos_i: linear in θ, the 80° value beyond and for light from behind
// (cos θ ≤ 0) (shading::EntryShift::at is the CPU twin).
fn sss_entry_shift(m: u32, cos_i: f32) -> vec3<f32> {
    let a = angle_index(cos_i);
    let k = u32(a.x);
    return mix(sss_shift_entry(m, k), sss_shift_entry(m, min(k + 1u, 8u)), a.y);
}

// Where the light leaving at a point entered, relative to it [cm]: δ behind along the light's
// propagation over the surface, t = −l less its part along the unit normal n (l: the unit
// direction towards the light); 0 where the light arrives along n (|t| ≤ 1e-4)
// (shading::entry_offset is the CPU twin).
fn sss_entry_offset(n: vec3<f32>, l: vec3<f32>, delta: f32) -> vec3<f32> {
    let t = -l + dot(n, l) * n;
    let along = length(t);
    if along > 1e-4 {
        return -delta * t / along;
    }
    return vec3<f32>(0.0);
}
