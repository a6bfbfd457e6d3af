// Depth-only pass from one light.
@group(0) @binding(0) var<uniform> view_proj: mat4x4<f32>;

@vertex
fn vs(@location(0) pos: vec3<f32>) -> @builtin(position) vec4<f32> {
    return view_proj * vec4<f32>(pos, 1.0);
}
