// The area gather (Maisch & Ropinski 2020 §3.2, §4.2, eq. 6): each SSS pixel x_o sums, over the
// taps of the layered pattern, E·A·R′(|x − x_o|, A) with R′ the kernel averaged over a disc of
// area A (their eq. 5) and normalized to unit energy, E the cell's mean irradiance × pre-scatter
// albedo, x its mean position and A its area on the surface [cm²].
//
// Every pyramid level holds per texel the sums over its pixels of (A·E, A) in `light` and of
// (x, 1) over the material's pixels in `pos`, so that a bilinear fetch of any level gives the
// area-weighted mean irradiance, the area per texel and the mean position directly; level 0 is
// the image (entry point `level0`), level l + 1 sums 2×2 texels of level l (`reduce`). Pixels of
// other materials or without SSS carry nothing, pixels at grazing view A = 0 (they still count
// as positions: the splats' receivers). area_kernel.wgsl is prepended.

struct Params {
    width: u32,
    height: u32,
    taps: u32,
    material: u32,
    kernel: AreaKernel,
    levels: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    // Per pyramid level: x offset into the buffers (texels), y width, z height.
    level: array<vec4<u32>, 16>,
};

struct Reduce {
    // x offset, y width, z height of the level read and of the level written.
    src: vec4<u32>,
    dst: vec4<u32>,
};

struct Tap {
    // From the pixel [px], the cell's size [px] and the pyramid level read.
    offset: vec2<f32>,
    cell: f32,
    level: u32,
    weight: f32,
};

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> taps: array<Tap>;
// R′/energy per texel (rgb) [1/cm²], row j (disc radius (j + ½)·r_max/n_a) by column i
// (distance (i + ½)·r_max/n_r), as fit::area_table::AreaTable.
@group(0) @binding(2) var<storage, read> table: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> light: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> pos: array<vec4<f32>>;
// xyz: world position [cm], w: area [cm²] of the pixel's footprint (0: grazing or background).
@group(0) @binding(5) var<storage, read_write> surface: array<vec4<f32>>;
// x: view depth, y: SSS strength, z: material.
@group(0) @binding(6) var<storage, read> geometry: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> out: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read> diffuse: array<vec4<f32>>;
@group(0) @binding(9) var surface_target: texture_2d<f32>;
@group(0) @binding(10) var<uniform> r: Reduce;
@group(0) @binding(11) var<storage, read> points: array<vec2<f32>>;
@group(0) @binding(12) var<storage, read_write> values: array<vec4<f32>>;

@compute @workgroup_size(64)
fn lookup(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&points) {
        return;
    }
    let q = points[id.x];
    values[id.x] = vec4<f32>(area_kernel(p.kernel, q.x, q.y), 0.0);
}

@compute @workgroup_size(8, 8)
fn level0(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height {
        return;
    }
    let i = id.y * p.width + id.x;
    let s = textureLoad(surface_target, vec2<i32>(id.xy), 0);
    let g = geometry[i];
    let sss = g.y > 0.0 && u32(g.z + 0.5) == p.material;
    let a = select(0.0, s.w, sss);
    let count = select(0.0, 1.0, sss);
    surface[i] = vec4<f32>(s.xyz, a);
    light[i] = vec4<f32>(diffuse[i].rgb * a, a);
    pos[i] = vec4<f32>(s.xyz * count, count);
}

@compute @workgroup_size(8, 8)
fn reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= r.dst.y || id.y >= r.dst.z {
        return;
    }
    var l = vec4<f32>(0.0);
    var q = vec4<f32>(0.0);
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let x = 2u * id.x + dx;
            let y = 2u * id.y + dy;
            if x < r.src.y && y < r.src.z {
                let k = r.src.x + y * r.src.y + x;
                l += light[k];
                q += pos[k];
            }
        }
    }
    let k = r.dst.x + id.y * r.dst.y + id.x;
    light[k] = l;
    pos[k] = q;
}

struct Sums {
    light: vec4<f32>,
    pos: vec4<f32>,
};

fn fetch(l: u32, x: i32, y: i32) -> Sums {
    let lv = p.level[l];
    if x < 0 || y < 0 || x >= i32(lv.y) || y >= i32(lv.z) {
        return Sums(vec4<f32>(0.0), vec4<f32>(0.0));
    }
    let k = lv.x + u32(y) * lv.y + u32(x);
    return Sums(light[k], pos[k]);
}

// The sums of level l interpolated bilinearly at full-resolution pixel coordinates `at` (pixel
// centres on integers); outside the image the sums are 0.
fn sample_level(l: u32, at: vec2<f32>) -> Sums {
    let u = (at + 0.5) / f32(1u << l) - 0.5;
    let b = floor(u);
    let f = u - b;
    let x = i32(b.x);
    let y = i32(b.y);
    let s00 = fetch(l, x, y);
    let s10 = fetch(l, x + 1, y);
    let s01 = fetch(l, x, y + 1);
    let s11 = fetch(l, x + 1, y + 1);
    return Sums(
        mix(mix(s00.light, s10.light, f.x), mix(s01.light, s11.light, f.x), f.y),
        mix(mix(s00.pos, s10.pos, f.x), mix(s01.pos, s11.pos, f.x), f.y),
    );
}

@compute @workgroup_size(8, 8)
fn gather(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height {
        return;
    }
    let i = id.y * p.width + id.x;
    let g = geometry[i];
    if !(g.y > 0.0 && u32(g.z + 0.5) == p.material) {
        out[i] = vec4<f32>(0.0);
        return;
    }
    let xo = surface[i].xyz;
    var sum = vec3<f32>(0.0);
    for (var t = 0u; t < p.taps; t++) {
        let tap = taps[t];
        let l = min(tap.level, p.levels - 1u);
        let s = sample_level(l, vec2<f32>(id.xy) + tap.offset);
        if !(s.light.w > 0.0) {
            continue;
        }
        // The cell's area: the level's area per texel × the cell's share of a texel.
        let texel_px = f32(1u << l);
        let a = s.light.w * tap.cell * tap.cell / (texel_px * texel_px);
        let e = s.light.rgb / s.light.w;
        let x = s.pos.xyz / s.pos.w;
        sum += tap.weight * e * a * area_kernel(p.kernel, distance(x, xo), a);
    }
    out[i] = vec4<f32>(sum, 1.0);
}
