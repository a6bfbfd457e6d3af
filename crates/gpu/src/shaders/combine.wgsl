// Recombination: scattered diffuse (at least 0) × post-scatter albedo + specular (linear), then
// exposure, ACES tone curve (Narkowicz's fit) and sRGB encoding into RGBA8.
struct Params {
    width: u32,
    height: u32,
    exposure: f32,
    _pad: u32,
};

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> diffuse: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> specular: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> albedo: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> linear: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> display: array<u32>;
// The unscattered diffuse and x: depth, y: SSS strength: pixels without SSS keep their light.
@group(0) @binding(6) var<storage, read> unscattered: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read> geom: array<vec4<f32>>;

fn aces(x: vec3<f32>) -> vec3<f32> {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn srgb(c: vec3<f32>) -> vec3<f32> {
    return select(1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * c, c <= vec3<f32>(0.0031308));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height {
        return;
    }
    let i = id.y * p.width + id.x;
    // Light is never negative: a disc gather's estimate may be at a single pixel (its control
    // variate's, whose mean is exact), after its frames and its denoiser have averaged it.
    let d = max(select(unscattered[i].rgb, diffuse[i].rgb, geom[i].y > 0.0), vec3<f32>(0.0));
    let c = d * albedo[i].rgb + specular[i].rgb;
    linear[i] = vec4<f32>(c, 1.0);
    display[i] = pack4x8unorm(vec4<f32>(srgb(aces(c * p.exposure)), 1.0));
}
