// The directional dipole (Frisvad et al. 2014) as the disc gather's model (disc_gather.wgsl,
// draft §4.2–4.3): radii drawn from a mixture over channels of truncated exponentials
// σ·e^{−σr}/(1 − e^{−σr*}), the response T(ω_i)·S_d(x_i, ω₁₂; x_o), and π·T(ω_o) at the exit.

struct Dipole {
    // Per channel (rgb): D [cm], σtr [cm⁻¹], d_e [cm], back-lit depth 1/(3σt) [cm],
    // 1/(4C_φ(1/η)·4π²) [sr⁻¹], sampling rate of the radius [cm⁻¹].
    d: vec4<f32>,
    sigma_tr: vec4<f32>,
    d_e: vec4<f32>,
    backlit: vec4<f32>,
    norm: vec4<f32>,
    rate: vec4<f32>,
    // x: A, y: C_φ(η), z: C_E(η), w: η.
    boundary: vec4<f32>,
};

@group(0) @binding(7) var<uniform> dp: Dipole;

// S′_d of eq. 3.7 for channel c without its normalisation.
fn source(c: u32, rho: f32, x_w: f32, w_n: f32, x_n: f32) -> f32 {
    let d = dp.d[c];
    let s = dp.sigma_tr[c] * rho;
    let bracket = dp.boundary.y * (rho * rho / d + 3.0 * (1.0 + s) * x_w)
        - dp.boundary.z * (3.0 * d * (1.0 + s) * w_n
            - ((1.0 + s) + 3.0 * d * (3.0 * (1.0 + s) + s * s) / (rho * rho) * x_w) * x_n);
    return exp(-s) / (rho * rho * rho) * bracket;
}

// S_d(x_i, ω₁₂; x_o) per channel [cm⁻² sr⁻¹] (fit::analytic::DirectionalDipole).
fn s_d(xi: vec3<f32>, ni: vec3<f32>, w12: vec3<f32>, xo: vec3<f32>, no: vec3<f32>) -> vec3<f32> {
    let x = xo - xi;
    let r2 = dot(x, x);
    let r = sqrt(r2);
    let side = cross(ni, x);
    var n_star = ni;
    if r > 0.0 && length(side) > 1e-6 * r {
        n_star = cross(x / r, normalize(side));
    }
    let x_w = dot(x, w12);
    let mu0 = -dot(w12, no);
    let w_v = w12 - 2.0 * dot(w12, n_star) * n_star;
    var result = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        if dp.norm[c] == 0.0 {
            continue;
        }
        var d_r: f32;
        if mu0 > 0.0 {
            let de = dp.d_e[c];
            let cos_beta = -sqrt(max(r2 - x_w * x_w, 0.0) / (r2 + de * de));
            d_r = sqrt(r2 + dp.d[c] * mu0 * (dp.d[c] * mu0 - 2.0 * de * cos_beta));
        } else {
            d_r = sqrt(r2 + dp.backlit[c] * dp.backlit[c]);
        }
        let real = source(c, d_r, x_w, dot(w12, no), dot(x, no));
        let xv = xo - (xi + 2.0 * dp.boundary.x * dp.d_e[c] * n_star);
        let virt = source(c, length(xv), dot(xv, w_v), dot(w_v, no), dot(xv, no));
        result[c] = max(dp.norm[c] * (real - virt), 0.0);
    }
    return result;
}

// A radius from the truncated exponential of a channel picked uniformly, both from one uniform
// number v in [0, 1): its third picks the channel, what is left of it within that third the
// radius (so stratified v give stratified radii in each channel).
// Returned as the disc gather takes it: (the centre's offset, 0; the radius).
fn model_sample(v: f32) -> vec4<f32> {
    let c = min(u32(v * 3.0), 2u);
    let s = dp.rate[c];
    let rest = clamp(v * 3.0 - f32(c), 0.0, 0.99999994);
    return vec4<f32>(vec3<f32>(0.0), -log(1.0 - rest * (1.0 - exp(-s * u.disc.x))) / s);
}

// The sample density per unit disc area at the point d from the disc's centre.
fn model_pdf_disc(d: vec3<f32>, axis: vec3<f32>) -> f32 {
    return model_pdf_area(length(d));
}

// The sample density per unit disc area at radius r: the mean over channels of the truncated
// exponential σ·e^{−σr}/(1 − e^{−σr*}) spread over the circle 2πr.
fn model_pdf_area(r: f32) -> f32 {
    var p = 0.0;
    for (var c = 0u; c < 3u; c++) {
        let s = dp.rate[c];
        p += s * exp(-s * r) / (1.0 - exp(-s * u.disc.x));
    }
    return p / (3.0 * 2.0 * PI * r);
}

// The disc around x_o itself.
fn model_centre(xo: vec3<f32>, no: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    return xo;
}

// No control variate (disc_gather.wgsl) for the dipole: its gather is an offline reference.
fn model_flat(axis: vec3<f32>, n: vec3<f32>, n_entry: vec3<f32>, cos_o: f32,
              chord: f32) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn model_control(on_plane: vec3<f32>, jacobian: f32) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn model_lit_tolerance() -> f32 {
    return 0.0;
}

// T(ω_i)·S_d with ω₁₂ the refracted direction of light arriving from wi.
fn model_response(xi: vec3<f32>, ni: vec3<f32>, wi: vec3<f32>, cos_i: f32, xo: vec3<f32>,
                  no: vec3<f32>) -> vec3<f32> {
    let eta = dp.boundary.w;
    let t_in = 1.0 - fresnel(eta, cos_i);
    let inv = 1.0 / eta;
    let ct = sqrt(max(1.0 - inv * inv * (1.0 - cos_i * cos_i), 0.0));
    let w12 = normalize(-wi * inv + ni * (inv * cos_i - ct));
    return t_in * s_d(xi, ni, w12, xo, no);
}

// π·T(ω_o): leaving at exterior angle θ_o transmits as entering at θ_o does (Stokes
// reciprocity); the entry angle is the response's.
fn model_exit(cos_o: f32, cos_i: f32) -> vec3<f32> {
    return vec3<f32>(PI * (1.0 - fresnel(dp.boundary.w, cos_o)));
}
