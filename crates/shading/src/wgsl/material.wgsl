// One material's tables as a renderer uploads them (shading::PackedShading; 11,488 bytes, every
// member a vec4 so the layout is the same in uniform and storage buffers, std140 and std430).
struct SssMaterial {
    // ρ(θ)/ρ(0) at θ = 0°, 10°, …, 80° (rgb), and the ambient light's factor: its cosine-weighted
    // hemispherical mean (rgb). All ones: off.
    incidence: array<vec4<f32>, 9>,
    incidence_ambient: vec4<f32>,
    // Tt(d)/ρ at d_k = first·ratio^k (rgb); x: first [cm], y: ln ratio, z: 1 on / 0 off,
    // w: the boundary's relative index η.
    translucency: array<vec4<f32>, 16>,
    translucency_params: vec4<f32>,
    // h_T(θ_o; d_k) at θ_o = 0°, 10°, …, 80° for each d_k, [9·k + o] (rgb; all ones: Lambertian).
    translucency_exit: array<vec4<f32>, 144>,
    // h(θ_o; θ_i) at 0°, 10°, …, 80°, [9·i + o] (rgb; all ones: off).
    exit: array<vec4<f32>, 81>,
    // δ(θ) [cm] at θ = 0°, 10°, …, 80° (rgb); shift[0].w: 1 on, 0 off.
    shift: array<vec4<f32>, 9>,
    // The shape table (shading::ShapeTable): rgb σ_tr per channel [cm⁻¹], w: 1 on / 0 off; the
    // curvature nodes κ, four per vec4 (15); E, ⟨x⟩ [cm] and ⟨s⟩ [cm] (q = 0, 1, 2) at node i and
    // θ = 0°, 10°, …, 80°, [135·q + 9·i + θ index] (rgb; E ones, the others zeros: off).
    shape_params: vec4<f32>,
    shape_grid: array<vec4<f32>, 4>,
    shape: array<vec4<f32>, 405>,
    // The slabs: their thicknesses τ [-], four per vec4 (5); E at slab k and θ = 0°, 10°, …,
    // 80°, [9·k + θ index] (rgb; ones: off).
    shape_slab_grid: array<vec4<f32>, 2>,
    shape_slab: array<vec4<f32>, 45>,
};
