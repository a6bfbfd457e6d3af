//! A sphere of radius R through the entry point: the inside of a sphere (a convex body) or its
//! outside (the medium around a spherical cavity, a concave surface).
//!
//! Units: cm. Frame: the entry point is the origin and +z its inward normal (into the medium), as
//! in every `mc` run; the centre lies at σRẑ with σ = +1 for the medium inside (convex) and
//! σ = −1 for the medium outside (concave). Positions are kept relative to the entry point, never
//! to the centre, so that a sphere of 10⁸ cm is as precise as a half-space near the entry: with
//! q = p − σRẑ, |q|² − R² = |p|² − 2σRz and q·u = p·u − σRu_z carry no cancellation.

/// The sphere of a convex body or of a cavity.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sphere {
    /// Radius R [cm].
    pub radius: f64,
    /// σ: +1 with the medium inside the sphere, −1 with the medium outside it.
    pub side: f64,
}

impl Sphere {
    /// Distance [cm] from `p` along the unit direction `u` to the sphere, where the ray leaves
    /// the medium; `None` when it never does (in a cavity's medium, a ray that misses or moves
    /// away from the sphere).
    ///
    /// The ray p + d·u meets the sphere where d² + 2bd + c = 0, b = q·u, c = |q|² − R². Inside
    /// (c ≤ 0) the exit is the larger root −b + √(b² − c); outside (c ≥ 0, b < 0) the entry into
    /// the sphere is the smaller root −b − √(b² − c). Each is evaluated in the form without
    /// cancellation (Numerical Recipes §5.6), and c is clamped to the medium's side, so a photon
    /// that rounding put a hair beyond the surface still leaves from it.
    #[inline]
    pub fn distance(&self, p: [f64; 3], u: [f64; 3]) -> Option<f64> {
        let sr = self.side * self.radius;
        let c = dot(p, p) - 2.0 * sr * p[2];
        let b = dot(p, u) - sr * u[2];
        if self.side > 0.0 {
            let c = c.min(0.0);
            let root = (b * b - c).sqrt();
            Some(if b <= 0.0 { root - b } else { -c / (b + root) })
        } else {
            let c = c.max(0.0);
            let disc = b * b - c;
            (b < 0.0 && disc >= 0.0).then(|| c / (disc.sqrt() - b))
        }
    }

    /// The unit normal at a point `p` of the sphere pointing out of the medium: σ·q/|q|.
    #[inline]
    pub fn outward_normal(&self, p: [f64; 3]) -> [f64; 3] {
        let q = [p[0], p[1], p[2] - self.side * self.radius];
        let k = self.side / dot(q, q).sqrt();
        [q[0] * k, q[1] * k, q[2] * k]
    }

    /// Geodesic distance [cm] from the entry point to a point `p` of the sphere: R·α, α the angle
    /// between the two points seen from the centre, α = atan2(|q₀ × q|, q₀·q) with q₀ = −σRẑ:
    /// |q₀ × q| = R·√(x² + y²) and q₀·q = R(R − σz).
    #[inline]
    pub fn geodesic(&self, p: [f64; 3]) -> f64 {
        let rho = p[0].hypot(p[1]);
        self.radius * rho.atan2(self.radius - self.side * p[2])
    }

    /// Area [cm²] of the band of the sphere between geodesic distances `s0` < `s1` [cm] from the
    /// entry point: 2πR²(cos α₀ − cos α₁) = 4πR² sin((α₀ + α₁)/2) sin((α₁ − α₀)/2), α = s/R
    /// clamped to π (no cancellation for R ≫ s; the plane's π(s₁² − s₀²) as R → ∞).
    pub fn band_area(&self, s0: f64, s1: f64) -> f64 {
        let r = self.radius;
        let a0 = (s0 / r).min(std::f64::consts::PI);
        let a1 = (s1 / r).min(std::f64::consts::PI);
        4.0 * std::f64::consts::PI * r * r * (0.5 * (a0 + a1)).sin() * (0.5 * (a1 - a0)).sin()
    }
}

#[inline]
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// From the entry point straight in, a sphere's chord along the normal is its diameter and a
    /// chord at angle θ to it is 2R cos θ; inside a cavity's medium, the same rays never return.
    #[test]
    fn chords_from_the_entry_point() {
        let sphere = Sphere {
            radius: 2.0,
            side: 1.0,
        };
        let cavity = Sphere {
            side: -1.0,
            ..sphere
        };
        for theta in [0.0f64, 0.3, 1.2] {
            let u = [theta.sin(), 0.0, theta.cos()];
            let d = sphere.distance([0.0; 3], u).unwrap();
            assert!((d - 4.0 * theta.cos()).abs() < 1e-14, "{theta}: {d}");
            assert_eq!(cavity.distance([0.0; 3], u), None);
        }
    }

    /// A point of the medium one unit above a cavity of radius 1 sees the sphere at distance 1
    /// straight at it, and misses it looking sideways past its tangent cone.
    #[test]
    fn a_cavity_is_hit_from_outside_only_within_its_tangent_cone() {
        let cavity = Sphere {
            radius: 1.0,
            side: -1.0,
        };
        // The centre is at −ẑ; the point (0, 0, 1) is 2 from it.
        let d = cavity.distance([0.0, 0.0, 1.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((d - 1.0).abs() < 1e-15);
        // Half-angle of the tangent cone: asin(1/2) = 30°.
        let past = 31f64.to_radians();
        let u = [past.sin(), 0.0, -past.cos()];
        assert_eq!(cavity.distance([0.0, 0.0, 1.0], u), None);
        let within = 29f64.to_radians();
        let u = [within.sin(), 0.0, -within.cos()];
        assert!(cavity.distance([0.0, 0.0, 1.0], u).is_some());
    }

    /// The normal points out of the medium, and the geodesic to the antipode is πR; for a sphere
    /// of 10⁸ cm, both agree with the half-space's to rounding at a point 1 cm from the entry.
    #[test]
    fn normals_and_geodesics() {
        let r = 3.0;
        for side in [1.0, -1.0] {
            let s = Sphere { radius: r, side };
            assert_eq!(s.outward_normal([0.0; 3]), [0.0, 0.0, -1.0]);
            let antipode = [0.0, 0.0, 2.0 * side * r];
            assert!((s.geodesic(antipode) - std::f64::consts::PI * r).abs() < 1e-14);
            let equator = [side * r, 0.0, side * r];
            assert!((s.geodesic(equator) - std::f64::consts::FRAC_PI_2 * r).abs() < 1e-14);
            let n = s.outward_normal(equator);
            assert!((n[0] - 1.0).abs() < 1e-15 && n[2].abs() < 1e-15, "{n:?}");
            let huge = Sphere { radius: 1e8, side };
            // The point of the sphere 1 cm from the entry along x: z = σ(R − √(R² − 1)).
            let z = side * 1.0 / (1e8 + (1e16f64 - 1.0).sqrt());
            assert!((huge.geodesic([1.0, 0.0, z]) - 1.0).abs() < 1e-12);
            // The whole sphere's area in bands, and the plane's annulus for a huge one.
            let total: f64 = (0..10).map(|i| s.band_area(i as f64, i as f64 + 1.0)).sum();
            assert!(
                (total - 4.0 * std::f64::consts::PI * r * r).abs() < 1e-12,
                "{total}"
            );
            let annulus = std::f64::consts::PI * (4.0 - 1.0);
            assert!((huge.band_area(1.0, 2.0) - annulus).abs() < 1e-12 * annulus);
            let up = huge.distance([1.0, 0.0, 0.25], [0.0, 0.0, -1.0]).unwrap();
            assert!((up - (0.25 - z)).abs() < 1e-14, "{up}");
        }
    }
}
