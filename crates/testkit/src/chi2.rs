//! The one χ² judgement of the statistical tests: how large a reduced χ² two estimates that truly
//! agree may show over `dof` terms before the agreement is refused.

/// The largest χ²/dof over `dof` rings (terms): `bound`, or where `dof` is too small for that to be rare,
/// the value a true agreement exceeds with probability 10⁻⁴ (Wilson–Hilferty's cube-root normal
/// approximation of the χ² quantile, within 10 % of that probability from 20 dof up: 2.17 over
/// 34 rings, 1.92 over 50, 1.34 over 288, 1.22 over 635). Over 34 rings a true agreement exceeds
/// 1.5 with probability 2.5 %, so a fixed 1.5 per albedo failed a correct table of 11 albedos
/// about one time in four; it did (1.53, pooled 1.23 over 288 rings at g = 0.5, GPU per albedo
/// against the CPU's white table) when the CPU tracer's streams changed, where eight other seed
/// pairs of the CPU's builds pooled 0.80–1.12.
pub fn reduced_limit(dof: usize, bound: f64) -> f64 {
    let a = 2.0 / (9.0 * dof as f64);
    let quantile = (1.0 - a + 3.719 * a.sqrt()).powi(3);
    quantile.max(bound)
}
