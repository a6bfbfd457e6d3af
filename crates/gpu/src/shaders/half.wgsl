// Half-resolution SSS (what Unreal ships by default): `down` averages each 2×2 block into one
// pixel, `up` brings the blurred half-resolution light back to full resolution.
//
// down: a block's SSS pixels of the material of its first SSS pixel are averaged (irradiance and
// depth; the largest strength); a block without SSS averages all four, strength 0.
// up: each full-resolution SSS pixel interpolates the four nearest half-resolution pixels
// bilinearly, each weighted by e^{−(Δz/tolerance)²} and left out when of another material or
// without SSS; where none is left, the pixel keeps its own unblurred light.

struct Params {
    width: u32,
    height: u32,
    half_width: u32,
    half_height: u32,
    // Depth difference [cm] over which a half-resolution sample's weight falls by e.
    tolerance: f32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(0) @binding(0) var<uniform> p: Params;
// Full resolution: irradiance, and x: view depth [cm], y: SSS strength, z: material.
@group(0) @binding(1) var<storage, read> full_diffuse: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> full_geom: array<vec4<f32>>;
// Half resolution, written by `down`.
@group(0) @binding(3) var<storage, read_write> half_diffuse: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> half_geom: array<vec4<f32>>;

@compute @workgroup_size(8, 8)
fn down(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.half_width || id.y >= p.half_height {
        return;
    }
    var sum = vec3<f32>(0.0);
    var depth = 0.0;
    var strength = 0.0;
    var material = -1.0;
    var n = 0.0;
    for (var k = 0u; k < 8u; k++) {
        // First pass (k < 4): SSS pixels of the first SSS material; second: all, if none.
        if k == 4u && n > 0.0 {
            break;
        }
        let x = min(2u * id.x + (k & 1u), p.width - 1u);
        let y = min(2u * id.y + ((k >> 1u) & 1u), p.height - 1u);
        let j = y * p.width + x;
        let g = full_geom[j];
        if k < 4u {
            if !(g.y > 0.0) {
                continue;
            }
            if material < 0.0 {
                material = g.z;
            }
            if g.z != material {
                continue;
            }
            strength = max(strength, g.y);
        }
        sum += full_diffuse[j].rgb;
        depth += g.x;
        n += 1.0;
    }
    let i = id.y * p.half_width + id.x;
    half_diffuse[i] = vec4<f32>(sum / n, 1.0);
    half_geom[i] = vec4<f32>(depth / n, strength, max(material, 0.0), 1.0);
}

// `up` reads what the blur made of `down`'s output and writes the full-resolution result.
@group(0) @binding(5) var<storage, read> half_scattered: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> scattered: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read> half_geom_in: array<vec4<f32>>;

@compute @workgroup_size(8, 8)
fn up(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height {
        return;
    }
    let i = id.y * p.width + id.x;
    let g = full_geom[i];
    if !(g.y > 0.0) {
        scattered[i] = vec4<f32>(0.0, 0.0, 0.0, 1.0);
        return;
    }
    // The pixel's centre in half-resolution pixel coordinates.
    let u = (vec2<f32>(f32(id.x), f32(id.y)) + 0.5) * 0.5 - 0.5;
    let base = floor(u);
    let f = u - base;
    var acc = vec3<f32>(0.0);
    var total = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let dx = k & 1u;
        let dy = k >> 1u;
        let hx = clamp(i32(base.x) + i32(dx), 0, i32(p.half_width) - 1);
        let hy = clamp(i32(base.y) + i32(dy), 0, i32(p.half_height) - 1);
        let j = u32(hy) * p.half_width + u32(hx);
        let hg = half_geom_in[j];
        if !(hg.y > 0.0) || hg.z != g.z {
            continue;
        }
        let bx = select(1.0 - f.x, f.x, dx == 1u);
        let by = select(1.0 - f.y, f.y, dy == 1u);
        let dz = (hg.x - g.x) / p.tolerance;
        let w = bx * by * exp(-dz * dz);
        acc += w * half_scattered[j].rgb;
        total += w;
    }
    scattered[i] = vec4<f32>(select(full_diffuse[i].rgb, acc / total, total > 1e-4), 1.0);
}
