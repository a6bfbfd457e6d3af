// The fast path of blur.wgsl (as SSSS): the source in an rgba16float texture holding the light
// and the view depth, each sample one bilinearly filtered fetch along the pass axis (the same
// linear interpolation as the exact path, at half precision). One SSS material per frame: a
// sample does not know its pixels' materials.

@group(0) @binding(2) var src_tex: texture_2d<f32>;
@group(0) @binding(6) var src_sampler: sampler;
// The horizontal pass's output: the pass result and the pixel's depth, for the vertical pass.
@group(0) @binding(7) var tmp_out: texture_storage_2d<rgba16float, write>;

fn centre_colour(i: u32, x: i32, y: i32) -> vec3<f32> {
    return textureLoad(src_tex, vec2<i32>(x, y), 0).rgb;
}

// At the samples' half precision, so that the centre tap sees no depth difference.
fn centre_depth(i: u32, x: i32, y: i32) -> f32 {
    return textureLoad(src_tex, vec2<i32>(x, y), 0).a;
}

fn filtered(x: i32, y: i32, pos: f32) -> Sample {
    let size = vec2<f32>(f32(p.width), f32(p.height));
    let dir = select(vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), p.horizontal == 1u);
    let uv = (vec2<f32>(f32(x), f32(y)) + 0.5 + dir * pos) / size;
    let s = textureSampleLevel(src_tex, src_sampler, uv, 0.0);
    return Sample(s.rgb, s.a, 1.0);
}

fn store(i: u32, x: i32, y: i32, value: vec3<f32>) {
    if p.accumulate == 1u {
        accumulate(i, value);
    } else {
        textureStore(tmp_out, vec2<i32>(x, y), vec4<f32>(value, geom[i].x));
    }
}

// Packs the blur's input for the fast path: light and view depth into one texture.
@group(0) @binding(8) var<storage, read> pack_src: array<vec4<f32>>;

@compute @workgroup_size(8, 8)
fn pack(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height {
        return;
    }
    let i = id.y * p.width + id.x;
    textureStore(tmp_out, vec2<i32>(id.xy), vec4<f32>(pack_src[i].rgb, geom[i].x));
}
