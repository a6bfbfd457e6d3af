// Scene pass: shadowed irradiance (rgba32float), specular with the SSS strength in alpha
// (rgba16float), and linear view depth with the post-scatter albedo (times the exit-angle factor)
// packed as RGBA8 bits (rg32float): 32 bytes per pixel, WebGPU's portable limit. World units
// are cm; fresnel.wgsl and lighting.wgsl (the lights, tables, shadows and `shade`) are prepended.

struct VIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    @location(3) strength: f32,
    @location(4) material: u32,
    @location(5) curvature: vec3<f32>,
};

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    @location(3) strength: f32,
    @location(4) view_depth: f32,
    @location(5) @interpolate(flat) material: u32,
    @location(6) curvature: vec3<f32>,
};

@vertex
fn vs(v: VIn) -> VOut {
    var o: VOut;
    o.clip = g.view_proj * vec4<f32>(v.pos, 1.0);
    o.world = v.pos;
    o.normal = v.normal;
    o.albedo = v.albedo;
    o.strength = v.strength;
    o.material = v.material;
    o.curvature = v.curvature;
    o.view_depth = -(g.view * vec4<f32>(v.pos, 1.0)).z;
    return o;
}

// The post-scatter albedo times the exit factor, c ≥ 0 per channel, as RGBA8 bits: rgb = c/m,
// alpha = m/4, with m ≥ max(1, max c) on the alpha's 8-bit steps (so m ≤ 4); unpack.wgsl decodes.
fn pack_albedo(c: vec3<f32>) -> u32 {
    let a = min(ceil(max(1.0, max(c.r, max(c.g, c.b))) * 255.0 / 4.0), 255.0);
    return pack4x8unorm(vec4<f32>(c / (a * 4.0 / 255.0), a / 255.0));
}

struct FOut {
    @location(0) diffuse: vec4<f32>,
    @location(1) specular: vec4<f32>,
    @location(2) geometry: vec4<f32>,
};

@fragment
fn fs(v: VOut, @builtin(front_facing) front: bool) -> FOut {
    let n = select(-1.0, 1.0, front) * normalize(v.normal);
    // How the surface turns here (entry-shifted shading, lighting.wgsl).
    let loc = Local(dpdxFine(v.world), dpdyFine(v.world), dpdxFine(n), dpdyFine(n));
    let view_dir = normalize(g.camera_pos.xyz - v.world);
    let sss = v.strength > 0.0;
    let m = min(v.material, 3u);
    // The curvature the light travels over (the vertices' bake; a back face sees it mirrored).
    let curvature = select(-1.0, 1.0, front) * v.curvature;
    let lit = shade(v.world, n, view_dir, m, sss, true, loc, curvature);
    let split = albedo_split(v.albedo);
    var o: FOut;
    // Alpha: the material index (unpack.wgsl moves it next to depth and strength).
    o.diffuse = vec4<f32>(lit.diffuse * split[0], f32(m));
    o.specular = vec4<f32>(lit.specular, v.strength);
    // What leaves towards the camera: h(θ_o; θ_i) on SSS surfaces (`shade`).
    o.geometry = vec4<f32>(v.view_depth, bitcast<f32>(pack_albedo(split[1] * lit.exit)), 0.0, 1.0);
    return o;
}
