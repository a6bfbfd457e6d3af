// One 1D pass of a separable SSS kernel (Jimenez et al. 2015; Freude 2014 §4.2–4.4).
//
// Tap offsets are in cm on the surface; a pixel at view depth z [cm] covers
// z / px_per_cm_at_unit_depth cm, so offset_px = offset·sss_width·strength·px_per_cm_at_unit_depth/z
// (eq. 4.11 with the NDC→pixel factor ½·height and square pixels: no aspect error). Samples are
// linear interpolations of the two nearest pixels along the pass axis, clamped to the edge.

struct Params {
    width: u32,
    height: u32,
    taps: u32,
    horizontal: u32,
    sign: vec4<f32>,
    px_per_cm_at_unit_depth: f32,
    sss_width: f32,
    // Depth difference [cm] at which a sample is fully replaced (mode 1) or rejected (mode 2).
    tolerance: f32,
    // 0: no depth test, 1: lerp towards the centre sample (eq. 4.12), 2: reject and renormalize.
    mode: u32,
    jitter: f32,
    // 0: write the pass result; 1: add sign·result to what dst holds.
    accumulate: u32,
    // > 0: use this depth [cm] for every pixel's kernel scale.
    fixed_depth: f32,
    _pad: u32,
};

@group(0) @binding(0) var<uniform> p: Params;
// xyz: RGB weight, w: offset [cm].
@group(0) @binding(1) var<storage, read> taps: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> src: array<vec4<f32>>;
// x: view depth [cm], y: SSS strength.
@group(0) @binding(3) var<storage, read> geom: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> dst: array<vec4<f32>>;

fn index(x: i32, y: i32) -> u32 {
    let cx = clamp(x, 0, i32(p.width) - 1);
    let cy = clamp(y, 0, i32(p.height) - 1);
    return u32(cy) * p.width + u32(cx);
}

fn hash(x: u32, y: u32) -> f32 {
    var h = x * 73856093u ^ y * 19349663u;
    h = (h ^ (h >> 16u)) * 0x45d9f3bu;
    h = (h ^ (h >> 16u)) * 0x45d9f3bu;
    h = h ^ (h >> 16u);
    return f32(h & 0xffffu) / 65535.0;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height {
        return;
    }
    let x = i32(id.x);
    let y = i32(id.y);
    let i = id.y * p.width + id.x;
    let centre = src[i];
    let depth = select(geom[i].x, p.fixed_depth, p.fixed_depth > 0.0);
    let strength = geom[i].y;
    var scale = p.sss_width * strength * p.px_per_cm_at_unit_depth / max(depth, 1e-6);
    if p.jitter > 0.0 {
        scale *= 1.0 + p.jitter * (hash(id.x, id.y) - 0.5);
    }
    var sum = vec3<f32>(0.0);
    var kept = vec3<f32>(0.0);
    var all = vec3<f32>(0.0);
    for (var t = 0u; t < p.taps; t++) {
        let tap = taps[t];
        let pos = tap.w * scale;
        let base = floor(pos);
        let f = pos - base;
        var a: u32;
        var b: u32;
        if p.horizontal == 1u {
            a = index(x + i32(base), y);
            b = index(x + i32(base) + 1, y);
        } else {
            a = index(x, y + i32(base));
            b = index(x, y + i32(base) + 1);
        }
        var s = mix(src[a].rgb, src[b].rgb, f);
        var w = tap.xyz;
        all += w;
        if p.mode != 0u {
            let dz = abs(mix(geom[a].x, geom[b].x, f) - geom[i].x);
            if p.mode == 1u {
                s = mix(s, centre.rgb, clamp(dz / p.tolerance, 0.0, 1.0));
            } else if dz > p.tolerance {
                w = vec3<f32>(0.0);
            }
        }
        kept += w;
        sum += w * s;
    }
    if p.mode == 2u {
        // Rejected samples' weight goes to those kept, per channel; none kept: the centre.
        sum = select(all * centre.rgb, sum * all / max(kept, vec3<f32>(1e-30)), kept > vec3<f32>(0.0));
    }
    if p.accumulate == 1u {
        dst[i] = vec4<f32>(dst[i].rgb + p.sign.rgb * sum, 1.0);
    } else {
        dst[i] = vec4<f32>(sum, 1.0);
    }
}
