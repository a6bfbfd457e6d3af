//! The bodies a beam enters: a sphere (convex), a spherical cavity (concave) and a slab, and the
//! geometry the walk asks of them: where a ray leaves the medium, the normal there, and where on
//! the surface an exit lies relative to the entry point.
//!
//! Units: cm. Frame: the entry point is the origin, +z its inward normal, and the beam comes in
//! in the x–z plane travelling towards +x (as [`crate::Incidence`] in a half-space).

use serde::{Deserialize, Serialize};

use super::slab::{Face, Slab};
use super::sphere::Sphere;

/// The shape of the body a beam enters; its medium is given apart ([`super::Coefficients`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Body {
    /// The inside of a sphere of radius R [cm]: a convex body.
    Sphere {
        /// Radius R [cm].
        radius_cm: f64,
    },
    /// The medium outside a spherical cavity of radius R [cm], infinite: a concave surface.
    Cavity {
        /// Radius R [cm].
        radius_cm: f64,
    },
    /// A slab of thickness t [cm]: light enters one face and leaves by either.
    Slab {
        /// Thickness t [cm].
        thickness_cm: f64,
    },
}

impl Body {
    /// The size that defines the body (radius or thickness) [cm].
    pub fn size_cm(&self) -> f64 {
        match *self {
            Body::Sphere { radius_cm } | Body::Cavity { radius_cm } => radius_cm,
            Body::Slab { thickness_cm } => thickness_cm,
        }
    }

    /// Whether light can leave through a far face (a slab's), tallied as transmittance.
    pub fn has_far_face(&self) -> bool {
        matches!(self, Body::Slab { .. })
    }
}

/// Where an exit lies on the body's surface, seen from the entry point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SurfacePoint {
    /// Distance from the entry point along the surface [cm]: the geodesic on a sphere, the
    /// planar distance on a slab's entry face, the planar distance from the point below the entry
    /// on its far face.
    pub radius: f64,
    /// Azimuth about the entry normal from the direction the beam travels along the surface
    /// (+x), folded onto [0, π] by the symmetry of the plane of incidence [rad].
    pub azimuth: f64,
    /// The signed coordinate along the plane of incidence, radius·cos(azimuth) [cm]: positive
    /// ahead of the entry, in the direction the beam travels along the surface.
    pub along: f64,
}

/// A body prepared for the walk.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Shape {
    Sphere(Sphere),
    Slab(Slab),
}

impl From<Body> for Shape {
    fn from(body: Body) -> Self {
        match body {
            Body::Sphere { radius_cm } => Shape::Sphere(Sphere {
                radius: radius_cm,
                side: 1.0,
            }),
            Body::Cavity { radius_cm } => Shape::Sphere(Sphere {
                radius: radius_cm,
                side: -1.0,
            }),
            Body::Slab { thickness_cm } => Shape::Slab(Slab {
                thickness: thickness_cm,
            }),
        }
    }
}

impl Shape {
    /// Distance [cm] along the unit direction `u` from `p` to where the ray leaves the medium,
    /// and through which face; `None` when it never does.
    #[inline]
    pub fn distance(&self, p: [f64; 3], u: [f64; 3]) -> Option<(f64, Face)> {
        match self {
            Shape::Sphere(s) => s.distance(p, u).map(|d| (d, Face::Entry)),
            Shape::Slab(s) => s.distance(p, u),
        }
    }

    /// The unit normal out of the medium at the point `p` of `face`.
    #[inline]
    pub fn outward_normal(&self, p: [f64; 3], face: Face) -> [f64; 3] {
        match self {
            Shape::Sphere(s) => s.outward_normal(p),
            Shape::Slab(_) => Slab::outward_normal(face),
        }
    }

    /// Area [cm²] of the surface between distances `s0` < `s1` [cm] from the entry point (on a
    /// slab's far face, from the point below it): a spherical band, or the annulus
    /// π(s₁² − s₀²) = 2π(i + ½)dr² of MCML's radial bin i.
    pub fn band_area(&self, s0: f64, s1: f64) -> f64 {
        match self {
            Shape::Sphere(s) => s.band_area(s0, s1),
            Shape::Slab(_) => std::f64::consts::PI * (s1 * s1 - s0 * s0),
        }
    }

    /// Where the point `p` of the surface lies relative to the entry point.
    #[inline]
    pub fn surface_point(&self, p: [f64; 3]) -> SurfacePoint {
        let rho = p[0].hypot(p[1]);
        let radius = match self {
            Shape::Sphere(s) => s.geodesic(p),
            Shape::Slab(_) => rho,
        };
        SurfacePoint {
            radius,
            azimuth: p[1].abs().atan2(p[0]),
            along: if rho > 0.0 { radius * p[0] / rho } else { 0.0 },
        }
    }
}
