// The angle tables' grid, θ = 0°, 10°, …, 80° (the incidence, exit, entry-shift and
// transmitted-exit tables read it).

// arccos x [rad] for 0 ≤ x ≤ 1: Abramowitz & Stegun 4.4.46 (within 2·10⁻⁸; 2.4·10⁻⁷ absolute
// and relative in f32). The built-in acos may be off by thousands of ulp (Vulkan allows it):
// lavapipe's moved an incidence-table lookup at 10° by 3·10⁻⁴ of its value; with this one every
// lookup is within 1.5·10⁻⁶ of its CPU twin on every GPU (gpu/tests/lookups.rs).
fn sss_acos(x: f32) -> f32 {
    let p = 1.5707963050 + x * (-0.2145988016 + x * (0.0889789874 + x * (-0.0501743046
        + x * (0.0308918810 + x * (-0.0170881256 + x * (0.0066700901 + x * -0.0012624911))))));
    return sqrt(1.0 - x) * p;
}

// The entry at or below cos θ (x, 0–8) and the weight of the next (y): linear in θ, the 80°
// entry beyond, also for cos θ ≤ 0 (shading::incidence_ratio reads it so).
fn angle_index(cos_t: f32) -> vec2<f32> {
    let t = degrees(sss_acos(clamp(cos_t, 0.0, 1.0))) / 10.0;
    let i = min(floor(t), 8.0);
    return vec2<f32>(i, select(t - i, 0.0, i >= 8.0));
}
