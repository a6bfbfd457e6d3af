// The tables of an exported package bound as one storage buffer, tables.bin (an array of
// SssMaterial, material.wgsl), with the accessors the lookups read. A renderer with its tables
// elsewhere (ours keeps them in a uniform block) defines these eleven functions over its own storage
// instead.

@group(0) @binding(0) var<storage, read> sss_materials: array<SssMaterial>;

fn sss_incidence_entry(m: u32, k: u32) -> vec3<f32> {
    return sss_materials[m].incidence[k].rgb;
}

fn sss_exit_entry(m: u32, k: u32) -> vec3<f32> {
    return sss_materials[m].exit[k].rgb;
}

fn sss_shift_entry(m: u32, k: u32) -> vec3<f32> {
    return sss_materials[m].shift[k].rgb;
}

fn sss_translucency_grid(m: u32) -> vec2<f32> {
    return sss_materials[m].translucency_params.xy;
}

fn sss_translucency_entry(m: u32, k: u32) -> vec3<f32> {
    return sss_materials[m].translucency[k].rgb;
}

fn sss_translucency_exit_entry(m: u32, k: u32) -> vec3<f32> {
    return sss_materials[m].translucency_exit[k].rgb;
}

fn sss_shape_params(m: u32) -> vec4<f32> {
    return sss_materials[m].shape_params;
}

fn sss_shape_grid(m: u32, j: u32) -> vec4<f32> {
    return sss_materials[m].shape_grid[j];
}

fn sss_shape_entry(m: u32, q: u32, i: u32, k: u32) -> vec3<f32> {
    return sss_materials[m].shape[135u * q + 9u * i + k].rgb;
}

fn sss_shape_slab_grid(m: u32, j: u32) -> vec4<f32> {
    return sss_materials[m].shape_slab_grid[j];
}

fn sss_shape_slab_entry(m: u32, i: u32, k: u32) -> vec3<f32> {
    return sss_materials[m].shape_slab[9u * i + k].rgb;
}
