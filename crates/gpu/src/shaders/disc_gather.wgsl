// The disc gather shared by the methods that integrate a BSSRDF over the lit surface (the
// directional dipole, draft §4.2–4.3, and the Monte Carlo BSSRDF), one progressive frame: for
// each SSS pixel x_o and each light, `samples` points p on a disc of radius r* around x_o (the
// model's centre for it) in the plane perpendicular to the light ray, at the first points of
// the R2 sequence rotated per pixel (a component's centre and a radius around it drawn by the
// model from the first coordinate, `model_sample`, density per unit disc area `model_pdf_disc`;
// the angle from the second); each p is carried along the light ray onto the first
// surface the light sees (the light's position/normal map), the lit entry point x_i. The flux
// through the disc element dA⊥ is E⊥·dA⊥ (directional) or I·cos α·dA⊥/|p − x_light|² (point;
// I times the cosine off the light's normal for a point of an area light), so
//   π·L_o ≈ (1/N)·Σ exit(ω_o; ω_i) · flux density · response(x_i, ω_i; x_o) / pdf_A(p),
// `model_response` the exitance at x_o per unit power entering at x_i [cm⁻²] and
// `model_exit(cos_o, cos_i)` what turns exitance into π·L_o towards the camera for light that
// entered at cos_i. Light the map marks as a
// non-SSS surface (an occluder, the floor) contributes nothing: shadows come for free. Each
// frame adds its estimate × 1/(samples·frames) (π·L_o: the exitance convention of the separable
// pipeline) into `out`; with the denoiser, into `out` and `base` together: `base` the control's
// deterministic part (below), `out` what the samples add to it (w 1 where x_o is lit by some
// light), so that the denoiser can filter the samples' part alone and keep the control's detail
// (passes/denoise.rs).
//
// With a control variate: where x_o is lit, K = flux at x_o × model_flat (what a flat,
// evenly lit half-space returns), and each sample subtracts K × model_control / pdf, a density
// whose disc integral is exactly 1, so the mean is unchanged and only the response's departure
// from the flat one is left to the samples.
//
// The model's file (prepended in Rust) defines model_sample, model_pdf_disc,
// model_response, model_exit, model_centre (called once per pixel with x_o, its normal and the
// direction to the camera before the samples: the disc's centre, x_o or where the model's
// response peaks), model_flat (which also sets the control's plane for the light), model_control
// and model_lit_tolerance (0 and 0 for no control variate), and its own bindings from 7 on.

struct Light {
    view_proj: mat4x4<f32>,
    // xyz: direction towards the light (w = 0) or its position (w = 1) [cm].
    pos_or_dir: vec4<f32>,
    // rgb: irradiance at normal incidence (directional) or intensity [irradiance × cm²] (point);
    // w: layer of the light maps.
    color: vec4<f32>,
    // A point of an area light (w = 1): its intensity falls as the cosine off xyz, the light's
    // unit normal on its emitting side (a Lambertian emitter); w = 0: isotropic.
    lobe: vec4<f32>,
};

struct Gather {
    lights: array<Light, 4>,
    camera_pos: vec4<f32>,
    // x: r* [cm], y: weight of one sample in the final image, 1/(samples·frames); z: 1 where the
    // control's part goes to `base` for the denoiser, 0 where it is added to `out` at once.
    disc: vec4<f32>,
    // width, height, light count, samples per pixel and light.
    size: vec4<u32>,
    // frame index, seed, light-map size, 0.
    frame: vec4<u32>,
};

@group(0) @binding(0) var<uniform> u: Gather;
@group(0) @binding(1) var cam_pos: texture_2d<f32>;
@group(0) @binding(2) var cam_normal: texture_2d<f32>;
@group(0) @binding(3) var light_pos: texture_2d_array<f32>;
@group(0) @binding(4) var light_normal: texture_2d_array<f32>;
@group(0) @binding(5) var<storage, read_write> out: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> base: array<vec4<f32>>;

const PI: f32 = 3.14159265358979;

// PCG hash (Jarzynski & Olano 2020).
fn pcg(v: u32) -> u32 {
    let s = v * 747796405u + 2891336453u;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}

fn uniform01(state: ptr<function, u32>) -> f32 {
    *state = pcg(*state);
    return f32(*state >> 8u) / 16777216.0;
}

// Interleaved gradient noise (Jimenez 2014) at pixel p, in [0, 1): neighbouring pixels get
// well-spread values, so the pixels' errors are of high frequency on screen, what the denoiser
// takes out best.
fn ign(p: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

// Point k of the R2 sequence (Roberts 2018: k·(1/g, 1/g²) mod 1, g the plastic number), shifted
// by `shift` (a Cranley–Patterson rotation): any number of points of it cover the square evenly.
fn r2(k: u32, shift: vec2<f32>) -> vec2<f32> {
    return fract(shift + f32(k) * vec2<f32>(0.75487766625, 0.56984029100));
}

struct Entry {
    x: vec3<f32>,
    n: vec3<f32>,
    // The body's chord along the light through x [cm] (the nearest texel's normal.w; 0 where the
    // maps do not carry it).
    chord: f32,
    // ∂x/∂t per unit texel coordinate along the map's x and y [cm] on a smooth patch (the
    // bilinear interpolant's derivatives at t); 0 elsewhere.
    dx: vec3<f32>,
    dy: vec3<f32>,
    ok: u32,
};

// The current sample's Entry.chord, for the model's response (mc_bssrdf.wgsl).
var<private> gather_entry_chord: f32;

// The lit entry point where the light ray (origin ray_o, unit direction ray_d) through the
// disc point meets the surface, from the light's maps at continuous texel coordinate t. Where
// the four surrounding texels are one smooth SSS surface, their positions and normals are
// interpolated bilinearly: laterally exact for an orthographic light map, and a linear
// interpolation of depth (snapping to a texel centre instead would integrate S_d by the midpoint
// rule on the map's grid, overweighting its peak at x_o). Elsewhere (depth discontinuities, the
// light-space silhouette) the ray meets the nearest texel's tangent plane, a point inside that
// texel's footprint; snapping to the texel centre there instead draws the staircase of the
// rasterized silhouette into the terminator as scalloped dots. Only where the ray runs within
// 0.6° of that plane is the texel centre kept.
fn entry_point(t: vec2<f32>, layer: i32, ray_o: vec3<f32>, ray_d: vec3<f32>) -> Entry {
    var e: Entry;
    e.ok = 0u;
    e.dx = vec3<f32>(0.0);
    e.dy = vec3<f32>(0.0);
    let size = vec2<i32>(textureDimensions(light_pos));
    let base = vec2<i32>(floor(t - 0.5));
    let f = t - 0.5 - vec2<f32>(base);
    let i00 = clamp(base, vec2<i32>(0), size - 1);
    let i11 = clamp(base + 1, vec2<i32>(0), size - 1);
    let p00 = textureLoad(light_pos, i00, layer, 0);
    let p10 = textureLoad(light_pos, vec2<i32>(i11.x, i00.y), layer, 0);
    let p01 = textureLoad(light_pos, vec2<i32>(i00.x, i11.y), layer, 0);
    let p11 = textureLoad(light_pos, i11, layer, 0);
    // A smooth patch: all four on SSS surfaces, neighbours no further apart along the ray than
    // 8 times across it (surfaces up to ~83° from facing the light).
    let across = length(cross(p10.xyz - p00.xyz, ray_d)) + length(cross(p01.xyz - p00.xyz, ray_d));
    let along = abs(dot(p10.xyz - p00.xyz, ray_d)) + abs(dot(p01.xyz - p00.xyz, ray_d))
        + abs(dot(p11.xyz - p00.xyz, ray_d));
    if min(min(p00.w, p10.w), min(p01.w, p11.w)) > 0.5 && along <= 8.0 * across {
        e.x = mix(mix(p00.xyz, p10.xyz, f.x), mix(p01.xyz, p11.xyz, f.x), f.y);
        let n00 = textureLoad(light_normal, i00, layer, 0).xyz;
        let n10 = textureLoad(light_normal, vec2<i32>(i11.x, i00.y), layer, 0).xyz;
        let n01 = textureLoad(light_normal, vec2<i32>(i00.x, i11.y), layer, 0).xyz;
        let n11 = textureLoad(light_normal, i11, layer, 0).xyz;
        e.n = normalize(mix(mix(n00, n10, f.x), mix(n01, n11, f.x), f.y));
        e.chord = textureLoad(light_normal, clamp(vec2<i32>(floor(t)), vec2<i32>(0), size - 1), layer, 0).w;
        e.dx = mix(p10.xyz - p00.xyz, p11.xyz - p01.xyz, f.y);
        e.dy = mix(p01.xyz - p00.xyz, p11.xyz - p10.xyz, f.x);
        e.ok = 1u;
        return e;
    }
    let near = clamp(vec2<i32>(floor(t)), vec2<i32>(0), size - 1);
    let pc = textureLoad(light_pos, near, layer, 0);
    if pc.w < 0.5 {
        return e;
    }
    let nc = textureLoad(light_normal, near, layer, 0);
    e.n = normalize(nc.xyz);
    e.chord = nc.w;
    e.x = pc.xyz;
    let facing = dot(ray_d, e.n);
    if abs(facing) > 0.01 {
        e.x = ray_o + ray_d * (dot(pc.xyz - ray_o, e.n) / facing);
    }
    e.ok = 1u;
    return e;
}

// The lit entry point of the light ray through the disc point p (ok = 0 where the ray leaves
// the light's maps or meets no SSS surface).
fn light_entry(light: Light, axis: vec3<f32>, point: bool, p: vec3<f32>) -> Entry {
    var none: Entry;
    none.ok = 0u;
    let clip = light.view_proj * vec4<f32>(p, 1.0);
    if clip.w <= 0.0 {
        return none;
    }
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return none;
    }
    var ray_o = p;
    var ray_d = axis;
    if light.pos_or_dir.w > 0.5 {
        ray_o = light.pos_or_dir.xyz;
        ray_d = normalize(p - ray_o);
    }
    return entry_point(uv * f32(u.frame.z), i32(light.color.w), ray_o, ray_d);
}

// The light's flux per unit disc area at the disc point p: E⊥ (directional), or
// I·cos α/|p − x_light|² (point; times the cosine off the light's normal for a point of an
// area light).
fn light_flux(light: Light, axis: vec3<f32>, point: bool, p: vec3<f32>) -> vec3<f32> {
    if !point {
        return light.color.rgb;
    }
    let to_light = light.pos_or_dir.xyz - p;
    var flux = light.color.rgb * abs(dot(normalize(to_light), axis)) / dot(to_light, to_light);
    if light.lobe.w > 0.5 {
        flux *= max(dot(light.lobe.xyz, -normalize(to_light)), 0.0);
    }
    return flux;
}

// The light maps' surface around the entry `own` of the light ray through the point p, as a
// linear map of the disc's plane (unit basis t1, t2): where the entry moves per unit step of p
// along t1 (columns[0]) and t2 (columns[1]) [cm/cm], the smooth patch's derivatives chained with
// the map's projection at p (0 off a smooth patch).
fn entry_map(light: Light, p: vec3<f32>, own: Entry, t1: vec3<f32>, t2: vec3<f32>) -> mat2x3<f32> {
    let clip = light.view_proj * vec4<f32>(p, 1.0);
    let map = f32(u.frame.z);
    var cols = array<vec3<f32>, 2>(vec3<f32>(0.0), vec3<f32>(0.0));
    let basis = array<vec3<f32>, 2>(t1, t2);
    for (var j = 0u; j < 2u; j++) {
        let dclip = light.view_proj * vec4<f32>(basis[j], 0.0);
        let dndc = (dclip.xy * clip.w - clip.xy * dclip.w) / (clip.w * clip.w);
        let dt = map * vec2<f32>(0.5 * dndc.x, -0.5 * dndc.y);
        cols[j] = own.dx * dt.x + own.dy * dt.y;
    }
    return mat2x3<f32>(cols[0], cols[1]);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let width = u.size.x;
    if id.x >= width || id.y >= u.size.y {
        return;
    }
    let i = id.y * width + id.x;
    let po = textureLoad(cam_pos, vec2<i32>(id.xy), 0);
    if po.w < 0.5 {
        return;
    }
    let xo = po.xyz;
    let no = normalize(textureLoad(cam_normal, vec2<i32>(id.xy), 0).xyz);
    let wo = normalize(u.camera_pos.xyz - xo);
    let cos_o = dot(wo, no);
    // The samples of a pixel and light are the first points of R2, rotated by the pixel's
    // interleaved gradient noise plus one uniform shift per frame, light and seed: each pixel's
    // rotation is then uniform on the square, so its estimate is unbiased, and frames are
    // independent of each other. The first coordinate, stratified (sample k of N in
    // [k/N, (k+1)/N)), draws the radius, the second the angle.
    var state = pcg(u.frame.x * 9781u + pcg(u.frame.y));
    let pixel = vec2<f32>(id.xy);
    let noise = vec2<f32>(ign(pixel), ign(pixel.yx + vec2<f32>(17.0, 41.0)));
    var sum = vec3<f32>(0.0);
    var control = vec3<f32>(0.0);
    let centre = model_centre(xo, no, wo);
    for (var l = 0u; l < u.size.z; l++) {
        let light = u.lights[l];
        let point = light.pos_or_dir.w > 0.5;
        var axis = normalize(light.pos_or_dir.xyz);
        if point {
            axis = normalize(light.pos_or_dir.xyz - xo);
        }
        // An orthonormal basis of the disc's plane (Duff et al. 2017).
        let sgn = select(-1.0, 1.0, axis.z >= 0.0);
        let a = -1.0 / (sgn + axis.z);
        let b = axis.x * axis.y * a;
        let t1 = vec3<f32>(1.0 + sgn * axis.x * axis.x * a, sgn * b, -sgn * axis.x);
        let t2 = vec3<f32>(b, sgn + axis.y * axis.y * a, -axis.y);
        let shift = fract(noise + vec2<f32>(uniform01(&state), uniform01(&state)));
        // The control variate. Where x_o is lit (its own light ray first meets the light maps'
        // surface within model_lit_tolerance of it, on a smooth patch), K is what a flat,
        // evenly lit half-space returns there, and the light maps' surface around that entry
        // is taken as the plane the linear map A spans (entry_map): each sample then adds its
        // response less K times the model's control density, its response's shape laid on that
        // plane (a density of disc integral exactly 1, so the mean is unchanged: the estimate is
        // unbiased for any K) over the sample's density. Where the surface is flat and evenly
        // lit around x_o, only the response's departure from the plane's is left to the
        // samples. Distances are then measured from that entry, x_o on the light maps'
        // surface (within the tolerance of x_o; by bilinear interpolation 10⁻³ cm on the
        // bust at 99 %), so that response and control read the profile's bins from one surface;
        // the shape-aware response's curvature then compares the entry's normal with that
        // entry's normal on the same maps (exit_n) rather than with the camera's.
        var flat = vec3<f32>(0.0);
        var exit_at = xo;
        var exit_n = no;
        var lin = mat2x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0));
        var jacobian = 0.0;
        let own = light_entry(light, axis, point, xo);
        if own.ok != 0u && length(own.x - xo) <= model_lit_tolerance() {
            lin = entry_map(light, xo, own, t1, t2);
            let across = cross(lin[0], lin[1]);
            jacobian = length(across);
            let cos_own = dot(axis, own.n);
            if jacobian > 0.0 && cos_own > 0.0 {
                let plane_n = across / jacobian * sign(dot(across, own.n));
                exit_at = own.x;
                exit_n = own.n;
                flat = light_flux(light, axis, point, xo)
                    * model_flat(axis, plane_n, own.n, cos_o, own.chord);
            }
        }
        control += flat * f32(u.size.w);
        // x_o's offset from the disc's centre, in the disc's plane.
        let from_centre = vec2<f32>(dot(xo - centre, t1), dot(xo - centre, t2));
        for (var k = 0u; k < u.size.w; k++) {
            // Stratified over the model's mixture: sample k draws from [k/N, (k+1)/N).
            let draw = r2(k, shift);
            let drawn = model_sample((f32(k) + draw.x) / f32(u.size.w));
            let r = drawn.w;
            let phi = 2.0 * PI * draw.y;
            if !(r > 0.0) {
                continue;
            }
            // The component's centre in the disc's plane.
            let d = drawn.xyz - dot(drawn.xyz, axis) * axis + r * (cos(phi) * t1 + sin(phi) * t2);
            let pdf = model_pdf_disc(d, axis);
            if !(pdf > 0.0) {
                continue;
            }
            if any(flat != vec3<f32>(0.0)) {
                // The entry on the plane, from x_o's entry: A·(p − x_o) in the disc's basis.
                let v = vec2<f32>(dot(d, t1), dot(d, t2)) - from_centre;
                let on_plane = lin * v;
                sum -= flat * model_control(on_plane, jacobian) / pdf;
            }
            let p = centre + d;
            let hit = light_entry(light, axis, point, p);
            if hit.ok == 0u {
                continue;
            }
            let xi = hit.x;
            let ni = hit.n;
            var wi = axis;
            if point {
                wi = normalize(light.pos_or_dir.xyz - xi);
            }
            let cos_i = dot(wi, ni);
            if cos_i <= 0.0 {
                continue;
            }
            gather_entry_chord = hit.chord;
            sum += light_flux(light, axis, point, p) * model_response(xi, ni, wi, cos_i, exit_at, exit_n)
                * model_exit(cos_o, cos_i) / pdf;
        }
    }
    // Kept apart for the denoiser (disc.z = 1), else summed here.
    if u.disc.z > 0.5 {
        let lit = select(0.0, 1.0, any(control != vec3<f32>(0.0)));
        out[i] += vec4<f32>(sum * u.disc.y, lit / f32(u.frame.w));
        base[i] += vec4<f32>(control * u.disc.y, 0.0);
    } else {
        out[i] += vec4<f32>((sum + control) * u.disc.y, 0.0);
    }
}
