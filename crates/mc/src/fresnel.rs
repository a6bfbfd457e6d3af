//! Fresnel reflectance of unpolarized light at a smooth interface (MCML's `RFresnel`) and the
//! specular reflectance at the entry surface (MCML's `Rspecular`).
//!
//! Angles are given by their cosines to the surface normal, in [0, 1].

/// cos θ above which incidence is treated as normal (MCML's `COSZERO`).
pub const COS_ZERO: f64 = 1.0 - 1.0e-12;
/// cos θ below which incidence is treated as grazing (MCML's `COS90D`).
pub const COS_90D: f64 = 1.0e-6;

/// Reflectance and transmission cosine for light going from index `n_i` to `n_t` with incidence
/// cosine `cos_i`. Returns `(R, cos_t)`; total internal reflection gives `(1, 0)`.
///
/// R = ½ [sin²(θi−θt)/sin²(θi+θt) + tan²(θi−θt)/tan²(θi+θt)] (Born & Wolf), written with
/// sums and differences of angles as MCML does to stay accurate near normal incidence.
pub fn fresnel(n_i: f64, n_t: f64, cos_i: f64) -> (f64, f64) {
    if n_i == n_t {
        return (0.0, cos_i);
    }
    if cos_i > COS_ZERO {
        let r = (n_i - n_t) / (n_i + n_t);
        return (r * r, cos_i);
    }
    if cos_i < COS_90D {
        return (1.0, 0.0);
    }
    let sin_i = (1.0 - cos_i * cos_i).sqrt();
    let sin_t = n_i * sin_i / n_t;
    if sin_t >= 1.0 {
        return (1.0, 0.0);
    }
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let cap = cos_i * cos_t - sin_i * sin_t; // cos(θi+θt)
    let cam = cos_i * cos_t + sin_i * sin_t; // cos(θi−θt)
    let sap = sin_i * cos_t + cos_i * sin_t; // sin(θi+θt)
    let sam = sin_i * cos_t - cos_i * sin_t; // sin(θi−θt)
    let r = 0.5 * sam * sam * (cam * cam + cap * cap) / (sap * sap * cam * cam);
    (r, cos_t)
}

/// Cosine of the critical angle for light going from `n_i` to `n_t`; 0 when there is none.
pub fn cos_critical(n_i: f64, n_t: f64) -> f64 {
    if n_i > n_t {
        (1.0 - (n_t / n_i).powi(2)).sqrt()
    } else {
        0.0
    }
}

/// Specular reflectance of a normally incident beam: ((n₁−n₂)/(n₁+n₂))². When the first layer is
/// glass (μa = μs = 0), the multiple reflections inside it are included:
/// Rsp = r₁ + (1−r₁)² r₂ / (1 − r₁ r₂) (MCML's `Rspecular`).
pub fn specular(n_above: f64, n1: f64, glass_below: Option<f64>) -> f64 {
    let r = |a: f64, b: f64| ((a - b) / (a + b)).powi(2);
    let r1 = r(n_above, n1);
    match glass_below {
        None => r1,
        Some(n2) => {
            let r2 = r(n1, n2);
            r1 + (1.0 - r1).powi(2) * r2 / (1.0 - r1 * r2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_matches_closed_form() {
        let (r, c) = fresnel(1.0, 1.5, 1.0);
        assert!((r - 0.04).abs() < 1e-15);
        assert_eq!(c, 1.0);
    }

    #[test]
    fn continuous_near_normal() {
        // The general formula must approach ((n1-n2)/(n1+n2))² as θ → 0.
        let (r, _) = fresnel(1.0, 1.5, 0.999_999);
        assert!((r - 0.04).abs() < 1e-6, "{r}");
    }

    #[test]
    fn total_internal_reflection_beyond_critical_angle() {
        let cc = cos_critical(1.5, 1.0);
        assert_eq!(fresnel(1.5, 1.0, cc * 0.999).0, 1.0);
        assert!(fresnel(1.5, 1.0, cc * 1.001 + 1e-9).0 < 1.0);
    }

    #[test]
    fn matches_s_and_p_average_and_is_reciprocal() {
        // Independent formula: Rs, Rp from Snell's law.
        for &(n1, n2) in &[(1.0, 1.3), (1.0, 1.5), (1.5, 1.0), (1.3, 2.4)] {
            for k in 1..50 {
                let ci: f64 = k as f64 / 50.0;
                let si = (1.0 - ci * ci).sqrt();
                let st: f64 = n1 * si / n2;
                if st >= 1.0 {
                    continue;
                }
                let ct = (1.0 - st * st).sqrt();
                let rs = ((n1 * ci - n2 * ct) / (n1 * ci + n2 * ct)).powi(2);
                let rp = ((n1 * ct - n2 * ci) / (n1 * ct + n2 * ci)).powi(2);
                let (r, c) = fresnel(n1, n2, ci);
                assert!(
                    (r - 0.5 * (rs + rp)).abs() < 1e-12,
                    "n1={n1} n2={n2} ci={ci}"
                );
                assert!((c - ct).abs() < 1e-12);
                // Reciprocity: the same reflectance from the other side along the refracted ray.
                assert!((fresnel(n2, n1, ct).0 - r).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn glass_layer_specular_sums_the_geometric_series() {
        let r1: f64 = 0.04;
        let r2 = ((1.5f64 - 1.33) / (1.5 + 1.33)).powi(2);
        let mut series = r1;
        let mut t = (1.0 - r1) * (1.0 - r1) * r2;
        for _ in 0..200 {
            series += t;
            t *= r1 * r2;
        }
        assert!((specular(1.0, 1.5, Some(1.33)) - series).abs() < 1e-15);
    }
}
