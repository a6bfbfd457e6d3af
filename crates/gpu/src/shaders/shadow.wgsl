// Depth-only passes from one light: its shadow map (`vs` alone), and where a material reads the
// body's thickness along the light (shading::ShapeTable's slabs), the next surface beyond it:
// `fs_peel` keeps only fragments behind the shadow map's first surface (depth peeling, Everitt
// 2001), so the nearest of them is where the light ray leaves the body it entered.
@group(0) @binding(0) var<uniform> view_proj: mat4x4<f32>;
// The light's shadow map (its first surfaces).
@group(0) @binding(1) var first: texture_depth_2d;

// Depth [NDC] within which a fragment counts as the first surface itself: the same triangle
// drawn again gives the same depth; its neighbours at a crease differ by rounding.
const PEEL_BIAS: f32 = 1e-6;

@vertex
fn vs(@location(0) pos: vec3<f32>) -> @builtin(position) vec4<f32> {
    return view_proj * vec4<f32>(pos, 1.0);
}

@fragment
fn fs_peel(@builtin(position) pos: vec4<f32>) {
    if pos.z <= textureLoad(first, vec2<i32>(pos.xy), 0) + PEEL_BIAS {
        discard;
    }
}
