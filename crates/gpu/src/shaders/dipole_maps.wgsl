// Position and normal maps for the directional-dipole method: seen from the camera (the exit
// points x_o) and from each light (the lit entry points x_i, a translucent-shadow-map-style
// light-space G-buffer). position.w is 1 on SSS surfaces, 0 on anything else (the floor, an
// occluder) and on the cleared background. World units are cm.

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
