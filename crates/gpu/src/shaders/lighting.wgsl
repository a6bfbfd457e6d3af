// Lighting shared by the scene pass (scene.wgsl) and the splats of the area gather (splat.wgsl):
// the lights, the SSS materials' tables, shadows, and the albedo split. World units are cm;
// shading::LOOKUPS_WGSL (Fresnel, the angle grid, the tables' lookups and `SssMaterial`) is
// prepended; the accessors below give its lookups the tables of g.materials.

// One emitter (gpu::Emitter): a directional or point light, or one cell of an area light.
struct Light {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // xyz: direction towards the light (w = 0) or its position (w = 1).
    pos_or_dir: vec4<f32>,
    // rgb: radiance scale (irradiance at normal incidence for directional lights, intensity for
    // point lights and cells, divided by distance² [cm²]); w: shadow-map layer, < 0 for none.
    color: vec4<f32>,
    // A cell of an area light: xyz its half edges [cm] (u × v points to the emitting side),
    // cell_u.w = 1 (0: not a cell).
    cell_u: vec4<f32>,
    cell_v: vec4<f32>,
};

struct Globals {
    view_proj: mat4x4<f32>,
    view: mat4x4<f32>,
    camera_pos: vec4<f32>,
    // x: light count, y: albedo mode (0 pre, 1 post, 2 pre+post), z: specular intensity,
    // w: Blinn–Phong exponent.
    params: vec4<f32>,
    // rgb: the ambient irradiance; w: the layer where the back maps start in shadow_maps (0:
    // none; gpu's shadow::back_layers).
    ambient: vec4<f32>,
    lights: array<Light, 64>,
    // Per SSS material (the vertices' material index): shading::PackedShading.
    materials: array<SssMaterial, 4>,
};

@group(0) @binding(0) var<uniform> g: Globals;
@group(0) @binding(1) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;

// The tables the lookups of shading::LOOKUPS_WGSL read (shading::BINDINGS_WGSL's over a storage
// buffer).
fn sss_incidence_entry(m: u32, k: u32) -> vec3<f32> {
    return g.materials[m].incidence[k].rgb;
}

fn sss_exit_entry(m: u32, k: u32) -> vec3<f32> {
    return g.materials[m].exit[k].rgb;
}

fn sss_shift_entry(m: u32, k: u32) -> vec3<f32> {
    return g.materials[m].shift[k].rgb;
}

fn sss_translucency_grid(m: u32) -> vec2<f32> {
    return g.materials[m].translucency_params.xy;
}

fn sss_translucency_entry(m: u32, k: u32) -> vec3<f32> {
    return g.materials[m].translucency[k].rgb;
}

fn sss_translucency_exit_entry(m: u32, k: u32) -> vec3<f32> {
    return g.materials[m].translucency_exit[k].rgb;
}

fn sss_shape_params(m: u32) -> vec4<f32> {
    return g.materials[m].shape_params;
}

fn sss_shape_grid(m: u32, j: u32) -> vec4<f32> {
    return g.materials[m].shape_grid[j];
}

fn sss_shape_entry(m: u32, q: u32, i: u32, k: u32) -> vec3<f32> {
    return g.materials[m].shape[135u * q + 9u * i + k].rgb;
}

fn sss_shape_slab_grid(m: u32, j: u32) -> vec4<f32> {
    return g.materials[m].shape_slab_grid[j];
}

fn sss_shape_slab_entry(m: u32, i: u32, k: u32) -> vec3<f32> {
    return g.materials[m].shape_slab[9u * i + k].rgb;
}

// The fraction of emitter i's light that reaches `world` (unit normal n, `l` the unit direction
// towards the light, n_dot_l = n·l > 0): its shadow map's 3×3 comparison filter. The depth bias
// is a world distance along the ray to the light: one shadow-map texel's footprint at `world`
// times 1.5 + 2·tan θ (half a texel of rasterization plus the surface's rise across the filter's
// ±1 texel), so an occluder farther than that in front of the point always hides it. (A bias in
// NDC depth is not: where the map's near plane lies close to the light, 0.0015 of NDC depth
// spanned 3 cm at the far side of the fin scene, and the 3 mm fin cast no shadow on the 1 mm one.)
fn shadow(i: u32, world: vec3<f32>, l: vec3<f32>, n_dot_l: f32) -> f32 {
    let layer = g.lights[i].color.w;
    if layer < 0.0 {
        return 1.0;
    }
    let p = g.lights[i].view_proj * vec4<f32>(world, 1.0);
    let ndc = p.xyz / p.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 {
        return 1.0;
    }
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let footprint = length(entry(i, ndc.xy + vec2<f32>(2.0 / size.x, 0.0), ndc.z) - entry(i, ndc.xy, ndc.z));
    let tan_theta = min(sqrt(max(1.0 - n_dot_l * n_dot_l, 0.0)) / max(n_dot_l, 1e-3), 8.0);
    let biased = g.lights[i].view_proj * vec4<f32>(world + l * footprint * (1.5 + 2.0 * tan_theta), 1.0);
    let depth = biased.z / biased.w;
    let texel = 1.0 / size;
    var lit = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            lit += textureSampleCompareLevel(shadow_maps, shadow_sampler,
                uv + vec2<f32>(f32(dx), f32(dy)) * texel, i32(layer), depth);
        }
    }
    return lit / 9.0;
}

// The thickness [cm] of an SSS part behind `world` as light `i` crosses it: the distance along
// the light ray to where the light enters (its shadow map's first surface); < 0 without a shadow
// map or outside it.
fn thickness(i: u32, world: vec3<f32>) -> f32 {
    let layer = g.lights[i].color.w;
    if layer < 0.0 {
        return -1.0;
    }
    let p = g.lights[i].view_proj * vec4<f32>(world, 1.0);
    let ndc = p.xyz / p.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return -1.0;
    }
    // The entry depth interpolated bilinearly between the four nearest texel centres (exact on
    // flat parts; the nearest texel alone is off by up to half a texel times the slope).
    let size = vec2<i32>(textureDimensions(shadow_maps));
    let t = uv * vec2<f32>(size) - 0.5;
    let base = vec2<i32>(floor(t));
    let f = t - vec2<f32>(base);
    let lo = clamp(base, vec2<i32>(0), size - 1);
    let hi = clamp(base + 1, vec2<i32>(0), size - 1);
    let l = i32(layer);
    let z = array<f32, 4>(
        textureLoad(shadow_maps, lo, l, 0),
        textureLoad(shadow_maps, vec2<i32>(hi.x, lo.y), l, 0),
        textureLoad(shadow_maps, vec2<i32>(lo.x, hi.y), l, 0),
        textureLoad(shadow_maps, hi, l, 0));
    let depth = mix(mix(z[0], z[1], f.x), mix(z[2], z[3], f.x), f.y);
    // Where the four disagree by more than a plane tilted 76° from the light would (4 texels
    // across one), the map does not resolve the surface there: a silhouette of the light's view,
    // such as a curved body's terminator, where the chord shrinks to 0 within a texel and the
    // interpolated entry lands on the point itself. There the thickest reading is taken (too
    // little light rather than a speckle of a thin-slab's transmittance).
    let texel = length(entry(i, ndc.xy + vec2<f32>(2.0 / f32(size.x), 0.0), depth) - entry(i, ndc.xy, depth));
    var near = 1e30;
    var far = 0.0;
    for (var k = 0; k < 4; k++) {
        let d = length(world - entry(i, ndc.xy, z[k]));
        near = min(near, d);
        far = max(far, d);
    }
    if far - near > 4.0 * texel {
        return far;
    }
    return length(world - entry(i, ndc.xy, depth));
}

// The world point [cm] of light i's view at NDC `xy` and shadow-map depth `z`.
fn entry(i: u32, xy: vec2<f32>, z: f32) -> vec3<f32> {
    let e = g.lights[i].inv_view_proj * vec4<f32>(xy, z, 1.0);
    return e.xyz / e.w;
}

// The body's chord [cm] along light i's ray through `world`, a point the light reaches first: the
// distance to the next surface behind it, the light's back map (shadow::back_layers: the layer
// g.ambient.w after its shadow map's), at the nearest texel; 0 (unknown) without back maps or a
// shadow map, outside the map, or where nothing lies behind.
fn chord(i: u32, world: vec3<f32>) -> f32 {
    let back = g.ambient.w;
    let layer = g.lights[i].color.w;
    if back < 0.5 || layer < 0.0 {
        return 0.0;
    }
    let p = g.lights[i].view_proj * vec4<f32>(world, 1.0);
    let ndc = p.xyz / p.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return 0.0;
    }
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let z = textureLoad(shadow_maps, vec2<i32>(uv * size), i32(layer + back), 0);
    if z >= 1.0 {
        return 0.0;
    }
    return length(entry(i, ndc.xy, z) - world);
}

// The body's shape for light i entering SSS material m at `world` (unit normal n, `l` the unit
// direction towards the light, cos θ = cos_i, `loc` the surface's turn): E per channel at the
// curvature the light travels over, `light_scale` [cm⁻¹] (the vertices' baked chord curvature,
// shading::light_scale_curvature), times what a body thinner along the light than its curvature
// keeps (sss_shape_thin at the chord, with the normal curvature in the plane of n and l: a
// sphere's 1/R, a cylinder's 1/r across its axis and 0 along it, so that on both the chord is
// what the curvature makes it; at normal incidence the larger principal curvature `principal`,
// whose chord along the normal is the shorter: 2r on a cylinder); ones where the material's shape
// table is off.
fn shape_factor(i: u32, m: u32, world: vec3<f32>, n: vec3<f32>, l: vec3<f32>, loc: Local,
                light_scale: vec3<f32>, principal: f32) -> vec3<f32> {
    if g.materials[m].shape_params.w < 0.5 {
        return vec3<f32>(1.0);
    }
    let cos_i = dot(n, l);
    let along = l - cos_i * n;
    var k = principal;
    if dot(along, along) > 1e-8 {
        let t = normalize(along);
        k = dot(normal_derivative(loc, t), t);
    }
    // E with each channel at its own curvature: one lookup (the table is on, checked above).
    return sss_shape_at(m, 0u, light_scale, cos_i) * sss_shape_thin(m, k, chord(i, world), cos_i);
}

// π × the radiance a smooth dielectric boundary of index eta at `world` (unit normal n) reflects
// towards the camera (`view_dir`) from cell i of an area light: the Fresnel reflectance at the
// view angle times the cell's radiance, where the mirror ray hits the cell's front face (π: the
// image holds π × radiance, as it holds irradiance × albedo for Lambertian surfaces). `shade`
// multiplies it by the cell's shadow test.
fn mirror(i: u32, world: vec3<f32>, n: vec3<f32>, view_dir: vec3<f32>, eta: f32) -> vec3<f32> {
    let u = g.lights[i].cell_u.xyz;
    let v = g.lights[i].cell_v.xyz;
    let normal = cross(u, v);
    let r = reflect(-view_dir, n);
    let facing = dot(r, normal);
    if facing >= 0.0 {
        return vec3<f32>(0.0);
    }
    let c = g.lights[i].pos_or_dir.xyz;
    let t = dot(c - world, normal) / facing;
    let p = world + t * r - c;
    if t <= 0.0 || abs(dot(p, u)) > dot(u, u) || abs(dot(p, v)) > dot(v, v) {
        return vec3<f32>(0.0);
    }
    let radiance = g.lights[i].color.rgb / (4.0 * length(normal));
    return 3.14159265 * fresnel(eta, dot(n, view_dir)) * radiance;
}

// How the surface turns around a point: the screen-space derivatives of the position [cm] and of
// the unit normal (scene.wgsl); all 0 where they are unknown (the splats), read as flat.
struct Local {
    dpx: vec3<f32>,
    dpy: vec3<f32>,
    dnx: vec3<f32>,
    dny: vec3<f32>,
};

// The unit normal's first-order change over a displacement d [cm] along the surface: d written
// in the position's two screen derivatives (least squares), the normal's derivatives applied; 0
// where the derivatives do not span the surface.
fn normal_derivative(loc: Local, d: vec3<f32>) -> vec3<f32> {
    let a = dot(loc.dpx, loc.dpx);
    let b = dot(loc.dpx, loc.dpy);
    let c = dot(loc.dpy, loc.dpy);
    let det = a * c - b * b;
    if !(det > 1e-6 * a * c) {
        return vec3<f32>(0.0);
    }
    let u = dot(loc.dpx, d);
    let v = dot(loc.dpy, d);
    return ((c * u - b * v) * loc.dnx + (a * v - b * u) * loc.dny) / det;
}

// The change of the unit normal over a displacement d [cm] along the surface (normal_derivative),
// at most half a unit (≈ 30°): across a crease or a silhouette the derivatives say nothing of the
// surface.
fn normal_turn(loc: Local, d: vec3<f32>) -> vec3<f32> {
    let dn = normal_derivative(loc, d);
    return dn * min(1.0, 0.5 / max(length(dn), 1e-30));
}

// The surface's larger principal curvature κ₁ [cm⁻¹] at a point of unit normal n, from the shape
// operator: the normal's derivative along two orthonormal tangents t (Duff et al. 2017's basis)
// projected on them (dn/ds·t, symmetrised), its larger eigenvalue. > 0 where the surface is
// convex (its normal turns the way one moves: 1/R on a sphere of radius R), < 0 concave, 0 flat
// and where the derivatives are unknown (the splats).
fn larger_curvature(loc: Local, n: vec3<f32>) -> f32 {
    let sgn = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sgn + n.z);
    let b = n.x * n.y * a;
    let t1 = vec3<f32>(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
    let t2 = vec3<f32>(b, sgn + n.y * n.y * a, -n.y);
    let d1 = normal_derivative(loc, t1);
    let d2 = normal_derivative(loc, t2);
    let s11 = dot(d1, t1);
    let s22 = dot(d2, t2);
    let s12 = 0.5 * (dot(d1, t2) + dot(d2, t1));
    let half = 0.5 * (s11 - s22);
    return 0.5 * (s11 + s22) + sqrt(half * half + s12 * s12);
}

// Light i entering SSS material m where it leaves at `world` (unit normal n, `l` the unit
// direction towards the light, `scale` its irradiance at normal incidence), entry-shifted
// (shading::EntryShift): light entering at θ leaves a half-space δ(θ) ahead of its entry along the
// propagation projected on the surface, t = −l less its part along n. So the light that leaves
// here entered δ behind, at world − δ·t (per channel), where the normal has turned by the
// surface's curvature (normal_turn) and the shadow is that point's: the light's incidence there,
// the incidence table at it, its shadow map. δ is read at the angle here (from behind, cos ≤ 0,
// the 80° value: what enters just before the terminator reaches past it). The view's obliquity
// shifts it too, by reciprocity: light leaving towards the camera at θ_o (`view_dir`, cos θ_o =
// n·v) last scattered, on average, δ(θ_o) further along the view ray's propagation into the
// surface (away from the camera) than where it leaves, just as light entering at θ_o would
// return δ(θ_o) ahead; so the light the camera sees here entered at world − δ(θ_i)·t +
// δ(θ_o)·t_v, t_v = −v less its part along n (`exit`, per channel: the pixel's, exit_offsets).
// `light_scale` and `principal`: the curvatures the shape table is read at (shape_factor).
struct Entry {
    // The entering light (rgb), and without shadows (what weighs the exit law's entry angle).
    light: vec3<f32>,
    unshadowed: vec3<f32>,
    // Σ over channels of the unshadowed light × its cosine of incidence.
    cos_weighted: f32,
};

// The view's part of the shifted entry per channel, the same for every light: δ(θ_o)·t_v.
fn exit_offsets(m: u32, n: vec3<f32>, view_dir: vec3<f32>) -> array<vec3<f32>, 3> {
    let delta_o = sss_entry_shift(m, max(dot(n, view_dir), 0.0));
    return array<vec3<f32>, 3>(sss_entry_offset(n, view_dir, -delta_o.r),
                               sss_entry_offset(n, view_dir, -delta_o.g),
                               sss_entry_offset(n, view_dir, -delta_o.b));
}

fn shifted_entry(i: u32, m: u32, world: vec3<f32>, n: vec3<f32>, l: vec3<f32>,
                 exit: array<vec3<f32>, 3>, scale: vec3<f32>, loc: Local, light_scale: vec3<f32>,
                 principal: f32) -> Entry {
    let delta = sss_entry_shift(m, dot(n, l));
    // The shape's E at the angle here (as δ), the same for every channel's entry point.
    let energy = shape_factor(i, m, world, n, l, loc, light_scale, principal);
    var e = Entry(vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    for (var c = 0u; c < 3u; c++) {
        var p = world;
        var nc = n;
        let d = sss_entry_offset(n, l, delta[c]) + exit[c];
        if any(d != vec3<f32>(0.0)) {
            p = world + d;
            nc = normalize(n + normal_turn(loc, d));
        }
        let ndl = dot(nc, l);
        if ndl > 0.0 {
            let u = scale[c] * ndl * sss_incidence(m, ndl)[c] * energy[c];
            e.unshadowed[c] = u;
            e.light[c] = u * shadow(i, p, l, ndl);
            e.cos_weighted += u * ndl;
        }
    }
    return e;
}

struct Lit {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
    // On SSS surfaces the exit factor h(θ_o; θ_i) towards the camera (1 elsewhere): the exit
    // table at the view angle and at the cosine of incidence of the point's lights, weighted by
    // the irradiance each brings unshadowed (its shadow is its neighbours' light), the
    // normal-entry row where none faces it (light that diffused there from far).
    exit: vec3<f32>,
};

// What arrives at `world` with unit normal `n`, seen from `view_dir`: the diffuse irradiance (on
// SSS surfaces of material m with its incidence table and, with `through`, the light that crosses
// thin parts from behind; entry-shifted where the material says so, `loc` the surface's turn,
// `light_scale` its curvature at the scale light travels [cm⁻¹], per channel, for the shape
// table) and the specular: Blinn–Phong, plus on SSS surfaces the mirror image of area lights in
// their dielectric boundary.
fn shade(world: vec3<f32>, n: vec3<f32>, view_dir: vec3<f32>, m: u32, sss: bool, through: bool,
         loc: Local, light_scale: vec3<f32>) -> Lit {
    var irradiance = g.ambient.rgb * select(vec3<f32>(1.0), g.materials[m].incidence_ambient.rgb, sss);
    var spec = vec3<f32>(0.0);
    var entry_w = 0.0;
    var entry_c = 0.0;
    // Light through thin parts, with its own angular distribution h_T.
    var through_light = vec3<f32>(0.0);
    let cos_o = dot(n, view_dir);
    let shifting = sss && g.materials[m].shift[0].w > 0.5;
    // The principal curvature the thin factor is read at (only where the table is on: WGSL's
    // select would evaluate it on every pixel).
    var principal = 0.0;
    if sss && g.materials[m].shape_params.w > 0.5 {
        principal = larger_curvature(loc, n);
    }
    var exit_offset = array<vec3<f32>, 3>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    if shifting {
        exit_offset = exit_offsets(m, n, view_dir);
    }
    for (var i = 0u; i < u32(g.params.x); i++) {
        let l4 = g.lights[i].pos_or_dir;
        var l = normalize(l4.xyz);
        var scale = g.lights[i].color.rgb;
        if l4.w > 0.5 {
            let d = l4.xyz - world;
            l = normalize(d);
            scale = scale / dot(d, d);
        }
        let cell = g.lights[i].cell_u.w > 0.5;
        if cell {
            // A cell of an area light emits ∝ cos θ off the light's normal, from its front.
            scale *= max(dot(normalize(cross(g.lights[i].cell_u.xyz, g.lights[i].cell_v.xyz)), -l), 0.0);
        }
        let n_dot_l = max(dot(n, l), 0.0);
        if n_dot_l <= 0.0 {
            // Light from behind: what crosses a thin part.
            if through && sss && g.materials[m].translucency_params.z > 0.5 {
                let d = thickness(i, world);
                if d >= 0.0 {
                    // Entering the (parallel) back face at incidence |n·l|, relative to normal.
                    let c = -dot(n, l);
                    let eta = g.materials[m].translucency_params.w;
                    through_light += scale * c * sss_back_face_entry(eta, c) * sss_translucency(m, d)
                        * sss_translucency_exit(m, d, cos_o);
                }
            }
        }
        let eta = g.materials[m].translucency_params.w;
        let mirrored = cell && sss && eta != 1.0;
        if shifting {
            let e = shifted_entry(i, m, world, n, l, exit_offset, scale, loc, light_scale, principal);
            irradiance += e.light;
            entry_w += e.unshadowed.r + e.unshadowed.g + e.unshadowed.b;
            entry_c += e.cos_weighted;
            // What remains here is the specular light: without any, no shadow test here.
            if !(g.params.z > 0.0 || mirrored) {
                continue;
            }
        }
        if n_dot_l <= 0.0 {
            continue;
        }
        let vis = shadow(i, world, l, n_dot_l);
        if mirrored {
            // The mirror ray meets the cell within half a cell of its centre: what hides the
            // centre (the cell's shadow map) hides the mirror image.
            spec += mirror(i, world, n, view_dir, eta) * vis;
        }
        if !shifting {
            // Only SSS surfaces read the tables (the shape's chord is a texture read).
            var entering = scale * n_dot_l;
            if sss {
                entering *= sss_incidence(m, n_dot_l)
                    * shape_factor(i, m, world, n, l, loc, light_scale, principal);
            }
            irradiance += entering * vis;
            let w = entering.r + entering.g + entering.b;
            entry_w += w;
            entry_c += w * n_dot_l;
        }
        let h = normalize(l + view_dir);
        spec += scale * g.params.z * pow(max(dot(n, h), 0.0), g.params.w) * n_dot_l * vis;
    }
    let entry_cos = select(1.0, entry_c / entry_w, entry_w > 0.0);
    // Transmitted light leaves with its own angular distribution h_T; the scattered light is
    // multiplied by the reflection's h after the blur, which this divides out.
    let exit = select(vec3<f32>(1.0), sss_exit(m, cos_o, entry_cos), sss);
    irradiance += through_light / max(exit, vec3<f32>(1e-3));
    return Lit(irradiance, spec, exit);
}

// The albedo applied before scattering ([0]) and after it ([1]), by the mode in g.params.y
// (0 pre, 1 post, 2 pre+post).
fn albedo_split(albedo: vec3<f32>) -> array<vec3<f32>, 2> {
    var pre = albedo;
    var post = vec3<f32>(1.0);
    let mode = u32(g.params.y);
    if mode == 1u {
        pre = vec3<f32>(1.0);
        post = albedo;
    } else if mode == 2u {
        pre = sqrt(albedo);
        post = sqrt(albedo);
    }
    return array<vec3<f32>, 2>(pre, post);
}
