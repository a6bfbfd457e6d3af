// The area pre-integrated kernel shared by the gather (area_gather.wgsl) and the splats
// (splat.wgsl), which declare `table`: R′/energy per texel (rgb) [1/cm²], row j (disc radius
// (j + ½)·r_max/n_a) by column i (distance (i + ½)·r_max/n_r), as fit::area_table::AreaTable.

const PI: f32 = 3.14159265358979;

struct AreaKernel {
    // The kernel's width factor s: R′_s(r, A) = R′(r/s, A/s²)/s².
    scale: f32,
    // The table: r_max [cm], texels along r and along the disc radius.
    r_max: f32,
    n_r: u32,
    n_a: u32,
};

fn texel(k: AreaKernel, j: u32, i: u32) -> vec3<f32> {
    return table[min(j, k.n_a - 1u) * k.n_r + min(i, k.n_r - 1u)].rgb;
}

// R′_s(d, a)/energy at distance d [cm] and area a [cm²]: bilinear between texel centres, clamped
// to them (as fit's AreaTable::lookup), 0 beyond s·r_max (gpu::AreaKernel::lookup is its twin).
fn area_kernel(k: AreaKernel, d: f32, a: f32) -> vec3<f32> {
    let s = k.scale;
    let rs = d / s;
    if !(rs <= k.r_max) {
        return vec3<f32>(0.0);
    }
    let ra = sqrt(max(a, 0.0) / PI) / s;
    let x = clamp(rs / k.r_max * f32(k.n_r) - 0.5, 0.0, f32(k.n_r - 1u));
    let y = clamp(ra / k.r_max * f32(k.n_a) - 0.5, 0.0, f32(k.n_a - 1u));
    let i = min(u32(floor(x)), k.n_r - 2u);
    let j = min(u32(floor(y)), k.n_a - 2u);
    let ti = x - f32(i);
    let tj = y - f32(j);
    let lo = mix(texel(k, j, i), texel(k, j, i + 1u), ti);
    let hi = mix(texel(k, j + 1u, i), texel(k, j + 1u, i + 1u), ti);
    return mix(lo, hi, tj) / (s * s);
}

