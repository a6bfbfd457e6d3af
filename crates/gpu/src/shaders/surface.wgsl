// The surface pass of the area gather (Maisch & Ropinski 2020 §3.3, §6.2): per pixel the world
// position [cm] of the visible surface and the area [cm²] that the pixel covers on it, from the
// screen-space derivatives of the position (exact on a flat triangle: the pixel's footprint is the
// parallelogram |∂x/∂u × ∂x/∂v|, the frontal footprint over cos θ). At grazing view, cos θ below
// v.camera_pos.w (gpu::area_gather::GRAZING), the area is the frontal footprint over that bound
// instead: the true one grows without bound where a flat triangle stands in for a curved surface.

struct View {
    view_proj: mat4x4<f32>,
    // xyz: the camera [cm]; w: the grazing bound on cos θ.
    camera_pos: vec4<f32>,
};

@group(0) @binding(0) var<uniform> v: View;

struct VIn {
    @location(0) pos: vec3<f32>,
};

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs(i: VIn) -> VOut {
    var o: VOut;
    // The scene pass's expression, so that both rasterize the same pixels.
    o.clip = v.view_proj * vec4<f32>(i.pos, 1.0);
    o.world = i.pos;
    return o;
}

@fragment
fn fs(i: VOut) -> @location(0) vec4<f32> {
    let c = cross(dpdxFine(i.world), dpdyFine(i.world));
    let frontal = abs(dot(c, normalize(v.camera_pos.xyz - i.world)));
    let cos_view = frontal / max(length(c), 1e-30);
    return vec4<f32>(i.world, frontal / max(cos_view, v.camera_pos.w));
}
