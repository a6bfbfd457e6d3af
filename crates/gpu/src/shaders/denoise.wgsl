// One level of the disc gathers' denoiser (passes/denoise.rs): an edge-avoiding à-trous filter
// (Dammertz et al. 2010) over what the gather's samples add to its control variate, guided by
// the camera's position and normal maps; the last level adds the control's deterministic part
// (`base`) back. The level's 5 × 5 taps lie `step` pixels apart with the B3-spline weights
// (1, 4, 6, 4, 1)/16 per axis; each tap is weighted per channel by exp(−|x_q − x_p|²/(2σ_c²)),
// σ_c the channel's width in the world [cm] (at least a pixel's footprint), and taken only
// where the map marks an SSS surface facing the same hemisphere and the image's w (which the
// gather writes) marks x_o lit as at the centre. The world distance is what keeps light from
// crossing silhouettes and depth steps: pixels side by side on screen but apart in depth are
// apart in the world. The weights are normalized per pixel and channel, so a constant stays
// exactly constant. A pixel whose level's nearest taps lie beyond every channel's width (its
// step times the pixel's footprint) is copied: the level would not move its light.

struct Denoise {
    // rgb: σ per channel [cm] (0: the channel is copied); w: the least σ of a filtered channel
    // in pixels of its footprint (passes/denoise.rs, FLOOR_PX).
    width: vec4<f32>,
    // xyz: the camera's position [cm]; w: a pixel's footprint per cm of distance from the
    // camera, 2·tan(fov_y/2)/height [-].
    camera: vec4<f32>,
    // width, height [px], the level's step [px], 1 on the last level (which adds the base).
    size: vec4<u32>,
};

@group(0) @binding(0) var<uniform> u: Denoise;
@group(0) @binding(1) var cam_pos: texture_2d<f32>;
@group(0) @binding(2) var cam_normal: texture_2d<f32>;
@group(0) @binding(3) var<storage, read> src: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> dst: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> base: array<vec4<f32>>;

// The B3 spline's weights at offsets −2 … 2.
fn b3(k: i32) -> f32 {
    return select(select(0.0625, 0.25, abs(k) == 1), 0.375, k == 0);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(u.size.xy);
    let p = vec2<i32>(id.xy);
    if p.x >= size.x || p.y >= size.y {
        return;
    }
    let i = id.y * u.size.x + id.x;
    let centre = src[i];
    // The last level adds the base and clears the lit mark.
    let added = select(vec4<f32>(0.0), vec4<f32>(base[i].rgb, -centre.w), u.size.w == 1u);
    let lit = centre.w > 0.5;
    let xp = textureLoad(cam_pos, p, 0);
    let step = i32(u.size.z);
    let footprint = distance(xp.xyz, u.camera.xyz) * u.camera.w;
    let sigma = select(vec3<f32>(0.0), max(u.width.xyz, vec3<f32>(u.width.w * footprint)),
                       u.width.xyz > vec3<f32>(0.0));
    if xp.w < 0.5 || f32(step) * footprint > max(sigma.x, max(sigma.y, sigma.z)) {
        dst[i] = centre + added;
        return;
    }
    let np = textureLoad(cam_normal, p, 0).xyz;
    // 1/(2σ²) per channel; a channel of width 0 keeps only the centre.
    let live = sigma > vec3<f32>(0.0);
    let inv = select(vec3<f32>(0.0), 0.5 / max(sigma * sigma, vec3<f32>(1e-30)), live);
    var sum = 0.140625 * centre.rgb;
    var weight = vec3<f32>(0.140625);
    for (var dy = -2; dy <= 2; dy++) {
        for (var dx = -2; dx <= 2; dx++) {
            let q = p + step * vec2<i32>(dx, dy);
            if (dx == 0 && dy == 0) || any(q < vec2<i32>(0)) || any(q >= size) {
                continue;
            }
            let xq = textureLoad(cam_pos, q, 0);
            let s = src[u32(q.y) * u.size.x + u32(q.x)];
            if xq.w < 0.5 || dot(np, textureLoad(cam_normal, q, 0).xyz) <= 0.0 || (s.w > 0.5) != lit {
                continue;
            }
            let d = xq.xyz - xp.xyz;
            let w = select(vec3<f32>(0.0), b3(dx) * b3(dy) * exp(-dot(d, d) * inv), live);
            sum += w * s.rgb;
            weight += w;
        }
    }
    dst[i] = vec4<f32>(sum / weight, centre.w) + added;
}
