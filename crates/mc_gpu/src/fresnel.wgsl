// Fresnel reflectance of unpolarized light at a smooth interface (MCML's RFresnel; Wang, Jacques
// & Zheng 1995, eq. 3.20-3.21), in f32. Cosines to the normal, in [0, 1].

// cos θ above which incidence counts as normal. MCML's COSZERO is 1 - 1e-12 in double; in f32
// that is 1, so the GPU uses 1 - 1e-6, as GPU-MCML does.
const COS_ZERO: f32 = 0.999999;
// cos θ below which incidence counts as grazing (MCML's COS90D).
const COS_90D: f32 = 1.0e-6;

// (R, cos θt) for light from index n_i to n_t at incidence cosine cos_i; total internal
// reflection gives (1, 0). R = ½ [sin²(θi−θt)/sin²(θi+θt) + tan²(θi−θt)/tan²(θi+θt)], written
// with sums and differences of angles as MCML does.
fn fresnel(n_i: f32, n_t: f32, cos_i: f32) -> vec2<f32> {
    if (n_i == n_t) {
        return vec2<f32>(0.0, cos_i);
    }
    if (cos_i > COS_ZERO) {
        let r = (n_i - n_t) / (n_i + n_t);
        return vec2<f32>(r * r, cos_i);
    }
    if (cos_i < COS_90D) {
        return vec2<f32>(1.0, 0.0);
    }
    let sin_i = sqrt(1.0 - cos_i * cos_i);
    let sin_t = n_i * sin_i / n_t;
    if (sin_t >= 1.0) {
        return vec2<f32>(1.0, 0.0);
    }
    let cos_t = sqrt(1.0 - sin_t * sin_t);
    let cap = cos_i * cos_t - sin_i * sin_t; // cos(θi+θt)
    let cam = cos_i * cos_t + sin_i * sin_t; // cos(θi−θt)
    let sap = sin_i * cos_t + cos_i * sin_t; // sin(θi+θt)
    let sam = sin_i * cos_t - cos_i * sin_t; // sin(θi−θt)
    let r = 0.5 * sam * sam * (cam * cam + cap * cap) / (sap * sap * cam * cam);
    return vec2<f32>(r, cos_t);
}
