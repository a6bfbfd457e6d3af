//! Shared by the thesis-figure tests.

/// Skin1 from the material library and its photon-beam-diffusion profile on `sss reproduce
/// --quick`'s grid (dr = smallest MFP / 6 [cm], out to 10 of the largest MFP), with the
/// material's mean free path per channel [cm].
pub fn skin1_quick() -> (fit::Profile, [f64; 3]) {
    let m = mc::Material::builtin("skin1").unwrap();
    let mfp = [0, 1, 2].map(|c| m.mfp(c));
    let lo = mfp.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = mfp.iter().copied().fold(0.0, f64::max);
    let dr = lo / 6.0;
    let p = fit::analytic::profile(
        fit::analytic::Model::Pbd,
        &m,
        dr,
        (10.0 * hi / dr).ceil() as usize,
    )
    .unwrap();
    (p, mfp)
}
