// The body's shape (shading::ShapeTable): light entering a sphere of radius R (convex) or the
// medium around a spherical cavity of radius R (concave) at θ returns E(κ, θ) times what a
// half-space returns within 8 diffusion lengths of its entry, centred ⟨x⟩(κ, θ) [cm] ahead of it
// and ⟨s⟩(κ, θ) [cm] from it on average, κ = 1/(σ_tr·R) per channel, signed (> 0 convex). The
// scene pass multiplies the light entering an SSS surface by E at the surface's curvature at the
// scale the light travels (shading::light_scale_curvature, baked per vertex, per channel: read
// each channel's E at its own curvature); the shape-aware surface gather scales the half-space's Rd(x, y; θ) by E and its width
// by ⟨s⟩(κ)/⟨s⟩(0) at the curvature of the chord from entry to exit.
// A slab of thickness t returns E_slab(τ, θ), τ = σ_tr·t, within the same window: a body thinner
// along the light than its curvature makes it loses light through its far side
// (sss_shape_thin).
// Reads, which the host defines: sss_shape_params(m) (rgb: σ_tr per channel [cm⁻¹]; w: 1 on, 0
// off), sss_shape_grid(m, j) (the curvature nodes κ 4j … 4j + 3, SSS_SHAPE_STEPS of them),
// sss_shape_entry(m, q, i, k) (quantity q: 0 E, 1 ⟨x⟩ [cm], 2 ⟨s⟩ [cm]; node i; θ = 10°·k),
// sss_shape_slab_grid(m, j) (the slabs' τ 4j … 4j + 3, SSS_SLAB_STEPS of them) and
// sss_shape_slab_entry(m, i, k) (E of slab i at θ = 10°·k).

// Nodes of the curvature axis (shading::CURVATURE_STEPS) and of the thickness axis
// (shading::THICKNESS_STEPS).
const SSS_SHAPE_STEPS: u32 = 15u;
const SSS_SLAB_STEPS: u32 = 5u;

fn sss_shape_node(m: u32, i: u32) -> f32 {
    return sss_shape_grid(m, i / 4u)[i % 4u];
}

// The node at or below κ (x) and the weight of the next (y): κ clamped to the first and last
// node, NaN read as 0 (shading::curvature_position is the CPU twin).
fn sss_curvature_position(m: u32, kappa: f32) -> vec2<f32> {
    let first = sss_shape_node(m, 0u);
    let last = sss_shape_node(m, SSS_SHAPE_STEPS - 1u);
    let k = select(clamp(kappa, first, last), 0.0, kappa != kappa);
    var i = 0u;
    for (var j = 1u; j < SSS_SHAPE_STEPS - 1u; j++) {
        if sss_shape_node(m, j) <= k {
            i = j;
        }
    }
    let lo = sss_shape_node(m, i);
    return vec2<f32>(f32(i), (k - lo) / (sss_shape_node(m, i + 1u) - lo));
}

// Quantity q (rgb) where the surface's signed curvature is `curvature` [cm⁻¹] per channel (±1/R,
// > 0 convex; the scalar lookups below pass one to all three, the scene pass each channel's at
// the scale its light travels) and the light enters at cos θ = cos_i: linear in κ = curvature/σ_tr
// between the nodes, linear in θ as the angle tables (shading::ShapeTable::at is the CPU twin).
fn sss_shape_at(m: u32, q: u32, curvature: vec3<f32>, cos_i: f32) -> vec3<f32> {
    let sigma_tr = sss_shape_params(m).rgb;
    let a = angle_index(cos_i);
    let k0 = u32(a.x);
    let k1 = min(k0 + 1u, 8u);
    var v = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        let s = sss_curvature_position(m, curvature[c] / sigma_tr[c]);
        let i = u32(s.x);
        let lo = mix(sss_shape_entry(m, q, i, k0)[c], sss_shape_entry(m, q, i, k1)[c], a.y);
        let hi = mix(sss_shape_entry(m, q, i + 1u, k0)[c], sss_shape_entry(m, q, i + 1u, k1)[c], a.y);
        v[c] = mix(lo, hi, s.y);
    }
    return v;
}

// E (rgb): what the body returns over a half-space; 1 where the table is off.
fn sss_shape_energy(m: u32, curvature: f32, cos_i: f32) -> vec3<f32> {
    if sss_shape_params(m).w < 0.5 {
        return vec3<f32>(1.0);
    }
    return sss_shape_at(m, 0u, vec3<f32>(curvature), cos_i);
}

// ⟨x⟩ [cm] (rgb), the returned light's centroid ahead of its entry along the light's direction
// over the surface (`curvature` along that direction); 0 where the table is off.
fn sss_shape_shift(m: u32, curvature: f32, cos_i: f32) -> vec3<f32> {
    if sss_shape_params(m).w < 0.5 {
        return vec3<f32>(0.0);
    }
    return sss_shape_at(m, 1u, vec3<f32>(curvature), cos_i);
}

// ⟨s⟩(κ)/⟨s⟩(0) (rgb): how much wider than a half-space's the returned light spreads (its mean
// distance from the entry along the surface); 1 where the table is off or returns nothing.
fn sss_shape_width(m: u32, curvature: f32, cos_i: f32) -> vec3<f32> {
    if sss_shape_params(m).w < 0.5 {
        return vec3<f32>(1.0);
    }
    let body = sss_shape_at(m, 2u, vec3<f32>(curvature), cos_i);
    let half = sss_shape_at(m, 2u, vec3<f32>(0.0), cos_i);
    return select(vec3<f32>(1.0), body / half, half > vec3<f32>(0.0));
}

fn sss_slab_node(m: u32, i: u32) -> f32 {
    return sss_shape_slab_grid(m, i / 4u)[i % 4u];
}

// E (rgb) of a slab `thickness` [cm] thick entered at cos θ = cos_i: linear in ln τ, τ = σ_tr·t,
// between the slabs' nodes, the first below the first (and for t ≤ 0 or NaN), 1 (the
// half-space) beyond the last; in θ as sss_shape_at (shading::ShapeTable::slab_at's energy).
fn sss_shape_slab(m: u32, thickness: f32, cos_i: f32) -> vec3<f32> {
    let sigma_tr = sss_shape_params(m).rgb;
    let a = angle_index(cos_i);
    let k0 = u32(a.x);
    let k1 = min(k0 + 1u, 8u);
    let first = sss_slab_node(m, 0u);
    let last = sss_slab_node(m, SSS_SLAB_STEPS - 1u);
    var v = vec3<f32>(1.0);
    for (var c = 0u; c < 3u; c++) {
        let tau = sigma_tr[c] * thickness;
        if tau > last {
            continue;
        }
        var i = 0u;
        var f = 0.0;
        if tau > first {
            for (var j = 1u; j < SSS_SLAB_STEPS - 1u; j++) {
                if sss_slab_node(m, j) <= tau {
                    i = j;
                }
            }
            let lo = sss_slab_node(m, i);
            f = log(tau / lo) / log(sss_slab_node(m, i + 1u) / lo);
        }
        let e0 = mix(sss_shape_slab_entry(m, i, k0)[c], sss_shape_slab_entry(m, i, k1)[c], a.y);
        let e1 = mix(sss_shape_slab_entry(m, i + 1u, k0)[c], sss_shape_slab_entry(m, i + 1u, k1)[c], a.y);
        v[c] = mix(e0, e1, f);
    }
    return v;
}

// The light a body keeps where it is thinner along the light than its curvature makes it (rgb,
// ≤ 1): light entering at cos θ = cos_i where the body's chord along the light is `chord` [cm]
// and its signed curvature `curvature` [cm⁻¹]. A slab t thick has the chord t/cos θ and a sphere
// of radius R the chord 2R·cos θ, so the body is read as a slab t = chord·cos θ and its own
// curvature as one of 2cos²θ/curvature (none where concave or flat): E_slab(t)/E_slab(t_κ), at
// most 1. A sphere keeps E(κ) alone (the ratio is 1), a flat plate E_slab(t); 1 where the table
// is off or the chord unknown (≤ 0, NaN) (shading::ShapeTable::thin_factor is the CPU twin).
fn sss_shape_thin(m: u32, curvature: f32, chord: f32, cos_i: f32) -> vec3<f32> {
    if sss_shape_params(m).w < 0.5 || !(chord > 0.0) {
        return vec3<f32>(1.0);
    }
    let c = clamp(cos_i, 0.0, 1.0);
    let slab = sss_shape_slab(m, chord * c, cos_i);
    var own = vec3<f32>(1.0);
    if curvature > 0.0 {
        own = sss_shape_slab(m, 2.0 * c * c / curvature, cos_i);
    }
    return select(vec3<f32>(1.0), min(slab / own, vec3<f32>(1.0)), own > vec3<f32>(0.0));
}
