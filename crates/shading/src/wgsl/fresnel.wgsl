// Shared by shaders that need it (prepended to them in Rust, WGSL has no includes).

// Unpolarized Fresnel reflectance from outside (index 1) into index η at cos θ_i = c; an
// index-matched boundary (η = 1) reflects nothing, at grazing incidence too
// (shading::fresnel is the CPU twin).
fn fresnel(eta: f32, c: f32) -> f32 {
    if eta == 1.0 {
        return 0.0;
    }
    let ci = clamp(c, 0.0, 1.0);
    let st2 = (1.0 - ci * ci) / (eta * eta);
    if st2 >= 1.0 {
        return 1.0;
    }
    let ct = sqrt(1.0 - st2);
    let rs = (ci - eta * ct) / (ci + eta * ct);
    let rp = (eta * ci - ct) / (eta * ci + ct);
    return 0.5 * (rs * rs + rp * rp);
}

