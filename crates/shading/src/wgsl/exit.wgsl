// h(θ_o; θ_i), the exit table: the radiance material m's scattered light leaves with at polar
// angle θ_o, relative to a Lambertian surface's of the same total reflectance, for light that
// entered at θ_i (shading::AngleTables::exit). The recombination multiplies the blurred light of
// each pixel by it at the view angle and at the pixel's mean cosine of incidence.
// Reads sss_exit_entry(m, k), k = 9·i + o for θ_i = 10°·i and θ_o = 10°·o, which the host
// defines.

// h(θ_o; θ_i) (rgb) at exit cosine cos_o and entry cosine cos_i: linear in both angles between
// entries, the 80° values beyond (shading::exit_ratio is the CPU twin).
fn sss_exit(m: u32, cos_o: f32, cos_i: f32) -> vec3<f32> {
    let o = angle_index(cos_o);
    let e = angle_index(cos_i);
    let o0 = u32(o.x);
    let i0 = u32(e.x);
    let o1 = min(o0 + 1u, 8u);
    let i1 = min(i0 + 1u, 8u);
    let a = mix(sss_exit_entry(m, i0 * 9u + o0), sss_exit_entry(m, i0 * 9u + o1), o.y);
    let b = mix(sss_exit_entry(m, i1 * 9u + o0), sss_exit_entry(m, i1 * 9u + o1), o.y);
    return mix(a, b, e.y);
}
