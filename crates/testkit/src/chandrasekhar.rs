//! Chandrasekhar's (1960) H-function for an index-matched, isotropically scattering half-space:
//! the exact results the tracer (`crates/mc/tests/validation.rs`) and the renderer's angle tables
//! (`crates/shading/tests/angle_tables.rs`) are checked against. Its own identities are tested in
//! the former.

/// Chandrasekhar's H-function for isotropic scattering with albedo a, by iterating
/// 1/H(μ) = √(1−a) + (a/2) ∫₀¹ μ' H(μ')/(μ+μ') dμ' on Gauss–Legendre nodes.
pub fn h_function(a: f64, mu: f64) -> f64 {
    h_solver(a)(mu)
}

/// H(·) for albedo a: the fixed point solved once on the nodes, then evaluated anywhere by the
/// same equation.
pub fn h_solver(a: f64) -> impl Fn(f64) -> f64 {
    let (x, w) = gauss_legendre_01(96);
    // The right-hand side of the H equation at μ, from H on the nodes.
    let step = move |h: &[f64], mu: f64| {
        let s: f64 = x
            .iter()
            .zip(&w)
            .zip(h)
            .map(|((&xp, &wp), &hp)| wp * xp * hp / (mu + xp))
            .sum();
        1.0 / ((1.0 - a).sqrt() + 0.5 * a * s)
    };
    let nodes = gauss_legendre_01(96).0;
    let mut h = vec![1.0; nodes.len()];
    for _ in 0..10_000 {
        let next: Vec<f64> = nodes.iter().map(|&m| step(&h, m)).collect();
        let diff = next
            .iter()
            .zip(&h)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        h = next;
        if diff < 1e-14 {
            break;
        }
    }
    move |mu: f64| step(&h, mu)
}

/// Gauss–Legendre nodes and weights on [0, 1] (`gauss-quad`'s rule on [−1, 1], mapped).
pub fn gauss_legendre_01(n: usize) -> (Vec<f64>, Vec<f64>) {
    let rule = gauss_quad::legendre::GaussLegendre::new(n.try_into().expect("n > 0"));
    rule.iter().map(|(x, w)| (0.5 * (x + 1.0), 0.5 * w)).unzip()
}
