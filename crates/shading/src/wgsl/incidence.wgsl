// ρ(θ)/ρ(0), the incidence table: material m's total diffuse reflectance for light entering at θ
// relative to normal incidence (shading::AngleTables::incidence). The scene pass multiplies each
// light's irradiance n·l on a subsurface-scattering surface by it, before the blur.
// Reads sss_incidence_entry(m, k), θ = 10°·k (k = 0…8), which the host defines.

// ρ(θ)/ρ(0) (rgb) at cos θ = cos_i: linear in θ between entries, the 80° entry beyond
// (shading::incidence_ratio is the CPU twin).
fn sss_incidence(m: u32, cos_i: f32) -> vec3<f32> {
    let a = angle_index(cos_i);
    let k = u32(a.x);
    return mix(sss_incidence_entry(m, k), sss_incidence_entry(m, min(k + 1u, 8u)), a.y);
}
