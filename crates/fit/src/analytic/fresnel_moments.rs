//! Hemispherical moments of the Fresnel reflectance, the boundary terms of every diffusion model.
//!
//! Convention (d'Eon 2012; Frisvad et al. 2014; the directional-dipole draft §3.5.8): η is the
//! index of the medium the light travels in relative to the medium behind the interface, and
//! Cₙ(η) = ∫₀¹ R(η, μ) μⁿ dμ with R the unpolarized reflectance for internal cosine μ. For a
//! material of index 1.3 in air, C₁(1.3) is the moment for light leaving the material (with total
//! internal reflection) and C₁(1/1.3) the moment for light arriving from air. 2C₁ is the classical
//! diffuse Fresnel reflectance F_dr.

/// 2C₁(η) by the polynomial fit quoted in the draft §3.5.8 (d'Eon 2012).
pub fn two_c1(eta: f64) -> f64 {
    let n = eta;
    if n < 1.0 {
        0.919317 + n * (-3.4793 + n * (6.75335 + n * (-7.80989 + n * (4.98554 - 1.36881 * n))))
    } else {
        -9.23372 + n * (22.2272 + n * (-20.9292 + n * (10.2291 + n * (-2.54396 + 0.254913 * n))))
    }
}

/// 3C₂(η) by the polynomial fit quoted in the draft §3.5.8 (d'Eon 2012).
pub fn three_c2(eta: f64) -> f64 {
    let n = eta;
    if n < 1.0 {
        0.828421 + n * (-2.62051 + n * (3.36231 + n * (-1.95284 + n * (0.236494 + 0.145787 * n))))
    } else {
        -1641.1 + 135.926 / n.powi(3) - 656.175 / n.powi(2)
            + 1376.53 / n
            + n * (1213.67 + n * (-568.556 + n * (164.798 + n * (-27.0181 + 1.91826 * n))))
    }
}

/// C₁(η) = ∫₀¹ R(η, μ) μ dμ (polynomial fit).
pub fn c1(eta: f64) -> f64 {
    0.5 * two_c1(eta)
}

/// C₂(η) = ∫₀¹ R(η, μ) μ² dμ (polynomial fit).
pub fn c2(eta: f64) -> f64 {
    three_c2(eta) / 3.0
}

/// C_φ(η) = ¼(1 − 2C₁(η)): the fluence's share of the exitance (eq. 3.9 of the draft).
pub fn c_phi(eta: f64) -> f64 {
    0.25 * (1.0 - two_c1(eta))
}

/// C_E(η) = ½(1 − 3C₂(η)): the flux's share of the exitance (eq. 3.9 of the draft).
pub fn c_e(eta: f64) -> f64 {
    0.5 * (1.0 - three_c2(eta))
}

/// The classical fit of the diffuse Fresnel reflectance (Egan & Hilgeman 1979, used by Jensen et
/// al. 2001): F_dr(η) = −1.440/η² + 0.710/η + 0.668 + 0.0636·η.
///
/// The draft prints the last coefficient as 0.0036; that value is a typo (it misses the numerical
/// integral by ≈ 0.08 at η = 1.3, see the tests), so Jensen's published 0.0636 is used.
pub fn f_dr(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

/// Cₙ(η) by numerical integration of the exact Fresnel reflectance (Gauss–Legendre on panels
/// split at the critical angle, where R has a kink, and refined geometrically towards grazing
/// incidence and above the critical angle, where R behaves like a square root). The reference for the fits above.
pub fn moment_numeric(eta: f64, n: i32) -> f64 {
    let rule = gauss_quad::legendre::GaussLegendre::new(64.try_into().expect("64 > 0"));
    let f = |mu: f64| mc::fresnel(eta, 1.0, mu).0 * mu.powi(n);
    let mu_c = mc::cos_critical(eta, 1.0);
    let panels = 16;
    let mut edges: Vec<f64> = (0..=panels).map(|i| i as f64 / panels as f64).collect();
    edges.extend((1..40).map(|k| 0.5f64.powi(k) / panels as f64));
    if mu_c > 0.0 {
        // Above the critical angle R falls from 1 like √(μ − μ_c).
        edges.push(mu_c);
        edges.extend((1..40).map(|k| mu_c + 0.5f64.powi(k) / panels as f64));
        edges.retain(|&e| e <= 1.0);
    }
    edges.sort_by(f64::total_cmp);
    edges
        .windows(2)
        .map(|w| rule.integrate(w[0], w[1], f))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fits against the Fresnel equations, over the indices materials have.
    #[test]
    fn polynomial_moments_match_the_fresnel_integrals() {
        for i in 0..=40 {
            let eta = 0.6 + 0.04 * i as f64; // 0.6 … 2.2
            let (n1, n2) = (moment_numeric(eta, 1), moment_numeric(eta, 2));
            assert!(
                (c1(eta) - n1).abs() < 4e-3,
                "C1({eta}) = {} vs {n1}",
                c1(eta)
            );
            assert!(
                (c2(eta) - n2).abs() < 4e-3,
                "C2({eta}) = {} vs {n2}",
                c2(eta)
            );
        }
        // Index matched: no reflection at all.
        assert_eq!(moment_numeric(1.0, 1), 0.0);
        assert!(c1(1.0).abs() < 3e-3 && c2(1.0).abs() < 3e-3);
    }

    #[test]
    fn classical_f_dr_matches_twice_the_first_moment() {
        for i in 0..=20 {
            let eta = 1.0 + 0.05 * i as f64; // 1.0 … 2.0
            let exact = 2.0 * moment_numeric(eta, 1);
            assert!(
                (f_dr(eta) - exact).abs() < 1e-2,
                "F_dr({eta}) = {} vs {exact}",
                f_dr(eta)
            );
        }
        // The draft's printed coefficient 0.0036 instead of 0.0636 misses by 0.06·η.
        let draft = |e: f64| -1.440 / (e * e) + 0.710 / e + 0.668 + 0.0036 * e;
        assert!((draft(1.3) - 2.0 * moment_numeric(1.3, 1)).abs() > 0.05);
    }

    /// Reciprocity of the Fresnel equations: what light from outside does not reflect, it
    /// transmits, and by étendue 1 − 2C₁(1/η) = η²(1 − 2C₁(η)).
    #[test]
    fn hemispherical_transmittance_obeys_the_eta_squared_law() {
        for eta in [1.1, 1.3, 1.5, 2.0, 2.5] {
            let outside = 1.0 - 2.0 * moment_numeric(1.0 / eta, 1);
            let inside = 1.0 - 2.0 * moment_numeric(eta, 1);
            assert!(
                (outside - eta * eta * inside).abs() < 1e-9,
                "{eta}: {outside} vs {}",
                eta * eta * inside
            );
        }
    }
}
