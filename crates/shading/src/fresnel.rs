//! The smooth boundary's Fresnel reflectance, as the shaders evaluate it (`wgsl/fresnel.wgsl`):
//! mirror reflection of area lights at the view angle, and the transmittance T(θ)/T(0) of light
//! entering a thin part's back face.

/// The WGSL of `fresnel(eta, cos_i) -> f32`, prepended to the shaders that need it.
pub const FRESNEL_WGSL: &str = include_str!("wgsl/fresnel.wgsl");

/// Unpolarized Fresnel reflectance from outside (index 1) into index `eta` at incidence cosine
/// `cos_i` (clamped to [0, 1]); 1 beyond total internal reflection (η < 1): the CPU twin of
/// `fresnel.wgsl`, from `mc`'s (Born & Wolf's) formula.
pub fn fresnel(eta: f64, cos_i: f64) -> f64 {
    mc::fresnel(1.0, eta, cos_i.clamp(0.0, 1.0)).0
}

/// The light entering a thin part's far face at incidence cosine `cos_i` relative to normal
/// incidence: the smooth boundary's Fresnel transmittance T(θ)/T(0) into index `eta`. The CPU
/// twin of `sss_back_face_entry` ([`crate::TRANSLUCENCY_WGSL`]).
pub fn back_face_entry(eta: f64, cos_i: f64) -> f64 {
    (1.0 - fresnel(eta, cos_i)) / (1.0 - fresnel(eta, 1.0))
}
