//! Artist parameters ↔ optical coefficients, as production renderers map them (OpenPBR's
//! `subsurface_color` and `subsurface_radius`; pbrt-v4's `reflectance` and `mfp`).
//!
//! - **color** A [-]: the multiple-scattering albedo, the total diffuse reflectance of a
//!   half-space with an index-matched boundary under diffuse illumination.
//! - **radius** ℓ [cm]: the mean free path 1/σt (extinction, not reduced), per channel.
//!
//! The albedo inversion is van de Hulst's fit for a semi-infinite medium (van de Hulst 1980;
//! Christensen & Burley 2015 §5; the OpenPBR 1.1 specification, "Subsurface"):
//! A = (1 − s)(1 − 0.139s)/(1 + 1.17s) with s = √((1 − α)/(1 − αg)), solved for s:
//! s = 4.09712 + 4.20863A − √(9.59217 + 41.6808A + 17.7126A²), α = (1 − s²)/(1 − g·s²).
//! Its reduced form is α′ = σs′/σt′ = 1 − s², independent of g (similarity). Then σs = α/ℓ and
//! σa = (1 − α)/ℓ.

use crate::channel::CHANNELS;
use crate::error::{McError, Result};

/// van de Hulst's s for a multiple-scattering albedo A ∈ [0, 1]: s(0) = 1, s(1) = 0.
fn s_of(a: f64) -> f64 {
    (4.09712 + 4.20863 * a - (9.59217 + 41.6808 * a + 17.7126 * a * a).sqrt()).max(0.0)
}

/// The reduced single-scattering albedo α′ = 1 − s² of a multiple-scattering albedo A.
pub fn reduced_albedo(a: f64) -> f64 {
    1.0 - s_of(a).powi(2)
}

/// The multiple-scattering albedo A of a reduced single-scattering albedo α′ ∈ [0, 1]: the
/// inverse of [`reduced_albedo`] (bisection; the fit is monotone with A(0) = 0, A(1) = 1).
pub fn multiple_scattering_albedo(alpha_reduced: f64) -> f64 {
    if alpha_reduced <= 0.0 {
        return 0.0;
    }
    // The fit's s reaches 0 (clamped) a few 10⁻⁶ below A = 1: a conservative medium is A = 1.
    if alpha_reduced >= 1.0 {
        return 1.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if reduced_albedo(mid) < alpha_reduced {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// An artist's description of a medium, per channel R, G, B.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Artist {
    /// Multiple-scattering albedo A [-], in [0, 1].
    pub color: [f64; 3],
    /// Mean free path ℓ = 1/σt [cm], positive.
    pub radius: [f64; 3],
}

impl Artist {
    /// Checks the ranges; the error names the field and channel.
    pub fn validate(&self) -> Result<()> {
        for (c, ch) in CHANNELS.iter().enumerate() {
            let (a, l) = (self.color[c], self.radius[c]);
            if !(a.is_finite() && (0.0..=1.0).contains(&a)) {
                return Err(McError::invalid(
                    format!("color[{ch}]"),
                    a,
                    "must lie in [0, 1]",
                ));
            }
            if !(l.is_finite() && l > 0.0) {
                return Err(McError::invalid(
                    format!("radius[{ch}]"),
                    l,
                    "mean free path must be positive and finite",
                ));
            }
        }
        Ok(())
    }

    /// σa and σs [cm⁻¹] for HG anisotropy `g` per channel.
    pub fn coefficients(&self, g: [f64; 3]) -> Result<([f64; 3], [f64; 3])> {
        self.validate()?;
        let alpha = |c: usize| {
            let s2 = s_of(self.color[c]).powi(2);
            // α = (1 − s²)/(1 − g s²); g = 1 with s = 1 (A = 0) has no scattering either way.
            let den = 1.0 - g[c] * s2;
            if den > 0.0 {
                ((1.0 - s2) / den).clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        let sigma_s = [0, 1, 2].map(|c| alpha(c) / self.radius[c]);
        let sigma_a = [0, 1, 2].map(|c| (1.0 - alpha(c)) / self.radius[c]);
        Ok((sigma_a, sigma_s))
    }

    /// The artist parameters of coefficients σa, σs [cm⁻¹] with HG anisotropy `g` per channel
    /// (the forward map of [`Artist::coefficients`]); a channel that does not interact has an
    /// infinite radius.
    pub fn of_coefficients(sigma_a: [f64; 3], sigma_s: [f64; 3], g: [f64; 3]) -> Artist {
        let color = [0, 1, 2].map(|c| {
            let s_red = sigma_s[c] * (1.0 - g[c]);
            let t_red = sigma_a[c] + s_red;
            multiple_scattering_albedo(if t_red > 0.0 { s_red / t_red } else { 0.0 })
        });
        let radius = [0, 1, 2].map(|c| 1.0 / (sigma_a[c] + sigma_s[c]));
        Artist { color, radius }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;

    #[test]
    fn fit_ends_and_van_de_hulst_form() {
        assert!((s_of(0.0) - 1.0).abs() < 1e-5);
        assert!(s_of(1.0).abs() < 1e-5);
        // s solves van de Hulst's A = (1 − s)(1 − 0.139s)/(1 + 1.17s) (the fit's coefficients
        // carry five digits).
        for i in 0..=20 {
            let a = i as f64 / 20.0;
            let s = s_of(a);
            let back = (1.0 - s) * (1.0 - 0.139 * s) / (1.0 + 1.17 * s);
            assert!((back - a).abs() < 2e-5, "A = {a}: {back}");
        }
    }

    #[test]
    fn forward_then_inverse_returns_the_input() {
        let m = Material {
            name: "t".into(),
            source: String::new(),
            sigma_a: [0.32, 1.7, 4.8],
            sigma_s: [7.4, 8.8, 10.1],
            g: [0.0, 0.5, 0.9],
            eta: 1.3,
            thickness: None,
        };
        let art = m.artist();
        let (sa, ss) = art.coefficients(m.g).unwrap();
        for c in 0..3 {
            assert!((sa[c] / m.sigma_a[c] - 1.0).abs() < 1e-9, "σa[{c}] {sa:?}");
            assert!((ss[c] / m.sigma_s[c] - 1.0).abs() < 1e-9, "σs[{c}] {ss:?}");
        }
    }

    /// A material file may give `color` and `radius` (in its unit) instead of coefficients.
    #[test]
    fn material_files_take_artist_keys() {
        let m = Material::from_toml(
            "name = \"a\"\nunit = \"mm\"\ncolor = [0.6, 0.4, 0.2]\nradius = [0.5, 0.4, 0.3]\ng = 0.5\neta = 1.4\n",
            "a.toml",
        )
        .unwrap();
        let (sa, ss) = Artist {
            color: [0.6, 0.4, 0.2],
            radius: [0.05, 0.04, 0.03],
        }
        .coefficients([0.5; 3])
        .unwrap();
        // The file's radius in mm becomes cm before the inversion (rounding aside).
        for c in 0..3 {
            assert!((m.sigma_a[c] / sa[c] - 1.0).abs() < 1e-12);
            assert!((m.sigma_s[c] / ss[c] - 1.0).abs() < 1e-12);
        }
        // A colour without its radius names the radius alone; a mixed set names both kinds.
        for (bad, named) in [
            (
                "name = \"a\"\nunit = \"cm\"\ncolor = [0.6, 0.4, 0.2]\ng = 0\neta = 1.4\n",
                "invalid radius",
            ),
            (
                "name = \"a\"\nunit = \"cm\"\ncolor = [0.6, 0.4, 0.2]\nradius = [1, 1, 1]\nsigma_a = [1, 1, 1]\nsigma_s = [1, 1, 1]\ng = 0\neta = 1.4\n",
                "color/radius",
            ),
        ] {
            let e = Material::from_toml(bad, "a.toml").unwrap_err().to_string();
            assert!(e.contains(named), "{e}");
        }
    }

    #[test]
    fn bad_values_name_the_field() {
        let e = Artist {
            color: [0.5, 1.2, 0.5],
            radius: [1.0; 3],
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("color[G]") && e.contains("1.2"), "{e}");
        let e = Artist {
            color: [0.5; 3],
            radius: [1.0, 1.0, -2.0],
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("radius[B]"), "{e}");
    }
}
