// Splatted translucency of the area gather (Maisch & Ropinski 2020 §5, §6.2, §6.3): the light
// that enters the SSS surface where the camera does not see it, one splat per triangle of the
// material, accumulated at the pyramid level whose texels are 4×4 pixels and upsampled.
// fresnel.wgsl, lighting.wgsl (bindings 0–2) and area_kernel.wgsl are prepended.
//
// `light` (per triangle): the irradiance × pre-scatter albedo at its centre, and whether it
// splats: wherever the gather does not count it, i.e. where the camera does not see it (their
// eq. 2, at the pixel of the triangle's centre: a view depth off the G-buffer's by more than
// 10⁻³ of it plus the surface's depth slope over two pixels), and faces turned away (n·v ≤ 0,
// their eq. 3), however close they lie to a face that is seen (a thin slab's back). The paper's
// bound n·v < 0.2 (eq. 8) is not needed: the gather counts every pixel seen, at grazing view
// too. `vs`/`fs`: a screen-aligned quad bounding the kernel's reach around the centre; per
// receiver texel (the material's mean position x_o there) E·A·R′(|x′ − x_o|, A) with x′ the
// triangle's centre or, optionally, their eq. 9's point. `up`: the receiver texels' sum back at
// full resolution.

struct Splat {
    view_proj: mat4x4<f32>,
    // xyz: the camera [cm]; w: 1 moves each splat's point by their eq. 9, 0 keeps the centre.
    camera_pos: vec4<f32>,
    kernel: AreaKernel,
    // x, y: the projection's scale factors P₀₀ and P₁₁; z: the kernel's reach s·r_max [cm];
    // w: the near plane [cm].
    proj: vec4<f32>,
    // x, y: image size; z, w: the splat target's (the pyramid level `level.y`).
    size: vec4<u32>,
    // x: offset of the splat level in the pyramid, y: the level, z: triangles, w: the material.
    level: vec4<u32>,
    // x: the far plane [cm] (the background's depth); y: the depth tolerance of `light` [cm per
    // cm of view depth]; z: its pixels of depth slope; w: the grazing bound on n·v.
    far: vec4<f32>,
};

struct Tri {
    // xyz: centre [cm], w: area [cm²].
    centre: vec4<f32>,
    // xyz: unit normal, outwards.
    normal: vec4<f32>,
    // rgb: albedo; w: material.
    albedo: vec4<f32>,
};

@group(0) @binding(3) var<uniform> sp: Splat;
@group(0) @binding(4) var<storage, read> tris: array<Tri>;
@group(0) @binding(5) var<storage, read_write> splat_out: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read> splats: array<vec4<f32>>;
// x: view depth [cm] (background: far), y: SSS strength.
@group(0) @binding(7) var<storage, read> geometry: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read> table: array<vec4<f32>>;
// The gather's position pyramid: Σx and the count of the material's pixels per texel.
@group(0) @binding(9) var<storage, read> pos: array<vec4<f32>>;
@group(0) @binding(10) var accumulated: texture_2d<f32>;
@group(0) @binding(11) var<storage, read_write> scattered: array<vec4<f32>>;


@compute @workgroup_size(64)
fn light(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= sp.level.z {
        return;
    }
    let t = tris[id.x];
    let c = t.centre.xyz;
    let n = t.normal.xyz;
    let m = u32(t.albedo.w);
    // A triangle's centre: the surface's turn unknown, read as flat.
    let flat = Local(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    let e = shade(c, n, n, m, true, false, flat, vec3<f32>(0.0)).diffuse * albedo_split(t.albedo.rgb)[0];
    // Turned away, off screen or behind the camera: not seen, so splatted.
    var hidden = true;
    let v = normalize(sp.camera_pos.xyz - c);
    let clip = sp.view_proj * vec4<f32>(c, 1.0);
    let cos_v = dot(n, v);
    if clip.w > 0.0 && cos_v > 0.0 {
        let ndc = clip.xy / clip.w;
        let px = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(sp.size.xy);
        if all(px >= vec2<f32>(0.0)) && all(px < vec2<f32>(sp.size.xy)) {
            let k = u32(px.y) * sp.size.x + u32(px.x);
            // The depth seen there may differ from the centre's by the surface's depth slope over
            // the pixel's offset from the centre (a pixel's side at that depth over cos θ).
            let pixel = clip.w / (0.5 * sp.proj.y * f32(sp.size.y));
            let tolerance = sp.far.y * clip.w + sp.far.z * pixel / max(cos_v, sp.far.w);
            // Over the background the triangle is not seen either (a silhouette).
            hidden = geometry[k].x >= sp.far.x || abs(clip.w - geometry[k].x) > tolerance;
        }
    }
    let keep = any(e > vec3<f32>(0.0)) && hidden;
    splat_out[id.x] = vec4<f32>(e, select(0.0, 1.0, keep));
}

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) tri: u32,
};

@vertex
fn vs(@builtin(vertex_index) k: u32, @builtin(instance_index) t: u32) -> VOut {
    var o: VOut;
    o.tri = t;
    // Culled: all six corners at one point, no fragments.
    o.clip = vec4<f32>(2.0, 2.0, 0.5, 1.0);
    if splats[t].w <= 0.0 {
        return o;
    }
    let reach = sp.proj.z;
    let clip = sp.view_proj * vec4<f32>(tris[t].centre.xyz, 1.0);
    if clip.w + reach < sp.proj.w {
        return o;
    }
    // The kernel's sphere seen from the camera fits in this square, at its nearest depth.
    let near = max(clip.w - reach, sp.proj.w);
    let centre = clip.xy / max(clip.w, near);
    let half = reach * sp.proj.xy / near;
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    o.clip = vec4<f32>(centre + corner[k] * half, 0.5, 1.0);
    return o;
}

@fragment
fn fs(i: VOut) -> @location(0) vec4<f32> {
    let px = vec2<u32>(i.clip.xy);
    let q = pos[sp.level.x + px.y * sp.size.z + px.x];
    if q.w <= 0.0 {
        discard;
    }
    let xo = q.xyz / q.w;
    let t = tris[i.tri];
    let xi = t.centre.xyz;
    let n = t.normal.xyz;
    let a = t.centre.w;
    // Eq. 9: the centre moved towards x̄, the point of the splat's plane nearest to x_o, by at
    // most the radius of the disc of the triangle's area. (The paper writes
    // x̄ = x_o + n(n·(x_o − x_i)), which leaves the plane; the projection subtracts.)
    var x = xi;
    let xb = xo - n * dot(xo - xi, n);
    let to = xb - xi;
    let l = length(to);
    if sp.camera_pos.w > 0.5 && l > 0.0 {
        x = xi + to / l * min(sqrt(a / PI), l);
    }
    return vec4<f32>(splats[i.tri].rgb * a * area_kernel(sp.kernel, distance(x, xo), a), 1.0);
}

// The accumulated texels of receivers (texels with the material's pixels) at full-resolution
// pixel `p`: a cubic B-spline over 4×4 texels, as Sigg & Hadwiger's bicubic filter, but with
// texels without receivers left out and the weights renormalized, so that light does not fade at
// the material's silhouette.
fn bspline(f: f32) -> vec4<f32> {
    let f2 = f * f;
    let f3 = f2 * f;
    return vec4<f32>(
        (1.0 - 3.0 * f + 3.0 * f2 - f3) / 6.0,
        (4.0 - 6.0 * f2 + 3.0 * f3) / 6.0,
        (1.0 + 3.0 * f + 3.0 * f2 - 3.0 * f3) / 6.0,
        f3 / 6.0,
    );
}

@compute @workgroup_size(8, 8)
fn up(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= sp.size.x || id.y >= sp.size.y {
        return;
    }
    let i = id.y * sp.size.x + id.x;
    if geometry[i].y <= 0.0 || u32(geometry[i].z + 0.5) != sp.level.w {
        return;
    }
    let texel = f32(1u << sp.level.y);
    let u = (vec2<f32>(id.xy) + 0.5) / texel - 0.5;
    let b = vec2<i32>(floor(u));
    let f = u - floor(u);
    let wx = bspline(f.x);
    let wy = bspline(f.y);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var dy = 0; dy < 4; dy++) {
        for (var dx = 0; dx < 4; dx++) {
            let t = b + vec2<i32>(dx - 1, dy - 1);
            if any(t < vec2<i32>(0)) || t.x >= i32(sp.size.z) || t.y >= i32(sp.size.w) {
                continue;
            }
            if pos[sp.level.x + u32(t.y) * sp.size.z + u32(t.x)].w <= 0.0 {
                continue;
            }
            let w = wx[dx] * wy[dy];
            sum += w * textureLoad(accumulated, t, 0).rgb;
            weight += w;
        }
    }
    if weight > 0.0 {
        scattered[i] += vec4<f32>(sum / weight, 0.0);
    }
}
