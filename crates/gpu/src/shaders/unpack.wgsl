// Render targets → storage buffers (one vec4 per pixel, row-major), where the blur passes work.
@group(0) @binding(0) var diffuse: texture_2d<f32>;
@group(0) @binding(1) var specular: texture_2d<f32>;
@group(0) @binding(2) var geometry: texture_2d<f32>;
@group(0) @binding(3) var<storage, read_write> out_diffuse: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> out_specular: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> out_geometry: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> out_albedo: array<vec4<f32>>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(diffuse);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let i = id.y * size.x + id.x;
    let d = textureLoad(diffuse, p, 0);
    out_diffuse[i] = vec4<f32>(d.rgb, 1.0);
    let spec = textureLoad(specular, p, 0);
    out_specular[i] = vec4<f32>(spec.rgb, 1.0);
    // x: view depth [cm], y: SSS strength (stored in the specular target's alpha), z: material
    // index (the diffuse target's alpha; 0 on the cleared background).
    let geo = textureLoad(geometry, p, 0);
    out_geometry[i] = vec4<f32>(geo.x, spec.a, d.a, 1.0);
    // scene.wgsl's pack_albedo: rgb × m with m = 4·alpha.
    let a = unpack4x8unorm(bitcast<u32>(geo.y));
    out_albedo[i] = vec4<f32>(a.rgb * (4.0 * a.a), 1.0);
}
