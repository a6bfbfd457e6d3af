// Henyey–Greenstein scattering (MCML's Spin; Wang, Jacques & Zheng 1995, eq. 3.28-3.30), in f32.

const TWO_PI: f32 = 6.283185307179586;

// cos θ of the Henyey–Greenstein phase function by inversion of its CDF (eq. 3.28), ξ in [0, 1).
// g = 0 is isotropic (cos θ = 2ξ − 1); |g| = 1 (also a g that rounds to ±1 in f32, within 6e-8
// of it) is the delta it tends to. 1 − g² is formed as (1 − g)(1 + g), exact in f32 near
// |g| = 1. The branches of g = 0 and g ≠ 0 are compiled only where some layer has them
// (tracer.wgsl's ISOTROPIC and ANISOTROPIC).
fn sample_cos_theta(g: f32, xi: f32) -> f32 {
    if (ISOTROPIC && (!ANISOTROPIC || g == 0.0)) {
        return 2.0 * xi - 1.0;
    }
    if (abs(g) >= 1.0) {
        return g;
    }
    let t = (1.0 - g) * (1.0 + g) / (1.0 - g + 2.0 * g * xi);
    return clamp((1.0 + g * g - t * t) / (2.0 * g), -1.0, 1.0);
}

// The new direction after a scattering with anisotropy g (eq. 3.29-3.30): cos θ from the phase
// function, ψ uniform. Isotropic scattering forgets the old direction (the new one is uniform on
// the sphere); near-vertical directions use eq. 3.30. The result is renormalized, which f32's
// rounding would otherwise let drift over long walks.
fn spin(p: ptr<function, Photon>, g: f32, rng: ptr<function, Rng>) {
    let cos_t = sample_cos_theta(g, rand01(rng));
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let psi = TWO_PI * rand01(rng);
    let cos_p = cos(psi);
    let sin_p = sin(psi);
    let u = (*p).u;
    var v: vec3<f32>;
    if (ISOTROPIC && (!ANISOTROPIC || g == 0.0)) {
        v = vec3<f32>(sin_t * cos_p, sin_t * sin_p, cos_t);
    } else if (abs(u.z) > COS_ZERO) {
        v = vec3<f32>(sin_t * cos_p, sin_t * sin_p, select(-cos_t, cos_t, u.z > 0.0));
    } else {
        let t = sqrt(1.0 - u.z * u.z);
        v = vec3<f32>(
            sin_t * (u.x * u.z * cos_p - u.y * sin_p) / t + u.x * cos_t,
            sin_t * (u.y * u.z * cos_p + u.x * sin_p) / t + u.y * cos_t,
            -sin_t * cos_p * t + u.z * cos_t,
        );
    }
    (*p).u = v * inverseSqrt(dot(v, v));
}
