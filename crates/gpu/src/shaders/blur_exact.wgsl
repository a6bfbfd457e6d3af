// The exact path of blur.wgsl: the source in a storage buffer, each sample the linear
// interpolation of its two nearest pixels along the pass axis (two reads), with another SSS
// material's pixel left out (its share of the weight dropped).

@group(0) @binding(2) var<storage, read> src: array<vec4<f32>>;

fn centre_colour(i: u32, x: i32, y: i32) -> vec3<f32> {
    return src[i].rgb;
}

fn centre_depth(i: u32, x: i32, y: i32) -> f32 {
    return geom[i].x;
}

// 1 where pixel j may give light to this pass's material: its own pixels and those without SSS.
fn accepts(j: u32) -> f32 {
    return select(1.0, 0.0, geom[j].y > 0.0 && u32(geom[j].z) != p.material);
}

fn filtered(x: i32, y: i32, pos: f32) -> Sample {
    let base = floor(pos);
    let f = pos - base;
    var a: u32;
    var b: u32;
    if p.horizontal == 1u {
        a = index(x + i32(base), y);
        b = index(x + i32(base) + 1, y);
    } else {
        a = index(x, y + i32(base));
        b = index(x, y + i32(base) + 1);
    }
    let ka = accepts(a);
    let kb = accepts(b);
    if ka * kb > 0.0 {
        return Sample(mix(src[a].rgb, src[b].rgb, f), mix(geom[a].x, geom[b].x, f), 1.0);
    }
    // One of the two pixels (or both) belongs to another material: the sample is the other one,
    // with its share of the weight.
    let share = (1.0 - f) * ka + f * kb;
    let j = select(b, a, ka > 0.0);
    return Sample(src[j].rgb, geom[j].x, share);
}

fn store(i: u32, x: i32, y: i32, value: vec3<f32>) {
    accumulate(i, value);
}
