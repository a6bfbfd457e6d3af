// One 1D pass of a separable SSS kernel (Jimenez et al. 2015; Freude 2014 §4.2–4.4): what both
// paths share. blur_exact.wgsl (storage buffers, two reads per tap, several materials) or
// blur_fast.wgsl (one filtered texture fetch per tap, one material) is appended and defines
// `centre_colour`, `centre_depth`, `filtered` and `store`.
//
// Tap offsets are in cm on the surface; a pixel at view depth z [cm] covers
// z / px_per_cm_at_unit_depth cm, so offset_px = offset·sss_width·strength·px_per_cm_at_unit_depth/z
// (eq. 4.11 with the NDC→pixel factor ½·height and square pixels: no aspect error). Samples are
// linear interpolations of the two nearest pixels along the pass axis, clamped to the edge.
//
// Several SSS materials: each material's passes run over the image and write only its own pixels
// (geom.z is the material index). Of a sample's two pixels, one of another SSS material is left
// out of the interpolation and the sample's weight shrinks by its share; the weight lost goes to
// the samples kept, per channel. So no light crosses from one material into another, and a
// uniformly lit material stays uniform up to its border. Pixels without SSS (strength 0) are
// sampled as before, subject to the depth test.

struct Params {
    width: u32,
    height: u32,
    taps: u32,
    horizontal: u32,
    sign: vec4<f32>,
    // Σ of the taps' weights (rgb).
    tap_sum: vec4<f32>,
    px_per_cm_at_unit_depth: f32,
    sss_width: f32,
    // Depth difference [cm] at which a sample is fully replaced (mode 1) or rejected (mode 2); the
    // standard deviation √τ of the depth factor (mode 3).
    tolerance: f32,
    // 0: no depth test, 1: lerp towards the centre sample (eq. 4.12), 2: reject and renormalize,
    // 3: weight × e^{−Δz²/(2τ)} (SSSS supplement §E), renormalized like mode 2.
    mode: u32,
    // The fraction of taps jittered per pixel within their cells (supplement Fig. S.6–S.7).
    jitter: f32,
    // 0: write the pass result; 1: add sign·result to what dst holds.
    accumulate: u32,
    // > 0: use this depth [cm] for every pixel's kernel scale.
    fixed_depth: f32,
    // The material whose pixels this pass writes.
    material: u32,
    // 1: pixels without SSS and pixels of other materials do no tap work.
    skip_empty: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(0) @binding(0) var<uniform> p: Params;
// xyz: RGB weight, w: offset [cm].
@group(0) @binding(1) var<storage, read> taps: array<vec4<f32>>;
// x: view depth [cm], y: SSS strength, z: material index.
@group(0) @binding(3) var<storage, read> geom: array<vec4<f32>>;
// The vertical pass's output (accumulated over the kernel's terms); the exact path's horizontal
// pass writes here too.
@group(0) @binding(4) var<storage, read_write> dst: array<vec4<f32>>;
// Each tap's cell [cm] (lo, hi): where a jittered tap samples.
@group(0) @binding(5) var<storage, read> cells: array<vec2<f32>>;

// A sample of the source at `pos` pixels along the pass axis from pixel (x, y): its colour, its
// view depth [cm] and the share of its weight it keeps (< 1 where part of it belongs to another
// material).
struct Sample {
    rgb: vec3<f32>,
    z: f32,
    share: f32,
};

// Adds sign·value into dst (vertical pass) or writes value (horizontal pass).
fn accumulate(i: u32, value: vec3<f32>) {
    if p.accumulate == 1u {
        dst[i] = vec4<f32>(dst[i].rgb + p.sign.rgb * value, 1.0);
    } else {
        dst[i] = vec4<f32>(value, 1.0);
    }
}

fn index(x: i32, y: i32) -> u32 {
    let cx = clamp(x, 0, i32(p.width) - 1);
    let cy = clamp(y, 0, i32(p.height) - 1);
    return u32(cy) * p.width + u32(cx);
}

// Uniform in [0, 1] from a pixel, a tap and a stream.
fn hash(x: u32, y: u32, t: u32) -> f32 {
    var h = (x * 73856093u) ^ (y * 19349663u) ^ (t * 83492791u);
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
    let centre = centre_colour(i, x, y);
    let strength = geom[i].y;
    let own = strength > 0.0 && u32(geom[i].z) == p.material;
    if p.skip_empty == 1u && !own {
        // Another material's pixel: left alone. A pixel without SSS: a zero-width kernel, which
        // the vertical pass may sample.
        if p.accumulate == 0u && !(strength > 0.0) {
            store(i, x, y, p.tap_sum.rgb * centre);
        }
        return;
    }
    let depth = select(geom[i].x, p.fixed_depth, p.fixed_depth > 0.0);
    let scale = p.sss_width * strength * p.px_per_cm_at_unit_depth / max(depth, 1e-6);
    let z0 = centre_depth(i, x, y);
    var sum = vec3<f32>(0.0);
    // Σ|w| of the samples kept and of all taps: the renormalization's ratio, bounded also for
    // the signed terms of SVD kernels (their plain sums can be near 0).
    var kept = vec3<f32>(0.0);
    var all_abs = vec3<f32>(0.0);
    var all = vec3<f32>(0.0);
    for (var t = 0u; t < p.taps; t++) {
        let tap = taps[t];
        var offset = tap.w;
        // The horizontal and vertical passes draw independent streams.
        let stream = 2u * t + p.horizontal;
        if p.jitter > 0.0 && hash(id.x, id.y, 2u * stream) < p.jitter {
            let c = cells[t];
            offset = mix(c.x, c.y, hash(id.x, id.y, 2u * stream + 1u));
        }
        let pos = offset * scale;
        let sample = filtered(x, y, pos);
        var w = tap.xyz;
        all += w;
        all_abs += abs(w);
        if sample.share <= 0.0 {
            continue;
        }
        var s = sample.rgb;
        w *= sample.share;
        let dz = abs(sample.z - z0);
        if p.mode == 1u {
            s = mix(s, centre, clamp(dz / p.tolerance, 0.0, 1.0));
        } else if p.mode == 2u && dz > p.tolerance {
            w = vec3<f32>(0.0);
        } else if p.mode == 3u {
            w *= exp(-dz * dz / (2.0 * p.tolerance * p.tolerance));
        }
        kept += abs(w);
        sum += w * s;
    }
    // Rejected samples' weight goes to those kept, per channel; none kept: the centre. (Without
    // rejections kept = all_abs, summed in the same order, and this changes nothing.)
    sum = select(all * centre, sum * all_abs / max(kept, vec3<f32>(1e-30)), kept > vec3<f32>(0.0));
    if !own {
        // skip_empty off: the work is done (to be timed), but only the pass's own pixels are
        // written by its vertical pass, and other materials' pixels by neither.
        if p.accumulate == 1u || strength > 0.0 {
            return;
        }
    }
    store(i, x, y, sum);
}
