// Position and normal maps for the directional-dipole method: seen from the camera (the exit
// points x_o) and from each light (the lit entry points x_i, a translucent-shadow-map-style
// light-space G-buffer). position.w is 1 on SSS surfaces, 0 on anything else (the floor, an
// occluder) and on the cleared background; normal.w is 0, or in a light's maps for the
// shape-aware gather the body's chord along the light [cm] (`fs_chord`). World units are cm.

struct View {
    view_proj: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> view: View;

struct VIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(3) strength: f32,
};

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) strength: f32,
};

@vertex
fn vs(v: VIn) -> VOut {
    var o: VOut;
    o.clip = view.view_proj * vec4<f32>(v.pos, 1.0);
    o.world = v.pos;
    o.normal = v.normal;
    o.strength = v.strength;
    return o;
}

struct FOut {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
};

@fragment
fn fs(v: VOut, @builtin(front_facing) front: bool) -> FOut {
    var n = normalize(v.normal);
    if !front {
        n = -n;
    }
    var o: FOut;
    o.position = vec4<f32>(v.world, select(0.0, 1.0, v.strength > 0.0));
    o.normal = vec4<f32>(n, 0.0);
    return o;
}

// The layer's first surfaces (its depth and positions), which `fs_chord` looks behind.
@group(0) @binding(1) var first_depth: texture_depth_2d;
@group(0) @binding(2) var first_position: texture_2d<f32>;

// The next surface behind the first one (depth peeling, Everitt 2001; the same bias as the
// shadow pass's), drawn into the normal map's w alone: the body's chord along the light ray
// through the texel's first surface [cm], where that is an SSS surface.
@fragment
fn fs_chord(v: VOut) -> @location(0) vec4<f32> {
    let t = vec2<i32>(v.clip.xy);
    if v.clip.z <= textureLoad(first_depth, t, 0) + 1e-6 {
        discard;
    }
    let p = textureLoad(first_position, t, 0);
    return vec4<f32>(0.0, 0.0, 0.0, select(0.0, length(v.world - p.xyz), p.w > 0.5));
}
