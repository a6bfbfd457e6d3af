// The material's own Monte Carlo transport as the disc gather's model (disc_gather.wgsl;
// gpu::surface_gather): `mc`'s half-space tables, no diffusion model.
// - radial: Rd(|x_o − x_i|) of the Monte Carlo profile (annulus averages, piecewise constant in
//   r) times the incidence table ρ(θ_i)/ρ(0);
// - directional: Rd(x, y; θ) of `mc` at oblique incidence, tabulated at θ = 0°, 10°, …, 80°,
//   85° (linear in θ between them; bilinear between the cells' centres), laid on the modified tangent
//   plane of Frisvad et al. 2014 (§3.3; the directional dipole's, dipole.wgsl): the plane
//   through x_i that holds x_o and is closest to x_i's tangent plane, normal n* = n_i less its
//   part along x_o − x_i. θ* is the light's angle to n*, x runs along the light's propagation
//   in that plane, y ≥ 0 across it (the table is folded: Rd is even in y), x² + y² =
//   |x_o − x_i|²; the amount is the true entry angle's, Rd(θ_i)/Rd(θ*) times the table at θ*.
//   On a flat surface n* = n_i. On a curved one the normal turns between entry and exit: on a
//   sphere under a distant light n* is the chord's bisector, half-way between n_i and n_o, so
//   light entering at θ_i next to the point under the light reaches it as if entering at θ_i/2.
//   With n_i's plane the forward shift carried light from a sphere's lit top towards its
//   terminator (Skin1 red 7 % short at the top, Mitsuba's reference not); with n* the Mitsuba
//   sphere's error fell from 7.0 to 5.7 % and the bust's from 22.0 to 16.1 % (CI size).
// - shape-aware: the directional response scaled for the body's shape (shading::ShapeTable) at
//   the signed curvature of the chord from x_i to x_o, κ = (n_o − n_i)·d/|d|², d = x_o − x_i
//   (on a sphere of radius R, n = (x − c)/R: (n_o − n_i)·d = |d|²/R for any two points, so κ =
//   1/R exactly; −1/R around a cavity; 0 on a plane): E(κ, θ_i)·Rd(x/w, y/w; θ)/w² per channel,
//   w = ⟨s⟩(κ)/⟨s⟩(0), which returns E times the half-space's light spread w times as wide;
//   and where the body is thinner along the light at x_i than the chord's curvature makes it,
//   times sss_shape_thin at the body's chord there (the light maps' normal.w, disc_gather.wgsl's
//   gather_entry_chord): what a slab that thin keeps (1 on a sphere; E_slab on a flat plate).
// The directional and shape-aware responses are read at the exit moved by the view's shift: by
// reciprocity light leaving towards the camera at θ_o last scattered δ(θ_o) (the table's
// centroid at θ_o) further along the view ray's propagation over the surface, which a separable
// BSSRDF leaves out (exit_shift; docs/measurements.md, "The exit shift").
// All leave with h(θ_o; θ_i) (the exit table, at each sample's entry angle). Radii are drawn
// from a mixture of the profile's own area density per channel (its CDF) and a share of uniform
// disc sampling, which keeps the density positive wherever the 3-D distance may make the
// response non-zero.

struct Tables {
    // x: radial bin width dr [cm], y: r* [cm], z: share of uniform disc sampling, w: how far
    // the light maps' first surface along the light may lie from x_o for x_o to count as lit
    // (the control variate's test, model_lit) [cm].
    radial: vec4<f32>,
    // rgb: each channel's share of the profile sampling (0 for a channel reflecting nothing).
    share: vec4<f32>,
    // rgb: each channel's ∫Rd dA over the profile's bins [-].
    total: vec4<f32>,
    // rgb: cell side of each channel's directional table [cm].
    cell: vec4<f32>,
    // x: 0 radial, 1 directional, 2 shape-aware; y: the directional table's half width n;
    // z: profile bins.
    shape: vec4<u32>,
    // ρ(θ)/ρ(0) at θ = 0°, 10°, …, 80°, and h(θ_o; θ_i) at 0°, 10°, …, 80°, [θ_i·9 + θ_o] (rgb).
    incidence: array<vec4<f32>, 9>,
    exit: array<vec4<f32>, 81>,
    // rgb: mc's total diffuse reflectance at each of the directional table's 10 angles [-].
    directional_total: array<vec4<f32>, 10>,
    // rgb: the directional table's centroid δ at each of its angles [cm] (0 for the radial
    // BSSRDF): the view's exit shift.
    exit_shift: array<vec4<f32>, 10>,
    // rgb: the directional table's integral ∫∫ Rd dx dy over its cells at each angle [-] (the
    // control variate's normalization).
    directional_integral: array<vec4<f32>, 10>,
    // The shape table as shading::PackedShading holds it (rgb σ_tr, w on; curvature nodes; E,
    // ⟨x⟩, ⟨s⟩ at [135·q + 9·i + θ index]).
    shape_params: vec4<f32>,
    shape_grid: array<vec4<f32>, 4>,
    shape_entries: array<vec4<f32>, 405>,
    // Its slabs: their τ nodes, four per vec4; E at [9·k + θ index] (rgb).
    shape_slab_grid: array<vec4<f32>, 2>,
    shape_slab: array<vec4<f32>, 45>,
};

@group(0) @binding(7) var<uniform> tb: Tables;
// Rd per profile bin (rgb) [cm⁻²].
@group(0) @binding(8) var<storage, read> profile: array<vec4<f32>>;
// The cumulative share of ∫Rd dA up to and including each bin (rgb), 1 at the last.
@group(0) @binding(9) var<storage, read> cdf: array<vec4<f32>>;
// Directional tables [cm⁻²]: [angle][channel][iy 0..=n][ix 0..=2n].
@group(0) @binding(10) var<storage, read> directional: array<f32>;

// The tables shading::INCIDENCE_WGSL's and EXIT_WGSL's lookups read (one material: m = 0).
fn sss_incidence_entry(m: u32, k: u32) -> vec3<f32> {
    return tb.incidence[k].rgb;
}

fn sss_exit_entry(m: u32, k: u32) -> vec3<f32> {
    return tb.exit[k].rgb;
}

// The shape table shading::SHAPE_WGSL's lookups read.
fn sss_shape_params(m: u32) -> vec4<f32> {
    return tb.shape_params;
}

fn sss_shape_grid(m: u32, j: u32) -> vec4<f32> {
    return tb.shape_grid[j];
}

fn sss_shape_entry(m: u32, q: u32, i: u32, k: u32) -> vec3<f32> {
    return tb.shape_entries[135u * q + 9u * i + k].rgb;
}

fn sss_shape_slab_grid(m: u32, j: u32) -> vec4<f32> {
    return tb.shape_slab_grid[j];
}

fn sss_shape_slab_entry(m: u32, i: u32, k: u32) -> vec3<f32> {
    return tb.shape_slab[9u * i + k].rgb;
}

// A point from the mixture of uniform disc sampling and each channel's profile, from one
// uniform number v in [0, 1): where v falls among the mixture's shares picks the component, what
// is left of it within that share the profile's bin (its cumulative share) and what is left
// within that bin the radius, uniform in area (so stratified v give stratified radii in every
// component). Returns the component's centre as an offset from the disc's centre (xyz: each
// channel is drawn around its own exit shift, `channel_offset`; the uniform disc around the
// centre) and the radius (w) [cm].
fn model_sample(v: f32) -> vec4<f32> {
    let r_max = u.disc.x;
    if v < tb.radial.z {
        return vec4<f32>(vec3<f32>(0.0), r_max * sqrt(v / tb.radial.z));
    }
    var c = 2u;
    var acc = tb.radial.z;
    for (var k = 0u; k < 2u; k++) {
        if v < acc + tb.share[k] {
            c = k;
            break;
        }
        acc += tb.share[k];
    }
    let share = select(1.0 - acc, tb.share[c], c < 2u);
    let w = clamp((v - acc) / max(share, 1e-30), 0.0, 0.99999994);
    // The first bin whose cumulative share exceeds w.
    var lo = 0u;
    var hi = tb.shape.z - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if cdf[mid][c] > w {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    let below = select(0.0, cdf[max(lo, 1u) - 1u][c], lo > 0u);
    let within = clamp((w - below) / max(cdf[lo][c] - below, 1e-30), 0.0, 1.0);
    let dr = tb.radial.x;
    let r0 = f32(lo) * dr;
    let r1 = r0 + dr;
    return vec4<f32>(channel_offset[c], sqrt(r0 * r0 + within * (r1 * r1 - r0 * r0)));
}

// The mixture's density per unit disc area [cm⁻²] at the point d [cm] from the disc's centre in
// its plane (normal `axis`): the uniform disc's within r*, and each channel's profile density at
// the distance from that channel's centre (its offset projected onto the plane, as the gather
// places it).
fn model_pdf_disc(d: vec3<f32>, axis: vec3<f32>) -> f32 {
    let r_max = u.disc.x;
    var p = select(0.0, tb.radial.z / (PI * r_max * r_max), length(d) < r_max);
    for (var c = 0u; c < 3u; c++) {
        if tb.share[c] > 0.0 {
            let o = channel_offset[c] - dot(channel_offset[c], axis) * axis;
            let bin = u32(length(d - o) / tb.radial.x);
            if bin < tb.shape.z {
                p += tb.share[c] * profile[bin][c] / tb.total[c];
            }
        }
    }
    return p;
}

// The control variate's plane for the current pixel and light, set by model_flat: per channel
// the table's read direction along it (x), its angle index and weight, the table's integral
// there, and the channel's centre (the view's exit shift) laid on it.
var<private> control_along: vec3<f32>;
var<private> control_angle: vec2<f32>;
var<private> control_integral: vec3<f32>;
var<private> control_centre: array<vec3<f32>, 3>;

// What a flat half-space lit from `axis` returns towards the camera at cos θ_o per unit
// irradiance normal to the light [-]: cos θ_i·Rd(θ_i)·h(θ_o; θ_i), θ_i the light's angle to the
// entry's shading normal n_entry, Rd(θ_i) what the response integrates to there (∫Rd dA·ρ(θ_i)/ρ(0)
// radial, the directional table's integral), the control variate's expectation; shape-aware,
// times what a slab as thin as the body's chord along the light at x_o keeps (model_response's
// factor at κ = 0). Sets the control's plane (unit normal n, the light maps' at x_o's entry) for
// model_control; 0 where the light runs along that plane.
fn model_flat(axis: vec3<f32>, n: vec3<f32>, n_entry: vec3<f32>, cos_o: f32,
              chord: f32) -> vec3<f32> {
    // The propagation as model_response takes it at the entry's shading normal (−axis less its
    // part along it; any direction at normal incidence), laid on the plane.
    let cos_i = dot(axis, n_entry);
    var along = -axis + cos_i * n_entry;
    if length(along) < 1e-4 {
        along = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n_entry.x) > 0.9);
    }
    along = along - dot(along, n) * n;
    if length(along) < 1e-6 {
        return vec3<f32>(0.0);
    }
    control_along = normalize(along);
    control_angle = directional_index(cos_i);
    let k = u32(control_angle.x);
    control_integral = mix(tb.directional_integral[k].rgb,
        tb.directional_integral[min(k + 1u, 9u)].rgb, control_angle.y);
    for (var c = 0u; c < 3u; c++) {
        control_centre[c] = pixel_exit[c] - dot(pixel_exit[c], n) * n;
    }
    var rd = tb.total.rgb * sss_incidence(0u, cos_i);
    if tb.shape.x != 0u {
        rd = control_integral;
    }
    if tb.shape.x == 2u {
        rd *= sss_shape_energy(0u, 0.0, cos_i) * sss_shape_thin(0u, 0.0, chord, cos_i);
    }
    return cos_i * rd * sss_exit(0u, cos_o, cos_i);
}

// The control variate (disc_gather.wgsl): per channel, a density on the disc [cm⁻²] whose
// integral over the disc is exactly 1, shaped as the response on a flat, evenly lit half-space:
// the sample's entry lies at `on_plane` from x_o's own entry on the plane model_flat set (the
// light maps' surface there), which has `jacobian` of area per unit disc area; the channel's
// profile density (radial) or its directional table at the light's angle over the table's
// integral is read there as model_response reads it (x along the light's propagation, from the
// channel's centre), times the Jacobian: its disc integral is the density's over the plane, 1.
fn model_control(on_plane: vec3<f32>, jacobian: f32) -> vec3<f32> {
    var q = vec3<f32>(0.0);
    let k0 = u32(control_angle.x);
    let k1 = min(k0 + 1u, 9u);
    for (var c = 0u; c < 3u; c++) {
        if tb.share[c] > 0.0 {
            // x_o − x_i plus the exit shift, as model_response reads the table, on the plane.
            let dc = control_centre[c] - on_plane;
            if tb.shape.x == 0u {
                let bin = u32(length(dc) / tb.radial.x);
                if bin < tb.shape.z {
                    q[c] = jacobian * profile[bin][c] / tb.total[c];
                }
            } else if control_integral[c] > 0.0 {
                let x = dot(dc, control_along);
                let y = sqrt(max(dot(dc, dc) - x * x, 0.0));
                let v = mix(directional_at(k0, c, x, y), directional_at(k1, c, x, y),
                    control_angle.y);
                q[c] = jacobian * v / control_integral[c];
            }
        }
    }
    return q;
}

// How far from x_o the first surface the light sees along its ray through x_o may lie for x_o
// to count as lit [cm].
fn model_lit_tolerance() -> f32 {
    return tb.radial.w;
}

// Channel c of the directional table at angle index k, local (x, y ≥ 0) [cm]: bilinear between
// the cells' centres, 0 one cell beyond the outermost (shading::DirectionalTable::at, its CPU
// twin: the same integral and centroid as the cells, and continuous).
fn directional_node(k: u32, c: u32, ix: i32, iy: i32) -> f32 {
    let n = i32(tb.shape.y);
    if ix < 0 || ix > 2 * n || iy > n {
        return 0.0;
    }
    return directional[((k * 3u + c) * u32(n + 1) + u32(iy)) * u32(2 * n + 1) + u32(ix)];
}

fn directional_at(k: u32, c: u32, x: f32, y: f32) -> f32 {
    let s = tb.cell[c];
    let f = vec2<f32>(x / s + f32(tb.shape.y), y / s);
    let lo = floor(f);
    let t = f - lo;
    // Beyond the table (or a NaN) reads nothing.
    if !(lo.x >= -1.0 && lo.x <= f32(2u * tb.shape.y) && lo.y >= 0.0 && lo.y <= f32(tb.shape.y)) {
        return 0.0;
    }
    let i = vec2<i32>(lo);
    return mix(
        mix(directional_node(k, c, i.x, i.y), directional_node(k, c, i.x + 1, i.y), t.x),
        mix(directional_node(k, c, i.x, i.y + 1), directional_node(k, c, i.x + 1, i.y + 1), t.x),
        t.y
    );
}

// The directional table's index and weight at cos θ: θ = 0°, 10°, …, 80° at indices 0–8, 85°
// at 9, held beyond.
fn directional_index(cos_t: f32) -> vec2<f32> {
    let theta = degrees(acos(clamp(cos_t, 0.0, 1.0)));
    var t = theta / 10.0;
    if theta > 80.0 {
        t = 8.0 + (theta - 80.0) / 5.0;
    }
    let k = min(floor(t), 9.0);
    return vec2<f32>(k, clamp(t - k, 0.0, 1.0));
}

fn directional_total_at(a: vec2<f32>) -> vec3<f32> {
    let k = u32(a.x);
    return mix(tb.directional_total[k].rgb, tb.directional_total[min(k + 1u, 9u)].rgb, a.y);
}

// The view's exit shift per channel at the current pixel, set once per pixel by model_centre.
var<private> pixel_exit: array<vec3<f32>, 3>;

// The view's exit shift per channel at x_o (unit normal no) seen from the unit direction wo
// (shading::DirectionalTable::exit_shift is the CPU twin): δ(θ_o) along the view ray's
// propagation over the surface.
fn exit_shift(no: vec3<f32>, wo: vec3<f32>) -> array<vec3<f32>, 3> {
    let cos_o = dot(no, wo);
    let t = -wo + cos_o * no;
    var out = array<vec3<f32>, 3>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    if tb.shape.x != 0u && length(t) > 1e-4 {
        let a = directional_index(max(cos_o, 0.0));
        let k = u32(a.x);
        let delta = mix(tb.exit_shift[k].rgb, tb.exit_shift[min(k + 1u, 9u)].rgb, a.y);
        let tn = normalize(t);
        for (var c = 0u; c < 3u; c++) {
            out[c] = delta[c] * tn;
        }
    }
    return out;
}

// Each channel's sampling centre as an offset from the disc's centre, set once per pixel by
// model_centre: the channel's own exit shift less their weighted mean.
var<private> channel_offset: array<vec3<f32>, 3>;

// The pixel's exit shift (kept for model_response) and the disc's centre: x_o moved by the
// channels' shifts weighted by their shares of the sampling (x_o for the radial BSSRDF, which
// has no shift); each channel's radii are drawn around its own shift (`channel_offset`), where
// its response peaks: a narrow channel (Skin1's blue) drawn around another's centre would find
// its peak where its density is low.
fn model_centre(xo: vec3<f32>, no: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    pixel_exit = exit_shift(no, wo);
    let s = tb.share.rgb;
    let total = s.r + s.g + s.b;
    var mean = vec3<f32>(0.0);
    if total > 0.0 {
        let e = pixel_exit;
        mean = (s.r * e[0] + s.g * e[1] + s.b * e[2]) / total;
    }
    for (var c = 0u; c < 3u; c++) {
        channel_offset[c] = pixel_exit[c] - mean;
    }
    return xo + mean;
}

fn model_response(xi: vec3<f32>, ni: vec3<f32>, wi: vec3<f32>, cos_i: f32, xo: vec3<f32>,
                  no: vec3<f32>) -> vec3<f32> {
    let d = xo - xi;
    let r = length(d);
    if tb.shape.x == 0u {
        let bin = u32(r / tb.radial.x);
        if bin >= tb.shape.z {
            return vec3<f32>(0.0);
        }
        return profile[bin].rgb * sss_incidence(0u, cos_i);
    }
    // The modified tangent plane's normal n* (n_i where x_o lies along n_i or on x_i).
    var n_star = ni;
    if r > 0.0 {
        let tilted = ni - dot(ni, d / r) * (d / r);
        if length(tilted) > 1e-6 {
            n_star = normalize(tilted);
        }
    }
    let cos_star = dot(wi, n_star);
    // The propagation's direction in that plane: −wi less its part along n* (any direction in
    // the plane at normal incidence, where the table is radially symmetric).
    var along = -wi + cos_star * n_star;
    if length(along) < 1e-4 {
        along = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n_star.x) > 0.9);
        along = along - dot(along, n_star) * n_star;
    }
    let along_n = normalize(along);
    let a = directional_index(cos_star);
    let k0 = u32(a.x);
    let k1 = min(k0 + 1u, 9u);
    let at_star = directional_total_at(a);
    let at_entry = directional_total_at(directional_index(cos_i));
    // The shape: E and the stretch w at the chord's curvature (1 and 1 unless shape-aware).
    var energy = vec3<f32>(1.0);
    var w = vec3<f32>(1.0);
    if tb.shape.x == 2u && r > 0.0 {
        let curvature = dot(no - ni, d) / (r * r);
        energy = sss_shape_energy(0u, curvature, cos_i)
            * sss_shape_thin(0u, curvature, gather_entry_chord, cos_i);
        w = max(sss_shape_width(0u, curvature, cos_i), vec3<f32>(1e-3));
    }
    var result = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        if at_star[c] > 0.0 {
            // Channel c's exit moved by the view's shift, on the plane d defines.
            let dc = d + pixel_exit[c];
            let x = dot(dc, along_n);
            let y = sqrt(max(dot(dc, dc) - x * x, 0.0));
            let xs = x / w[c];
            let ys = y / w[c];
            let v = mix(directional_at(k0, c, xs, ys), directional_at(k1, c, xs, ys), a.y);
            result[c] = v * at_entry[c] / at_star[c] * energy[c] / (w[c] * w[c]);
        }
    }
    return result;
}

fn model_exit(cos_o: f32, cos_i: f32) -> vec3<f32> {
    return sss_exit(0u, cos_o, cos_i);
}
